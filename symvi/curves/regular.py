"""Curves followed through an impact at zero velocity on a regular test (issue 27, item 2).

Where impact i of an n-p orbit slows to zero speed, the time-eliminated map has a pole
(eq. (30)): its Jacobian at impact i is DP_i = dh/dy - a b^T / w, w = dg/dT of flight i
(-> 0 with the speed), so one multiplier of the monodromy M grows like 1/w and the
bordered test functions of :mod:`symvi.curves.system` cannot be evaluated there
(:data:`symvi.curves.curve.MULTIPLIER_CUT` ends a curve before).  By the matrix
determinant lemma, with L and R the finite products of the other flights' DP_j,

    q(z) = w det(M - z I) = det([[L (dh/dy) R - z I, L dh/dT], [R^T (dg/dy)^T, w]]),

a polynomial in z whose coefficients are smooth in the shooting unknowns through w = 0
(there its degree drops by one: the multiplier at infinity has gone).  The curves are
followed on q instead:

    fold:  G(u; a, b) = 0,  q(1) = 0                       (m + 1 equations, X = (u, a, b))
    flip:  G(u; a, b) = 0,  q(-1) = 0
    NS:    G(u; a, b) = 0,  Re q(e^{i theta}) = Im q(e^{i theta}) = 0
                                                     (m + 2 equations, X = (u, theta, a, b))

G the multiple-shooting system with the flight times as unknowns (smooth through zero
speed, :mod:`symvi.curves.grazing`).  Where q vanishes with w != 0 the curve is the
standard one; so the bridge of :func:`bridge` joins two pieces of one curve across
grazing: it locates each zero of the impact's speed on the way (a grazing-NS, -fold or
-flip point: the curve meets the grazing curve there) and hands over to the standard
test where the orbit is admissible again.  Its derivatives are central differences of
step :data:`STEP` (the test is evaluated only on this stretch; the normal-form
coefficients are not: the jets have the pole).
"""
import math

import numpy as np

from ..continuation import engine
from ..continuation.engine import Client, correct
from ..continuation.result import EVENT_KINDS
from ..errors import SymviError
from ..orbits.periodic import orbit_of
from .frame import first_tangent, reindex
from .points import Codim2Point, CurvePoint
from .system import CurveSystem

#: the step of the central differences of q (relative to 1 + |X_k|)
STEP = 1e-7
#: the corrector's step tolerance on q (relative to 1 + max|X|)
BRIDGE_TOL = 1e-9
#: the bridge hands over to the standard test where the orbit is admissible again and
#: its multipliers are below this modulus (a quarter of the cut that ended the curve,
#: :data:`symvi.curves.curve.MULTIPLIER_CUT`, so that the two do not alternate)
HANDOVER_MULTIPLIER = 25.0


def regular_char(pr, u, lam, i, zs):
    """[q(z) for z in zs] = w det(M - z I) of the module docstring at the solution u of the
    shooting problem ``pr`` at lam, regular where impact i grazes (complex z allowed)."""
    _, Gu, _ = pr.evaluate(u, lam, check=False)
    d, p = pr.d, pr.p
    mats, blocks = [], None
    for j in range(p):
        r0, ct = j * d, p * d + j
        dhdy = Gu[r0:r0 + d, r0:r0 + d] + (np.eye(d) if p == 1 else 0)   # minus y_{j+1}
        dhdt, dgdy, dgdt = Gu[r0:r0 + d, ct], Gu[ct, r0:r0 + d], Gu[ct, ct]
        if j == i:
            blocks = (dhdy, dhdt, dgdy, dgdt)
            mats.append(None)
        else:
            mats.append(dhdy - np.outer(dhdt, dgdy) / dgdt)
    R, L = np.eye(d), np.eye(d)
    for D in mats[:i]:
        R = D @ R
    for D in mats[i + 1:]:
        L = D @ L
    dhdy, dhdt, dgdy, w = blocks
    complex_ = any(isinstance(z, complex) for z in zs)
    A = np.empty((d + 1, d + 1), dtype=complex if complex_ else float)
    C = L @ dhdy @ R
    A[:d, d], A[d, :d], A[d, d] = L @ dhdt, R.T @ dgdy, w
    out = []
    for z in zs:
        A[:d, :d] = C - z * np.eye(d)
        out.append(np.linalg.det(A))
    return out


class RegularSystem(CurveSystem):
    """The ``kind`` curve (ns, flip, fold) of the n-p orbits of ``model`` in ``names`` on
    the regular test q of impact ``impact`` (module docstring); X = (u, theta, a, b) for
    NS, (u, a, b) otherwise."""

    #: the corrector's step tolerance: q's derivatives are differences, and its Newton
    #: steps stall at ~1e-10 (residuals at rounding), above the engine's CORR_TOL
    corr_tol = BRIDGE_TOL

    def __init__(self, model, n, p, names, kind, impact, omega=None, signature=None):
        super().__init__(model, n, p, names, kind, omega=omega, signature=signature)
        self.impact = int(impact)
        self.extra = 1 if kind == "ns" else 0
        self.size = self.m + 1 + self.extra

    def _q(self, X):
        """The test's values at X: (Re q, Im q)(e^{i theta}) for NS, q(-+1) otherwise."""
        m = self.m
        if self.kind == "ns":
            c = regular_char(self.problem(X[-1]), X[:m], X[m + 1], self.impact,
                             [complex(math.cos(X[m]), math.sin(X[m]))])[0]
            return np.array([c.real, c.imag])
        z = 1.0 if self.kind == "fold" else -1.0
        return np.array([regular_char(self.problem(X[-1]), X[:m], X[m], self.impact, [z])[0]])

    def evaluate(self, v, lam, jac=True, dparam=False, check=True):
        """(F, dF/dv, dF/db) at v = (u[, theta], a), b = lam; F = (G, the test)."""
        m, e = self.m, self.extra
        X = np.append(np.asarray(v, dtype=float), float(lam))
        u, a = X[:m], float(X[m + e])
        pr = self.problem(lam)
        G, Gu, Ga = pr.evaluate(u, a, jac=jac, dparam=jac, check=check)
        F = np.concatenate([G, self._q(X)])
        if not jac:
            return F, None, None
        rows = np.empty((1 + e, len(X)))
        for k in range(len(X)):
            h = STEP * (1 + abs(X[k]))
            dX = np.zeros(len(X))
            dX[k] = h
            rows[:, k] = (self._q(X + dX) - self._q(X - dX)) / (2 * h)
        DF = np.zeros((m + 1 + e, m + 1 + e))
        DF[:m, :m], DF[:m, m + e] = Gu, Ga
        DF[m:] = rows[:, :-1]
        if not dparam:
            return F, DF, None
        return F, DF, np.concatenate([pr.derivative(u, a, self.params[1]), rows[:, -1]])

    def lift(self, X, theta=None):
        """The curve state X = (u, a, b) of :class:`CurveSystem` in this system's layout."""
        X = np.asarray(X, dtype=float)
        return X if not self.extra else np.concatenate([X[:-2], [theta], X[-2:]])

    def drop(self, X):
        """This system's X in the layout (u, a, b) of :class:`CurveSystem`."""
        return X if not self.extra else np.concatenate([X[:self.m], X[-2:]])

    def point_at(self, X, admissibility=True):
        """({a, b}, the PeriodicOrbit) at this system's X (the multipliers have the pole)."""
        m, X2 = self.m, self.drop(X)
        a, b = self.names
        orbit = orbit_of(self.problem(X2[-1]), X2[:m], X2[m], admissibility=admissibility)
        return {a: float(X2[m]), b: float(X2[m + 1])}, orbit

    def speeds(self, X):
        """The approach speed of each impact of the orbit at X."""
        m, pr = self.m, self.problem(X[-1])
        fl, (_, flow, _) = pr.flights(X[:m], X[m + self.extra], check=False)
        return np.asarray(pr.approach_speeds(fl, flow), dtype=float)


class _Bridge(Client):
    """The bridge as a client of the engine: its points are the curve's points (not
    analysed: no l1 or c, the jets have the pole), and it stops where it has done its job
    (:func:`bridge`)."""

    def __init__(self, system, resume):
        self.system, self.names, self.resume = system, system.names, resume
        self.crossed = None

    def point(self, X, prev, Gu):
        s = self.system
        params, orbit = s.point_at(X)
        theta = float(X[s.m]) if s.extra else None
        kappa = math.cos(theta) if s.extra else None
        pt = CurvePoint(params, orbit, kappa, theta, None, None, True)
        crit = complex(math.cos(theta), math.sin(theta)) if s.extra else \
            (1.0 if s.kind == "fold" else -1.0)
        object.__setattr__(pt, "_pair", (crit, crit.conjugate() if s.extra else crit))
        object.__setattr__(pt, "_bridged", True)
        return pt

    def stop(self, X, pt):
        if not self.resume:
            return self.crossed or ""
        if pt.admissible and max(abs(z) for z in pt.orbit.multipliers) < HANDOVER_MULTIPLIER:
            return "resume"
        return ""


class _Crossings(engine.Tracker):
    """The zeros of the grazing impact's speed along the bridge: grazing-NS (-fold,
    -flip) points, where the curve meets the grazing curve of that impact."""

    def __init__(self, system, client):
        super().__init__(system)
        self.client = client

    def tests(self, X, t, pt):
        return {"v": float(pt.orbit.impact_velocities[self.system.impact])}

    def brackets(self, pa, pb, pta, ptb):
        return [("v", {})] if engine.sign_change(pa["v"], pb["v"]) else []

    def locate_event(self, kind, Xa, ta, Xb, index, **kw):
        s = self.system
        i = s.impact
        # the regular system is singular where the speed vanishes (the corrector stalls
        # next to it): the root of the speed interpolated along the arc, with its spread
        X, spread = engine.interpolated_root(s, lambda X, Gu: float(s.speeds(X)[i]),
                                             Xa, ta, Xb)
        params, orbit = s.point_at(X, admissibility=False)
        a, b = s.names
        # spread: the interpolation's; tolerance: the corrector's on the bridge (its
        # derivatives are differences), the larger of the two bounds the point's error
        coef = {"impact": i + 1, "spread": float(spread),
                "tolerance": BRIDGE_TOL * (1 + float(np.max(np.abs(X))))}
        if s.extra:
            coef["theta"] = float(X[s.m])
        name = "grazing-NS" if s.kind == "ns" else f"grazing-{s.kind}"
        what = (EVENT_KINDS[name] + f"; impact {i + 1} arrives with zero velocity (its "
                "speed changes sign: the orbit is admissible on one side only); located "
                "on the regular test w det(M - z I)")
        sp = Codim2Point(name, params, orbit, coef, what, index)
        self.client.crossed = self.client.crossed or (
            f"reached grazing at a {name} point {a} = {params[a]:.12g}, {b} = {params[b]:.12g} "
            f"(impact {i + 1} at zero velocity; followed past the multiplier cut on the "
            "regular test)")
        return sp

    def unlocated(self, kind, Xa, Xb, index, exc):
        s = self.system
        params, orbit = s.point_at(Xb, admissibility=False)
        a, b = s.names
        self.client.crossed = self.client.crossed or (
            f"reached grazing near {a} = {params[a]:.12g}, {b} = {params[b]:.12g} (impact "
            f"{s.impact + 1}'s speed changes sign; the point was not located: {exc})")
        return Codim2Point("unlocated", params, orbit,
                           {"kind": "grazing-NS" if s.kind == "ns" else f"grazing-{s.kind}"},
                           f"a zero of impact {s.impact + 1}'s speed on the bridge could not "
                           f"be located: {exc}", index)


def bridge(system, X, prev, lo, hi, *, h, h_max, max_points, through, theta=None):
    """Follow the curve of ``system`` (a :class:`CurveSystem`) from its state X (the point
    before it: ``prev``, for the direction) on the regular test of its slowest impact.

    Without ``through`` it ends at the first zero of that impact's speed, located and named
    (the curve's end); with ``through`` it goes on until the orbit is admissible again with
    its multipliers below HANDOVER_MULTIPLIER, where the standard test takes over.  Returns
    (points, states in the layout (u, a, b), located points, why it ended, the direction of
    its last step in that layout, resumed: bool); the first state (X itself) is not among
    the points."""
    m = system.m
    pr = system.problem(X[-1])
    fl, (_, flow, _) = pr.flights(X[:m], X[m], check=False)
    i = int(np.argmin(np.abs(pr.approach_speeds(fl, flow))))
    reg = RegularSystem(system.model, system.n, system.p, system.params, system.kind, i,
                        omega=system.omega, signature=system.signature)
    X0 = reg.lift(X, theta)
    e = np.zeros(len(X0))
    e[-1] = 1.0
    res = correct(reg, X0, e, X0[-1])
    if res is None:
        raise SymviError("the regular test could not be solved at the curve's last point")
    X0 = res[0]
    t = first_tangent(reg, X0, 1.0)
    if float(np.dot(reg.drop(t), np.asarray(X) - np.asarray(prev))) < 0:
        t = -t
    client = _Bridge(reg, through)
    tracker = _Crossings(reg, client)
    points, states, end = engine.run(reg, client, X0, t, lo, hi, h=h, h_max=h_max,
                                     max_points=max_points, tracker=tracker, through=True,
                                     chord_first=True)
    # the start (X itself) dropped: an event's index is that of the point after it
    points, states = points[1:], [reg.drop(S) for S in states[1:]]
    special = [reindex(sp, sp.index - 1) for sp in tracker.special]
    resumed = end == "resume"
    if not through and client.crossed:
        # the point past the zero speed is not the curve's: it ends at the located point
        keep = special[0].index
        points, states = points[:keep], states[:keep]
        special = special[:1]
        end = client.crossed
    elif resumed:
        end = ""
    Xl = states[-1] if states else np.asarray(X)
    Xp = states[-2] if len(states) > 1 else np.asarray(X)
    return points, states, special, end, Xl - Xp, resumed
