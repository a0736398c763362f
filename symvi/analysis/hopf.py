"""Neimark–Sacker (Hopf) points of period-1 orbits, (H1)–(H3), and their normal forms, Sec. 3.

``hopf_points(params, omega_min, omega_max)`` scans both orbit branches of
eqs. (10)–(16) with order-1 code only (orbit + multipliers), finds *every*
crossing of a complex pair through |lambda| = 1 of an admissible orbit, locates
it to 1e-12 in omega, and evaluates the order-3 jet and the normal form of
:mod:`symvi.normal_forms.normal_form` there.  Along the way it records the other events a
sweep in omega meets: a real multiplier through +1 or -1, the orbit becoming
admissible or inadmissible (grazing, or impact velocity through 0), the orbit
appearing or vanishing (eq. 16), and singular frequencies.

A natural frequency omega_j of an undamped mode strictly inside the interval
makes the forcing amplitude of eq. (7) infinite: the branches are cut there,
scanned on both sides up to a relative distance ``RESONANCE_GAP`` and a
``forcing-resonance`` event is recorded (an end within half that gap is refused).
A conservative model (r = 1 and no damping: det DP = r^2 exp(-tr(M^-1 C) T) = 1)
has multipliers on the unit circle over whole intervals and no Neimark–Sacker
point: none is sought, a ``conservative`` event spans the interval, and the
real multipliers through +/-1 (det(J -/+ I) changing sign) are still reported.
(H3) is claimed only for a resolvably nonzero crossing speed (:attr:`HopfPoint.detail`).

How the scan avoids missing a crossing
--------------------------------------
The interval is cut into segments; a segment [a, b] is *certified* from its
ends and its midpoint m.  Multipliers are matched a -> m -> b (minimum total
distance) and each one is followed along the polyline lambda(a), lambda(m),
lambda(b).  For a path whose second derivative is locally constant the
polyline is within |lambda(m) - (lambda(a) + lambda(b))/2| / 4 =: e/4 of the
true path, so the segment is accepted when, for every multiplier, either the
polyline stays a distance > 2e from the unit circle (no crossing possible), or
it crosses once, on one half, with a change of |lambda| there larger than 2e
(exactly one transversal crossing, bracketed).  Otherwise both halves are
certified recursively (this is what refines where |lambda| approaches 1, and
near a collision of two real multipliers, where the path has a square-root
corner).  A crossing between samples therefore needs the path to bend by 8
times more than its own local second difference predicts.  Segments narrower
than ``MIN_WIDTH`` that still fail (tangency, a collision on the real axis next to
+1, a near-singular map) are reported as ``unresolved`` events with their span.
Next to a located boundary (fold, admissibility change, a singular frequency
omega_j / n) a multiplier that approaches the circle monotonically towards the
boundary is accepted (e.g. the multiplier tending to +1 at a fold).

What the scan does not certify it says: :attr:`HopfResult.uncertified` lists the merged
spans where a crossing may have been missed, each also an ``unresolved`` event with its
reason; an empty list (``complete``) is the statement that every crossing was found.
Besides the unresolved segments above these are: the segments left when the budget of
orbit evaluations (``MAX_SAMPLES`` plus ``SAMPLES_PER_CUT`` per cut) runs out -- the
segments are certified breadth first, so what is left is where the finest resolution is
needed, not the end of the interval; the gap around a singular frequency where the branch
is admissible at the gap's edge; and, when more than ``MAX_SINGULAR`` of the omega_j / n
(which accumulate at 0) lie inside, the span below the largest ``MAX_SINGULAR`` of them.
So the points found on [a, c] are those found on [a, b] and [b, c] up to the spans
either declares uncertified (tests/property/test_scan_union.py).

Each bracket is handed to the continuation's locator
(:func:`symvi.continuation.locate.locate_between`, the one owner of locating special
points on any branch): the two closed-form orbits become two points of the 1-1
shooting problem continued in omega, and the crossing is located by Brent's method in
the arclength on the test function of its kind, the bialternate product
det(J (.) J - I) for a complex pair, det(J + I) for -1 (a flip, with its
period-doubling coefficient c) and det(J - I) for +1 inside a branch (a branch
point: the fixed point's index changes, so another branch of fixed points meets it).
A sign change that is no crossing (|lambda|^2 - 1 changing by a jump between two
complex pairs, near a collision off the circle as for a nearly conservative map, where
the bialternate product keeps its sign, or ||lambda1|^2 - 1| > ``NS_RESIDUAL`` at the
root) makes the bracket certified again, finer, and reported ``unresolved`` below
``MIN_WIDTH``.  The orbit's end is located by Brent's method on the existence ratio of
eq. (16), the impact velocity's zero likewise, and grazing by bisection of the
admissibility test, all to ``XTOL`` in omega.

The paper's numbers (Sec. 4) beside ours
-----------------------------------------
Each of ours agrees with an independent 80-digit finite-difference chain
(:mod:`symvi.studies.mpcheck`) to >= 40 digits.

============  ==========  ==================  =======================================
example       v_c         d|lambda1|/dv       f1(0)
============  ==========  ==================  =======================================
1, paper      0.7368      3.0701              1.361
1, symvi      0.73687692  2.35553882          0.6710 (eq. 60 printed), 0.02430 (corrected)
2, paper      0.4906      0.641               1.096
2, symvi      0.49051952  2.55555715          0.09229 (eq. 60 printed), 0.005016 (corrected)
============  ==========  ==================  =======================================

v_c and the kind (supercritical) are reproduced.  d|lambda1|/dv is not: ours
agrees three ways (eqs. A1–A3 on F11, |lambda1| differentiated along the
branch, chain B), and neither the explicit d/dv at fixed Delta X nor reading
omega_0 of (A3) as Im lambda gives the paper's values.  f1(0) depends on the
normalisation of r1, which the paper does not state; no single scaling of r1
maps our printed-(60) or corrected-(60) values onto both published ones (the
ratios differ between the examples), so only the sign is comparable (f1 > 0,
attracting, in all forms).

References
----------
[Kuznetsov, Elements of Applied Bifurcation Theory] Yu. A. Kuznetsov, Elements
of Applied Bifurcation Theory, 3rd ed., Springer 2004, Sec. 5.4.
"""
import math
import warnings
from collections import deque
from dataclasses import dataclass, field

import numpy as np

from ..errors import NearSingularWarning, ParameterError, SingularCaseError, SymviError
from ..numerics.tolerances import EPS64, FORCING_RESONANCE_CUT, OMEGA_RANGE
from ..normal_forms.normal_form import normal_form, resonance

#: the crossing is located to this absolute tolerance in omega (plus 4 eps relative)
XTOL = 2e-13
#: segments narrower than this (relative to the interval) are not split further
MIN_WIDTH = 1e-7
#: initial number of segments
N_INITIAL = 8
#: first step (relative to omega) of Ridders' differentiation of |lambda1| along the branch
BRANCH_H = 1e-3
#: the derivative along the branch is printed as uncertain above this estimated relative error
BRANCH_REL_ERR = 1e-6
#: Ridders' error estimate is multiplied by this (a heuristic, biased low: made a safe one)
RIDDERS_SAFETY = 10.0
#: (H2) is said to hold when min_m |lambda^m - 1| (m = 1..5) exceeds this
H2_TOL = 1e-6
#: base budget of orbit evaluations per scan, raised by SAMPLES_PER_CUT for every cut at a
#: singular frequency (each adds two segments to certify, with the orbit's folds between
#: them); past it nothing is split or sampled further and what is left is uncertified
MAX_SAMPLES = 20000
SAMPLES_PER_CUT = 40
#: at most this many singular frequencies omega_j / n (n >= 2) are cut, the largest ones:
#: they accumulate at omega = 0, and below the last one cut the scan does not go (that
#: region is reported uncertified).  Bounds the work and the events of a small omega_min
MAX_SINGULAR = 300
#: a located NS root is accepted only when ||lambda1|^2 - 1| there is below this (a jump
#: between two pairs, e.g. colliding off the circle, also changes the sign)
NS_RESIDUAL = 1e-6
#: (H3) is decided only when |d|lambda1|/domega| * omega_c exceeds this and its estimated
#: relative error is below H3_REL_ERR: a crossing of zero speed is not a crossing
H3_TOL = 1e-8
H3_REL_ERR = 0.1
#: an omega_j inside the interval cuts the scan this far (relative) on either side
RESONANCE_GAP = FORCING_RESONANCE_CUT
CONSERVATIVE = ("r = 1 and no damping: the map preserves volume (det DP = 1); multipliers "
                "lie on the unit circle over whole intervals and a Neimark-Sacker bifurcation "
                "(H3) cannot occur; no Neimark-Sacker point is reported (real multipliers "
                "through +1 or -1 still are)")
SAFETY = 2.0


# --------------------------------------------------------------------------- results
@dataclass(frozen=True)
class Event:
    """Something a sweep in omega meets (not a Hopf point)."""

    kind: str        # of symvi.continuation.result.EVENT_KINDS: multiplier+1, multiplier-1,
    #                  becomes-admissible, becomes-inadmissible, orbit-appears,
    #                  orbit-vanishes, singular, forcing-resonance, conservative,
    #                  unresolved, ns-unanalysable
    omega: float
    branch: str
    detail: str = ""
    span: tuple = None   # (lo, hi) for events that cover an interval
    coefficients: dict = None   # normal-form numbers of a multiplier through +/-1

    def __post_init__(self):
        # the one vocabulary of symvi.continuation.result (imported here: the package is
        # loaded by the scan's locator anyway, not at import time)
        from ..continuation.result import check_kind
        check_kind(self.kind)

    def as_dict(self):
        d = {"kind": self.kind, "omega": float(self.omega), "branch": self.branch,
             "detail": self.detail}
        if self.span is not None:
            d["span"] = [float(self.span[0]), float(self.span[1])]
        if self.coefficients is not None:
            d["coefficients"] = {k: (v if isinstance(v, str) else float(v))
                                 for k, v in self.coefficients.items()}
        return d


def spans_text(spans, limit=None):
    """Spans (lo, hi), e.g. :attr:`HopfResult.uncertified` or its JSON, as "[lo, hi], ..."
    to 10 significant digits; the first ``limit`` of them only, when given."""
    return ", ".join(f"[{lo:.10g}, {hi:.10g}]" for lo, hi in list(spans)[:limit])


def _budget_why(budget):
    return (f"the scan's budget of {budget} orbit evaluations ran out before this span was "
            "certified (the interval needs finer resolution elsewhere: scan a narrower "
            "interval); a crossing there may be missed")


_SWITCH = ("|lambda| - 1 changes sign by a jump between two complex pairs (pairs colliding "
           "off the unit circle, as near a conservative map), not by a crossing; a crossing "
           "there may be missed")


def _Unresolved(br, lo, hi, why=None):
    return Event("unresolved", 0.5 * (lo + hi), br,
                 f"multipliers within reach of the unit circle on [{lo:.12g}, {hi:.12g}] could "
                 "not be resolved (tangency, multipliers at +1 or a near-singular map); a "
                 "crossing there may be missed" if why is None else
                 f"on [{lo:.12g}, {hi:.12g}] {why}", (lo, hi))


@dataclass(frozen=True)
class HopfPoint:
    """A Neimark–Sacker point of an admissible period-1 orbit, with (H1)–(H3) and f1.

    ``dmod_domega`` is d|lambda1|/dv from F11 by eqs. (A1)–(A3);
    ``dmod_domega_branch`` by differentiating |lambda1| along the branch
    (Ridders' extrapolated central differences, first step ``BRANCH_H`` * omega), with its
    estimated error ``dmod_domega_branch_error`` (:attr:`branch_caveat` says when it is
    uncertain or disagrees with (A1)-(A3)).
    ``l1``: Kuznetsov, ||q||_2 = 1, <p,q> = 1, l1 < 0 stable.  The paper's f1 of
    eq. (60) (printed and corrected) belongs to its model:
    :class:`symvi.paper.hopf.PaperHopfPoint`.
    """

    omega_c: float
    branch: str
    multiplier: complex
    theta_over_2pi: float
    other_multipliers: tuple
    h1: bool
    h2: bool
    nearest_resonance: tuple        # (m, |lambda1^m - 1|)
    dmod_domega: float
    dmod_domega_branch: float
    dlam_domega: complex
    c1: complex
    l1: float
    orbit: object
    circle: object
    normal_form: object = field(repr=False, default=None)
    precision: object = field(repr=False, default=None)   # precision.HopfEstimate
    #: estimated absolute error of dmod_domega_branch (Ridders' tableau; inf: not computable)
    dmod_domega_branch_error: float = 0.0

    def trusted(self, name):
        """False when automatic precision could not make ``name`` trustworthy."""
        return self.precision is None or getattr(self.precision, name).trusted

    @property
    def kind(self):
        """'supercritical' (stable circle, l1 < 0), 'subcritical', or 'undetermined'
        when l1 cannot be trusted at any precision."""
        if not self.trusted("l1"):
            return "undetermined"
        return "supercritical" if self.l1 < 0 else "subcritical"

    @property
    def crossing_resolved(self):
        """Whether d|lambda1|/domega is resolvably nonzero (see :attr:`detail`): a zero-speed
        touch of |lambda1| = 1, e.g. of a nearly conservative map, is no transversal crossing."""
        return not self.detail

    @property
    def branch_caveat(self):
        """Why ``dmod_domega_branch`` does not confirm (A1)-(A3) to its printed digits, or ''.

        Its error is estimated by Ridders' tableau; near grazing, a fold or a singular
        frequency the branch varies on a scale below the steps (or its multipliers are
        ill-conditioned) and the estimate is large: the value is then uncertain."""
        v, e = self.dmod_domega_branch, self.dmod_domega_branch_error
        if not math.isfinite(v):
            return ("not computable along the branch (the branch is not defined on both "
                    "sides of omega_c)")
        if not math.isfinite(e):
            return ("uncertain along the branch: no error estimate (the branch is not "
                    "defined on both sides of omega_c at every step)")
        if e > BRANCH_REL_ERR * abs(v):
            return (f"uncertain along the branch: estimated error {e:.1e} (relative "
                    f"{e / max(abs(v), 1e-300):.1e}); the branch varies on a small scale "
                    "(near grazing, a fold, a collision of multipliers or a singular "
                    "frequency) or its multipliers are ill-conditioned")
        d = self.dmod_domega
        est = None if self.precision is None else self.precision.dmod_domega
        # Ridders' estimate is a heuristic and (A1)-(A3) has its own error: only a
        # disagreement beyond both and beyond BRANCH_REL_ERR is a caveat
        tol = 10 * e + BRANCH_REL_ERR * abs(d)
        if est is not None and math.isfinite(est.rel_err):
            tol += 10 * est.rel_err * abs(d)
        if self.trusted("dmod_domega") and math.isfinite(d) and abs(v - d) > tol:
            return (f"along the branch {v:.12g} differs from (A1)-(A3) by "
                    f"{abs(v - d) / max(abs(d), 1e-300):.1e} (relative), beyond both error "
                    "estimates")
        return ""

    @property
    def circle_caveat(self):
        """Why the invariant circle (normal form (58), l1 and d|lambda1|/domega) is not
        predicted here, or '' when its hypotheses hold: (H1) every other multiplier inside
        the unit circle, (H2) no resonance lambda1^m = 1 for m <= 5, a transversal
        crossing (resolved speed) and a trusted l1 != 0."""
        why = []
        if self.circle is None:
            why.append("no normal form")
        if not self.h1:
            lam = self.multiplier
            out = [z for z in self.other_multipliers if not abs(z) < 1]
            why.append("(H1) fails: " + (
                f"{len(out)} other multiplier(s) on or outside the unit circle" if out else
                f"|lambda1| - 1 = {abs(lam) - 1:.1e}, lambda1 not resolvably on the unit circle"
                if abs(lam.imag) > 1e-9 else "lambda1 is real"))
        if not self.h2:
            m, _ = self.nearest_resonance
            why.append(f"(H2) fails: lambda1^{m} = 1 (resonance 1:{m}), the cubic normal "
                       "form is not the normal form")
        if not self.crossing_resolved:
            why.append("the crossing speed d|lambda1|/domega is not resolved")
        if not self.trusted("l1") or not (math.isfinite(self.l1) and self.l1 != 0):
            why.append("l1 is not trusted or zero")
        return "; ".join(why)

    @property
    def h3(self):
        """(H3) as the paper states it: d|lambda1|/dv > 0 at v_c, and resolvably so."""
        return self.crossing_resolved and self.dmod_domega > 0

    @property
    def detail(self):
        """Why (H3) cannot be decided here, or '' when the crossing speed is resolved:
        trusted, |d|lambda1|/domega| * omega_c > H3_TOL, estimated relative error below
        H3_REL_ERR, and the same sign along the branch."""
        d, why = self.dmod_domega, ""
        est = None if self.precision is None else self.precision.dmod_domega
        if not self.trusted("dmod_domega") or not math.isfinite(d):
            why = "it cannot be trusted at any precision"
        elif abs(d) * abs(self.omega_c) <= H3_TOL:
            why = f"|d|lambda1|/domega| * omega_c <= {H3_TOL:g}"
        elif est is not None and not est.rel_err < H3_REL_ERR:
            why = f"its estimated relative error {est.rel_err:.1e} is not below {H3_REL_ERR:g}"
        elif not d * self.dmod_domega_branch > 0:
            why = f"along the branch it is {self.dmod_domega_branch:.3g}, of another sign"
        if not why:
            return ""
        return (f"(H3) not decided: d|lambda1|/domega = {d:.3g} is not resolvably nonzero "
                f"({why}); |lambda1| reaches 1 with no resolved speed, not a transversal "
                "crossing")

    def as_dict(self):
        m, dist = self.nearest_resonance
        from .precision import _json_float as _finite    # JSON has no inf / nan
        orb = self.orbit.as_dict()
        orb["omega"] = float(self.orbit.omega)
        num = lambda name: float(getattr(self, name)) if self.trusted(name) else None
        return {
            "omega_c": num("omega_c"), "branch": self.branch,
            "multiplier": [self.multiplier.real, self.multiplier.imag],
            "theta_over_2pi": float(self.theta_over_2pi),
            "other_multipliers": [[complex(x).real, complex(x).imag]
                                  for x in self.other_multipliers],
            "dmod_domega": num("dmod_domega"),
            "dmod_domega_branch": _finite(self.dmod_domega_branch),
            "dmod_domega_branch_error": _finite(self.dmod_domega_branch_error),
            "dmod_domega_branch_caveat": self.branch_caveat,
            "l1": num("l1"), "c1": [self.c1.real, self.c1.imag],
            # eq. (60) is the paper's own reduction: filled by its view (symvi.paper.hopf)
            "f1_paper": None, "f1_wan": None,
            "kind": self.kind, "h1": bool(self.h1), "h2": bool(self.h2), "h3": bool(self.h3),
            "crossing_resolved": bool(self.crossing_resolved), "detail": self.detail,
            "nearest_resonance": {"m": int(m), "distance": float(dist)},
            "orbit": orb,
            "circle": None if self.circle is None else self.circle.as_dict(),
            "circle_predicted": not self.circle_caveat, "circle_caveat": self.circle_caveat,
            "precision": None if self.precision is None else self.precision.as_dict(),
            "normalisation": {
                "l1": "Kuznetsov: ||q||_2 = 1, <p,q> = conj(p)^T q = 1, l1 = Re(e^{-i theta} c1),"
                      " l1 < 0 stable",
                "f1": "paper eqs. (58)-(60): ||r1||_2 = 1, z = y1 + i y2, f1 > 0 attracting; "
                      "f1_paper = eq. (60) as printed, f1_wan = eq. (60) corrected = -l1/4",
                "q_phase": "largest |q_k| real positive"},
        }


@dataclass(frozen=True)
class HopfResult:
    """All Hopf points and events of a scan of [omega_min, omega_max]."""

    params: object
    omega_min: float
    omega_max: float
    points: tuple
    events: tuple
    samples: int
    conservative: bool = False    # r = 1, no damping: no NS point is sought (CONSERVATIVE)
    #: merged, sorted (lo, hi) spans the scan could not certify (any branch): a crossing
    #: there may have been missed.  Empty: every crossing in the interval was found
    uncertified: tuple = ()
    #: a few words per distinct reason of those spans (their ``unresolved`` events say more)
    uncertified_reasons: tuple = ()

    @property
    def complete(self):
        """Whether the scan certified the whole interval (no crossing missed)."""
        return not self.uncertified

    def __iter__(self):
        return iter(self.points)

    def __len__(self):
        return len(self.points)

    def __getitem__(self, i):
        return self.points[i]

    def as_dict(self):
        return {**_system(self.params).as_dict(),
                "interval": [self.omega_min, self.omega_max],
                "points": [p.as_dict() for p in self.points],
                "events": [e.as_dict() for e in self.events],
                "samples": self.samples,
                "complete": self.complete,
                "uncertified": [[float(lo), float(hi)] for lo, hi in self.uncertified],
                "uncertified_reasons": list(self.uncertified_reasons),
                "conservative": self.conservative,
                "statement": CONSERVATIVE if self.conservative else None}


# --------------------------------------------------------------------------- systems
class _ModelSystem:
    """Any model (symvi.model.Model): period-1 orbits and jets of the any-model layers."""

    def __init__(self, model):
        from ..maps.section import Section
        self.params = self.model = model
        self.names = Section.of(model).names
        self.conservative = model.conservative       # r = 1 and C = 0 exactly

    def orbits(self, w):
        from ..orbits import period1_orbits
        return period1_orbits(self.model, w)

    def existence_ratio(self, w):
        from ..orbits import existence_ratio
        return existence_ratio(self.model, w)

    def undamped_frequencies(self):
        """Frequencies of the modes with no damping: there forcing is resonant and
        1 - cos(2 pi omega_j / omega) -> 0 makes the period-1 orbit non-isolated."""
        from ..flow.linear import LinearFlow
        lam = LinearFlow.of(self.model).lam
        return tuple(sorted(float(z.imag) for z in lam
                            if z.imag > 0 and abs(z.real) <= 1e-12 * abs(z)))

    def jet3(self, w, orbit):
        from ..codegen.jets import jet_at
        return jet_at(self.model, w, orbit.y, 2 * math.pi / w, 3)

    def accuracy(self, omega_c, branch, nf, jt):
        from .precision import estimate_model_hopf
        # the jet and normal form just computed are the base point: computed once
        return estimate_model_hopf(self.model, omega_c, branch, nf, jt)

    def as_dict(self):
        return {"model": self.params.as_dict()}


def _system(params):
    """The adapter of hopf_points: any Model (the paper's Params as its ``Model.luo_xie``,
    :meth:`symvi.Model.of`)."""
    from ..model import Model
    try:
        model = Model.of(params)
    except ParameterError:
        raise ParameterError("params", params, "a symvi.Model or the paper's symvi.Params") \
            from None
    return _ModelSystem(model)      # its own errors as they are (a model the flow refuses)


# --------------------------------------------------------------------------- sampling
_NONE, _INADM, _ADM, _SING = "none", "inadmissible", "admissible", "singular"


class _Sampler:
    """Order-1 evaluations (orbits + multipliers), cached; both branches per call."""

    def __init__(self, system):
        self.sys = system
        self.cache = {}

    def orbits(self, w):
        w = float(w)
        hit = self.cache.get(w)
        if hit is None:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", NearSingularWarning)
                try:
                    hit = {o.branch: o for o in self.sys.orbits(w)}
                except SingularCaseError as exc:
                    hit = exc
            self.cache[w] = hit
        return hit

    def state(self, br, w):
        """(kind, orbit or error)."""
        o = self.orbits(w)
        if isinstance(o, SingularCaseError):
            return _SING, o
        o = o.get(br)
        if o is None:
            return _NONE, None
        return (_ADM if o.admissible else _INADM), o


def _match(la, lb):
    """Permutation of lb closest to la (minimum total distance): the assignment
    problem, solved exactly in O(n^3) (2N multipliers: 8! permutations for N = 4)."""
    from scipy.optimize import linear_sum_assignment
    cost = np.abs(np.subtract.outer(np.asarray(la, dtype=complex), np.asarray(lb, dtype=complex)))
    rows, cols = linear_sum_assignment(cost)
    return [lb[j] for j in cols[np.argsort(rows)]]


# --------------------------------------------------------------------------- scan
class _Scan:
    def __init__(self, system, a, b, budget=MAX_SAMPLES):
        self.sys, self.a, self.b = system, a, b
        self.s = _Sampler(system)
        self.min_width = MIN_WIDTH * (b - a)
        self.delta = max(1e-10 * (b - a), 50 * XTOL)
        self.brackets = []     # (branch, kind, wl, wr, lam_l, lam_r)
        self.events = []
        self.unres = {}        # (branch, reason) -> spans not certified
        self.queue = deque()   # segments to certify: (branch, wa, wb, edges)
        self.budget = budget

    # ---- transitions -------------------------------------------------------
    def _event(self, kind, w, br, detail=""):
        self.events.append(Event(kind, float(w), br, detail))

    def _locate_kind_change(self, br, wa, wb):
        """Boundary between two states of different kinds on [wa, wb] (Brent / bisection)."""
        ka, oa = self.s.state(br, wa)
        kb, ob = self.s.state(br, wb)
        w = None
        if _SING not in (ka, kb) and _NONE in (ka, kb):
            def f(w):
                with warnings.catch_warnings():
                    # next to a cut at omega_j the forcing is expectedly near-singular
                    warnings.simplefilter("ignore", NearSingularWarning)
                    try:
                        return abs(self.sys.existence_ratio(w)) - 1
                    except SingularCaseError:
                        return math.nan
            w = _brent(f, wa, wb)
            why = "|alpha b / rho| of eq. (16) reaches 1: the two branches merge (fold)"
        elif {ka, kb} == {_ADM, _INADM}:
            bad = oa if ka == _INADM else ob
            if "impact velocity" in bad.reason:
                def fv(w):
                    k, o = self.s.state(br, w)
                    return float(o.impact_velocity) if k in (_ADM, _INADM) else math.nan
                w = _brent(fv, wa, wb)
                why = "impact velocity through 0"
        if w is not None:
            return w, why
        # generic: bisection on the kind
        lo, hi = wa, wb
        while hi - lo > XTOL + 4e-16 * abs(hi):
            mid = 0.5 * (lo + hi)
            if mid in (lo, hi):
                break
            if self.s.state(br, mid)[0] == ka:
                lo = mid
            else:
                hi = mid
        why = ""
        for w_ in (lo, hi):
            k, o = self.s.state(br, w_)
            if k == _SING:
                why = str(o)
            elif o is not None and o.reason:
                why = o.reason
        return 0.5 * (lo + hi), why

    def _transition(self, br, wa, wb, ka, kb):
        w, why = self._locate_kind_change(br, wa, wb)
        names = {(_NONE, _ADM): "orbit-appears", (_NONE, _INADM): "orbit-appears",
                 (_ADM, _NONE): "orbit-vanishes", (_INADM, _NONE): "orbit-vanishes",
                 (_INADM, _ADM): "becomes-admissible", (_ADM, _INADM): "becomes-inadmissible"}
        kind = names.get((ka, kb), "singular")
        if kind == "orbit-appears" and kb == _INADM:
            why += " (inadmissible)"
        self._event(kind, w, br, why)
        return w

    def _unresolved(self, br, wa, wb, why=None):
        """Record a span the certification could not resolve (merged with its neighbours of
        the same reason by :meth:`unresolved_events`)."""
        self.unres.setdefault((br, why), []).append((float(wa), float(wb)))

    def unresolved_events(self):
        """One ``unresolved`` event per maximal run of spans of one branch and reason."""
        out = []
        for (br, why), spans in self.unres.items():
            for lo, hi in _merge(spans, self.min_width):
                out.append(_Unresolved(br, lo, hi, why))
        return out

    def uncertified(self):
        """The merged, sorted spans where a crossing may have been missed (any branch)."""
        return _merge([sp for spans in self.unres.values() for sp in spans], self.min_width)

    @property
    def exhausted(self):
        return len(self.s.cache) >= self.budget

    # ---- certification -----------------------------------------------------
    def certify(self, br, wa, wb, edges=(False, False)):
        """Certify [wa, wb] on branch ``br``; collect crossing brackets and events."""
        self.queue.append((br, wa, wb, tuple(edges)))
        self.run()

    def run(self):
        """Certify every queued segment, breadth first across all segments and branches.

        ``edges``: whether the left / right end lies next to a located boundary (fold,
        grazing, singular frequency), where a multiplier may approach the circle.  Breadth
        first, so that a budget that runs out leaves uncertified the spans needing the finest
        resolution, not the end of the interval scanned last; what is left is reported."""
        q = self.queue
        while q:
            br, wa, wb, (ea, eb) = q.popleft()
            if self.exhausted:
                self._unresolved(br, wa, wb, _budget_why(self.budget))
                continue
            ka, oa = self.s.state(br, wa)
            kb, ob = self.s.state(br, wb)
            if ka != kb:
                w = self._transition(br, wa, wb, ka, kb)
                # keep scanning the inner parts, a safe distance from the boundary
                left, right = w - self.delta, w + self.delta
                if left > wa + self.delta:
                    q.append((br, wa, left, (ea, True)))
                if right < wb - self.delta:
                    q.append((br, right, wb, (True, eb)))
                continue
            wm = 0.5 * (wa + wb)
            km, om = self.s.state(br, wm)
            halves = [(br, wa, wm, (ea, False)), (br, wm, wb, (False, eb))]
            if km != ka:
                q.extend(halves)
                continue
            if ka != _ADM:
                # nothing to follow; split while the pieces are coarse, to catch a short
                # admissible (or existing) stretch between two samples
                if wb - wa > (self.b - self.a) / (4 * N_INITIAL):
                    q.extend(halves)
                continue
            if not self._accept(br, (wa, wm, wb), (oa, om, ob), (ea, eb)):
                if wb - wa > self.min_width:
                    q.extend(halves)
                else:
                    self._unresolved(br, wa, wb)

    def _accept(self, br, ws, orbits, edges):
        """Certify one segment from its ends and midpoint (see the module docstring)."""
        if self.sys.conservative:
            return self._accept_conservative(br, ws, orbits, edges)
        wa, wm, wb = ws
        la = [complex(x) for x in orbits[0].multipliers]
        lm = _match(la, [complex(x) for x in orbits[1].multipliers])
        lb = _match(lm, [complex(x) for x in orbits[2].multipliers])
        found = []
        for za, zm, zb in zip(la, lm, lb):
            ma, mm, mb = abs(za), abs(zm), abs(zb)
            # deviation of |lambda| from the chord; 1e-13: the noise of the eigenvalues
            tol = SAFETY * abs(mm - 0.5 * (ma + mb)) + 1e-13
            sa, sm, sb = ma > 1, mm > 1, mb > 1
            if sa == sm == sb:
                dist = (abs(ma - 1), abs(mm - 1), abs(mb - 1))
                if min(dist) > tol:
                    continue
                # next to a boundary a multiplier may approach the circle (e.g. +1 at a
                # fold, where the orbit ends): accept a monotone approach towards that end
                if edges[1] and dist[0] > dist[1] > dist[2]:
                    continue
                if edges[0] and dist[0] < dist[1] < dist[2]:
                    continue
                return False
            if sa != sm and sm != sb:
                return False                     # two crossings: split
            if sa != sm:
                z0, z1, w0, w1, rest = za, zm, wa, wm, mb
            else:
                z0, z1, w0, w1, rest = zm, zb, wm, wb, ma
            if abs(rest - 1) <= tol or abs(abs(z1) - abs(z0)) <= tol:
                return False
            real0, real1 = abs(z0.imag) < 1e-9, abs(z1.imag) < 1e-9
            if real0 and real1:
                kind = "multiplier+1" if z0.real + z1.real > 0 else "multiplier-1"
            elif not real0 and not real1:
                if z0.imag < 0:
                    continue                     # the conjugate reports it
                kind = "ns"
            else:
                return False                     # collision inside: split
            found.append((br, kind, w0, w1, z0, z1))
        self.brackets.extend(found)
        return True

    def _accept_conservative(self, br, ws, orbits, edges):
        """Certify one segment of a conservative model from det(J -/+ I) at its three samples.

        det DP = 1: multipliers on the unit circle stay on it over whole intervals, so
        |lambda| - 1 certifies nothing (its sign is rounding noise).  They leave the
        circle through +1 or -1, where a pair meets and splits into mu, 1/mu and
        det(J -/+ I) = prod(lambda -/+ 1) changes sign: the polyline test of the module
        docstring, applied to these two scalars (a complex pair never yields a bracket).
        """
        found = []
        for kind, sgn in (("multiplier+1", 1.0), ("multiplier-1", -1.0)):
            ls = [[complex(x) for x in o.multipliers] for o in orbits]
            g = [float(np.prod([x - sgn for x in l]).real) for l in ls]
            # 1e-12: rounding of a product of 2N factors of size 1 + |lambda|
            noise = 1e-12 * max(float(np.prod([1 + abs(x) for x in l])) for l in ls)
            tol = SAFETY * abs(g[1] - 0.5 * (g[0] + g[2])) + noise
            sides = [x > 0 for x in g]
            if sides[0] == sides[1] == sides[2]:
                dist = [abs(x) for x in g]
                if min(dist) > tol:
                    continue
                # towards a located boundary (a fold: the pair at +1) a monotone approach is fine
                if (edges[1] and dist[0] > dist[1] > dist[2]) or \
                        (edges[0] and dist[0] < dist[1] < dist[2]):
                    continue
                return False
            if sides[0] != sides[1] and sides[1] != sides[2]:
                return False                     # two crossings: split
            i = 0 if sides[0] != sides[1] else 1
            rest = g[2] if i == 0 else g[0]
            if abs(rest) <= tol or abs(g[i + 1] - g[i]) <= tol:
                return False
            z0, z1 = (min(l, key=lambda x: abs(x - sgn)) for l in (ls[i], ls[i + 1]))
            found.append((br, kind, ws[i], ws[i + 1], z0, z1))
        self.brackets.extend(found)
        return True

    # ---- location ----------------------------------------------------------
    def locate(self, bracket):
        """The special point of a certified bracket, located by the continuation's locator
        (:func:`symvi.continuation.locate.locate_between`, one owner for every branch):
        a SpecialPoint, or None when the sign change was no crossing (a jump between two
        complex pairs, a neutral saddle); a failure of the locator is raised."""
        from ..continuation.locate import locate_between
        br, kind, w0, w1, z0, z1 = bracket

        def between(wa, wb):
            (ka, oa), (kb, ob) = self.s.state(br, wa), self.s.state(br, wb)
            if oa is None or ob is None or _SING in (ka, kb):
                raise SymviError(f"branch {br} lost at the ends of [{wa!r}, {wb!r}]")
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", NearSingularWarning)
                return locate_between(self.sys.model, kind, oa, ob, coefficients=False)
        try:
            sp = between(w0, w1)
        except SymviError:
            if kind != "ns":
                raise
            # no sign change of the bialternate product: a jump between two pairs, or the
            # crossing at an end of the bracket itself (a sample landing on it); widen a little
            eps = 1e-3 * (w1 - w0)
            try:
                sp = between(w0 - eps, w1 + eps)
            except SymviError:
                return None
            w0, w1 = w0 - eps, w1 + eps
        if sp is None or not w0 - XTOL <= sp.value <= w1 + XTOL:
            return None
        if kind == "ns":
            mods = [abs(abs(complex(z)) ** 2 - 1) for z in sp.orbit.multipliers
                    if abs(complex(z).imag) > 1e-9]
            if not mods or min(mods) >= NS_RESIDUAL:
                return None
        return sp


def _brent(f, a, b):
    """Brent's method when f is finite with opposite signs at a and b, else None."""
    fa, fb = f(a), f(b)
    if not (math.isfinite(fa) and math.isfinite(fb)) or fa * fb > 0:
        return None
    from scipy.optimize import brentq     # ~0.1 s to import: only when a boundary is located
    try:
        return brentq(f, a, b, xtol=XTOL, rtol=4 * EPS64, maxiter=200)
    except (ValueError, RuntimeError):
        return None


def _lam_near(system, orbit_branch, w, target):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        o = {x.branch: x for x in system.orbits(w)}[orbit_branch]
    return min((complex(x) for x in o.multipliers), key=lambda x: abs(x - target))


def dmod_along_branch(params, omega, branch, lam, h=None, dlam=0j, domega=0.0, ref=None):
    """d|lambda1|/domega along the branch and a bound on its error: (value, error).

    The value is independent of eqs. (A1)-(A3): only orbits and eigenvalues at
    omega +/- h, the multiplier followed from ``lam`` at omega along
    ``lam + dlam (w - omega)``.  Ridders' extrapolation of central differences (Numerical
    Recipes, dfridr, :func:`_ridders`), twice, from h and 0.37 h: the error is the larger of
    the better tableau's estimate and the two results' difference, times ``RIDDERS_SAFETY``
    (each estimate is biased low, as the smallest of many; with pseudo-random rounding
    noise of 1e-13..1e-6 on |lambda1| the actual error reached 0.5 of this,
    tests/analysis/test_branch_derivative.py), plus 2 |d2|lambda1|/domega2| ``domega`` for an
    omega known to +/- ``domega`` (d2 from the evaluations the tableau made).

    ``ref`` = (value, absolute error) of an independent value, (A1)-(A3)'s: when the
    first tableau's own estimate is below 1e-9 relative, ``ref`` is no less precise and
    agrees with it within that estimate, two independent methods agree and the second
    tableau is skipped (the truth is within twice that estimate of the value, 1/5 of the
    error returned); otherwise the second cross-checks the first exactly as without
    ``ref``.  The value returned is the first tableau's either way, never ``ref``'s, and
    the same as without ``ref`` whenever the first tableau is chosen there.  (Example 1:
    8 evaluations of |lambda1| instead of 23, one tableau of 4 rows; stopping it at the
    row that ``ref`` confirms would save 2 more but change the value's 11th digit.)

    h is ``BRANCH_H`` * omega first, or less so that lambda moves by 1e-3 at most (``dlam``
    sets the scale only); unless the error is then below 1e-9 relative it is divided by
    10, five times at most (the branch varies on a smaller scale, or is not defined that
    far, next to a fold, grazing, a collision of multipliers or a singular frequency
    omega_j / n), each result's error raised to its distance from the results at the
    neighbouring steps, and the result of smallest error is returned; (nan, inf) when no
    step works.  (Hypothesis seed 2 found a point next to a collision of two pairs where
    a consistent-looking pair of steps was 0.47 % off: tests/analysis/test_branch_derivative.)"""
    system = params if isinstance(params, _ModelSystem) else _system(params)
    omega = float(omega)
    seen = {}                  # |lambda1| at each w evaluated: the d2 term reuses them

    def m(w):
        v = seen.get(w)
        if v is None:
            v = seen[w] = abs(_lam_near(system, branch, w, lam + dlam * (w - omega)))
        return v

    def central(h):
        return (m(omega + h) - m(omega - h)) / (2 * h)

    def confirmed(d, e):
        # (A1)-(A3) at least as precise, and within the tableau's estimate of it
        rv, re = ref
        return (math.isfinite(d) and e <= 1e-9 * abs(d) and math.isfinite(rv)
                and re <= e and abs(d - rv) <= e)

    def twice(h):
        d1, e1 = _ridders(central, h)
        if ref is not None and confirmed(d1, e1):
            return d1, e1
        # two tableaus from incommensurate first steps: an accidental agreement inside one
        # (which makes its own estimate too small) does not repeat in the other
        d2, e2 = _ridders(central, h * 0.37)
        return (d1 if e1 <= e2 else d2), max(min(e1, e2), abs(d1 - d2))
    h = BRANCH_H * omega if h is None else float(h)
    if abs(dlam) > 0:
        # lambda moves by at most 1e-3 over the first step: a steep branch (next to a
        # collision of multipliers) is smooth on a small scale only, and the multiplier
        # followed must stay the same one
        h = min(h, 1e-3 / abs(dlam))
    tries = []                 # (value, error, step), steps falling by 10
    best = (math.nan, math.inf, h)
    for k in range(6):
        try:
            d, e = twice(h)
        except (SymviError, KeyError):
            d, e = math.nan, math.inf
        tries.append((d, e, h))
        best = tries[0] if k == 0 else _cross_checked(tries)
        if best[1] <= 1e-9 * abs(best[0]):
            break
        h /= 10
    best_h = best[2]
    err = RIDDERS_SAFETY * best[1]
    if domega > 0 and math.isfinite(err):
        # omega itself known to +/- domega: the derivative there moves by |m''| domega;
        # m'' from the even parts at the tableau's first two steps (evaluated already):
        # m(w + h) + m(w - h) = 2 m(w) + m'' h^2 + O(h^4)
        h2 = best_h / 1.4
        try:
            m2 = ((m(omega + best_h) + m(omega - best_h)) - (m(omega + h2) + m(omega - h2))) \
                / (best_h ** 2 - h2 ** 2)
            err += 2 * abs(m2) * domega
        except (SymviError, KeyError):
            err = math.inf
    return best[0], err


def _cross_checked(tries):
    """The result of smallest error, each error raised to its distance from the nearer of
    the results at the neighbouring steps: a tableau can be consistent and wrong (at a
    step where the multiplier followed jumps to another, or the branch bends), two
    neighbouring steps agreeing by accident are unlikely."""
    out = []
    for j, (d, e, h) in enumerate(tries):
        near = [abs(d - x) for x, _, _ in (tries[j - 1:j] + tries[j + 1:j + 2])
                if math.isfinite(x)]
        out.append((d, max(e, min(near, default=math.inf)), h))
    return min(out, key=lambda t: t[1] if math.isfinite(t[0]) else math.inf)


def _ridders(central, h, con=1.4, ntab=10, safe=2.0):
    """Ridders' tableau on central(h), central(h/con), ...: (best value, its error).

    The error is the tableau's own estimate (a heuristic: consecutive entries that agree by
    accident make it too small; :func:`dmod_along_branch` cross-checks two tableaus, or
    the value with an independent one)."""
    con2 = con * con
    prev = [central(h)]
    best, err = prev[0], math.inf
    for i in range(1, ntab):
        h /= con
        row = [central(h)]
        fac = con2
        for j in range(1, i + 1):
            row.append((row[j - 1] * fac - prev[j - 1]) / (fac - 1))
            fac *= con2
            e = max(abs(row[j] - row[j - 1]), abs(row[j] - prev[j - 1]))
            if e <= err:
                best, err = row[j], e
        if abs(row[i] - prev[i - 1]) >= safe * err:
            break                     # higher orders only amplify rounding now
        prev = row
    return best, err


def hopf_point(params, omega_c, branch, *, sampler=None):
    """All of issue 4's quantities at a located Neimark–Sacker point (order-3 jet there)."""
    system = _system(params)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        orbit = {o.branch: o for o in system.orbits(omega_c)}[branch]
        j = system.jet3(omega_c, orbit)
        nf = normal_form(j.jacobian, j.d2, j.d3, j.dA, names=system.names)
    lam = complex(nf.lam)
    others = tuple(sorted((complex(x) for i, x in enumerate(nf.multipliers)
                           if i not in (_index_of(nf, lam), _index_of(nf, lam.conjugate()))),
                          key=lambda z: -abs(z)))
    h1 = abs(abs(lam) - 1) < 1e-9 and abs(lam.imag) > 1e-9 and all(abs(z) < 1 for z in others)
    m, dist = resonance(lam)
    # error estimates; recomputed in mpmath when float64 gives < 8 digits
    acc = system.accuracy(omega_c, branch, nf, j)
    if acc.omega_c.recomputed and acc.trusted:
        omega_c = float(acc.omega_c)
    dmod = float(acc.dmod_domega) if acc.dmod_domega.recomputed and acc.dmod_domega.trusted \
        else float(nf.dmod_dv)
    l1 = float(acc.l1) if acc.l1.recomputed and acc.l1.trusted else float(nf.l1)
    # at the reported omega_c, and for its uncertainty (a derivative at the true omega_c)
    rel = acc.omega_c.rel_err
    # (A1)-(A3)'s value with its error (inf when untrusted): when the first tableau
    # agrees with it within its own small estimate, the second is not needed
    est = acc.dmod_domega
    ref_err = abs(dmod) * est.rel_err if est.trusted and math.isfinite(est.rel_err) \
        else math.inf
    dbranch, dbranch_err = dmod_along_branch(
        system, omega_c, branch, lam, dlam=complex(nf.dlam_dv),
        domega=abs(omega_c) * rel if math.isfinite(rel) else 0.0, ref=(dmod, ref_err))
    return HopfPoint(
        omega_c=float(omega_c), branch=branch, multiplier=lam,
        theta_over_2pi=float(nf.theta) / (2 * math.pi), other_multipliers=others, h1=bool(h1),
        h2=bool(dist > H2_TOL), nearest_resonance=(m, float(dist)),
        dmod_domega=dmod, dmod_domega_branch=float(dbranch),
        dmod_domega_branch_error=float(dbranch_err),
        dlam_domega=complex(nf.dlam_dv), c1=complex(nf.c1), l1=l1,
        orbit=orbit, circle=nf.circle, normal_form=nf, precision=acc)


def _index_of(nf, z):
    return min(range(len(nf.multipliers)), key=lambda i: abs(complex(nf.multipliers[i]) - z))


def _check_interval(system, omega_min, omega_max):
    """Validated (a, b).  An end closer than RESONANCE_GAP / 2 (relative) to a natural
    frequency omega_j is refused: the response is infinite there (half the gap, so that
    an end at omega_j (1 +/- RESONANCE_GAP), where a cut scan stops, is accepted).  An
    omega_j further inside is cut instead (:func:`hopf_points`)."""
    for name, w in (("omega_min", omega_min), ("omega_max", omega_max)):
        try:
            w = float(w)
        except (TypeError, ValueError):
            raise ParameterError(name, w, f"a real number, {OMEGA_RANGE[0]:g} <= {name} <= "
                                          f"{OMEGA_RANGE[1]:g}") from None
        if not (math.isfinite(w) and OMEGA_RANGE[0] <= w <= OMEGA_RANGE[1]):
            # checked before any work: the orbit code refuses omega outside this range
            raise ParameterError(name, w, f"{OMEGA_RANGE[0]:g} <= {name} <= {OMEGA_RANGE[1]:g}")
    a, b = float(omega_min), float(omega_max)
    if not b > a:
        raise ParameterError("omega_max", omega_max, f"omega_max > omega_min = {a!r}")
    for j, wj in enumerate(system.undamped_frequencies(), start=1):
        for name, w in (("omega_min", a), ("omega_max", b)):
            if abs(w - wj) < 0.5 * RESONANCE_GAP * wj:
                raise SingularCaseError(
                    "forcing-resonance",
                    f"{name} = {w!r} is at the natural frequency omega_{j} = {wj:.12g} "
                    f"(relative distance < {0.5 * RESONANCE_GAP:g}), where the forcing amplitude "
                    f"of eq. (7) is infinite; move that end away from it (an omega_{j} strictly "
                    "inside the interval is cut there and reported)")
    return a, b


def hopf_points(params, omega_min, omega_max):
    """Every Neimark–Sacker point of an admissible period-1 orbit in [omega_min, omega_max].

    Returns a :class:`HopfResult`: ``points`` (each a :class:`HopfPoint` with
    the normal form and the predicted circle) sorted by omega, and ``events``
    (real multipliers through +/-1, admissibility changes, orbit appearing or
    vanishing, natural frequencies where the branches are cut).  See the module
    docstring for why no crossing is missed, and ``uncertified`` (empty: ``complete``) for
    the spans where one may have been (a budget that ran out, a span not scanned).  A
    conservative model (r = 1, no damping) has no Neimark–Sacker point: ``conservative``
    is set, an event of that kind spans the interval and only the other events are
    reported.  Both ends must lie in ``OMEGA_RANGE`` (checked before any work).
    """
    system = _system(params)
    a, b = _check_interval(system, omega_min, omega_max)
    # eq. (15) divides by 1 - cos(2 pi omega_j / omega): the orbit is not isolated at
    # omega = omega_j / n; those points cut the scan and are reported.  At n = 1 the
    # forcing of eq. (7) itself is infinite: cut wider (RESONANCE_GAP).  The omega_j / n
    # accumulate at 0: only the MAX_SINGULAR largest are cut, below them nothing is scanned
    sing, floor = _singular_frequencies(system, a, b)
    scan = _Scan(system, a, b, MAX_SAMPLES + SAMPLES_PER_CUT * len(sing))
    start = a
    if floor is not None:
        w, count = floor
        start = w + _sing_gap(w)
        for br in ("+", "-"):
            scan._unresolved(br, a, start, _floor_why(w, count))
    gaps = {}
    for w, what in sing:
        scan._event("singular", w, "", what)
        gaps[w] = _sing_gap(w)
    for w, what in _resonant_frequencies(system, a, b):
        scan._event("forcing-resonance", w, "", what)
        if w > start:
            gaps[w] = RESONANCE_GAP * w
    # a uniform cut inside a gap would start a segment there, unflagged: drop it
    grid = [w for w in np.linspace(start, b, N_INITIAL + 1).tolist()
            if w in (start, b) or all(abs(w - c) > 2 * g for c, g in gaps.items())]
    cuts = sorted(set(grid) | set(gaps))
    pieces = []
    for br in ("+", "-"):
        for wa, wb in zip(cuts[:-1], cuts[1:]):
            ea, eb = wa in gaps, wb in gaps
            lo = wa + gaps[wa] if ea else wa
            hi = wb - gaps[wb] if eb else wb
            if hi > lo:
                scan.queue.append((br, lo, hi, (ea, eb)))
                pieces.append((br, lo, hi, wa if ea else None, wb if eb else None))
            else:
                # two cuts closer than their gaps: nothing between them is scanned
                c = wa if ea else wb
                scan._unresolved(br, wa, wb, _gap_why(c, gaps[c]))
    scan.run()
    # within a gap the orbit is not scanned: uncertified where the branch is admissible at
    # the gap's edge, or that edge was never sampled (budget)
    for br, lo, hi, cut_lo, cut_hi in pieces:
        for w, edge in ((lo, cut_lo), (hi, cut_hi)):
            if edge is None:
                continue
            k = scan.s.state(br, w)[0] if w in scan.s.cache else None
            if k in (None, _ADM):
                g = gaps[edge]
                scan._unresolved(br, edge - g, edge + g, _gap_why(edge, g))
    points, seen = [], []
    i = 0
    while i < len(scan.brackets):
        br_ = scan.brackets[i]
        i += 1
        try:
            sp = scan.locate(br_)
        except SymviError as exc:
            scan.events.append(Event(br_[1], 0.5 * (br_[2] + br_[3]), br_[0],
                                     f"a real multiplier crosses "
                                     f"{'+1' if br_[1] == 'multiplier+1' else '-1'} in this "
                                     f"span, not located: {exc}", (br_[2], br_[3])))
            continue
        w = None if sp is None else sp.value
        if w is None:
            # no root: certify the bracket's half anew, finer (brackets are appended)
            if br_[3] - br_[2] <= scan.min_width:
                scan._unresolved(br_[0], br_[2], br_[3], _SWITCH)
            elif scan.exhausted:
                scan._unresolved(br_[0], br_[2], br_[3], _budget_why(scan.budget))
            else:
                scan.certify(br_[0], br_[2], br_[3])
            continue
        if br_[1] == "ns":
            if any(br == br_[0] and abs(w - x) < 1e-9 * (b - a) for br, x in seen):
                continue
            seen.append((br_[0], w))
            try:
                points.append(hopf_point(params, w, br_[0]))
            except SymviError as exc:
                # the crossing is there, but the map is (nearly) singular: say so
                scan._event("ns-unanalysable", w, br_[0], f"complex pair through |lambda| = 1, "
                            f"normal form not computable: {exc}")
        else:
            scan.events.append(Event(br_[1], float(w), br_[0], sp.detail, None,
                                     dict(sp.coefficients)))
    if system.conservative:
        # said once, over the whole interval; no "ns" bracket was formed
        scan.events.append(Event("conservative", a, "", CONSERVATIVE, (a, b)))
    events = tuple(sorted(_dedupe(scan.events + scan.unresolved_events()),
                          key=lambda e: (e.omega, e.branch)))
    return HopfResult(params, a, b, tuple(sorted(points, key=lambda p: (p.omega_c, p.branch))),
                      events, len(scan.s.cache), bool(system.conservative),
                      tuple(scan.uncertified()),
                      tuple(sorted({_why_short(why) for _, why in scan.unres})))


def _resonant_frequencies(system, a, b):
    """The natural frequencies omega_j of undamped modes strictly inside (a, b), eq. (7)."""
    return [(wj, f"natural frequency omega_{j} of an undamped mode: the forcing amplitude of "
                 f"eq. (7) and the steady-state response are infinite; the branches are cut "
                 f"here and scanned on both sides up to a relative distance {RESONANCE_GAP:g}")
            for j, wj in enumerate(system.undamped_frequencies(), start=1) if a < wj < b]


def _singular_frequencies(system, a, b, cap=None):
    """The omega_j / n (n >= 2) of the undamped modes inside (a, b), at most ``cap``
    (default MAX_SINGULAR), the largest: ([(omega, description)], floor).

    ``floor`` is None when every one is listed, else (the largest omega_j / n left out,
    how many are left out).  Counted in closed form first, so that a tiny ``a`` (where they
    accumulate) costs no more than ``cap`` of them."""
    cap = MAX_SINGULAR if cap is None else cap
    cand, total = [], 0
    for j, wj in enumerate(system.undamped_frequencies(), start=1):
        n_lo = max(2, math.floor(wj / b) + 1)              # omega_j / n < b
        q = wj / a
        n_hi = math.ceil(q) - 1 if math.isfinite(q) else math.inf    # omega_j / n > a
        if n_hi < n_lo:
            continue
        total += n_hi - n_lo + 1
        for n in range(n_lo, int(min(n_hi, n_lo + cap)) + 1):
            w = wj / n
            if a < w < b:
                cand.append((w, j, n))
    cand.sort(reverse=True)
    out = [(w, f"omega_{j} / omega = {n}: 1 - cos(2 pi omega_{j} / omega) = 0 in eq. (15), "
               "the period-1 orbit is not isolated") for w, j, n in cand[:cap]]
    floor = (cand[cap][0], total - cap) if len(cand) > cap else None
    return sorted(out), floor


def _floor_why(w, count):
    c = f"{count:.3g}" if count > 1e15 else str(count)
    return (f"below omega = {w:.12g} the singular frequencies omega_j / n accumulate ({c} more "
            f"of them); only the {MAX_SINGULAR} largest are cut and this span is not scanned; "
            "a crossing there may be missed (scan a part of it on its own)")


def _gap_why(w, gap):
    return (f"within a relative distance {gap / w:.3g} of the singular frequency {w:.12g} the "
            "orbit is not scanned, and the branch is admissible at the edge of that gap; a "
            "crossing there may be missed")


def _why_short(why):
    """A few words for the headline, from the detail of an ``unresolved`` span."""
    if why is None:
        return "multipliers at the unit circle not resolved (tangency, +1, near-singular map)"
    for start, short in (("the scan's budget", "orbit-evaluation budget ran out"),
                         ("below omega", "singular frequencies omega_j / n accumulate"),
                         ("within a relative", "next to a singular frequency"),
                         ("|lambda| - 1", "a jump between complex pairs")):
        if why.startswith(start):
            return short
    return why


def _sing_gap(w):
    # the orbit code refuses |sin(pi omega_j / omega)| < 1e-9; stay well clear of that
    return 1e-7 * w


def _merge(spans, tol=0.0):
    """Sorted union of the spans [lo, hi], joining those less than ``tol`` apart."""
    out = []
    for lo, hi in sorted(spans):
        if out and lo <= out[-1][1] + tol:
            out[-1][1] = max(out[-1][1], hi)
        else:
            out.append([lo, hi])
    return [(lo, hi) for lo, hi in out]


def _dedupe(events):
    out, seen = [], set()
    for e in events:
        key = (e.kind, e.branch, round(e.omega, 9))
        if key not in seen:
            seen.add(key)
            out.append(e)
    return out
