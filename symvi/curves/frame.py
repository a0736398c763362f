"""The frame every two-parameter curve runs in (fold, flip and NS curves of
:mod:`.curve`, grazing curves of :mod:`.grazing`): its arguments checked once, its box and
steps, its first tangent, its two halves joined into one curve."""
import dataclasses
import math

import numpy as np

from ..continuation.engine import tangent
from ..errors import ParameterError


def prepare(model, orbit, names, fixed, bounds):
    """What a curve in ``names`` from ``orbit`` needs of its arguments, checked: (names,
    the model with ``fixed`` set, omega (``fixed``'s or the orbit's), the parameters
    parsed once, whether one is omega, their start values, the box, and the fixed values
    a curve reports: ``fixed`` with omega when omega is not a curve parameter)."""
    names = tuple(names)
    if len(names) != 2:
        raise ParameterError("params", names, "two parameter names, e.g. omega,b")
    fixed = dict(fixed)
    omega = fixed.pop("omega", None)
    if omega is None:
        omega = orbit.omega
    for nm in names:
        if nm in fixed:                         # (omega was taken out of fixed above)
            raise ParameterError(nm, fixed[nm], "not fixed: it is a curve parameter")
    if fixed:
        model = model.with_(**fixed)
    # the names parsed once, here: the curve system gets the lenses
    pars = tuple(model.parameter(nm) for nm in names)
    on_omega = any(par.is_forcing_frequency for par in pars)
    start = {nm: float(par.get(model, omega)) for nm, par in zip(names, pars)}
    if not on_omega:
        fixed["omega"] = float(omega)
    return names, model, omega, pars, on_omega, start, bounds_of(names, start, bounds), fixed


def bounds_of(names, start, bounds):
    bounds = dict(bounds or {})
    out = {}
    for nm in names:
        if nm in bounds:
            lo, hi = (float(v) for v in bounds.pop(nm))
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise ParameterError(f"bounds[{nm}]", (lo, hi), "finite LO < HI")
            if not lo <= start[nm] <= hi:
                raise ParameterError(f"bounds[{nm}]", (lo, hi), f"an interval containing the "
                                     f"start value {start[nm]:.12g}")
        else:
            v = start[nm]
            lo, hi = (v / 2, 2 * v) if v > 0 else (2 * v, v / 2) if v < 0 else (-1.0, 1.0)
        out[nm] = (lo, hi)
    if bounds:
        raise ParameterError("bounds", sorted(bounds), f"bounds of the curve's parameters "
                             f"{', '.join(names)} only")
    return out


def steps(system, box, h, h_max):
    """(lo, hi, h, h_max) of a curve in ``box``: the bounds of (a, b) and the first and
    largest steps (by default a 200th and a 20th of the box's smaller side)."""
    a, b = system.names
    lo = np.array([box[a][0], box[b][0]])
    hi = np.array([box[a][1], box[b][1]])
    span = float(np.min(hi - lo))
    h_max = float(h_max) if h_max is not None else span / 20 + 0.02
    return lo, hi, float(h) if h is not None else min(h_max, span / 200), h_max


def first_tangent(system, X, sgn):
    """The unit tangent of a curve at X, pointing to increasing b for ``sgn`` = 1 (by a
    where the curve is parallel to b)."""
    F, DF, Fb = system.evaluate(X[:-1], X[-1], dparam=True)
    e = np.zeros(len(X))
    e[-1] = sgn
    t = tangent(DF, Fb, e)
    if abs(t[-1]) < 1e-3:                       # the curve is parallel to b here: orient by a
        e = np.zeros(len(X))
        e[-2] = sgn
        t = tangent(DF, Fb, e)
    return t


def join(halves):
    """One curve from the two directions: the second reversed, then the first."""
    pts, states, ends = list(halves[0][0]), list(halves[0][1]), [halves[0][3]]
    # a tracker's index is that of the point after the special one: make it the one before
    special = [reindex(s, s.index - 1) for s in halves[0][2]]
    if len(halves) == 2:
        p2, s2, sp2, e2 = halves[1]
        shift = len(p2) - 1
        pts = list(reversed(p2[1:])) + pts
        states = list(reversed(s2[1:])) + states
        # (an event beyond the second half's last point, a landing, is before point 0)
        special = [reindex(s, max(0, shift - s.index)) for s in sp2] + \
                  [reindex(s, s.index + shift) for s in special]
        ends = [e2, ends[0]]
        special.sort(key=lambda s: s.index)
    return pts, states, special, ends


def reindex(sp, i):
    """The located point ``sp`` at index ``i`` of its curve's points."""
    return dataclasses.replace(sp, index=i)
