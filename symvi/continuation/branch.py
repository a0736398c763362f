"""Pseudo-arclength continuation of n-p orbits in any named parameter (Keller's method).

X = (u, lam) with u the shooting unknowns of :mod:`symvi.orbits.periodic`.  From a
point X_j with unit tangent t_j (the kernel of [G_u G_lam], oriented by the
previous one), the predictor is X_j + h t_j and the corrector Newton on

    G(X) = 0,    t_j . (X - X_j) = h,

whose Jacobian [[G_u, G_lam], [t_j^T]] stays regular at a fold, so the branch
turns around it.  The step h adapts to the corrector's iteration count and to
the turning angle of the tangent.  Test functions are evaluated at each point;
a sign change brackets a special point, located by Brent's method along the
arclength (each trial point corrected on the hyperplane t_j . (X - X_j) = s),
see :mod:`symvi.continuation.special`.  The loop, the step control and the locator are
those of :mod:`symvi.continuation.engine`, shared with the curves of :mod:`symvi.curves`.
"""
import math

import numpy as np

from .._deprecated import moved_names as _moved_names
from ..errors import ParameterError, SingularCaseError, SymviError
from ..flow.linear import RESONANCE_CUT, LinearFlow
from ..model import Signature
from ..orbits.periodic import (ConvergenceError, PeriodicOrbit, Problem, initial_guess,
                               newton, orbit_of)
from . import engine
from .engine import Client, correct, tangent
from .points import Branch, BranchPoint, SpecialPoint
from .special import Codim1Tracker
#: |1 - e^{i omega_j T}| below which a one-impact branch of an undamped model is cut
ISOLATION_CUT = 1e-5


# --------------------------------------------------------------------------- entry point
def continue_branch(model, param, start, stop, *, orbit=None, guess=None, n=1, p=1,
                    h=None, h_max=None, max_points=5000, locate=True, through=False,
                    signature=None, **fixed):
    """Continue one n-p orbit of ``model`` in the named parameter ``param`` (pseudo-arclength).

    From ``start`` towards ``stop`` (the interval between them bounds the branch).
    The first orbit is ``orbit`` (a :class:`PeriodicOrbit` or a period-1
    :class:`symvi.orbits.Orbit`), or the solution near ``guess``, or else the
    first admissible period-1 orbit at ``start``.  ``fixed`` sets the other
    parameters, omega included when it is not ``param``.  The branch ends where its
    orbit stops being admissible (the grazing point located), unless ``through``:
    then it is followed on, its points marked inadmissible.  Returns a
    :class:`Branch`; see the module docstring.  Keller's method: predictor along the
    unit tangent of G(u, lam) = 0 (u the shooting unknowns), Newton corrector on the
    hyperplane orthogonal to it, so the branch turns around folds; special points are
    located by Brent's method on their test functions.  A one-impact branch of an
    undamped model is cut next to a natural frequency (eq. (15): the orbit is not
    isolated there).

    Parameters
    ----------
    model : Model
        The model (the paper's Params as ``Model.of(params)``).
    param : str
        The continued parameter: ``"omega"`` or a named parameter of the model
        (:meth:`symvi.Model.parameter`: ``"gap"``, ``"stiffness[1,2]"``, ...).
    start : float
        The value where the branch starts (finite).
    stop : float
        The value it is continued towards, != ``start``; the branch stays between the
        two.
    orbit : PeriodicOrbit or Orbit, optional
        The first orbit (its n, p and signature are used).
    guess : optional
        A start for Newton instead: a section point (2N numbers), a simulation that
        settled on the orbit (its last p impacts give the signature), or an orbit.
        Required for an orbit other than 1-1 when no ``orbit`` is given.
    n : int, optional
        Forcing periods of the orbit (default 1).
    p : int, optional
        Impacts per orbit (default 1).
    h : float, optional
        First step in arclength (default ``min(h_max, (hi - lo) / 100)``).
    h_max : float, optional
        Largest step in arclength (default ``(hi - lo) / 25 + 0.05``).
    max_points : int, optional
        Most points on the branch (default 5000).
    locate : bool, optional
        Locate special points (default True); False gives none.
    through : bool, optional
        Follow the branch on where its orbits are inadmissible (default False: end
        there).
    signature : Signature or sequence of int, optional
        The constraint (0-based) each impact hits, for a ``guess`` that does not carry
        it (a section point, an orbit passed as ``guess``); default: ``orbit``'s, or the
        last p impacts of the simulation passed as ``guess``, else every impact on
        stop 1.
    **fixed : float
        The other parameters' values: ``omega=...`` (required when ``param`` is not
        omega) and any named parameter of the model.

    Returns
    -------
    Branch
        Its points in arclength order, the special points located on it (folds, flips,
        Neimark–Sacker points, branch points, grazing: :data:`EVENT_KINDS`) and why it
        ended (``end``: ``"reached omega = 0.75"``, the orbit stops being admissible,
        the branch closes on itself, ``max_points`` reached, ...).

    Raises
    ------
    ParameterError
        ``model`` not a Model; ``start`` or ``stop`` not finite, or equal; ``param`` not
        a parameter of the model; ``omega`` missing (``param`` not omega) or given
        (``param`` omega); a fixed value the model refuses; no ``guess`` for an orbit
        other than 1-1.
    SingularCaseError
        ``"no-orbit"``: no admissible period-1 orbit at ``start`` to begin with.
    SymviError
        Newton does not converge from the first orbit or guess (a ConvergenceError).

    Examples
    --------
    >>> from symvi import Model, Stop
    >>> from symvi.continuation import continue_branch
    >>> m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
    ...           stop=Stop(mass=1, gap=0.0, restitution=0.8))
    >>> br = continue_branch(m, "omega", 2.5, 2.8)
    >>> br.n, br.p, br.end
    (1, 1, 'reached omega = 2.8')
    >>> [(sp.kind, round(sp.value, 6)) for sp in br.special]
    [('flip', 2.656177)]
    >>> continue_branch(m, "gap", 0.0, 0.1, omega=2.6).end     # another parameter
    'reached gap = 0.1'
    """
    problem, X0 = _start(model, param, start, stop, orbit, guess, n, p, fixed, signature)
    lo, hi = sorted((float(start), float(stop)))
    if not hi > lo:
        raise ParameterError("stop", stop, f"a value != start = {float(start)!r}")
    lo, hi, cut = _resonance_bounds(problem, float(start), lo, hi)
    h, h_max = _steps(lo, hi, h, h_max)
    e = np.zeros(problem.size + 1)
    e[-1] = 1.0 if float(stop) > float(start) else -1.0
    return _run(problem, X0, e, lo, hi, h, h_max, max_points, cut,
                Codim1Tracker(problem) if locate else None, through)


def switch_at_flip(branch, special, *, h=None, h_max=None, max_points=5000, locate=True,
                   through=False):
    """The period-doubled branch (2n-2p orbits) born at a located flip point of ``branch``.

    Continued within the branch's parameter bounds, away from the flip.
    At the flip the doubled system G2(u2; lam) = 0 (the n-p orbit traversed twice) has a
    one-dimensional kernel phi of dG2/du2 (the multiplier -1 of P^p is +1 of P^2p); the
    doubled branch leaves tangent to (phi, 0).  The first point solves G2 = 0 on the
    hyperplane (phi, 0) . (X - X*) = h, phi taken orthogonal to the primary branch.

    Parameters
    ----------
    branch : Branch
        A branch from :func:`continue_branch` or :func:`continue_orbits`.
    special : SpecialPoint
        One of its special points of kind ``"flip"``.
    h : float, optional
        Step in arclength of the first point of the new branch (default
        ``1e-3 * (1 + max(abs(u)))``, u the shooting unknowns of the orbit at the flip,
        doubled until the point leaves it); the steps after it follow
        :func:`continue_branch`'s default.
    h_max : float, optional
        Largest step in arclength (default as :func:`continue_branch`).
    max_points : int, optional
        Most points on the new branch (default 5000).
    locate : bool, optional
        Locate special points on it (default True).
    through : bool, optional
        Follow it on where its orbits are inadmissible (default False).

    Returns
    -------
    Branch
        The branch of 2n-2p orbits, in the same parameter.

    Raises
    ------
    ParameterError
        ``special`` is not a flip point.
    SymviError
        No doubled orbit found next to the flip (a ConvergenceError).

    Examples
    --------
    >>> from symvi import Model, Stop
    >>> from symvi.continuation import continue_branch, switch_at_flip
    >>> m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
    ...           stop=Stop(mass=1, gap=0.0, restitution=0.8))
    >>> br = continue_branch(m, "omega", 2.5, 2.8)
    >>> doubled = switch_at_flip(br, br.special[0])
    >>> doubled.n, doubled.p, doubled.bounds
    (2, 2, (2.5, 2.8))
    """
    if not isinstance(special, SpecialPoint) or special.kind != "flip":
        raise ParameterError("special", getattr(special, "kind", special), "a flip point of "
                             "the branch (kind 'flip')")
    pr, lam = branch.problem, special.value
    Y, T = pr.split(special.orbit.u)
    Y2 = Y.copy()
    Y2[:, -1] += 2 * math.pi * pr.n_periods
    u2 = np.concatenate([Y.ravel(), Y2.ravel(), T, T])
    pr2 = Problem(pr.model, 2 * pr.n_periods, 2 * pr.p, omega=pr.omega, param=pr.parameter,
                  signature=Signature(pr.signature.hits * 2, pr.signature.contact))
    G, Gu, Gl = pr2.evaluate(u2, lam, dparam=True)
    phi = np.linalg.svd(Gu)[2][-1]
    # the primary branch's tangent, doubled, and phi made orthogonal to it
    _, Gu1, Gl1 = pr.evaluate(special.orbit.u, lam, dparam=True)
    t1 = np.linalg.svd(np.column_stack([Gu1, Gl1]))[2][-1]
    tY, tT = pr.split(t1[:-1])
    t2 = np.concatenate([tY.ravel(), tY.ravel(), tT, tT, [t1[-1]]])
    t2 /= np.linalg.norm(t2)
    return _switch(pr2, u2, lam, phi, t2, branch, "period-doubled orbit", "flip", h,
                   h_max, max_points, locate, through)


def switch_at_branch_point(branch, special, *, h=None, h_max=None, max_points=5000,
                           locate=True, through=False):
    """The other branch through a located branch point of ``branch``.

    Of kind "symmetry-breaking" or "branch-point", continued within the branch's
    parameter bounds: at a symmetry-breaking pitchfork, one of the two mirror-image
    asymmetric branches (the other is its mirror image,
    :meth:`symvi.orbits.periodic.Problem.half`).

    There G_u has a one-dimensional kernel phi (the multiplier +1 of the monodromy) and
    [G_u G_lam] a two-dimensional one, spanned by the branch's tangent and (phi, 0): the
    other branch leaves along (phi, 0) taken orthogonal to the branch's tangent, as at a
    flip (:func:`switch_at_flip`), on the same n-p system.

    Parameters
    ----------
    branch : Branch
        A branch from :func:`continue_branch` or :func:`continue_orbits`.
    special : SpecialPoint
        One of its special points of kind ``"symmetry-breaking"`` or
        ``"branch-point"``.
    h : float, optional
        Step in arclength of the first point of the new branch (default
        ``1e-3 * (1 + max(abs(u)))``, u the shooting unknowns of the orbit there, doubled
        until the point's parameter leaves the branch point).
    h_max : float, optional
        Largest step in arclength (default as :func:`continue_branch`).
    max_points : int, optional
        Most points on the new branch (default 5000).
    locate : bool, optional
        Locate special points on it (default True).
    through : bool, optional
        Follow it on where its orbits are inadmissible (default False).

    Returns
    -------
    Branch
        The other branch, n-p orbits in the same parameter.

    Raises
    ------
    ParameterError
        ``special`` is not a branch point.
    SymviError
        No other branch found next to the point (a ConvergenceError).
    """
    if not isinstance(special, SpecialPoint) or special.kind not in ("symmetry-breaking",
                                                                     "branch-point"):
        raise ParameterError("special", getattr(special, "kind", special), "a branch point "
                             "of the branch (kind 'symmetry-breaking' or 'branch-point')")
    pr, lam = branch.problem, special.value
    u = special.orbit.u
    _, Gu, Gl = pr.evaluate(u, lam, dparam=True)
    phi = np.linalg.svd(Gu)[2][-1]
    # the kernel of [G_u G_lam] is two-dimensional here: the branch's tangent is the part
    # of it orthogonal to (phi, 0) (at a pitchfork the symmetric and the antisymmetric
    # directions are orthogonal: S permutes and negates coordinates)
    V = np.linalg.svd(np.column_stack([Gu, Gl]))[2][-2:]
    e = np.append(phi, 0.0)
    t1 = max((v - np.dot(v, e) * e for v in V), key=np.linalg.norm)
    t1 /= np.linalg.norm(t1)
    return _switch(pr, u, lam, phi, t1, branch, "branch", special.kind, h, h_max,
                   max_points, locate, through)


def _switch(pr, u, lam, phi, t_old, branch, what, where, h, h_max, max_points, locate,
            through):
    """The branch of ``pr`` leaving (u, lam) along (phi, 0) made orthogonal to the unit
    tangent ``t_old`` of the branch met there: its first point corrected on the hyperplane
    e . (X - X*) = step, the step doubled until the point's parameter has left lam."""
    e = np.append(phi, 0.0)
    e -= np.dot(e, t_old) * t_old
    e /= np.linalg.norm(e)
    X0 = np.append(u, lam)
    lo, hi = branch.bounds
    step = h if h is not None else 1e-3 * (1 + np.max(np.abs(u)))
    for _ in range(12):
        res = correct(pr, X0 + step * e, e, np.dot(e, X0) + step)
        if res is not None and abs(res[0][-1] - lam) > 1e-14 * (1 + abs(lam)):
            break
        step *= 2
    else:
        raise ConvergenceError(f"no {what} found next to the {where} point at "
                               f"{pr.param} = {lam:.12g}", math.inf)
    h, h_max = _steps(lo, hi, None, h_max)
    return _run(pr, res[0], e, lo, hi, h, h_max, max_points, None,
                Codim1Tracker(pr) if locate else None, through)


def _steps(lo, hi, h, h_max):
    """(first step, largest step) in arclength, which mixes the parameter and the orbit
    (whose size sets the scale, hence the absolute part of the default largest step)."""
    h_max = float(h_max) if h_max is not None else (hi - lo) / 25 + 0.05
    return (float(h) if h is not None else min(h_max, (hi - lo) / 100)), h_max


def _start(model, param, start, stop, orbit, guess, n, p, fixed, signature=None):
    from ..model import Model
    from ..orbits.period1 import Orbit
    if not isinstance(model, Model):
        raise ParameterError("model", model, "a symvi.Model")
    for name, v in (("start", start), ("stop", stop)):
        try:
            ok = math.isfinite(float(v))
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ParameterError(name, v, "a finite real number")
    fixed = dict(fixed)
    try:                                # the name parsed once: the lens passed down
        par = model.parameter(param)
    except SymviError:
        raise ParameterError("param", param, "omega or a named parameter of the model: "
                             + ", ".join(model.parameter_names())) from None
    if par.is_forcing_frequency:
        if "omega" in fixed:
            raise ParameterError("omega", fixed["omega"], "not fixed: it is the continued "
                                 "parameter")
        omega = None
    else:
        if "omega" not in fixed:
            raise ParameterError("omega", None, f"a fixed forcing frequency when continuing "
                                 f"in {param} (--set omega=...)")
        omega = fixed.pop("omega")
        if param in fixed:
            raise ParameterError(param, fixed[param], "not fixed: it is the continued parameter")
    if fixed:
        model = model.with_(**fixed)
        par = model.parameter(par)      # the fixed values may leave the preset: names it
    if not par.is_forcing_frequency:
        model = par.apply(model, float(start))
    if isinstance(orbit, PeriodicOrbit):
        n, p = orbit.n, orbit.p
        signature = signature if signature is not None else orbit.itinerary
    if signature is None and getattr(guess, "hits", None) is not None and len(guess.hits) >= p:
        signature = tuple(int(k) for k in guess.hits[-p:])
        if getattr(guess, "active", None) is not None:     # a run through contact phases
            signature = Signature(signature, guess.active[-p])
    problem = Problem(model, n, p, omega=omega, param=par, signature=signature)
    lam0 = float(start)
    problem.at(lam0)                                # validates the start
    if isinstance(orbit, Orbit):
        guess = orbit.y
    elif isinstance(orbit, PeriodicOrbit):
        guess = orbit
    if guess is None:
        if (n, p) != (1, 1):
            raise ParameterError("guess", None, f"a guess for a {n}-{p} orbit (a section "
                                 "point, a simulation or an orbit)")
        from ..orbits.period1 import admissible_orbits
        m, flow, F = problem.at(lam0)
        orbs = admissible_orbits(m, float(F.omega), multipliers=False)
        if not orbs:
            raise SingularCaseError("no-orbit", f"no admissible period-1 orbit at "
                                    f"{param} = {lam0!r}")
        guess = orbs[0].y
    fix = Problem(problem.model, n, p, omega=lam0 if par.is_forcing_frequency else omega,
                  signature=problem.signature)
    u0 = newton(fix, initial_guess(fix, guess), None)
    return problem, np.append(u0, lam0)


def _resonance_bounds(problem, start, lo, hi):
    """An omega interval cut short of the undamped natural frequencies on either side of
    ``start`` (the steady-state response is infinite there): (lo, hi, cut or None)."""
    if (not problem.parameter.is_forcing_frequency or problem.model.damped
            or problem.nonlinear):         # a numerical flow: no steady state to blow up
        return lo, hi, None
    cut = None
    for w in (float(w) for w in LinearFlow.of(problem.model).omegas):
        if start < w < hi:
            hi, cut = w * (1 - RESONANCE_CUT), w
        elif lo < w < start:
            lo, cut = w * (1 + RESONANCE_CUT), w
    return lo, hi, cut


# --------------------------------------------------------------------------- the loop
class _BranchRun(Client):
    """A branch of orbits as a client of :func:`symvi.continuation.engine.run`."""

    def __init__(self, problem):
        self.problem = problem
        self.names = (problem.param,)

    def point(self, X, prev, Gu):
        m = self.problem.size
        return BranchPoint(float(X[m]), orbit_of(self.problem, X[:m], X[m], Gu))

    def stop(self, X, pt):
        return _not_isolated(self.problem, X)


def _run(problem, X, e, lo, hi, h, h_max, max_points, cut, tracker, through=True):
    """Continue from X, the first tangent oriented along e, within lo <= lam <= hi."""
    m = problem.size
    G, Gu, Gl = problem.evaluate(X[:m], X[m], dparam=True)
    t = tangent(Gu, Gl, e)
    points, states, end = engine.run(problem, _BranchRun(problem), X, t, lo, hi, h=h,
                                     h_max=h_max, max_points=max_points, tracker=tracker,
                                     through=through, grow_with_orbit=True)
    X, notes = states[-1], []
    if cut and abs(X[m] - cut) <= 1e-2 * cut:
        end = (f"forcing resonance: the branch is cut at omega = {X[m]:.12g}, next to the "
               f"natural frequency {cut:.12g} of an undamped mode (the steady-state response "
               f"is infinite there)" + (f"; {end}" if not end.startswith("reached") else ""))
    if problem.model.conservative:
        notes.append("conservative model (r = 1, no damping): the map preserves volume, "
                     "multipliers lie on the unit circle over whole intervals; no "
                     "Neimark-Sacker point is sought")
    special = tuple(tracker.special) if tracker else ()
    return Branch(problem.param, problem.n_periods, problem.p, tuple(points), special, end,
                  tuple(notes), problem, tuple(states), (lo, hi))


def _not_isolated(problem, X):
    """A reason to cut a one-impact branch where an undamped mode's period divides the
    orbit's: |1 - e^{i omega_j T}| -> 0 (eq. (15): 1 - cos(2 pi omega_j / omega) = 0), the
    orbit is not isolated there and its amplitude diverges."""
    if problem.p != 1 or problem.model.damped or problem.nonlinear:
        return ""                      # (a linear flow's closed form: eq. (15))
    model, flow, F = problem.at(X[-1], check=False)
    if model.damped:
        return ""
    T = float(X[problem.d])
    d = np.abs(2 * np.sin(np.asarray(flow.omegas, dtype=float) * T / 2))
    j = int(np.argmin(d))
    if d[j] < ISOLATION_CUT:
        return (f"not isolated: |1 - exp(i omega_{j + 1} T)| = {d[j]:.2g} at {problem.param} = "
                f"{X[-1]:.12g} (T = {T:.12g}, omega_{j + 1} = {float(flow.omegas[j]):.12g}): an "
                "undamped mode's period divides the orbit's, the orbit's amplitude diverges "
                "(1 - cos(2 pi omega_j / omega) -> 0 in eq. (15)); the branch is cut")
    return ""


def same_branch(a, b):
    """Whether branch a retraces b.

    E.g. the two period-1 orbits at A joined by a fold; an isola switched to from both
    of its pitchforks: two closed loops over one range.  True when a and b have the same
    n-p and either both close on themselves over the same parameter range (to 1e-6,
    relative), or a's last point is a point of b (parameter to 1e-9, relative; section
    point to 1e-7).  Not symmetric: a branch that stops inside another retraces it, not
    the other way round.

    Parameters
    ----------
    a : Branch
        The branch that may retrace ``b``.
    b : Branch
        A branch of the same parameter.

    Returns
    -------
    bool

    Examples
    --------
    >>> from symvi import Model, Stop
    >>> from symvi.continuation import continue_branch, same_branch
    >>> m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
    ...           stop=Stop(mass=1, gap=0.0, restitution=0.8))
    >>> up = continue_branch(m, "omega", 2.5, 2.8)
    >>> down = continue_branch(m, "omega", 2.8, 2.5)        # ends where up starts
    >>> same_branch(down, up), same_branch(up, continue_branch(m, "omega", 2.5, 2.6))
    (True, False)
    """
    if (a.n, a.p) != (b.n, b.p):
        return False
    closed = "closes on itself"
    if closed in a.end and closed in b.end:
        va, vb = a.values, b.values
        tol = 1e-6 * (1 + float(np.max(np.abs(va))))
        if abs(va.min() - vb.min()) <= tol and abs(va.max() - vb.max()) <= tol:
            return True
    end = a.points[-1]
    return any(abs(pt.value - end.value) <= 1e-9 * (1 + abs(end.value))
               and np.allclose(pt.y, end.y, atol=1e-7) for pt in b.points)


# names that moved to the one engine (issue 24, item 4): they warn for one release
_TO_ENGINE = _moved_names(__name__, "symvi.continuation.engine", ("MIN_COS",))
# period1_branches and diagram_branches went to start.py (their nonlinear starts come from
# the homotopy, a client of this module): they warn for one release
_TO_START = _moved_names(__name__, "symvi.continuation.start",
                         ("period1_branches", "diagram_branches"))


def __getattr__(name):
    if name in ("period1_branches", "diagram_branches"):
        return _TO_START(name)
    return _TO_ENGINE(name)
