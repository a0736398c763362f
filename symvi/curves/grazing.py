"""Grazing curves in two parameters: the n-p orbits one of whose impacts arrives with zero
velocity (issue 27, item 1, the first kind of grazing).

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
"""
from dataclasses import dataclass, field

import numpy as np

from ..continuation import engine
from ..continuation.engine import Client, correct, tangent
from ..continuation.result import Result
from ..errors import ParameterError, SymviError
from ..orbits.admissibility import check_flight
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

    def __init__(self, model, n, p, names, impact, omega=None, signature=None):
        if model.elastic:
            raise ParameterError("kind", "grazing", "a model of rigid stops (an elastic "
                                 "stop's entry at zero speed is a touch: its contact time "
                                 "vanishes, and no curve of touches is followed)")
        if not 0 <= int(impact) < int(p):
            raise ParameterError("impact", impact, f"an impact of the orbit, 0 .. {p - 1}")
        super().__init__(model, n, p, names, "grazing", omega=omega, signature=signature)
        self.impact = int(impact)
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

    def as_dict(self):
        out = {"params": dict(self.params), "admissible": bool(self.admissible),
               "y": [list(p) for p in self.y], "times": list(self.times),
               "impact_velocities": list(self.impact_velocities)}
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
    return GrazingPoint({a: float(X[m]), b: float(X[m + 1])},
                        tuple(tuple(float(v) for v in y) for y in Y),
                        tuple(float(t) for t in T), tuple(float(s) for s in speeds), ok, why, u)


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
        return True, ""          # several stops: the interior is judged on branches only
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
class GrazingCurve(Result):
    """A continued grazing curve of impact ``impact`` (1-based) of n-p orbits in the
    parameters ``names``: the same shape as :class:`symvi.curves.curve.Curve` (its points
    :class:`GrazingPoint`; ``special`` is empty: its codimension-two points are not
    located yet)."""

    names: tuple
    n: int
    p: int
    impact: int
    points: tuple
    ends: tuple
    bounds: dict
    fixed: dict
    signature: tuple = ()
    special: tuple = ()
    notes: tuple = ()
    states: tuple = field(repr=False, default=())
    kind: str = "grazing"

    @property
    def stop_reasons(self):
        return tuple(self.ends)

    def values(self, name):
        return np.array([pt.params[name] for pt in self.points])

    def plot_data(self, sides=24):
        """Plain data for :func:`symvi.reporting.figures.two_parameter`."""
        a, b = self.names
        n = len(self.points)
        return {"kind": "grazing", "a": [pt.params[a] for pt in self.points],
                "b": [pt.params[b] for pt in self.points], "subcritical": [False] * n,
                "admissible": [bool(pt.admissible) for pt in self.points],
                "bifurcation": [True] * n, "sides": [], "special": []}

    def as_dict(self):
        return {"kind": "grazing", "params": list(self.names), "orbit": f"{self.n}-{self.p}",
                "impact": self.impact, "signature": list(self.signature),
                "fixed": dict(self.fixed),
                "bounds": {k: list(v) for k, v in self.bounds.items()},
                "normalisation": DEFINITION,
                "points": [pt.as_dict() for pt in self.points], "special": [],
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
    from .curve import _bounds
    fixed = dict(fixed)
    impact = fixed.pop("impact", None)
    coef = getattr(point, "coefficients", {}) or {}
    if getattr(point, "kind", "grazing") != "grazing":
        raise ParameterError("point", point.kind, "a grazing point")
    if impact is None:
        if "impact" not in coef:
            raise ParameterError("point", getattr(point, "detail", point),
                                 "a grazing impact (an impact velocity through 0); a flight "
                                 "touching a stop inside it starts no curve here")
        impact = int(coef["impact"])
    orbit = getattr(point, "orbit", point)
    # the model at the point (a branch in another parameter moved it), then ``fixed``
    model = Model.of(getattr(orbit, "model", None) or model)
    names = tuple(names)
    if len(names) != 2:
        raise ParameterError("params", names, "two parameter names, e.g. omega,b")
    omega = fixed.pop("omega", None)
    omega = orbit.omega if omega is None else omega
    if fixed:
        model = model.with_(**fixed)
    pars = tuple(model.parameter(nm) for nm in names)
    on_omega = any(par.is_forcing_frequency for par in pars)
    start_values = {nm: float(par.get(model, omega)) for nm, par in zip(names, pars)}
    box = _bounds(names, start_values, bounds)
    system = GrazingSystem(model, orbit.n, orbit.p, pars, impact - 1,
                           omega=None if on_omega else omega, signature=orbit.itinerary)
    X0 = start(system, orbit, start_values)
    pts, states, ends = follow(system, X0, box, h=h, h_max=h_max, max_points=max_points,
                               both=both, through=through)
    fx = dict(fixed)
    if not on_omega:
        fx["omega"] = float(omega)
    notes = ("codimension-two points on grazing curves (resonant grazing, grazing-fold, "
             "-flip, -NS, double and degenerate grazing) are not located yet",)
    return GrazingCurve(names, orbit.n, orbit.p, impact, tuple(pts), tuple(ends), box, fx,
                        tuple(orbit.signature_names), (), notes, tuple(states))


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
    m = system.m
    a, b = system.names
    lo = np.array([box[a][0], box[b][0]])
    hi = np.array([box[a][1], box[b][1]])
    span = float(np.min(hi - lo))
    h_max = float(h_max) if h_max is not None else span / 20 + 0.02
    h = float(h) if h is not None else min(h_max, span / 200)
    first = grazing_point(system, X0)
    halves = []
    for sgn in ((1.0, -1.0) if both else (1.0,)):
        F, DF, Fb = system.evaluate(X0[:-1], X0[-1], dparam=True)
        e = np.zeros(m + 2)
        e[-1] = sgn
        t = tangent(DF, Fb, e)
        if abs(t[-1]) < 1e-3:                   # the curve is parallel to b: orient by a
            e = np.zeros(m + 2)
            e[-2] = sgn
            t = tangent(DF, Fb, e)
        halves.append(engine.run(system, _GrazingRun(system), X0, t, lo, hi, h=h,
                                 h_max=h_max, max_points=max_points, through=through,
                                 chord_first=True, first=first))
    pts, states, ends = list(halves[0][0]), list(halves[0][1]), [halves[0][2]]
    if len(halves) == 2:
        p2, s2, e2 = halves[1]
        pts = list(reversed(p2[1:])) + pts
        states = list(reversed(s2[1:])) + states
        ends = [e2, ends[0]]
    return pts, states, ends


def start(system, orbit, start_values):
    """X0 = (u, a, b) on the grazing curve, corrected at fixed b from ``orbit`` (the orbit
    of a located grazing point, whose impact speed is ~0 already)."""
    a, b = system.names
    m = system.m
    X = np.concatenate([orbit.u, [start_values[a], start_values[b]]])
    e = np.zeros(m + 2)
    e[-1] = 1.0
    res = correct(system, X, e, start_values[b])
    if res is None:
        raise SymviError(f"no grazing orbit found near {a} = {start_values[a]:.12g} at {b} = "
                         f"{start_values[b]:.12g}: the start is not on a grazing curve")
    return res[0]
