"""Continuation of fold, flip and Neimark–Sacker curves in two named parameters.

The defining system is :class:`symvi.curves.system.CurveSystem`; its points are
followed by the pseudo-arclength engine of :mod:`symvi.continuation.engine` (chord
corrector first), the bordering vectors renewed every BORDER_EVERY accepted points.  From the start the curve is
followed both ways until, on each side, it

* leaves the parameter box (the last point lands on the bound),
* stops being admissible (the grazing or penetration located, the point beyond kept
  and marked inadmissible),
* meets a model the parameters make invalid, a forcing resonance, or a corrector
  that fails below the smallest step (the reason is stated).

At every point: the orbit (multipliers, admissibility), and for NS curves theta
and l1 (Kuznetsov, ||q||_2 = 1, <p, q> = 1), for flip curves c, for fold curves a,
plus the side of the curve on which the orbit is stable.  Codimension-two points
are located on the way by :mod:`symvi.curves.special`.
"""
import math
from dataclasses import dataclass

import numpy as np

from .._deprecated import moved_names as _moved_names
from ..continuation import engine
from ..continuation.engine import Client, correct
from ..errors import ParameterError, SymviError
from ..normal_forms.normal_form import flip_coefficient, fold_coefficient
from ..orbits.periodic import PeriodicOrbit, orbit_of
from .frame import first_tangent, join, prepare, reindex, steps
from .points import NORMALISATION, CurvePoint, TwoParameter, first_lyapunov, mono
from .special import Codim2Tracker
from .system import CurveSystem, kappa_pair, theta_of

#: a multiplier beyond this modulus ends a curve: the orbit is close to grazing, where the
#: impact map's Jacobian has a pole (eq. (30)) and no test function of M can be evaluated
MULTIPLIER_CUT = 1e2
#: the note of a curve followed near or past grazing on the regular test
BRIDGED = ("near grazing the curve is followed on the regular test w det(M - z I) "
           "(symvi.curves.regular; no multiplier cut there): those points carry theta "
           "and their orbit, but no l1 or c (the jets have the 1/v pole), and past a "
           "zero impact speed they are not admissible")
#: accepted points between renewals of the bordering vectors
BORDER_EVERY = 8


@dataclass(frozen=True)
class Curve(TwoParameter):
    """A continued curve of ``kind`` (ns, flip, fold) in the parameters ``names`` (a
    :class:`symvi.curves.points.TwoParameter`: ``ends`` are its stop reasons)."""

    def plot_data(self, sides=24):
        """Plain data for :func:`symvi.reporting.figures.two_parameter`; the stable side computed at
        about ``sides`` points along the curve."""
        a, b = self.names
        sub = [(pt.l1 is not None and pt.l1 > 0) if self.kind == "ns" else
               (pt.coefficient is not None and self.kind == "flip" and pt.coefficient < 0)
               for pt in self.points]
        return {"kind": self.kind, "a": [pt.params[a] for pt in self.points],
                "b": [pt.params[b] for pt in self.points], "subcritical": sub,
                "admissible": [bool(pt.admissible) for pt in self.points],
                "bifurcation": [bool(pt.ns) for pt in self.points],
                "sides": stable_sides(self, max(1, len(self.points) // max(1, sides))),
                "special": [(s.kind, s.params[a], s.params[b]) for s in self.special
                            if s.kind != "unlocated"]}

    def as_dict(self):
        sig = self.points[0].orbit.signature_names if self.points else []
        return {"kind": self.kind, "params": list(self.names), "orbit": f"{self.n}-{self.p}",
                "signature": sig, "fixed": dict(self.fixed), "bounds": {k: list(v) for k, v in self.bounds.items()},
                "normalisation": NORMALISATION,
                "points": [pt.as_dict() for pt in self.points],
                "special": [s.as_dict() for s in self.special],
                "ends": list(self.ends), "notes": list(self.notes)}


# --------------------------------------------------------------------------- entry point
def continue_curve(model, kind, names, orbit, *, bounds=None, h=None, h_max=None,
                   max_points=2000, both=True, locate=True, through=False, **fixed):
    """Continue the ``kind`` curve (ns, flip or fold) of ``orbit`` in the two named
    parameters ``names`` = (a, b).

    ``orbit`` is a :class:`PeriodicOrbit` at (or near) a point of the curve, or what
    holds one: a special point that :func:`symvi.continuation.continue_branch` located,
    a :class:`symvi.analysis.hopf.HopfPoint` of :func:`symvi.hopf_points`, or a period-1 orbit;
    ``model`` a :class:`symvi.Model` or the paper's Params; ``fixed`` gives the model's other parameters (omega included when it is
    not one of ``names``), and the start values of a and b are the orbit's (omega)
    or the model's.  ``bounds`` maps a name to (lo, hi); by default each parameter may
    range over half to twice its start value (omega and positive parameters).  With
    ``both`` the curve is followed both ways from the start and joined.
    """
    from ..model import Model
    model = Model.of(model)
    orbit = _as_periodic(model, orbit)
    names, model, omega, pars, on_omega, start, box, fixed = prepare(model, orbit, names,
                                                                     fixed, bounds)
    system = CurveSystem(model, orbit.n, orbit.p, pars, kind,
                         omega=None if on_omega else omega, signature=orbit.itinerary)
    X0 = _first(system, orbit, start)
    first = _point(system, X0, None)
    if not first.admissible and not through:
        raise SymviError(f"the starting orbit is not admissible ({first.orbit.reason}): a "
                         "curve of an unphysical orbit is not followed (through=True to "
                         "follow it anyway)")
    halves = []
    directions = (1.0, -1.0) if both else (1.0,)
    for sgn in directions:
        tracker = Codim2Tracker(system) if locate else None
        half = _run(system, X0, first, sgn, box, h, h_max, max_points, tracker, through)
        if kind in ("fold", "flip"):
            # landed on its resonant (grazing-fold, -flip) point; --through goes on past it
            half = _land_end(system, half, box)
        if kind == "ns" or through:
            half = _past_grazing(system, half, box, h, h_max, max_points, through, locate)
        halves.append(half)
    pts, states, special, ends = join(halves)
    notes = []
    if any(getattr(pt, "_bridged", False) for pt in pts):
        notes.append(BRIDGED)
    if model.conservative:
        notes.append("conservative model (r = 1, no damping): the map preserves volume and "
                     "multipliers lie on the unit circle over whole intervals; (H3) has no "
                     "meaning and NS curves are not defined")
    return Curve(kind, names, orbit.n, orbit.p, tuple(pts), tuple(special), tuple(ends),
                 box, fixed, tuple(notes), tuple(states), model)


def _as_periodic(model, start):
    """The :class:`PeriodicOrbit` of a start: itself, the ``orbit`` of a located point
    (SpecialPoint, HopfPoint), or a period-1 orbit's fixed point solved as a 1-1 orbit."""
    from ..orbits.periodic import periodic_orbit
    orbit = getattr(start, "orbit", start)
    if isinstance(orbit, PeriodicOrbit):
        return orbit
    y, omega = getattr(orbit, "y", None), getattr(orbit, "omega", None)
    if y is None or omega is None:
        raise ParameterError("orbit", type(start).__name__, "a PeriodicOrbit, a located point "
                             "(continue_branch's special point, a HopfPoint) or a period-1 orbit")
    return periodic_orbit(model, n=1, p=1, guess=tuple(float(v) for v in y),
                          omega=float(omega))


def _first(system, orbit, start):
    """X0 = (u, a, b) on the curve, corrected at fixed b from the orbit's shooting data."""
    a, b = system.names
    m = system.m
    X = np.concatenate([orbit.u, [start[a], start[b]]])
    pr = system.problem(start[b])
    G, Gu, _ = pr.evaluate(X[:m], X[m])
    system.set_border(pr.monodromy(X[:m], Gu)[1])
    e = np.zeros(m + 2)
    e[-1] = 1.0
    res = correct(system, X, e, start[b])
    if res is None:
        raise SymviError(f"no {system.kind} point of the orbit found near {a} = "
                         f"{start[a]:.12g} at {b} = {start[b]:.12g}: the start is not on a "
                         f"{system.kind} curve")
    X = res[0]
    system.set_border(mono(system, X))
    return X


def _point(system, X, prev, Gu=None):
    """The :class:`CurvePoint` at X (prev: the previous point, for the critical pair)."""
    m = system.m
    a, b = system.names
    pr, G, Gu, _ = system.orbit_data(X)
    orbit = orbit_of(pr, X[:m], X[m], Gu)
    params = {a: float(X[m]), b: float(X[m + 1])}
    mu = np.array(orbit.multipliers)
    if system.kind == "ns":
        pair = kappa_pair(mu, None if prev is None else prev._pair)[1]
        kappa = float(((pair[0] + pair[1]) / 2).real)
        ns = abs(kappa) < 1 and abs(pair[0].imag) > 1e-12
        l1 = theta = noise = None
        if ns:
            theta = theta_of(pair)
            l1, noise = first_lyapunov(orbit, pair[0])
        pt = CurvePoint(params, orbit, kappa, theta, l1, None, ns, noise)
        object.__setattr__(pt, "_pair", pair)
        return pt
    try:
        if system.kind == "flip":
            A, d2, d3 = orbit.jet(3)
            c = flip_coefficient(A, d2, d3)[0]
        else:
            A, d2, _ = orbit.jet(2)
            c = fold_coefficient(A, d2)[0]
    except (SymviError, np.linalg.LinAlgError):
        c = None
    crit = min(mu, key=lambda z: abs(z - (-1.0 if system.kind == "flip" else 1.0)))
    pt = CurvePoint(params, orbit, None, None, None, c, True)
    object.__setattr__(pt, "_pair", (crit, crit))
    return pt


def stable_sides(curve, every=1):
    """The :func:`stable_side` of every ``every``-th point of an NS or flip curve:
    [(index, unit normal or None)]."""
    if curve.kind == "fold":
        return []
    system = CurveSystem(curve.model, curve.n, curve.p, curve.names, curve.kind,
                         omega=curve.fixed.get("omega"))
    out = []
    for i in range(0, len(curve.points), max(1, int(every))):
        pt = curve.points[i]
        out.append((i, stable_side(system, curve.states[i], pt.orbit, pt._pair[0])))
    return out


def stable_side(system, X, orbit, lam):
    """Unit normal (in the plane of the two parameters) pointing to the side where the
    orbit is stable, from d|lambda|/d(a, b) along the orbit (exact: generated jets), or
    None when another multiplier lies outside the unit circle (unstable on both sides)."""
    others = [z for z in orbit.multipliers if abs(z - lam) > 1e-9 and abs(z - np.conj(lam)) > 1e-9]
    if any(abs(z) >= 1 for z in others):
        return None
    m = system.m
    pr = system.problem(X[-1])
    G, Gu, Ga = pr.evaluate(X[:m], X[m], dparam=True, check=False)
    Gb = pr.derivative(X[:m], X[m], system.names[1])
    mats, M = pr.monodromy(X[:m], Gu)
    w, V = np.linalg.eig(M)
    k = int(np.argmin(np.abs(w - lam)))
    q = V[:, k]
    pv = np.linalg.inv(V)[k]                      # row k of V^-1: paired with q
    K = np.outer(pv, q)                          # dlambda = sum K * dM
    try:
        gu, ga, gb = system._grad(pr, X[:m], X[m], K)
        du = np.linalg.solve(Gu, -np.column_stack([Ga, Gb]))
    except (SymviError, np.linalg.LinAlgError):
        return None
    dlam = np.array([ga, gb]) + gu @ du
    lamc = w[k]
    grad = np.array([(np.conj(lamc) * z).real / abs(lamc) for z in dlam])
    nrm = float(np.linalg.norm(grad))
    if not nrm > 0:
        return None
    return tuple(float(v) for v in -grad / nrm)


# --------------------------------------------------------------------------- the loop
class _CurveRun(Client):
    """A curve as a client of :func:`symvi.continuation.engine.run`."""

    def __init__(self, system):
        self.system = system
        self.names = system.names

    def point(self, X, prev, Gu):
        return _point(self.system, X, prev)

    def accepted(self, X, index):
        if index % BORDER_EVERY == 0:
            # new bordering vectors keep the bordered matrix well conditioned; the
            # derivatives are taken again with them (g's row depends on the border)
            self.system.set_border(mono(self.system, X))
            return self.system.evaluate(X[:-1], X[-1], dparam=True)[1:]
        return None

    def stop(self, X, pt):
        v = min(pt.orbit.impact_velocities)
        if v < 0:
            # past an impact at zero speed (through=True; at resonant grazing the pole's
            # residue vanishes and no multiplier grows): the regular test takes it on
            return (f"past grazing at {_where(self.system, X)}: an impact arrives with "
                    f"velocity {v:.3g} < 0")
        big = max(abs(z) for z in pt.orbit.multipliers)
        if big > MULTIPLIER_CUT:
            v = min(pt.orbit.impact_velocities)
            return (f"near grazing at {_where(self.system, X)}: a multiplier of modulus "
                    f"{big:.3g} (smallest impact velocity {v:.3g}); the impact map's Jacobian "
                    "has a pole at grazing (eq. (30)), the curve is ended here")
        return ""

    def finish(self, end, X):
        return end + _diagnosis(self.system, X) if end.startswith("step below") else end


def _run(system, X, first, sgn, box, h, h_max, max_points, tracker, through, direction=None):
    lo, hi, h, h_max = steps(system, box, h, h_max)
    system.set_border(mono(system, X))
    t = first_tangent(system, X, sgn)
    if direction is not None and float(np.dot(t, direction)) < 0:
        t = -t                              # resumed: on in the direction it came
    points, states, end = engine.run(system, _CurveRun(system), X, t, lo, hi, h=h,
                                     h_max=h_max, max_points=max_points, tracker=tracker,
                                     through=through, chord_first=True, first=first)
    return points, states, (tracker.special if tracker else []), end


def _land_end(system, half, box):
    """A fold or flip curve that runs into grazing ends exactly there: where its last
    point has an impact slower than grazing.LAND_SPEED, the resonant grazing point is
    solved for by Newton on the regular test (:func:`symvi.curves.grazing.land`) and
    becomes the curve's last event (RG) and its end."""
    from .grazing import LAND_SPEED, land
    points, states, special, end = half
    if end.startswith("reached "):              # the box: not grazing
        return half
    size = 1 + max(abs(v) for pt in points for y in pt.orbit.points for v in y[:-1])
    if min(points[-1].orbit.impact_velocities) > LAND_SPEED * size:
        return half
    got = land(system, states[-1], system.kind)
    if got is None:
        return half
    X, gp, i = got
    a, b = system.names
    span = min(box[a][1] - box[a][0], box[b][1] - box[b][0])
    gap = float(np.hypot(*(X[-2:] - states[-1][-2:])))
    if not (box[a][0] <= X[-2] <= box[a][1] and box[b][0] <= X[-1] <= box[b][1]) or \
            gap > 0.05 * span:
        return half
    # an admissibility change the last step met is this grazing, not located further
    special = [s for s in special if not (s.kind == "admissibility"
                                          and s.index >= len(points) - 1)]
    rg = _grazing_special(system, X, gp, i, len(points), "ends here")
    what = "the resonant grazing point" if rg.kind == "RG" else f"a grazing-{system.kind} point"
    end = (f"reached grazing at {what} {_where(system, X)} (impact {i + 1} at zero "
           f"velocity; solved on the regular test, {gap:.2g} beyond the last point)")
    return points, states, special + [rg], end


def _grazing_special(system, X, gp, i, index, how):
    """The located point where the fold or flip curve at X (on grazing, impact i: its
    :class:`GrazingPoint` gp) meets the grazing curve: RG with both kappas when the other
    curve (flip for a fold) meets it there too, else grazing-fold (-flip) with its own."""
    from ..continuation.result import EVENT_KINDS
    from .grazing import RG_TOL, GrazingSpecial, land, tangency
    other = "flip" if system.kind == "fold" else "fold"
    mate = land(system, X, other)
    both = mate is not None and all(abs(mate[0][k] - X[k]) <= RG_TOL * (1 + abs(X[k]))
                                    for k in (-2, -1))
    kind = "RG" if both else f"grazing-{system.kind}"
    coef = {"impact": i + 1, **tangency(system, X, i, ("fold", "flip") if both
                                        else (system.kind,))}
    return GrazingSpecial(kind, dict(gp.params), gp, coef,
                          EVENT_KINDS[kind] + f"; the {system.kind} curve {how}, impact "
                          f"{i + 1} arriving with zero velocity", index)


def _named_crossing(system, sp):
    """A zero impact speed the bridge located on a fold or flip curve, solved again on its
    regular test (:func:`symvi.curves.grazing.land`) and named as a landing is (RG or
    grazing-fold/-flip, with kappa); the bridge's point when that fails."""
    from .grazing import land
    if system.kind == "ns" or sp.kind == "unlocated":
        return sp
    X = np.concatenate([np.asarray(sp.orbit.u, dtype=float),
                        [sp.params[n] for n in system.names]])
    got = land(system, X, system.kind)
    if got is None:
        return sp
    X, gp, i = got
    return _grazing_special(system, X, gp, i, sp.index, "crosses grazing here")


#: an NS curve crosses grazing at most this many times on each side of its start
MAX_BRIDGES = 8


def _past_grazing(system, half, box, h, h_max, max_points, through, locate):
    """An NS curve that ends near grazing (an impact slower than grazing.LAND_SPEED
    relative to the orbit's size, not at its box) is followed on on the regular test of
    :mod:`symvi.curves.regular`: to the zero of that impact's speed, located and named
    grazing-NS, where it ends; with ``through`` (any kind: a fold or flip curve after its
    landing), across the stretch where the orbit is not admissible to the next admissible
    piece, where the standard test and its located points take over again (as often as
    the curve crosses grazing, within the box and ``max_points``); a fold or flip curve's
    crossings are named as its landings are (RG or grazing-fold/-flip, with kappa)."""
    from .grazing import LAND_SPEED
    from .regular import bridge
    points, states, special, end = half
    lo, hi, hh, hm = steps(system, box, h, h_max)
    for _ in range(MAX_BRIDGES):
        box_end = end.startswith("reached ") and not end.startswith("reached grazing")
        if box_end or len(points) < 2 or len(points) >= max_points:
            break
        size = 1 + max(abs(v) for y in points[-1].orbit.points for v in y[:-1])
        if min(points[-1].orbit.impact_velocities) > LAND_SPEED * size:
            break
        theta = abs(float(np.angle(points[-1]._pair[0])))
        try:
            bp, bs, bsp, bend, direction, resumed = bridge(
                system, states[-1], states[-2], lo, hi, h=hh, h_max=hm,
                max_points=max_points - len(points) + 1, through=through, theta=theta)
        except (SymviError, np.linalg.LinAlgError) as exc:
            end += f"; not followed past grazing: {exc}"
            break
        # a zero speed the fold or flip curve was landed on already (RG) is not repeated
        bsp = [_named_crossing(system, s) for s in bsp if not any(_same(s, o) for o in special)]
        special = special + [reindex(s, s.index + len(points)) for s in bsp]
        points, states = points + bp, states + bs
        if not resumed:
            end = bend
            break
        tracker = Codim2Tracker(system) if locate else None
        np_, ns_, nsp, end = _run(system, states[-1], points[-1], 1.0, box, h, h_max,
                                  max_points - len(points) + 1, tracker, through, direction)
        special = special + [reindex(s, s.index + len(points) - 1) for s in nsp]
        points, states = points + list(np_[1:]), states + list(ns_[1:])
    return points, states, special, end


def _same(a, b):
    """Two located points at one place (RG_TOL relative): a landing and its bridge."""
    from .grazing import RG_TOL
    return all(abs(a.params[n] - b.params.get(n, math.inf)) <= RG_TOL * 10 * (1 + abs(a.params[n]))
               for n in a.params)


def _diagnosis(system, X):
    """Why the corrector may fail where a curve stops: a second singular direction of the
    test matrix (two pairs with product 1, as in the conservative limit r = 1 without
    damping, where the map preserves volume and NS curves end)."""
    s = np.linalg.svd(system.matrix(mono(system, X)), compute_uv=False)
    if len(s) > 1 and s[-2] < 1e-4 * s[0]:
        det = abs(np.prod(np.linalg.eigvals(mono(system, X))))
        return (f"; the test matrix has a second near-null direction (singular value "
                f"{s[-2]:.2g}): two multiplier pairs have product 1 there, |det M| = "
                f"{det:.9g}" + (" (the conservative limit: r -> 1 without damping, the map "
                                "preserves volume)" if abs(det - 1) < 1e-4 else ""))
    return ""


def _where(system, X):
    a, b = system.names
    return f"{a} = {X[-2]:.12g}, {b} = {X[-1]:.12g}"


# names that moved to the one engine (issue 24, item 4): they warn for one release
__getattr__ = _moved_names(__name__, "symvi.continuation.engine",
                           {"CURVE_MIN_COS": "MIN_COS", "CHORD_MAXIT": "CHORD_MAXIT"})
