"""What a branch is made of (points, special points, the branch) and the corrector that
computes its points: the pseudo-arclength step of :mod:`symvi.continuation.branch`."""
from dataclasses import dataclass, field

import numpy as np

from ..orbits.periodic import PeriodicOrbit, Problem

#: corrector: iteration limit and relative step tolerance
CORR_MAXIT = 8
CORR_TOL = 1e-11


@dataclass(frozen=True)
class BranchPoint:
    """One point of a branch: the parameter value and the orbit there."""

    value: float
    orbit: PeriodicOrbit = field(repr=False)

    @property
    def y(self):
        return self.orbit.y

    @property
    def multipliers(self):
        return self.orbit.multipliers

    @property
    def stable(self):
        return self.orbit.stable

    @property
    def admissible(self):
        return self.orbit.admissible

    def as_dict(self):
        return {"value": self.value, "y": [float(v) for v in self.orbit.y],
                "multipliers": [[z.real, z.imag] for z in self.orbit.multipliers],
                "stable": bool(self.orbit.stable), "admissible": bool(self.orbit.admissible)}


@dataclass(frozen=True)
class SpecialPoint:
    """A located special point: ``kind`` is fold, flip, ns, grazing, admissibility,
    or R3/R4 (strong resonance); ``coefficients`` its normal-form numbers."""

    kind: str
    value: float
    orbit: PeriodicOrbit = field(repr=False)
    coefficients: dict
    detail: str
    index: int = 0              # the branch point after which it lies

    def as_dict(self):
        return {"kind": self.kind, "value": self.value,
                "admissible": bool(self.orbit.admissible),
                "y": [float(v) for v in self.orbit.y],
                "multipliers": [[z.real, z.imag] for z in self.orbit.multipliers],
                "coefficients": {k: (float(v) if isinstance(v, (int, float, np.floating))
                                     else v) for k, v in self.coefficients.items()},
                "detail": self.detail}


@dataclass(frozen=True)
class Branch:
    """A continued branch of n-p orbits: points in arclength order, special points
    located on it, and why it ended."""

    param: str
    n: int
    p: int
    points: tuple
    special: tuple
    end: str
    notes: tuple = ()
    problem: Problem = field(repr=False, default=None)
    states: tuple = field(repr=False, default=())      # X = (u, lam) of each point
    bounds: tuple = (None, None)

    def __len__(self):
        return len(self.points)

    @property
    def values(self):
        return np.array([pt.value for pt in self.points])

    def curve(self, component=0):
        """Plain data for a figure: values, the section coordinate ``component`` of each
        impact point (points x p), stability, admissibility and the special points."""
        return {"values": [pt.value for pt in self.points],
                "Y": [[y[component] for y in pt.orbit.points] for pt in self.points],
                "stable": [bool(pt.stable) for pt in self.points],
                "admissible": [bool(pt.admissible) for pt in self.points],
                "special": [(sp.kind, sp.value, [y[component] for y in sp.orbit.points])
                            for sp in self.special]}

    def as_dict(self):
        return {"param": self.param, "orbit": f"{self.n}-{self.p}",
                "points": [pt.as_dict() for pt in self.points],
                "special": [s.as_dict() for s in self.special],
                "end": self.end, "notes": list(self.notes)}


def tangent(Gu, Gl, t_prev):
    m = Gu.shape[0]
    A = np.empty((m + 1, m + 1))
    A[:m, :m], A[:m, m], A[m] = Gu, Gl, t_prev
    rhs = np.zeros(m + 1)
    rhs[m] = 1.0
    t = np.linalg.solve(A, rhs)
    return t / np.linalg.norm(t)


def root_on_arc(problem, f, Xa, ta, Xb):
    """A zero of f(X, t, Gu) between two points of a branch, by Brent's method in the
    arclength s along ta, each trial point corrected on t_a . (X - X_a) = s; (X, t, Gu)."""
    from scipy.optimize import brentq
    sb = float(np.dot(ta, Xb - Xa))
    cache = {}

    def g(s):
        Xp = Xa + (s / sb) * (Xb - Xa)
        res = correct(problem, Xp, ta, float(np.dot(ta, Xa)) + s)
        if res is None:
            raise RuntimeError(f"the corrector failed at arclength {s:.3g}")
        X, Gu, Gl, _ = res
        cache[s] = (X, tangent(Gu, Gl, ta), Gu)
        return f(*cache[s])
    s = brentq(g, 0.0, sb, xtol=1e-14 * max(1.0, abs(sb)), rtol=8.9e-16)
    if s not in cache:
        g(s)
    return cache[s]


def correct(problem, Xp, t, c):
    """Newton on G(X) = 0, t . X = c from Xp; (X, G_u, G_lam, iterations) or None."""
    X = Xp.copy()
    m = problem.size
    A = np.empty((m + 1, m + 1))
    F = np.empty(m + 1)
    problem.at(X[m])                      # validates the predicted parameter value once
    for it in range(1, CORR_MAXIT + 1):
        G, Gu, Gl = problem.evaluate(X[:m], X[m], dparam=True, check=False)
        A[:m, :m], A[:m, m], A[m] = Gu, Gl, t
        F[:m], F[m] = G, np.dot(t, X) - c
        try:
            dX = np.linalg.solve(A, -F)
        except np.linalg.LinAlgError:
            return None
        if not np.isfinite(dX).all():
            return None
        X = X + dX
        if np.abs(dX).max() <= CORR_TOL * (1 + np.abs(X).max()):
            # residual and derivatives at the final X itself: the multipliers, the tangent
            # and every test function of the point are then those of X, not of the last
            # iterate O(CORR_TOL) away (which moved located points by up to ~4e-12)
            G, Gu, Gl = problem.evaluate(X[:m], X[m], dparam=True, check=False)
            if np.abs(G).max() <= 1e3 * CORR_TOL * (1 + np.abs(X).max()):
                return X, Gu, Gl, it
            return None
    return None
