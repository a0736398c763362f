"""Periodic orbits with a sticking phase, on the release section (issue 27, item 4).

The release section.  A mass held on a rigid stop (:class:`symvi.flow.sticking.Stuck`) is
released where the contact force changes sign: there x_p = xp, v_p = 0, mu = 0 and
falling.  Its coordinates xi = (y, y', tau) are the other coordinates of the flow (the
reduced state, 2N - 2 numbers) and the forcing phase, 2N - 1 in all.  The release map

    R(xi) = (y, y', tau) at the next release

is: the free flight from the release with its impacts, each stepped by the exact flow and
the compiled finder (any stop, a finite number); the chatter on the holding stop, summed
to its accumulation point in closed form (:func:`symvi.flow.sticking.accumulate`: the
chatter map of Budd & Dux); the held motion in modal form to the release, where the
contact force changes sign.  An orbit is a fixed point R(xi) = xi + 2 pi n e_tau (n
forcing periods, one sticking phase in them), solved by Newton (:func:`sticking_orbit`).
Off the release manifold (mu != 0) R is still defined: mu > 0 holds the mass at once
(an accumulation at t = 0), mu < 0 lets it leave; the two agree to second order, so R is
C^1 across mu = 0.

Its signature (:class:`StickingSignature`): the holding stop, the forcing periods n and
the number j of impacts before the chatter, printed ``"n-j+stick"`` (``"1-0+stick"``: one
period, the flight from the release ends in the chatter; a stop other than the first is
named, ``"1-2+stick@2"``).  The chatter is the longest tail of the flight's impacts on
the holding stop along which both the approach speeds and the flight times decrease;
the impacts before it are the ordinary ones.

Derivatives.  DR and dR/dlam are central differences, step DIFF_STEP (1 + |xi_i|): the
map is exact to its finder's O(v_graze^2) ~ 1e-14, so the derivatives carry ~1e-14 /
1e-6 = 1e-8 of noise and an O(step^2) truncation (where R is only C^1, across the
release manifold, O(step) ~ 1e-6): DR, and the multipliers, to ~1e-6.  Newton's steps
stall at that noise, hence its tolerance NEWTON_TOL_FD.

Multipliers.  The eigenvalues of DR (2N - 1 of them), the *reduced* multipliers.  The held
phase removes two dimensions of the full state (x_p = xp, v_p = 0 at every release), so
the full-state monodromy has two more, zero multipliers, not reported; and R's image lies
on the release manifold mu = 0, so one of the reduced multipliers is 0 too (to the
differences' accuracy).  One mass (N = 1): the reduced state is empty, xi = (tau,), and
for x'' + c x' + k x = P sin(omega t + tau) held at x = gap, mu = P sin(phase) - k gap,
so every release is at the phase pi - asin(k gap / P) (mod 2 pi), whatever came before:
R is constant, its one multiplier 0, the orbit superstable (a run that sticks forgets
its state).

Admissibility (:attr:`StickingOrbit.admissible`, with its ``reason``): every flight free
of the stops (the finder's first event), every impact with approach speed above the
finder's grazing speed, the chatter converging (0 <= r < 1) on the holding stop with the
guard's acceleration pushing into it, the held phase positive in length with the contact
force >= 0 throughout (the release is its first sign change: a release in the middle
would be another orbit), and the signature's count of ordinary impacts.

References
----------
[Budd & Dux] C. Budd, F. Dux, Chattering and related behaviour in impact oscillators,
Phil. Trans. R. Soc. A 347 (1994) 365-389.
"""
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ConvergenceError, ParameterError, SingularCaseError
from ..flow import compiled as cf
from ..flow.linear import LinearFlow
from ..flow.sticking import Stuck, _section, accumulate

__all__ = ["StickingSignature", "StickingOrbit", "ReleaseMap", "sticking_orbit"]

_TWO_PI = 2.0 * math.pi
#: central differences: the step, relative to 1 + |value| (module docstring: accuracy)
DIFF_STEP = 1e-6
#: Newton on differenced derivatives: relative size of the last correction at convergence
NEWTON_TOL_FD = 1e-10
NEWTON_MAXIT = 30
#: impacts of one free flight before the map gives up (a chatter that never starts)
MAX_IMPACTS = 10_000


@dataclass(frozen=True)
class StickingSignature:
    """What a sticking orbit does in one period of it: ``periods`` forcing periods,
    ``impacts`` ordinary impacts after the release, then a chatter and a held phase on
    ``stop`` (0-based).  ``str``: ``"n-j+stick"``, ``"@k"`` appended for a stop k > 1."""

    stop: int = 0
    impacts: int = 0
    periods: int = 1

    def __post_init__(self):
        for name, v, lo in (("stop", self.stop, 0), ("impacts", self.impacts, 0),
                            ("periods", self.periods, 1)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < lo:
                raise ParameterError(f"signature.{name}", v, f"an integer >= {lo}")

    def __str__(self):
        at = f"@{self.stop + 1}" if self.stop else ""
        return f"{self.periods}-{self.impacts}+stick{at}"


@dataclass(frozen=True)
class Trip:
    """One application of R: the image (tau unwrapped), the flight's impacts (times
    from the release, approach speeds, stops), where the chatter begins among them, the
    time of the accumulation point and the held phase's length; ``reason`` why the trip
    is no sticking trip ("" if it is)."""

    image: np.ndarray
    t_impacts: tuple
    speeds: tuple
    stops: tuple
    chatter: int
    t_stick: float
    hold: float
    reason: str = ""


def _chatter_start(t, speeds, stops, g):
    """The index of the chatter's first impact: the longest tail on stop g with decreasing
    approach speeds and flight times (module docstring)."""
    i = len(t)
    while i > 0 and stops[i - 1] == g:
        j = i - 1
        if i < len(t):
            if not speeds[i] < speeds[j]:
                break
            if i + 1 < len(t) and not t[i + 1] - t[i] < t[i] - t[j]:
                break
        i = j
    return i


class ReleaseMap:
    """R of the module docstring for one model, holding stop and n, at a parameter value.

    A system of :func:`symvi.continuation.engine.run`: ``evaluate(xi, lam)`` gives
    (F, F_xi, F_lam) of F = R(xi; lam) - xi - 2 pi n e_tau, by central differences;
    ``at(lam)`` validates lam.  ``param`` is a parameter name (or None: lam unused) and
    ``omega`` the forcing frequency when it is not the parameter."""

    corr_tol = NEWTON_TOL_FD

    def __init__(self, model, stop=0, periods=1, omega=None, param=None):
        if not hasattr(model, "require_rigid_stops"):
            raise ParameterError("model", model, "a symvi.Model")
        model.require_rigid_stops()
        if model.elastic:
            raise ParameterError("stop", "elastic", "rigid stops (an elastic stop holds no "
                                 "mass: no sticking orbit)")
        nc = len(model.constraints)
        if not isinstance(stop, (int, np.integer)) or not 0 <= stop < nc:
            raise ParameterError("signature.stop", stop, f"0 to {nc - 1} (0-based)")
        self.model, self.stop, self.periods = model, int(stop), int(periods)
        self.parameter = None if param is None else model.parameter(param)
        self.param = None if param is None else self.parameter.name
        self.omega = omega
        self.n = LinearFlow.of(model).n
        self.size = 2 * self.n - 1
        self._cache = {}
        self.p = None
        if self.parameter is None:
            self._setup(None)

    # ---- the model at a parameter value
    def _cache_key(self, lam):
        return None if self.parameter is None else float(lam)

    def _setup(self, lam):
        if lam in self._cache:
            return self._cache[lam]
        par = self.parameter
        # the lens's set: omega for omega, the model for any other parameter
        model, omega = (self.model, self.omega) if par is None else \
            par.set(self.model, self.omega, lam)
        if omega is None:
            raise ParameterError("omega", None, "the forcing frequency (a float)")
        c = cf.constants(model, omega)
        try:
            held = Stuck(c, LinearFlow.of(model), self.stop)
        except ValueError as exc:
            raise SingularCaseError("sticking", str(exc)) from None
        self.p = held.p
        if len(self._cache) > 64:
            self._cache.clear()
        self._cache[lam] = (model, float(c[cf._OM]), c, held)
        return self._cache[lam]

    def at(self, lam, check=True):
        return self._setup(self._cache_key(lam))

    @property
    def names(self):
        o = [i for i in range(self.n) if i != self.p]
        return (*(f"x{i + 1}" for i in o), *(f"v{i + 1}" for i in o), "tau")

    # ---- one trip
    def release_state(self, xi, held):
        """The full state (flow order) at the release point xi, and its phase."""
        n, p = self.n, held.p
        o = held.o
        z = np.zeros(2 * n)
        z[p] = held.xp
        z[o] = xi[:n - 1]
        z[[n + i for i in o]] = xi[n - 1:2 * n - 2]
        return z, float(xi[-1])

    def trip(self, xi, lam=None):
        """R(xi) at lam, with what the trip met (a :class:`Trip`)."""
        _, omega, c, held = self._setup(self._cache_key(lam))
        z, tau0 = self.release_state(xi, held)
        y = _section(z, held.p, self.n, tau0)
        return _trip(c, held, y, self.stop, tau0, omega)

    def residual(self, xi, lam=None):
        tr = self.trip(xi, lam)
        if tr.reason:
            raise SingularCaseError("sticking", tr.reason)
        F = tr.image - np.asarray(xi, float)
        F[-1] -= _TWO_PI * self.periods
        return F, tr

    def evaluate(self, v, lam=None, jac=True, dparam=False, check=True):
        v = np.asarray(v, dtype=float)
        F, _ = self.residual(v, lam)
        if not jac:
            return F, None, None
        m = len(v)
        J = np.empty((m, m))
        for i in range(m):
            h = DIFF_STEP * (1.0 + abs(v[i]))
            e = np.zeros(m)
            e[i] = h
            J[:, i] = (self.residual(v + e, lam)[0] - self.residual(v - e, lam)[0]) / (2 * h)
        Fl = None
        if dparam:
            h = DIFF_STEP * (1.0 + abs(lam))
            Fl = (self.residual(v, lam + h)[0] - self.residual(v, lam - h)[0]) / (2 * h)
        return F, J, Fl


def _trip(c, held, y, k, tau0, omega):
    """R from section point y of constraint k (phase tau0, unwrapped): the impacts stepped
    exactly, the chatter's accumulation point, the held phase, the release."""
    n = int(c[cf._NN])
    g = held.g
    T, ts, sp, st = 0.0, [], [], []
    image = np.full(2 * n - 1, np.nan)
    for _ in range(MAX_IMPACTS):
        status, te, y2, vm, _, _, gh = cf.step(c, y, k)
        if status != cf.IMPACT:
            break
        T += te
        ts.append(T)
        sp.append(float(vm))
        st.append(int(gh))
        y, k = y2, int(gh)
    else:
        return Trip(image, tuple(ts), tuple(sp), tuple(st), len(ts), math.nan, math.nan,
                    f"{MAX_IMPACTS} impacts with no accumulation point")
    ch = _chatter_start(ts, sp, st, g)
    if status == cf.NO_IMPACT:
        return Trip(image, tuple(ts), tuple(sp), tuple(st), ch, math.nan, math.nan,
                    "no return to a stop within the flight bound")
    ta, zacc, gh = accumulate(c, y, k)
    if ta is None:
        why = zacc
        if "does not end on a stop" in why:
            why = ("the flight grazes a stop it is not pushed into (grazing), or the "
                   "chatter's accumulation point lies where the contact force pulls")
        return Trip(image, tuple(ts), tuple(sp), tuple(st), ch, math.nan, math.nan, why)
    if gh != g:
        return Trip(image, tuple(ts), tuple(sp), tuple(st), ch, math.nan, math.nan,
                    f"the chatter accumulates on stop {gh + 1}, not on stop {g + 1}")
    t_stick = T + ta
    tau_s = tau0 + omega * t_stick
    kind, th, zr = held.run(zacc, tau_s, float(c[cf._TMAX]))
    reason = ""
    if kind is None:
        reason = "held on the stop past the flight bound"
    elif kind != -1:
        reason = f"stop {kind + 1} met while stop {g + 1} holds its mass"
    else:
        o = held.o
        image = np.concatenate([zr[o], zr[[n + i for i in o]], [tau_s + omega * th]])
    return Trip(image, tuple(ts), tuple(sp), tuple(st), ch, t_stick, th, reason)


@dataclass(frozen=True)
class StickingOrbit:
    """A periodic orbit with a sticking phase, at its release point (module docstring).

    Attributes
    ----------
    xi : tuple
        The release point: the reduced state (``names``) and the phase tau (unwrapped;
        ``tau_release`` is it mod 2 pi).
    signature : StickingSignature
    omega : float
    t_impacts, speeds, stops : tuple
        Every impact of the flight stepped exactly (ordinary ones, then the chatter's down
        to the finder's grazing speed): times since the release, approach speeds, stops.
    t_stick : float
        The chatter's accumulation point, since the release: the held phase begins.
    hold : float
        The held phase's length; t_stick + hold = 2 pi n / omega.
    multipliers : tuple of complex
        The eigenvalues of DR (reduced multipliers, largest first; module docstring).
    admissible : bool, reason : str
    """

    xi: tuple
    signature: StickingSignature
    omega: float
    names: tuple
    t_impacts: tuple
    speeds: tuple
    stops: tuple
    t_stick: float
    hold: float
    multipliers: tuple
    admissible: bool
    reason: str = ""
    monodromy: np.ndarray = field(default=None, repr=False)

    @property
    def y(self):
        return self.xi

    @property
    def points(self):
        """(xi,): the orbit's one section point, as a branch's curve reads it."""
        return (self.xi,)

    @property
    def tau_release(self):
        return self.xi[-1] % _TWO_PI

    @property
    def period(self):
        return _TWO_PI * self.signature.periods / self.omega

    @property
    def stable(self):
        return self.admissible and max(abs(m) for m in self.multipliers) < 1.0

    @property
    def signature_names(self):
        return str(self.signature)

    #: no mirror symmetry is sought (read by the branch's as_dict)
    symmetric = None

    def as_dict(self):
        return {"signature": str(self.signature), "omega": self.omega,
                "xi": dict(zip(self.names, map(float, self.xi))),
                "tau_release": float(self.tau_release), "t_stick": self.t_stick,
                "hold": self.hold, "impacts": len(self.t_impacts),
                "multipliers": [[z.real, z.imag] for z in self.multipliers],
                "stable": bool(self.stable), "admissible": bool(self.admissible),
                "reason": self.reason}


def orbit_at(system, xi, lam=None, J=None, signature=None):
    """The :class:`StickingOrbit` at xi (a zero of ``system``: a :class:`ReleaseMap`)."""
    xi = np.asarray(xi, float)
    tr = system.trip(xi, lam)
    if J is None and not tr.reason:
        J = system.evaluate(xi, lam)[1]
    omega = system._setup(system._cache_key(lam))[1]
    sig = StickingSignature(system.stop, tr.chatter, system.periods)
    reasons = [tr.reason] if tr.reason else []
    if signature is not None and tr.chatter != signature.impacts and not tr.reason:
        reasons.append(f"{tr.chatter} impacts before the chatter, not the signature's "
                       f"{signature.impacts}")
    if not tr.reason and not tr.hold > 0.0:
        reasons.append("the held phase has zero length: the chatter accumulates at a release")
    if tr.reason:
        mult, M = (), None
    else:
        M = J + np.eye(len(xi))
        ev = np.linalg.eigvals(M)
        mult = tuple(complex(z) for z in ev[np.argsort(-np.abs(ev), kind="stable")])
    return StickingOrbit(tuple(float(v) for v in xi), sig if signature is None else signature,
                         omega, system.names, tr.t_impacts, tr.speeds, tr.stops,
                         tr.t_stick, tr.hold, mult, not reasons, "; ".join(reasons), M)


def newton(system, xi, lam=None, *, tol=NEWTON_TOL_FD, maxit=NEWTON_MAXIT):
    """Newton on R(xi) - xi - 2 pi n e_tau = 0 with the differenced Jacobian."""
    xi = np.asarray(xi, float).copy()
    res = math.inf
    for _ in range(maxit):
        F, J, _ = system.evaluate(xi, lam)
        res = float(np.abs(F).max())
        try:
            dx = np.linalg.solve(J, -F)
        except np.linalg.LinAlgError:
            break
        xi = xi + dx
        if np.abs(dx).max() <= tol * (1 + np.abs(xi).max()):
            return xi, J
    raise ConvergenceError(f"the sticking orbit's Newton did not converge (residual "
                           f"{res:.3g})", res)


def release_point(sim):
    """(xi, periods, stop) of the last complete sticking phase of a Simulation that sticks:
    the release state recomputed from the last impact before it (its chatter's)."""
    st = getattr(sim, "sticks", None)
    done = np.zeros((0, 3)) if st is None else st[np.isfinite(st[:, 1])]
    if len(done) < 2:
        raise ParameterError("guess", "a simulation", "a Simulation with at least two "
                             "complete sticking phases (its sticks)")
    (ts, tr, g), tr_prev = done[-1], done[-2, 1]
    periods = max(1, int(round(sim.omega * (tr - tr_prev) / _TWO_PI)))
    i = np.flatnonzero(np.asarray(sim.t) < ts)
    if len(i) == 0:
        raise ParameterError("guess", "a simulation", "a Simulation with stored impacts "
                             "before its last complete sticking phase")
    i = i[-1]
    model = _model_of(sim.params)
    c = cf.constants(model, sim.omega)
    held = Stuck(c, LinearFlow.of(model), int(g))
    y = np.array(sim.section[i], float)
    k = int(sim.hits[i])
    tr_ = _trip(c, held, y, k, float(y[-1]), float(sim.omega))
    if tr_.reason:
        raise ParameterError("guess", "a simulation", f"its last sticking phase cannot be "
                             f"recomputed: {tr_.reason}")
    xi = tr_.image.copy()
    xi[-1] %= _TWO_PI
    return xi, periods, int(g)


def _model_of(params):
    from ..model import Model
    return Model.of(params)


def sticking_orbit(model, *, guess, omega=None, signature=None, **fixed):
    """A periodic orbit with a sticking phase: the fixed point of the release map R.

    ``guess``: a :class:`symvi.simulations.simulation.Simulation` that sticks (its release
    points: ``sticks``), or a release point xi (2N - 1 numbers: the reduced state in flow
    order without the held coordinate, then tau).  ``signature`` (a
    :class:`StickingSignature`): the holding stop and the periods, default the
    simulation's; its ``impacts`` is checked against the solved orbit (an orbit with
    another count is reported inadmissible with the reason).  ``fixed``: other named
    parameters set on the model.  Returns a :class:`StickingOrbit`; ConvergenceError if
    Newton fails, SingularCaseError("sticking") where R is not a sticking trip.
    """
    model = _model_of(model)
    for name, v in fixed.items():
        model = model.parameter(name).apply(model, v)
    if hasattr(guess, "sticks"):
        xi, periods, stop = release_point(guess)
        omega = guess.omega if omega is None else omega
        sig = signature
        if sig is None:
            sig = StickingSignature(stop, 0, periods)
            check_count = False
        else:
            check_count = True
    else:
        xi = np.asarray(guess, float)
        sig = StickingSignature() if signature is None else signature
        check_count = signature is not None
    if not isinstance(sig, StickingSignature):
        raise ParameterError("signature", sig, "a StickingSignature")
    system = ReleaseMap(model, sig.stop, sig.periods, omega)
    if xi.shape != (system.size,) or not np.isfinite(xi).all():
        raise ParameterError("guess", tuple(xi), f"{system.size} finite numbers "
                             f"({', '.join(system.names)})")
    xi, J = newton(system, xi)
    return orbit_at(system, xi, None, J, sig if check_count else None)
