"""Codimension-two points on fold, flip and NS curves: test functions, location, normal forms.

With mu the multipliers at a curve point, the critical ones (the pair of an NS curve,
followed by continuity; -1 on a flip curve, +1 on a fold curve) and the others:

NS curve, kappa = (mu_1 + mu_2) / 2 of the pair (cos theta while |kappa| < 1):

* R1: kappa - 1, R2: kappa + 1, R3: kappa + 1/2, R4: kappa  (lambda^m = 1, m = 1..4);
* CH (Chenciner): l1, on the NS part only;
* LPNS: prod(others - 1), PDNS: prod(others + 1), NSNS: prod_{i<j}(others_i others_j - 1).

Flip curve: R2: prod(others + 1); LPPD (fold-flip): prod(others - 1);
PDNS: prod_{i<j}(others_i others_j - 1); GPD (degenerate flip): c.
Fold curve: R1: prod(others - 1); LPPD: prod(others + 1); LPNS: prod_{i<j}(...); CP: a.

A sign change between two points is located by Brent's method along the arclength
(:func:`symvi.continuation.engine.root_on_arc`); a zero of a pair product that turns
out real (a neutral saddle) is dropped.  Admissibility lost between two points ends
the curve; the grazing (an impact velocity through 0, or a flight touching the stop)
is located the same way.  Normal-form coefficients come from :mod:`symvi.normal_forms.codim2`
(Kuznetsov & Meijer 2005; ||q||_2 = 1, <p, q> = 1 throughout).
"""
import numpy as np

from ..continuation import engine
from ..continuation.engine import sign_change
from .._deprecated import moved_names as _moved_names
from ..errors import SymviError
from ..normal_forms.normal_form import flip_coefficient, fold_coefficient
from ..orbits.periodic import orbit_of
from .points import Codim2Point, first_lyapunov, mono
from .system import kappa_pair

#: what each curve kind tests for
TESTS = {"ns": ("R1", "R2", "R3", "R4", "CH", "LPNS", "PDNS", "NSNS"),
         "flip": ("R2", "LPPD", "PDNS", "GPD"),
         "fold": ("R1", "LPPD", "LPNS", "CP")}
#: a located zero is kept when its test function is this small (relative)
ACCEPT = 1e-6


def _others(mu, crit):
    """The multipliers other than the critical ones (each removed once, nearest match)."""
    rest = list(mu)
    for c in crit:
        k = int(np.argmin([abs(z - c) for z in rest]))
        rest.pop(k)
    return np.array(rest)


def _pair_prod(z):
    iu = np.triu_indices(len(z), 1)
    if len(iu[0]) == 0:
        return None
    return float(np.prod(z[iu[0]] * z[iu[1]] - 1).real)


class Codim2Tracker(engine.Tracker):
    """The codimension-two test functions along a curve, and the location of their zeros."""

    # ---- test functions -----------------------------------------------------------
    def critical(self, mu, prev):
        kind = self.system.kind
        if kind == "ns":
            pair = kappa_pair(mu, prev)[1]
            return pair, (pair[0], pair[1])
        target = -1.0 if kind == "flip" else 1.0
        c = min(mu, key=lambda z: abs(z - target) + (0 if prev is None else abs(z - prev[0])))
        return (complex(c), complex(c)), (c,)

    def psi(self, X, pt=None, prev=None, need=None):
        """The test functions at X (from ``pt`` when it is the point's :class:`CurvePoint`)."""
        kind = self.system.kind
        if pt is not None:
            mu, pair = np.array(pt.orbit.multipliers), pt._pair
            crit = pair if kind == "ns" else (pair[0],)
        else:
            mu = np.linalg.eigvals(self._mono(X))
            pair, crit = self.critical(mu, prev)
        others = _others(mu, crit)
        out = {"_pair": pair}
        if kind == "ns":
            kappa = float(((pair[0] + pair[1]) / 2).real)
            out.update(R1=kappa - 1, R2=kappa + 1, R3=kappa + 0.5, R4=kappa)
            if need in (None, "CH"):
                on = abs(kappa) < 1 and abs(pair[0].imag) > 1e-12
                l1, noise = ((pt.l1, pt.l1_noise) if pt is not None else
                             self._l1(X, pair[0])) if on else (None, None)
                out["CH"] = l1
                out["_noise"] = noise
            out["LPNS"] = float(np.prod(others - 1).real) if len(others) else None
            out["PDNS"] = float(np.prod(others + 1).real) if len(others) else None
            out["NSNS"] = _pair_prod(others)
        else:
            same, opp = (others + 1, others - 1) if kind == "flip" else (others - 1, others + 1)
            out[TESTS[kind][0]] = float(np.prod(same).real) if len(others) else None
            out["LPPD"] = float(np.prod(opp).real) if len(others) else None
            out[TESTS[kind][2]] = _pair_prod(others)
            last = TESTS[kind][3]
            if need in (None, last):
                out[last] = pt.coefficient if pt is not None else self._coef(X)
        return out

    def tests(self, X, t, pt):
        return self.psi(X, pt)

    def brackets(self, pa, pb, pta, pt):
        out = [("graze", {"pa": pa})] if pta.admissible != pt.admissible else []
        for key in TESTS[self.system.kind]:
            va, vb = pa.get(key), pb.get(key)
            if sign_change(va, vb):
                if key == "CH" and not (abs(va) > pa["_noise"] or abs(vb) > pb["_noise"]):
                    continue                  # l1 drowned in rounding at both ends
                out.append((key, {"pa": pa}))
        return out

    # ---- location -----------------------------------------------------------------
    def unlocated(self, kind, Xa, Xb, index, exc):
        return Codim2Point("unlocated", self._params(Xb), self._orbit(Xb), {},
                           f"the {kind} test function changes sign between "
                           f"{self._fmt(Xa)} and {self._fmt(Xb)}, but locating it "
                           f"failed: {exc}", index)

    def locate_event(self, kind, Xa, ta, Xb, index, pa):
        prev = pa["_pair"]
        if kind == "graze":
            return self._graze(Xa, ta, Xb, index)

        def f(X, t, DF):
            v = self.psi(X, prev=prev, need=kind)[kind]
            if v is None:
                raise RuntimeError(f"the {kind} test function cannot be evaluated at "
                                   f"{self._fmt(X)} (below its rounding bound, or off the "
                                   "Neimark-Sacker part)")
            return v
        X, t, DF = self.root(f, Xa, ta, Xb)
        ps = self.psi(X, prev=prev, need=kind)
        ends = max(abs(pa[kind]), abs(f(Xb, None, None)))
        if abs(ps[kind]) > 1e-3 * ends:
            return None                  # a sign change through a pole (e.g. c at a fold-flip)
        orbit = self._orbit(X)
        pair = ps["_pair"]
        mu = np.array(orbit.multipliers)
        others = _others(mu, pair if self.system.kind == "ns" else (pair[0],))
        if kind in ("NSNS", "PDNS", "LPNS") and self._pair_is_real(kind, others):
            return None                       # a neutral saddle among the others
        coeffs, detail = describe(kind, self.system.kind, orbit, pair, others)
        return Codim2Point(kind, self._params(X), orbit, coeffs, detail, index)

    def _pair_is_real(self, kind, others):
        if kind == "NSNS" or (kind == "PDNS" and self.system.kind == "flip") or \
                (kind == "LPNS" and self.system.kind == "fold"):
            z = min(((a, b) for i, a in enumerate(others) for b in others[i + 1:]),
                    key=lambda ab: abs(ab[0] * ab[1] - 1), default=None)
            return z is None or abs(z[0].imag) < 1e-8
        return False

    def _graze(self, Xa, ta, Xb, index):
        """Where the orbit stops (or starts) being admissible along the curve."""
        bad = Xb if self._orbit(Xa).admissible else Xa
        vb = self._vmin(bad)
        if vb <= 0:
            X, t, DF = self.root(lambda X, t, DF: self._vmin(X), Xa, ta, Xb)
            orbit = self._orbit(X, admissibility=False)
            return Codim2Point("grazing", self._params(X), orbit,
                               {"impact_velocity": self._vmin(X)},
                               "an impact arrives with zero velocity (grazing impact): the "
                               "curve's orbit is not admissible beyond", index)
        from ..continuation.special import Codim1Tracker as BranchTracker
        pr = self.system.problem(bad[-1])
        bt = BranchTracker(pr)
        i, val, tm, k = bt._worst_flight(bad[:-1])
        if val is None or val < -1e-9:
            orbit = self._orbit(bad)
            return Codim2Point("admissibility", self._params(bad), orbit, {},
                               f"the orbit's admissibility changes between {self._fmt(Xa)} "
                               f"and {self._fmt(Xb)}: {orbit.reason}", index)

        def excess(X, t, DF):
            return BranchTracker(self.system.problem(X[-1]))._interior(X[:-1], i, k)[0]
        X, t, DF = self.root(excess, Xa, ta, Xb)
        orbit = self._orbit(X, admissibility=False)
        tm = BranchTracker(self.system.problem(X[-1]))._interior(X[:-1], i, k)[1]
        coef = {"flight": i + 1, "t": tm, "duration": orbit.times[i]}
        stop = "the stop"
        if k is not None:
            coef["stop"] = k + 1
            stop = f"stop {k + 1}"
        return Codim2Point("grazing", self._params(X), orbit, coef,
                           f"flight {i + 1} touches {stop} with zero velocity at t = {tm:.9g} "
                           f"of {orbit.times[i]:.9g} (grazing inside a flight): the orbit "
                           f"penetrates {stop} beyond", index)

    # ---- scalar functions of a point ----------------------------------------------
    def _mono(self, X):
        return mono(self.system, X)

    def _orbit(self, X, admissibility=True):
        m = self.system.m
        pr = self.system.problem(X[-1])
        return orbit_of(pr, X[:m], X[m], admissibility=admissibility)

    def _params(self, X):
        a, b = self.system.names
        return {a: float(X[-2]), b: float(X[-1])}

    def _fmt(self, X):
        return ", ".join(f"{k} = {v:.12g}" for k, v in self._params(X).items())

    def _l1(self, X, lam):
        return first_lyapunov(self._orbit(X, admissibility=False), lam)

    def _coef(self, X):
        orbit = self._orbit(X, admissibility=False)
        if self.system.kind == "flip":
            A, d2, d3 = orbit.jet(3)
            return flip_coefficient(A, d2, d3)[0]
        A, d2, _ = orbit.jet(2)
        return fold_coefficient(A, d2)[0]

    def _vmin(self, X):
        m = self.system.m
        pr = self.system.problem(X[-1])
        fl, (_, flow, _) = pr.flights(X[:m], X[m], check=False)
        return float(min(pr.approach_speeds(fl, flow)))


# --------------------------------------------------------------------------- coefficients
MEANING = {
    "CH": "Chenciner (generalised Neimark-Sacker) point: l1 = 0",
    "R1": "strong resonance 1:1 (a double multiplier 1)",
    "R2": "strong resonance 1:2 (a double multiplier -1)",
    "R3": "strong resonance 1:3 (multipliers e^{+-2 pi i/3})",
    "R4": "strong resonance 1:4 (multipliers +-i)",
    "LPNS": "fold-Neimark-Sacker point (a multiplier 1 beside the critical pair)",
    "PDNS": "flip-Neimark-Sacker point (a multiplier -1 beside the critical pair)",
    "NSNS": "double Neimark-Sacker point (two pairs on the unit circle)",
    "LPPD": "fold-flip point (multipliers 1 and -1)",
    "CP": "cusp point (fold with a = 0)",
    "GPD": "generalised flip point (flip with c = 0)",
}


def describe(kind, curve_kind, orbit, pair, others):
    """(coefficients, detail) of a located codimension-two point, from :mod:`symvi.normal_forms.codim2`."""
    coeffs = {"multipliers_critical": [complex(z) for z in pair]}
    detail = MEANING.get(kind, kind)
    try:
        coeffs.update(_normal_form(kind, orbit))
    except (SymviError, np.linalg.LinAlgError, ValueError, ImportError) as exc:
        detail += f"; normal-form coefficients not computed: {exc}"
    return coeffs, detail


def _normal_form(kind, orbit):
    from ..normal_forms import codim2
    if kind in ("CH", "GPD"):
        args = orbit.jet(5)                   # orders 4-5, composed over the p impacts
        res = codim2.chenciner(*args) if kind == "CH" else codim2.degenerate_flip(*args)
    else:
        A, d2, d3 = orbit.jet(3)
        fn = {"R1": lambda: codim2.resonance_1_1(A, d2),
              "R2": lambda: codim2.resonance_1_2(A, d2, d3),
              "R3": lambda: codim2.resonance_1_3(A, d2, d3),
              "R4": lambda: codim2.resonance_1_4(A, d2, d3),
              "LPNS": lambda: codim2.fold_ns(A, d2, d3),
              "PDNS": lambda: codim2.flip_ns(A, d2, d3),
              "LPPD": lambda: codim2.fold_flip(A, d2, d3),
              "CP": lambda: codim2.cusp(A, d2, d3)}.get(kind)
        if fn is None:
            return {}
        res = fn()
    return _scalars(res)


def _scalars(res):
    """The scalar fields of a normal-form result (vectors and matrices left out)."""
    import dataclasses
    out = {}
    for f in dataclasses.fields(res):
        v = getattr(res, f.name)
        if isinstance(v, (bool, int, float, complex, str, np.number)):
            out[f.name] = complex(v) if isinstance(v, (complex, np.complexfloating)) else v
    return out


# names that moved to the one engine (issue 24, item 4): they warn for one release
__getattr__ = _moved_names(__name__, __name__, {"Tracker": "Codim2Tracker"})
