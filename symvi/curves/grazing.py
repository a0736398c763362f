"""Grazing curves in two parameters (issue 27, item 1): the n-p orbits one of whose
impacts arrives with zero velocity, or one of whose flights touches a stop inside it.

Unknowns X = (u, a, b), u the shooting unknowns of :mod:`symvi.orbits.periodic` (section
points and flight times); equations::

    G(u; a, b) = 0          the orbit (multiple shooting)
    g(u)       = y_j[0]     = v_k+ = -r v_k-, the speed just after impact i (j = i + 1)

The flight times are unknowns, so G stays smooth where an impact velocity passes through 0:
the 1/v pole of the time-eliminated map (eq. (30)) is never met, and g is linear in u
(dg = e_j, dg/da = dg/db = 0).  What has the pole is the monodromy matrix, so a grazing
curve's points carry no multipliers; they carry the orbit's section points, flight times
and the admissibility of every flight's interior (a flight that crosses a stop before its
end makes the point inadmissible; the grazing impact's own zero speed does not).

A flight that touches a stop inside it (the second kind) is the same point as an impact
at zero velocity of the orbit with one more impact: flight i split at the touch, a point
on the touched constraint's section inserted (speed 0, so the reset changes nothing).
That (p + 1)-impact orbit's grazing curve is followed, and its points are reported as
the n-p orbit's: the split flight joined again, the touch time beside it.
"""
from dataclasses import dataclass, field

import numpy as np

from ..continuation import engine
from ..continuation.engine import Client, correct
from ..continuation.result import EVENT_KINDS
from ..errors import ParameterError, SymviError
from ..orbits.admissibility import check_flight
from .frame import first_tangent, join, prepare, steps
from .points import Codim2Point, TwoParameter
from .regular import regular_char
from .system import CurveSystem

#: what vanishes on a grazing curve (its "normalisation" in the JSON, as the other curves'
#: state theirs)
DEFINITION = ("v_k+ = -r v_k- = 0 after the grazing impact; the flight times are unknowns "
              "(no 1/v pole); no multipliers (the monodromy has a pole at grazing)")

#: a flight that leaves its stop at zero speed is checked from this fraction of its time on
START_SHIFT = 1e-6
#: ... and one that ends at zero speed up to this fraction before its end: the tangency's
#: time is a double root, located to ~sqrt(eps) only, so a touch this close to the end is
#: taken for the grazing impact itself
END_SHIFT = 1e-4


class GrazingSystem(CurveSystem):
    """G(u; a, b) = 0 and v_k+ = 0 after impact ``impact`` (0-based) of the n-p orbits of
    ``model`` in the parameters ``names`` = (a, b): the grazing curve of that impact."""

    KINDS = ("grazing",)

    def __init__(self, model, n, p, names, impact, omega=None, signature=None, touch=None):
        _rigid(model)
        if not 0 <= int(impact) < int(p):
            raise ParameterError("impact", impact, f"an impact of the orbit, 0 .. {p - 1}")
        super().__init__(model, n, p, names, "grazing", omega=omega, signature=signature)
        self.impact = int(impact)
        #: the second kind (a touch inserted as impact ``impact`` into a flight of the
        #: n-(p-1) orbit, whose points are reported without it): that orbit's signature
        self.touch = touch
        #: the unknown that vanishes: the first coordinate (v_k+) of section point j
        self.slot = ((self.impact + 1) % self.p) * self.d

    def evaluate(self, v, lam, jac=True, dparam=False, check=True):
        """(F, dF/dv, dF/db) at v = (u, a), b = lam; F = (G, v_k+)."""
        m = self.m
        u, a = v[:m], float(v[m])
        pr = self.problem(lam)
        G, Gu, Ga = pr.evaluate(u, a, jac=jac, dparam=jac, check=check)
        F = np.append(G, u[self.slot])
        if not jac:
            return F, None, None
        DF = np.zeros((m + 1, m + 1))
        DF[:m, :m], DF[:m, m] = Gu, Ga
        DF[m, self.slot] = 1.0
        if not dparam:
            return F, DF, None
        return F, DF, np.append(pr.derivative(u, a, self.params[1]), 0.0)


def _rigid(model):
    """Refuse elastic stops: their entry at zero speed is a touch whose contact time
    vanishes, and no curve of touches is followed."""
    if model.elastic:
        raise ParameterError("kind", "grazing", "a model of rigid stops (an elastic "
                             "stop's entry at zero speed is a touch: its contact time "
                             "vanishes, and no curve of touches is followed)")


@dataclass(frozen=True)
class GrazingPoint:
    """One point of a grazing curve: both parameter values, the orbit's section points and
    flight times, the approach speed of each impact (the grazing one 0), and whether every
    flight stays off the stops inside it (``admissible``, with ``reason`` when not)."""

    params: dict
    y: tuple
    times: tuple
    impact_velocities: tuple
    admissible: bool
    reason: str = ""
    u: np.ndarray = field(repr=False, default=None)
    touch: dict = None          # second kind: {"flight", "stop" (1-based), "t"}
    #: the touch kind's n-p orbit is smooth at its touch: its multipliers (None for the
    #: impact kind, whose monodromy has the pole)
    multipliers: tuple = None
    #: the guard's second time derivative at the grazing (< 0: the flight turns back there)
    acceleration: float = None
    #: the impact kind: the regular fold and flip tests w det(M -+ I) at w = 0
    #: (:func:`regular_tests`): 0 where a fold or a flip curve meets the grazing curve
    fold_test: float = None
    flip_test: float = None

    def as_dict(self):
        out = {"params": dict(self.params), "admissible": bool(self.admissible),
               "y": [list(p) for p in self.y], "times": list(self.times),
               "impact_velocities": list(self.impact_velocities)}
        if self.touch is not None:
            out["touch"] = dict(self.touch)
        if self.multipliers is not None:
            out["multipliers"] = [[z.real, z.imag] for z in self.multipliers]
        if self.acceleration is not None:
            out["acceleration"] = self.acceleration
        if self.fold_test is not None:
            out["fold_test"], out["flip_test"] = self.fold_test, self.flip_test
        if self.reason:
            out["reason"] = self.reason
        return out


def grazing_point(system, X):
    """The :class:`GrazingPoint` at a solution X = (u, a, b) of ``system``."""
    from ..orbits import _shooting
    m = system.m
    a, b = system.names
    pr = system.problem(X[-1])
    u = np.array(X[:m], dtype=float)
    fl, (model, flow, F) = pr.flights(u, X[m], check=False)
    Y, T = pr.split(u)
    speeds = pr.approach_speeds(fl, flow)
    ok, why = _interior_admissible(pr, fl, flow, F, T, speeds, system.impact,
                                   _shooting.CompiledFinder(flow) if pr.compiled else flow)
    Y = [tuple(float(v) for v in y) for y in Y]
    T = [float(t) for t in T]
    speeds = [float(s) for s in speeds]
    i = system.impact
    acc = _acceleration(pr, fl, flow, F, T, i)
    touch = mult = None
    tests = (None, None)
    if system.touch is not None:          # the n-p orbit: the split flight joined again
        touch = {"flight": i + 1, "stop": int(pr.sig[i + 1]) + 1, "t": T[i]}
        T[i:i + 2] = [T[i] + T[i + 1]]
        del Y[i + 1]
        del speeds[i]
        mult = _smooth_multipliers(system, model, F.omega, np.concatenate([np.ravel(Y), T]))
    else:
        tests = regular_tests(pr, u, X[m], i)
    return GrazingPoint({a: float(X[m]), b: float(X[m + 1])}, tuple(Y), tuple(T),
                        tuple(speeds), ok, why, u, touch, mult, acc, *tests)


#: the time step of the central difference of the guard's speed (relative to the flight)
ACC_STEP = 1e-5


def _acceleration(pr, fl, flow, F, T, i):
    """h'' at the end of flight i (the grazing impact or the touch) of the guard it ends
    on: a central difference of the exact h' (error of order (ACC_STEP T)^2 times the
    fourth derivative of h)."""
    from ..orbits.periodic import _table
    N = pr.N
    g = _table(flow)[int(pr.sig[(i + 1) % pr.p])][3:3 + N]
    mo = flow.motion(F, fl[i][0], fl[i][1])
    dt = ACC_STEP * T[i]
    vp, vm = (float(g @ np.asarray(mo.state(T[i] + e), dtype=float)[N:]) for e in (dt, -dt))
    return (vp - vm) / (2 * dt)


def _smooth_multipliers(system, model, omega, u):
    """The multipliers of the touch kind's n-p orbit (the touch not an impact) of
    ``model`` at ``omega`` (both parameters of the point set): smooth at the touch, so
    finite, from its own shooting system."""
    from ..orbits.periodic import Problem, eigenvalues
    pr = Problem(model, system.n, system.p - 1, omega=omega, signature=system.touch)
    _, Gu, _ = pr.evaluate(u, None, check=False)
    return tuple(complex(z) for z in eigenvalues(pr.monodromy(u, Gu)[1]))


def _interior_admissible(pr, fl, flow, F, T, speeds, graze, finder):
    """(ok, reason): every impact but the grazing one arrives with positive speed, and no
    flight meets a stop before its end (one rigid stop: the first-contact finder of
    :func:`symvi.orbits.admissibility.check_flight`, the grazing ends given unit speeds
    so that only the interior is judged)."""
    p = pr.p
    for i, s in enumerate(speeds):
        if i != graze and not s > 0:
            return False, (f"impact {i + 1} arrives with speed {s:.6g} <= 0 (a second "
                           "grazing impact, or penetration)")
    if len(pr.model.constraints) > 1:
        return _several_admissible(pr, fl, flow, F, T, graze)
    k = finder.perm[0] + 1
    for i, (z0, tau, z, *_rest) in enumerate(fl):
        v_end = 1.0 if i == graze else flow.approach(z)
        if (i - 1) % p == graze:
            # a flight leaving the stop at zero speed touches it at t = 0: the finder
            # starts a moment later, off the stop (numpy's, as the state is off the section)
            dt = START_SHIFT * T[i]
            z1 = flow.motion(F, z0, tau).state(dt)
            first, t_end, v_start = (flow.motion(F, z1, tau + F.omega * dt).first_impact,
                                     T[i] - dt, -1.0)
        else:
            first, t_end, v_start = (finder.motion(F, z0, tau).first_impact, T[i],
                                     flow.approach(z0))
        if i == graze:
            t_end *= 1 - END_SHIFT
        ok, why = check_flight(first, t_end, v_start, v_end, mass=k, flight=i + 1)
        if not ok:
            return ok, why
    return True, ""


@dataclass(frozen=True)
class GrazingCurve(TwoParameter):
    """A continued grazing curve of impact ``impact`` (1-based) of n-p orbits in the
    parameters ``names`` (``of`` "touch": flight ``impact`` touches a stop inside it): a
    :class:`symvi.curves.points.TwoParameter` whose points are :class:`GrazingPoint` and
    whose codimension-two points are :class:`GrazingSpecial`."""

    impact: int = 1
    of: str = "grazing"
    signature: tuple = ()

    def plot_data(self, sides=24):
        """Plain data for :func:`symvi.reporting.figures.two_parameter`."""
        a, b = self.names
        n = len(self.points)
        return {"kind": "grazing", "a": [pt.params[a] for pt in self.points],
                "b": [pt.params[b] for pt in self.points], "subcritical": [False] * n,
                "admissible": [bool(pt.admissible) for pt in self.points],
                "bifurcation": [True] * n, "sides": [],
                "special": [(s.kind, s.params[a], s.params[b]) for s in self.special
                            if s.kind != "unlocated"]}

    def as_dict(self):
        where = {"impact": self.impact} if self.of == "grazing" else {"flight": self.impact}
        return {"kind": "grazing", "grazing": "impact" if self.of == "grazing" else "touch",
                "params": list(self.names), "orbit": f"{self.n}-{self.p}", **where,
                "signature": list(self.signature),
                "fixed": dict(self.fixed),
                "bounds": {k: list(v) for k, v in self.bounds.items()},
                "normalisation": DEFINITION,
                "points": [pt.as_dict() for pt in self.points],
                "special": [s.as_dict() for s in self.special],
                "ends": list(self.ends), "notes": list(self.notes)}


def continue_grazing(model, names, point, *, bounds=None, h=None, h_max=None,
                     max_points=2000, both=True, through=False, **fixed):
    """The grazing curve in the two named parameters ``names`` through ``point``: a
    grazing point that :func:`symvi.continuation.continue_branch` located (an impact
    arriving with zero velocity: its coefficient ``impact``), or a
    :class:`symvi.orbits.periodic.PeriodicOrbit` at one, with ``impact`` given in
    ``fixed`` (1-based). ``bounds``, ``through`` and ``fixed`` as
    :func:`symvi.curves.continue_curve`."""
    from ..model import Model
    fixed = dict(fixed)
    impact = fixed.pop("impact", None)
    coef = getattr(point, "coefficients", {}) or {}
    if getattr(point, "kind", "grazing") != "grazing":
        raise ParameterError("point", point.kind, "a grazing point")
    touch = None
    if impact is None:
        if "impact" not in coef and "flight" not in coef:
            raise ParameterError("point", getattr(point, "detail", point),
                                 "a grazing point (an impact velocity through 0, or a flight "
                                 "touching a stop)")
        if coef.get("exit"):
            raise ParameterError("point", point.detail, "a grazing impact or a touch of a "
                                 "rigid stop (an elastic contact's edge starts no curve)")
        if "impact" in coef:
            impact = int(coef["impact"])
        else:
            touch = (int(coef["flight"]) - 1, float(coef["t"]), int(coef.get("stop", 1)) - 1)
    orbit = getattr(point, "orbit", point)
    # the model at the point (a branch in another parameter moved it), then ``fixed``
    model = Model.of(getattr(orbit, "model", None) or model)
    _rigid(model)                     # before a touch is split on the rigid flow
    names, model, omega, pars, on_omega, start_values, box, fixed = prepare(
        model, orbit, names, fixed, bounds)
    if touch is None:
        system = GrazingSystem(model, orbit.n, orbit.p, pars, impact - 1,
                               omega=None if on_omega else omega, signature=orbit.itinerary)
        u0 = orbit.u
    else:
        u0, sig = _split_at_touch(model, orbit, *touch)
        impact = touch[0] + 1
        system = GrazingSystem(model, orbit.n, orbit.p + 1, pars, touch[0],
                               omega=None if on_omega else omega, signature=sig,
                               touch=orbit.itinerary)
    X0 = start(system, u0, start_values)
    pts, states, ends, special = follow(system, X0, box, h=h, h_max=h_max,
                                        max_points=max_points, both=both, through=through)
    notes = ("grazing-fold and -flip points are located on both kinds of curve (at an "
             "impact's zero velocity by the regular tests w det(M -+ I), with kappa), "
             "grazing-NS on touch curves only (an impact at zero velocity has no finite "
             "multipliers); a grazing-fold and a grazing-flip point together are one "
             "resonant grazing point (RG)",)
    return GrazingCurve("grazing", names, orbit.n, orbit.p, tuple(pts), tuple(special),
                        tuple(ends), box, fixed, notes, tuple(states), model, impact=impact,
                        of="grazing" if touch is None else "touch",
                        signature=tuple(orbit.signature_names))


def _split_at_touch(model, orbit, i, t, k):
    """(u, signature) of the n-(p+1) orbit that is ``orbit`` with flight i split at its
    touch of constraint k at time t: the touch's section point inserted (its speed ~0)."""
    from ..model import Signature
    from ..orbits.periodic import Problem
    pr = Problem(model, orbit.n, orbit.p, omega=orbit.omega, signature=orbit.itinerary)
    fl, (_, flow, F) = pr.flights(orbit.u, None, check=False)
    Y, T = pr.split(np.asarray(orbit.u, dtype=float))
    z0, tau = fl[i][0], fl[i][1]
    zt = flow.motion(F, z0, tau).state(t)               # flow order, as the frames
    y = np.append(np.asarray(zt, dtype=float)[pr.frames[k]], tau + F.omega * t)
    Y = np.insert(Y, i + 1, y, axis=0)
    T = np.insert(T, i, t)
    T[i + 1] -= t
    hits = list(orbit.itinerary.hits)
    hits.insert(i + 1, k)
    return np.concatenate([Y.ravel(), T]), Signature(tuple(hits))


def _several_admissible(pr, fl, flow, F, T, graze):
    """:func:`_interior_admissible` with several rigid stops: each flight walked by the
    contact walk over every guard (:mod:`symvi.flow.contact`), from its start's stop, or
    from a moment later, off every stop, where it leaves one at zero speed; it must end
    on the stop its signature names."""
    from ..flow import contact
    from ..orbits.periodic import _ContactHit, _table
    model, N, p = pr.model, pr.N, pr.p
    ends, rows = pr._ends(flow), _table(flow)
    G, lv = contact.guards(model, ())
    walk = contact.phase(model, ())
    for i, (z0, tau, z, *_rest) in enumerate(fl):
        ka, kb = int(pr.sig[i]), int(pr.sig[(i + 1) % p])
        t_end, start = T[i], ka
        if (i - 1) % p == graze:
            dt = START_SHIFT * T[i]
            z0, tau, t_end, start = (flow.motion(F, z0, tau).state(dt), tau + F.omega * dt,
                                     T[i] - dt, None)
            v_start = -1.0
        else:
            v_start = float(rows[ka][3:3 + N] @ z0[N:])     # leaving ka: < 0
        if i == graze:
            t_end *= 1 - END_SHIFT
        v_end = 1.0 if i == graze else float(ends[i][1] @ z[N:])
        mo = walk.motion(F.omega, flow.to_mass(np.asarray(z0, dtype=float)), tau)

        def first(t_max, mo=mo, start=start):
            return _ContactHit(mo.first_event(G, lv, start=start, t_max=t_max))

        ok, why = check_flight(first, t_end, v_start, v_end, mass=None, flight=i + 1,
                               stops=(ka, kb))
        if not ok:
            return ok, why
    return True, ""


#: the codimension-two points of a grazing curve: test function -> kind (of
#: :data:`symvi.continuation.result.EVENT_KINDS`, which says what each is)
CODIM2 = {"LP": "grazing-fold", "PD": "grazing-flip", "NS": "grazing-NS",
          "DG": "double-grazing", "AG": "degenerate-grazing"}


@dataclass(frozen=True)
class GrazingSpecial(Codim2Point):
    """A located codimension-two point of a grazing curve (or a fold or flip curve's
    landing on one): ``kind`` one of :data:`CODIM2`'s, ``orbit`` its :class:`GrazingPoint`
    (no multipliers at an impact's grazing)."""

    def as_dict(self):
        return {"kind": self.kind, "params": dict(self.params),
                "coefficients": dict(self.coefficients), "detail": self.detail,
                "admissible": bool(self.orbit.admissible)}


def _others(pt, impact):
    """[(speed, index)] of the point's impacts but the grazing one (the impact kind's own
    is ~0 all along; the touch kind's points leave the touch out already)."""
    return [(v, k) for k, v in enumerate(pt.impact_velocities)
            if pt.touch is not None or k != impact]


def _tests(pt, impact):
    """The test functions of :data:`CODIM2` at a grazing point (None: not defined)."""
    out = {"AG": pt.acceleration}
    others = _others(pt, impact)
    out["DG"] = min(others)[0] if others else None
    mu = None if pt.multipliers is None else np.array(pt.multipliers)
    if mu is None:                     # an impact at zero speed: the regular tests
        out.update(LP=pt.fold_test, PD=pt.flip_test, NS=None)
    else:
        out["LP"] = float(np.prod(mu - 1).real)
        out["PD"] = float(np.prod(mu + 1).real)
        n = len(mu)
        out["NS"] = float(np.prod([mu[i] * mu[j] - 1 for i in range(n)
                                   for j in range(i + 1, n)]).real) if n > 1 else None
    return out


class GrazingTracker(engine.Tracker):
    """The codimension-two test functions along a grazing curve, and their zeros."""

    def tests(self, X, t, pt):
        return _tests(pt, self.system.impact)

    def brackets(self, pa, pb, pta, ptb):
        return [(name, {}) for name in CODIM2
                if pa.get(name) is not None and pb.get(name) is not None
                and engine.sign_change(pa[name], pb[name])]

    def locate_event(self, kind, Xa, ta, Xb, index, **kw):
        system = self.system
        X, _, _ = self.root(lambda X, t, Gu: _tests(grazing_point(system, X),
                                                    system.impact)[kind], Xa, ta, Xb)
        pt = grazing_point(system, X)
        name = CODIM2[kind]
        what = EVENT_KINDS[name]
        coef = {}
        if kind in ("LP", "PD") and pt.multipliers is None:
            # an impact at zero speed: the fold (flip) curve meets the grazing curve here,
            # tangentially; kappa of b = b_graze(a) + kappa (a - a*)^2
            curve = "fold" if kind == "LP" else "flip"
            coef = tangency(system, X, system.impact, (curve,))
            what += (f"; it leaves as b = b_graze(a) + kappa (a - a*)^2, (a, b) = "
                     f"({', '.join(system.names)})" if coef else
                     f"; the {curve} curve found here is not tangent to the grazing curve")
        elif kind in ("LP", "PD", "NS"):
            target = {"LP": 1.0, "PD": -1.0}.get(kind)
            mu = np.array(pt.multipliers)
            if target is None:
                pairs = [z for z in mu if z.imag > 1e-9]
                if not pairs:
                    return None            # a real pair with product 1: a neutral saddle
                z = min(pairs, key=lambda z: abs(abs(z) - 1))
                if abs(abs(z) - 1) > 1e-6:
                    return None
                coef = {"theta": float(np.angle(z)), "modulus": float(abs(z))}
            else:
                z = min(mu, key=lambda z: abs(z - target))
                coef = {"multiplier": float(z.real)}
        elif kind == "DG":
            x, j = min(_others(pt, system.impact))
            coef = {"impact": j + 1, "impact_velocity": float(x)}
        else:
            coef = {"acceleration": float(pt.acceleration)}
        return GrazingSpecial(name, dict(pt.params), pt, coef, what, index)

    def unlocated(self, kind, Xa, Xb, index, exc):
        name = CODIM2[kind]
        pt = grazing_point(self.system, Xb)
        return GrazingSpecial("unlocated", dict(pt.params), pt, {"kind": name},
                              f"a {name} point between this curve point and the one "
                              f"before could not be located: {exc}", index)


class _GrazingRun(Client):
    """A grazing curve as a client of :func:`symvi.continuation.engine.run`."""

    def __init__(self, system):
        self.system = system
        self.names = system.names

    def point(self, X, prev, Gu):
        return grazing_point(self.system, X)


def follow(system, X0, box, *, h=None, h_max=None, max_points=2000, both=True, through=False):
    """The grazing curve of ``system`` through the solution X0, both ways within ``box``
    ({name: (lo, hi)}): (points, states, ends), the second direction reversed first; it
    ends where its orbit stops being admissible unless ``through``."""
    lo, hi, h, h_max = steps(system, box, h, h_max)
    first = grazing_point(system, X0)
    halves = []
    for sgn in ((1.0, -1.0) if both else (1.0,)):
        t = first_tangent(system, X0, sgn)
        tracker = GrazingTracker(system)
        points, states, end = engine.run(system, _GrazingRun(system), X0, t, lo, hi, h=h,
                                         h_max=h_max, max_points=max_points,
                                         through=through, chord_first=True, first=first,
                                         tracker=tracker)
        halves.append((points, states, tracker.special, end))
    pts, states, special, ends = join(halves)
    return pts, states, ends, resonant(system, special)


#: a grazing-fold and a grazing-flip point closer than this (relative to the parameters'
#: size) are one resonant grazing point
RG_TOL = 1e-7


def resonant(system, special):
    """The located points with each grazing-fold and grazing-flip point of an impact that
    lie together (both curves leave the grazing curve there: resonant grazing, as in one
    degree of freedom at omega* = 2 omega_d / m) made one RG point with both kappas."""
    out, used = [], set()
    for k, s in enumerate(special):
        if k in used:
            continue
        if s.kind == "grazing-fold" and s.orbit.multipliers is None:
            mate = next((j for j, o in enumerate(special) if j not in used and j != k
                         and o.kind == "grazing-flip" and all(
                             abs(o.params[n] - s.params[n]) <= RG_TOL * (1 + abs(s.params[n]))
                             for n in s.params)), None)
            if mate is not None:
                used.add(mate)
                coef = {**s.coefficients, **special[mate].coefficients}
                s = GrazingSpecial("RG", s.params, s.orbit, coef, EVENT_KINDS["RG"] + (
                    f"; the curves leave it as b = b_graze(a) + kappa (a - a*)^2, (a, b) = "
                    f"({', '.join(system.names)})"), s.index)
        out.append(s)
    return out


def start(system, u, start_values):
    """X0 = (u, a, b) on the grazing curve, corrected at fixed b from the shooting unknowns
    ``u`` of a located grazing point (its impact speed ~0 already)."""
    a, b = system.names
    m = system.m
    X = np.concatenate([u, [start_values[a], start_values[b]]])
    e = np.zeros(m + 2)
    e[-1] = 1.0
    res = correct(system, X, e, start_values[b])
    if res is None:
        raise SymviError(f"no grazing orbit found near {a} = {start_values[a]:.12g} at {b} = "
                         f"{start_values[b]:.12g}: the start is not on a grazing curve")
    return res[0]


# --------------------------------------------------------------------------- landing
#: a fold or flip curve that ends (not at its box) with an impact slower than this,
#: relative to its orbits' size 1 + max|y|, is landed on grazing (:func:`land`)
LAND_SPEED = 1e-1
#: Newton on the landing system: iterations, and the step of the test's differences
LAND_MAXIT, LAND_STEP = 30, 1e-7


def regular_tests(pr, u, lam, i, kinds=("fold", "flip")):
    """w det(M -+ I) of the fold (-) and flip (+) tests, regular where impact i grazes:
    with w = dg/dT of flight i (-> 0 with its speed) the time-eliminated DP_i has a 1/w
    part of rank one, DP_i = dh/dy - a b^T / w, so det(M -+ I) = det([[C, a], [b^T, w]]) / w
    with C = L (dh/dy) R -+ I, a = L dh/dT, b = R^T (dg/dy)^T, L and R the finite
    products of the other flights' DP_j (the matrix determinant lemma; one owner:
    :func:`symvi.curves.regular.regular_char`, q(z) = w det(M - z I) at z = +-1). The
    bordered determinant is smooth through w = 0; there it vanishes where the fold (flip)
    curve meets the grazing curve. One value per kind of ``kinds``, from one evaluation."""
    zs = [1.0 if kind == "fold" else -1.0 for kind in kinds]
    return tuple(float(v) for v in regular_char(pr, u, lam, i, zs))


def _test_row(graze, X, kind, i, cols=None):
    """(the regular ``kind`` test at X, its gradient in X = (u, a, b) by central
    differences of step LAND_STEP (1 + |X_k|); only in the entries ``cols`` when given,
    the others left 0)."""
    m = graze.m

    def phi(Z):
        return regular_tests(graze.problem(Z[-1]), Z[:m], Z[m], i, (kind,))[0]

    row = np.zeros(len(X))
    for k in range(len(X)) if cols is None else cols:
        h = LAND_STEP * (1 + abs(X[k]))
        e = np.zeros(len(X))
        e[k] = h
        row[k] = (phi(X + e) - phi(X - e)) / (2 * h)
    return phi(X), row


def land(system, X, kind):
    """The point where the fold or flip curve whose end is X = (u, a, b) meets grazing:
    Newton on G = 0, v_k+ = 0 after the slowest impact, and the regular ``kind`` test of
    :func:`regular_tests` = 0 (m + 2 equations in m + 2 unknowns; the test's row by central
    differences, :func:`_test_row`). Returns (X*, :class:`GrazingPoint`, impact) or None."""
    m = system.m
    pr = system.problem(X[-1])
    fl, (_, flow, _) = pr.flights(X[:m], X[m], check=False)
    speeds = pr.approach_speeds(fl, flow)
    i = int(np.argmin(np.abs(speeds)))
    graze = GrazingSystem(system.model, system.n, system.p, system.params, i,
                          omega=system.omega, signature=system.signature)
    X = np.array(X, dtype=float)
    for _ in range(LAND_MAXIT):
        F, DF, Fb = graze.evaluate(X[:-1], X[-1], dparam=True, check=False)
        f, row = _test_row(graze, X, kind, i)
        J = np.zeros((m + 2, m + 2))
        J[:m + 1, :m + 1], J[:m + 1, m + 1], J[m + 1] = DF, Fb, row
        try:
            dX = np.linalg.solve(J, -np.append(F, f))
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(dX)):
            return None
        X = X + dX
        if np.max(np.abs(dX)) <= 1e-13 * (1 + np.max(np.abs(X))):
            F = graze.evaluate(X[:-1], X[-1], jac=False, check=False)[0]
            if np.max(np.abs(F)) > 1e-9 * (1 + np.max(np.abs(X))):
                return None
            return X, grazing_point(graze, X), i
    return None


# --------------------------------------------------------------------------- kappa
#: the steps in the first parameter (relative to 1 + |P1*|) of the tangency coefficient's
#: symmetric differences, combined by Richardson extrapolation
KAPPA_STEP = 1e-3


def _solve_at(graze, X, a, kind, i):
    """X = (u, a, b) on the grazing curve (``kind`` None) or on the fold / flip curve
    (regular test) at the first parameter fixed to ``a``: Newton in (u, b) from X, or None."""
    m = graze.m
    X = np.array(X, dtype=float)
    X[m] = a
    for _ in range(LAND_MAXIT):
        F, DF, Fb = graze.evaluate(X[:-1], X[-1], dparam=True, check=False)
        J = np.zeros((m + 1, m + 1))
        J[:m, :m], J[:m, m] = DF[:m, :m], Fb[:m]
        if kind is None:
            r = F
            J[m, :m] = DF[m, :m]
        else:
            f, row = _test_row(graze, X, kind, i, [*range(m), m + 1])
            r = np.append(F[:m], f)
            J[m, :m], J[m, m] = row[:m], row[m + 1]          # a is fixed
        try:
            d = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(d)):
            return None
        X[:m] += d[:m]
        X[m + 1] += d[m]
        if np.max(np.abs(d)) <= 1e-13 * (1 + np.max(np.abs(X))):
            return X
    return None


def tangency(system, X, i, kinds=("fold", "flip")):
    """{"kappa_fold": ..., "kappa_flip": ...} at a point X = (u, a, b) where the fold or
    flip curve (each of ``kinds``) meets the grazing curve of impact i: it leaves as
    b = b_graze(a) + kappa (a - a*)^2 + ..., kappa from symmetric second differences of
    b_curve(a) - b_graze(a) at a* +- h and a* +- h/2, Richardson-extrapolated (each point
    solved by Newton at fixed a: the grazing system, the regular fold or flip test). A key
    is left out where that curve could not be solved for."""
    graze = system if isinstance(system, GrazingSystem) else GrazingSystem(
        system.model, system.n, system.p, system.params, i, omega=system.omega,
        signature=system.signature)
    m = graze.m
    a0 = float(X[m])
    h = KAPPA_STEP * (1 + abs(a0))
    # the grazing curve at each offset, once for every kind
    graz = {s: _solve_at(graze, X, a0 + s, None, i) for s in (h, -h, h / 2, -h / 2)}
    out = {}
    for kind in kinds:
        est, slope = [], None
        for step in (h, h / 2):
            diffs = []
            for s in (step, -step):
                g = graz[s]
                c = _solve_at(graze, X, a0 + s, kind, i)
                if g is None or c is None:
                    break
                diffs.append(c[-1] - g[-1])
            if len(diffs) < 2:
                break
            est.append((diffs[0] + diffs[1]) / (2 * step * step))
            slope = (diffs[0] - diffs[1]) / (2 * step)
        if len(est) == 2:
            kappa = (4 * est[1] - est[0]) / 3
            # tangent: the first difference is of the cubic term's order, not kappa h's
            if abs(slope) <= 0.1 * abs(kappa) * h:
                out[f"kappa_{kind}"] = float(kappa)
    return out
