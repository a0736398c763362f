"""The impact map P of any model on the section x_k = b, eqs. (26)–(31) generalised.

From y just after an impact (t reset to 0) the flight of :mod:`symvi.flow.linear`
runs to the first contact x_k = b, where the constraint's reset applies (v_k+ = -r v_k-
for the stop on mass k: :class:`symvi.model.Constraint`) and tau' = tau + omega t_e
(mod 2 pi).
"""
from dataclasses import dataclass

import mpmath
import numpy as np

from ..model import Model
from ..flow.linear import IMPACT, LinearFlow
from .section import Section


@dataclass(frozen=True)
class MapStep:
    """One application of P: the image, the flight time and the impact velocity."""

    y: tuple                 # section point after the impact, tau in [0, 2 pi)
    t: object                # flight time t_e
    impact_velocity: object  # v_k- just before the impact (> 0 on the physical branch)
    status: str              # "impact", "grazing" or "no-impact"
    tau_unwrapped: object    # tau + omega t_e, before reduction mod 2 pi


def step(flow, forcing, y, t_max=None):
    """Apply P once from y (flow and forcing in one backend, at its precision): the map of
    a model with one stop (several run in :mod:`symvi.flow.compiled`)."""
    flow.model.require_one_rigid_stop()
    sec = Section(flow.n, flow.perm)
    bk = flow.bk
    z0, tau = sec.state(y, flow.b)
    hit = flow.motion(forcing, z0, tau).first_impact(t_max=t_max)
    tau_u = tau + forcing.omega * hit.t
    z = hit.state
    y1 = sec.image(z, flow.reset, tau_u % (2 * bk.pi))
    return MapStep(tuple(y1), hit.t, flow.approach(z), hit.status, tau_u)


def poincare_map(model, omega, y, *, digits=None, t_max=None):
    """P(y; omega), eq. (31), of ``model`` (a Model, or the paper's Params: :meth:`Model.of`)
    on float64 or (``digits``) mpmath.  Raises nothing for a flight that grazes or never
    returns; inspect ``status``."""
    model = Model.of(model).require_one_rigid_stop()
    LinearFlow.of(model)                      # validates the model
    y = Section.of(model).check(y)
    if digits is None:
        flow = LinearFlow.of(model)
        omega = flow.check_omega(omega, warn=False)
        return step(flow, flow.forcing(omega), np.array(y, dtype=float), t_max)
    flow = LinearFlow.of(model, digits)
    with mpmath.mp.workdps(digits):
        flow.check_omega(float(omega), warn=False)
        y = np.array([mpmath.mpf(v) for v in y], dtype=object)
        return step(flow, flow.forcing(mpmath.mpf(omega)), y, t_max)


__all__ = ["MapStep", "step", "poincare_map", "IMPACT"]
