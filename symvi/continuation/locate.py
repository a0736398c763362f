"""Special points between two orbits of one period-1 branch, for a caller that brackets
the crossings itself: :func:`symvi.analysis.hopf.hopf_points`, whose certified scan of the
closed-form branches (eqs. (10)–(16)) finds each sign change and hands it here.

The two orbits become two points X = (y, T = 2 pi / omega, omega) of the 1-1 shooting
problem of :mod:`symvi.orbits.periodic` continued in omega, and the point is located
by the same arclength locator and given the same coefficients as on any branch of
:func:`symvi.continuation.continue_branch` (:class:`symvi.continuation.special.Codim1Tracker`):
one owner for locating fold, flip, Neimark–Sacker and branch points.
"""
import math

import numpy as np

from ..errors import SymviError
from ..orbits.periodic import Problem
from .engine import tangent
from .result import LOCATED_AS
from .special import Codim1Tracker

#: what a sign change of hopf_points' scan is, as a kind of special point (one vocabulary)
KINDS = LOCATED_AS


def _point(orbit, tau_near=None):
    y = np.array([float(v) for v in orbit.y])
    if tau_near is not None:              # the closed form reduces tau mod 2 pi
        y[-1] += 2 * math.pi * round((tau_near - y[-1]) / (2 * math.pi))
    w = float(orbit.omega)
    return np.concatenate([y, [2 * math.pi / w, w]])


def locate_between(model, kind, a, b, *, coefficients=True):
    """The special point of ``kind`` ("ns", "flip", "branch-point", or a key of
    :data:`KINDS`) between the period-1 orbits ``a`` and ``b`` of one branch of
    ``model`` (a :class:`symvi.Model`), as a :class:`SpecialPoint` with ``value`` =
    omega; None when the sign change was not that point (a neutral saddle for "ns").
    ``coefficients=False`` skips the Neimark–Sacker normal form (the caller computes
    its own).  Raises :class:`SymviError` when the locator fails."""
    kind = KINDS.get(kind, kind)
    problem = Problem(model, 1, 1, param="omega")
    Xa = _point(a)
    Xb = _point(b, tau_near=Xa[-3])
    m = problem.size
    _, Gu, Gl = problem.evaluate(Xa[:m], Xa[m], dparam=True)
    ta = tangent(Gu, Gl, (Xb - Xa) / np.linalg.norm(Xb - Xa))
    tracker = Codim1Tracker(problem, coefficients=coefficients)
    try:
        return tracker.locate(kind, Xa, ta, Xb)
    except (ValueError, RuntimeError, np.linalg.LinAlgError) as exc:
        raise SymviError(f"locating the {kind} point between omega = {float(Xa[m])!r} and "
                         f"{float(Xb[m])!r} failed: {exc}") from None
