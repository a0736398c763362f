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
    """P(y; omega), eq. (31): one application of the impact map.

    Of ``model`` (a Model, or the paper's Params: :meth:`Model.of`) on float64 or
    (``digits``) mpmath.  Raises nothing for a flight that grazes or never returns;
    inspect ``status``.  From y just after an impact (t reset to 0) the exact flow runs
    to the first contact with the stop, where the impact law v_k+ = -r v_k- (eq. (2))
    applies and tau' = tau + omega t_e (mod 2 pi), eqs. (26)–(31).

    Parameters
    ----------
    model : Model or Params
        A model with one rigid upper stop on one mass (the paper's Params as its
        ``Model.luo_xie``); with nonlinear forces the flight is the numerical flow's
        (:mod:`symvi.flow.nonlinear`, float64 only).
    omega : float
        Forcing frequency, 1e-4 <= omega <= 1e4, not at the natural frequency of an
        undamped mode.
    y : sequence of float
        The section point just after an impact, 2N finite numbers in the order of
        :class:`symvi.Orbit`'s ``names``: (v_k+, x_j, v_j for j != k, tau).  For a
        flight, v_k+ must point away from the stop.
    digits : int, optional
        Compute with mpmath at this many digits.  Default None: float64.
    t_max : float, optional
        Longest flight searched for the next impact; default None: 1000 forcing
        periods, 2000 pi / omega.

    Returns
    -------
    MapStep
        ``y`` the image P(y) (tau in [0, 2 pi)), ``t`` the flight time t_e,
        ``impact_velocity`` v_k- just before the impact (> 0 on the physical branch),
        ``status`` "impact", "grazing" (a contact at zero speed, or a start that does not
        leave the stop) or "no-impact" (no return within ``t_max``), and
        ``tau_unwrapped`` = tau + omega t_e before the reduction mod 2 pi.  Arrays are
        float64, or mpf with ``digits``.

    Raises
    ------
    ParameterError
        ``omega`` out of range, ``y`` not 2N finite numbers, or a model with several
        stops or a lower, elastic or between-masses stop.
    SingularCaseError
        ``"forcing-resonance"``: omega at an undamped natural frequency.

    Examples
    --------
    >>> import symvi
    >>> p = symvi.Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    >>> o = symvi.period1_orbits(p, 0.72)[0]
    >>> step = symvi.poincare_map(p, 0.72, o.y)          # the fixed point maps to itself
    >>> step.status
    'impact'
    >>> print(max(abs(a - b) for a, b in zip(step.y, o.y)) < 1e-12)
    True
    >>> round(float(step.t), 6)                          # one forcing period, 2 pi / omega
    8.726646
    """
    model = Model.of(model).require_one_rigid_stop()
    if model.nonlinear is not None:           # the numerical flow: FlowView's flights
        return _nonlinear_step(model, omega, y, digits, t_max)
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


def _nonlinear_step(model, omega, y, digits, t_max):
    """:func:`poincare_map` of a model with nonlinear forces (issue 28): :func:`step` on
    the numerical flow (:class:`symvi.flow.nljet.FlowView`: the Taylor method's flight,
    the linear part's constraint and section), float64 only."""
    from ..errors import ParameterError
    from ..flow.nljet import FlowView
    if digits is not None:
        raise ParameterError("digits", digits, "None with nonlinear forces (float64; the "
                             "40-digit map is symvi.studies.nonlinear_check.NonlinearChain)")
    flow = FlowView.of(model)
    y = Section.of(model).check(y)
    omega = flow.check_omega(omega)
    return step(flow, flow.forcing(omega), np.array(y, dtype=float), t_max)


__all__ = ["MapStep", "step", "poincare_map", "IMPACT"]
