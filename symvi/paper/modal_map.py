"""The paper's numeric Poincaré map P on the section x1 = b, eqs. (19)–(31), through
its 2-DOF modal closed form (:mod:`symvi.paper.modal_flow`): the independent oracle of the
impact map of every model (:mod:`symvi.maps.impact`), chain B of :mod:`symvi.studies.mpcheck` and
the reference run :func:`symvi.simulations.simulation.simulate_mp`.  ``symvi.poincare_map`` runs
:mod:`symvi.maps.impact` on ``Model.luo_xie`` since issue 11.

y = (x1dot+, x2, x2dot, tau) just after an impact, t reset to 0 there.  The
flight ends at the first crossing x1 = b (first-impact finder of
:mod:`symvi.flow`), where the impact law of eq. (2), x1dot+ = -r x1dot-, is
applied and tau' = tau + omega t_e (mod 2 pi), eq. (26).
"""
import contextlib
from dataclasses import dataclass

from ..numerics.backend import FLOAT64, backend
from .modal_flow import first_impact, motion_from
from .params import modal as _modal


@dataclass(frozen=True)
class MapStep:
    """One application of P: the image, the flight time and the impact velocity."""

    y: tuple             # (x1dot+, x2, x2dot, tau mod 2 pi) after the impact
    t: object            # flight time t_e of eq. (26)
    impact_velocity: object   # x1dot- just before the impact
    status: str          # "impact", "grazing" or "no-impact" (flow statuses)
    tau_unwrapped: object     # tau + omega t_e, before reduction mod 2 pi


def step(m, omega, b, r, y, lib=FLOAT64, t_max=None):
    """Apply P once from y with modal data m (already in backend ``lib``)."""
    v1, x2, v2, tau = y
    mot = motion_from(m, omega, (b, x2), (v1, v2), tau, lib)
    hit = first_impact(mot, b, lib, t_max=t_max)
    x1, x2n, v1m, v2n = hit.state
    tau_u = tau + omega * hit.t
    return MapStep((-r * v1m, x2n, v2n, tau_u % (2 * lib.pi)), hit.t, v1m, hit.status, tau_u)


def poincare_map(params, omega, y, *, digits=None):
    """P(y; omega) of a :class:`symvi.Params`, eq. (31), through the modal closed form,
    on float64 or (``digits``) mpmath.  Raises nothing for a flight that grazes or never
    returns; inspect ``MapStep.status``."""
    import mpmath

    if digits is None:
        return step(_modal(params), omega, params.b, params.r, tuple(map(float, y)))
    with mpmath.mp.workdps(digits):
        bk = backend(digits)
        m = _modal(params, bk)
        return step(m, bk.num(omega), bk.num(params.b), bk.num(params.r),
                    tuple(bk.num(v) for v in y), bk)


def fd_jacobian(params, omega, y, h=1e-6, digits=None):
    """Central finite-difference Jacobian of P at y (a check, not the production path).

    The tau component is differenced unwrapped, so the 2 pi cut does not matter.
    """
    import numpy as np
    import mpmath
    with mpmath.mp.workdps(digits) if digits else contextlib.nullcontext():
        lib = backend(digits) if digits else FLOAT64
        m = _modal(params, lib)
        om, b, r = lib.num(omega), lib.num(params.b), lib.num(params.r)
        yy = [lib.num(v) for v in y]
        hh = lib.num(h)
        cols = []
        for k in range(4):
            out = []
            for sgn in (1, -1):
                z = list(yy)
                z[k] += sgn * hh
                s = step(m, om, b, r, tuple(z), lib)
                out.append((*s.y[:3], s.tau_unwrapped))
            cols.append([(out[0][i] - out[1][i]) / (2 * hh) for i in range(4)])
        if digits:
            return mpmath.matrix([[cols[j][i] for j in range(4)] for i in range(4)])
        return np.array(cols, dtype=float).T
