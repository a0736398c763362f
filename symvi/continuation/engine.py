"""The one pseudo-arclength engine (Keller's method): predictor, corrector, step control,
and the bracketing and location of events.  Branches of orbits
(:mod:`symvi.continuation.branch`) and fold, flip and Neimark–Sacker curves
(:mod:`symvi.curves.curve`) are its clients.

A *system* is F(X) = 0 with X = (v, lam), n equations in n + 1 unknowns, evaluated as
``system.evaluate(v, lam, dparam=True) -> (F, F_v, F_lam)`` (``system.at(lam)`` validates
lam once per solve).  From a point X_j with unit tangent t_j (the kernel of
[F_v F_lam], oriented by the previous tangent) the predictor is X_j + h t_j and the
corrector solves

    F(X) = 0,    t_j . (X - X_j) = h,

whose Jacobian [[F_v, F_lam], [t_j^T]] stays regular at a fold, so the run turns around it
[Keller 1977; Kuznetsov, Elements of Applied Bifurcation Theory, Sec. 10.2.1].  The
corrector is Newton, or (``chord=True``) the chord method with the matrix of the last point
factorised once, Newton taking over when it fails.

One step control: the step h halves when the corrector fails or when the tangent turns by
more than arccos(MIN_COS); after an accepted step it grows by 1.5 when the corrector took at
most its nominal iteration count (2 for Newton, 3 for the chord method), stays below
nominal + 2 and shrinks by 0.6 above.  The parameters are held in a box: a step that
would leave it lands on the bound crossed (the point solved with that parameter fixed).

Events: a client's :class:`Tracker` evaluates its test functions at each accepted point;
a sign change between two points (:func:`sign_change`) brackets an event, located by
Brent's method in the arclength s (:func:`root_on_arc`), each trial point corrected on the
hyperplane t_a . (X - X_a) = s; at a branch point, where that corrector is singular, from a
Chebyshev interpolant of corrected nodes of the bracket (:func:`interpolated_root`).

References: H. B. Keller, Numerical solution of bifurcation and nonlinear eigenvalue
problems, in Applications of Bifurcation Theory (1977); Yu. A. Kuznetsov, Elements of
Applied Bifurcation Theory, 3rd ed. (2004).
"""
import math

import numpy as np

from ..errors import SymviError
from ..progress import tick

#: largest turn of the tangent accepted in one step, as the cosine between consecutive
#: tangents (else the step is halved).  One value for branches and curves (issue 24, item
#: 4): 0.95 (branches) and 0.97 (curves) were compared on both kinds of runs, see
#: benchmarks/README.md
MIN_COS = 0.97
#: corrector: iteration limit and relative step tolerance
CORR_MAXIT = 8
CORR_TOL = 1e-11
#: chord iterations of the corrector before full Newton takes over
CHORD_MAXIT = 8
#: corrector iterations at or below which the step grows (Newton converges quadratically
#: from a good predictor in 2, the chord method linearly in about 3)
NOMINAL_ITS = {False: 2, True: 3}


# --------------------------------------------------------------------------- predictor, corrector
def tangent(Gu, Gl, t_prev):
    """The unit kernel vector of [G_u G_lam], oriented by t_prev (t_prev . t = 1 > 0)."""
    m = Gu.shape[0]
    A = np.empty((m + 1, m + 1))
    A[:m, :m], A[:m, m], A[m] = Gu, Gl, t_prev
    rhs = np.zeros(m + 1)
    rhs[m] = 1.0
    t = np.linalg.solve(A, rhs)
    return t / np.linalg.norm(t)


def correct(problem, Xp, t, c):
    """Newton on G(X) = 0, t . X = c from Xp; (X, G_u, G_lam, iterations) or None.  The
    step's tolerance is CORR_TOL, or the problem's own ``corr_tol`` (a system whose
    derivatives are differences: its steps stall at their noise, above CORR_TOL)."""
    X = Xp.copy()
    m = problem.size
    tol = getattr(problem, "corr_tol", CORR_TOL)
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
        if np.abs(dX).max() <= tol * (1 + np.abs(X).max()):
            # residual and derivatives at the final X itself: the multipliers, the tangent
            # and every test function of the point are then those of X, not of the last
            # iterate O(CORR_TOL) away (which moved located points by up to ~4e-12)
            G, Gu, Gl = problem.evaluate(X[:m], X[m], dparam=True, check=False)
            if np.abs(G).max() <= 1e3 * tol * (1 + np.abs(X).max()):
                return X, Gu, Gl, it
            return None
    return None


def _factor(DF, Fb, t):
    """LU factors of the corrector's matrix [[DF, Fb], [t]] at the last point."""
    from scipy.linalg import lu_factor
    m1 = DF.shape[0]
    A = np.empty((m1 + 1, m1 + 1))
    A[:m1, :m1], A[:m1, m1], A[m1] = DF, Fb, t
    return lu_factor(A, check_finite=False)


def chord(system, Xp, t, c, lu):
    """Chord corrector: Newton on (F(X), t . X - c) with the matrix of the last point (one
    factorisation per point; each iteration only evaluates F).  (X, iterations) or None."""
    from scipy.linalg import lu_solve
    X = Xp.copy()
    system.at(X[-1])
    tol = getattr(system, "corr_tol", CORR_TOL)
    for it in range(1, CHORD_MAXIT + 1):
        F = system.evaluate(X[:-1], X[-1], jac=False, check=False)[0]
        r = np.append(F, np.dot(t, X) - c)
        if not np.all(np.isfinite(r)):
            return None
        dX = lu_solve(lu, -r, check_finite=False)
        X = X + dX
        if np.max(np.abs(dX)) <= tol * (1 + np.max(np.abs(X))):
            F = system.evaluate(X[:-1], X[-1], jac=False, check=False)[0]
            if np.max(np.abs(F)) <= 1e3 * tol * (1 + np.max(np.abs(X))):
                return X, it
            return None
    return None


# --------------------------------------------------------------------------- events
def sign_change(a, b):
    """Whether a test function changed sign between two points (None: not evaluated)."""
    return a is not None and b is not None and (a > 0) != (b > 0) and a != b


def root_on_arc(problem, f, Xa, ta, Xb):
    """A zero of f(X, t, F_v) between two points of a run, by Brent's method in the
    arclength s along ta, each trial point corrected on t_a . (X - X_a) = s; (X, t, F_v)."""
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


def interpolated_root(problem, f, Xa, ta, Xb, nodes=9):
    """A zero of f(X, G_u) on the arc from Xa to Xb where the corrector is singular (a
    branch point: [G_u G_lam] has a two-dimensional kernel, so points near it cannot be
    corrected to full accuracy).  X(s) and f(s) are smooth in the arclength s, so both are
    interpolated from corrected Chebyshev nodes of the bracket (any failed node dropped)
    and the root taken from the interpolant.  Returns (X, spread): spread = |root|
    change when the last node is dropped."""
    m = problem.size
    c0 = float(np.dot(ta, Xa))
    sb = float(np.dot(ta, Xb - Xa))
    S, F, Xs = [], [], []
    for k in range(nodes):
        s = 0.5 * sb * (1 - math.cos(math.pi * (k + 0.5) / nodes))
        res = correct(problem, Xa + (s / sb) * (Xb - Xa), ta, c0 + s)
        if res is not None:
            S.append(s)
            F.append(f(res[0], res[1]))
            Xs.append(res[0])
    if len(S) < 6:
        raise SymviError(f"only {len(S)} of {nodes} points of the bracket could be corrected")
    S, F, Xs = np.array(S), np.array(F), np.array(Xs)

    def root(k):
        P = np.polynomial.Chebyshev.fit(S[:k], F[:k], k - 1, domain=[0, sb])
        r = [z.real for z in P.roots() if abs(z.imag) < 1e-9 * sb and 0 <= z.real <= sb]
        if len(r) != 1:
            raise SymviError(f"the interpolated test function has {len(r)} roots in the "
                             "bracket")
        return r[0]
    s0 = root(len(S))
    spread = abs(s0 - root(len(S) - 1))
    X = np.array([np.polynomial.Chebyshev.fit(S, Xs[:, i], len(S) - 1, domain=[0, sb])(s0)
                  for i in range(m + 1)])
    return X, spread * abs(float(ta[-1])) + abs(float(np.dot(ta, X)) - c0 - s0)


class Tracker:
    """Test functions along a run, and the events where one changes sign.

    A client names its test functions (:meth:`tests`: a dict at each point), which sign
    changes bracket which event (:meth:`brackets`), how an event is located
    (:meth:`locate_event`, by :meth:`root`) and what is recorded when that fails
    (:meth:`unlocated`).  The engine calls :meth:`start` at the first point and
    :meth:`step` after each accepted step; the located events collect in ``special``.
    """

    #: exceptions of a locator that make an "unlocated" event instead of a failed run
    FAILURES = (SymviError, ValueError, RuntimeError, np.linalg.LinAlgError)

    def __init__(self, system):
        self.system = system
        self.special = []
        self.prev = None

    def tests(self, X, t, pt):                                   # pragma: no cover
        raise NotImplementedError

    def brackets(self, pa, pb, pta, ptb):                         # pragma: no cover
        """[(event kind, keyword arguments of locate_event)] for this step, in order."""
        raise NotImplementedError

    def locate_event(self, kind, Xa, ta, Xb, index, **kw):        # pragma: no cover
        raise NotImplementedError

    def unlocated(self, kind, Xa, Xb, index, exc):                # pragma: no cover
        raise NotImplementedError

    def start(self, X, t, pt):
        self.prev = (X, t, self.tests(X, t, pt), pt)

    def step(self, Xa, ta, Xb, tb, pt, index):
        pa, pta = self.prev[2], self.prev[3]
        pb = self.tests(Xb, tb, pt)
        self.prev = (Xb, tb, pb, pt)
        for kind, kw in self.brackets(pa, pb, pta, pt):
            self._try(kind, Xa, ta, Xb, index, **kw)

    def _try(self, kind, Xa, ta, Xb, index, **kw):
        try:
            sp = self.locate_event(kind, Xa, ta, Xb, index, **kw)
        except self.FAILURES as exc:
            sp = self.unlocated(kind, Xa, Xb, index, exc)
        if sp is not None:
            self.special.append(sp)

    def root(self, f, Xa, ta, Xb):
        return root_on_arc(self.system, f, Xa, ta, Xb)


# --------------------------------------------------------------------------- the loop
class Client:
    """What a kind of run adds to the engine: its points, where it stops, its names."""

    #: the names of the parameters held in the box (the last len(names) entries of X)
    names = ()

    def point(self, X, prev, Gu):
        """The result's point at X (``prev`` the previous one, Gu the corrector's F_v)."""
        raise NotImplementedError                                # pragma: no cover

    def where(self, X):
        return ", ".join(f"{nm} = {v:.12g}" for nm, v in zip(self.names, X[-len(self.names):]))

    def accepted(self, X, index):
        """Called at each accepted point before it is stored; may return new (F_v, F_lam)."""
        return None

    def stop(self, X, pt):
        """A reason to end the run at the accepted point X, or ''."""
        return ""

    def finish(self, end, X):
        return end


def run(system, client, X, t, lo, hi, *, h, h_max, max_points, tracker=None, through=True,
        chord_first=False, grow_with_orbit=False, first=None):
    """Continue from X (unit tangent t) within lo <= X[-k:] <= hi (k = len(lo)): the
    loop of the module docstring.  Returns (points, states, why it ended).

    ``grow_with_orbit``: the largest step grows with the orbit's size 1 + max|v[:-1]|
    relative to the start (towards a forcing resonance the orbit diverges); ``first``: the
    point at X when the client has it already."""
    lo, hi = np.atleast_1d(np.asarray(lo, float)), np.atleast_1d(np.asarray(hi, float))
    k = len(lo)
    # the box as Python floats: tested at every step, cheaper than numpy on 1-2 entries
    box = list(zip(lo.tolist(), hi.tolist()))
    near = [(1e-12 * (1 + abs(a)), 1e-12 * (1 + abs(b))) for a, b in box]
    m = len(X) - k                         # X = (u, parameters); the last k are boxed
    h_min = 1e-9 * float(np.min(hi - lo))
    nominal = NOMINAL_ITS[bool(chord_first)]
    scale0 = 1 + np.max(np.abs(X[:m]))
    F, DF, Fb = system.evaluate(X[:-1], X[-1], dparam=True)
    if first is None:
        first = client.point(X, None, DF)
    states, points = [X], [first]
    for j in range(k):                     # the start on a bound, the run leaving the box
        for bound, out in ((lo[j], t[m + j] < 0), (hi[j], t[m + j] > 0)):
            if out and abs(X[m + j] - bound) <= 1e-12 * (1 + abs(bound)):
                return points, states, f"reached {client.names[j]} = {bound:.12g}"
    if tracker:
        tracker.start(X, t, first)
    end, lu = "", None
    X0, t0 = X, t
    while len(points) < max_points:
        Xp = X + h * t
        if any(v < a or v > b for v, (a, b) in zip(Xp[m:].tolist(), box)):
            res, landed = _to_bound(system, client, X, t, h, lo, hi)
            if res is None:
                h /= 2
                if h < h_min:
                    end = "the corrector failed at the parameter bound"
                    break
                continue
            Xn, DFn, Fbn, its = res
        else:
            landed = ""
            c = float(np.dot(t, X)) + h
            why = "the corrector did not converge"
            try:
                res = None
                if chord_first:
                    if lu is None:
                        lu = _factor(DF, Fb, t)
                    res = chord(system, Xp, t, c, lu)
                    if res is not None:
                        Xn, its = res
                        DFn, Fbn = system.evaluate(Xn[:-1], Xn[-1], dparam=True)[1:]
                if res is None:
                    res = correct(system, Xp, t, c)
                    if res is not None:
                        Xn, DFn, Fbn, its = res
            except SymviError as exc:
                res, why = None, str(exc)
            if res is None:
                h /= 2
                if h < h_min:
                    end = f"step below {h_min:.2g}: {why}"
                    break
                continue
        tn = tangent(DFn, Fbn, t)
        if np.dot(tn, t) < MIN_COS and h > h_min:
            h /= 2
            continue
        try:
            pt = client.point(Xn, points[-1], DFn)
        except SymviError as exc:
            end = f"the orbit cannot be evaluated at {client.where(Xn)}: {exc}"
            break
        if tracker:
            tracker.step(X, t, Xn, tn, pt, len(points))
        tp = t
        X, t, DF, Fb, lu = Xn, tn, DFn, Fbn, None
        renewed = client.accepted(X, len(points))
        if renewed is not None:
            DF, Fb = renewed
        states.append(X)
        points.append(pt)
        tick()                             # the command's bar, if any (symvi.progress)
        # the step may grow with the orbit's size (towards a resonance it diverges)
        cap = h_max * (1 + np.max(np.abs(X[:m]))) / scale0 if grow_with_orbit else h_max
        h = min(cap, h * (1.5 if its <= nominal else 1.0 if its <= nominal + 2 else 0.6))
        end = client.stop(X, pt) or _closed(X0, t0, states[-2], X, tp, t, len(points), client)
        if end:
            break
        if not through and points[-2].admissible and not pt.admissible:
            end = (f"the orbit stops being admissible near {client.where(X)} "
                   f"({pt.orbit.reason}); the point beyond is kept, marked inadmissible")
            break
        if landed:
            end = landed
            break
        on = [j for j, v in enumerate(X[m:].tolist())
              if abs(v - box[j][0]) <= near[j][0] or abs(v - box[j][1]) <= near[j][1]]
        if on:
            end = f"reached {client.names[on[0]]} = {X[m + on[0]]:.12g}"
            break
    else:
        end = f"max_points = {max_points} reached"
    return points, states, client.finish(end, X)


def _closed(X0, t0, Xa, Xb, ta, tb, count, client):
    """Why the run ends where its last step passes through its first point again in the
    same direction (a closed curve: an isola of orbits, a loop of a curve), else ''.  The
    step from Xa (tangent ta) to Xb (tb) passes X0 when X0 projects inside its chord and
    lies within the arc's sagitta of it, L phi / 8 for a turn phi, plus a hundredth of L
    (the same solution curve retraced)."""
    if count < 4 or float(np.dot(tb, t0)) < 0.5:
        return ""
    d = Xb - Xa
    L2 = float(np.dot(d, d))
    if L2 == 0.0:
        return ""
    s = float(np.dot(X0 - Xa, d)) / L2
    if not 0.0 <= s <= 1.0:
        return ""
    phi = math.acos(min(1.0, max(-1.0, float(np.dot(ta, tb)))))
    if np.linalg.norm(Xa + s * d - X0) > math.sqrt(L2) * (phi / 4 + 1e-2):
        return ""
    return (f"the curve closes on itself at {client.where(Xb)}: it passes through its first "
            "point again in the same direction (a closed loop, followed once)")


def _to_bound(system, client, X, t, h, lo, hi):
    """Land on the first bound the step crosses: the point solved with that parameter
    fixed at the bound.  ((X, F_v, F_lam, iterations) or None, "reached ...")."""
    k = len(lo)
    m = len(X) - k
    steps = []
    for j in range(k):
        if t[m + j] != 0:
            for bound in (lo[j], hi[j]):
                s = (bound - X[m + j]) / t[m + j]
                if 0 < s <= h * (1 + 1e-12):
                    steps.append((s, j, bound))
    if not steps:
        return None, ""
    s, j, bound = min(steps)
    e = np.zeros(len(X))
    e[m + j] = 1.0
    try:
        res = correct(system, X + s * t, e, bound)
    except SymviError:
        res = None
    if res is None:
        return None, ""
    return res, f"reached {client.names[j]} = {bound:.12g}"
