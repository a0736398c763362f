"""Test functions along a branch, and the location and normal forms of its special points.

At each point, with mu_i the multipliers (eigenvalues of the monodromy matrix)
and t the unit tangent of :mod:`symvi.continuation.branch`:

* fold:  psi = t_lam, the parameter component of the tangent (the branch turns);
* flip:  psi = prod_i (mu_i + 1) = det(M + I);
* NS:    psi = prod_{i<j} (mu_i mu_j - 1) = det(M (.) M - I), the bialternate product
  (also zero at a neutral saddle, mu_i mu_j = 1 with both real: discarded on location);
* grazing, first kind: the velocity of each impact, v_k- (-> 0: the mass arrives at the
  stop with zero velocity);
* grazing, second kind: the largest interior maximum of x_k(t) - b over each flight
  (-> 0: the flight touches the stop with zero velocity), evaluated only where the
  orbit's admissibility changes.

A sign change between two points is located by Brent's method in the arclength s,
each trial point corrected on the hyperplane t_a . (X - X_a) = s, to |ds| <= 1e-14 (s).
Coefficients (all with ||q||_2 = 1 and <p, q> = 1, p the adjoint vector paired with
q explicitly, :func:`symvi.normal_forms.normal_form.real_critical`):

* fold: a = <p, B(q, q)> / 2 of eta -> eta + a eta^2;
* flip: c of eta -> -eta + c eta^3 (c > 0 supercritical), :func:`symvi.normal_forms.normal_form.flip_coefficient`;
* NS: l1 = Re(e^{-i theta} c1) (Kuznetsov), :func:`symvi.normal_forms.normal_form.normal_form`.

B, C are the second and third derivatives of P^p from the generated jets, composed.
"""
import functools
import math
import warnings

import numpy as np

from .._deprecated import moved_names as _moved_names
from ..errors import ConvergenceError, NearSingularWarning, SingularCaseError, SymviError
from ..normal_forms.normal_form import flip_coefficient, fold_coefficient, normal_form, real_critical
from ..orbits.periodic import newton, orbit_of
from . import engine
from .engine import interpolated_root, sign_change
from .points import SpecialPoint

#: strong resonances reported beside an NS point when |lambda^m - 1| is below this
STRONG_RESONANCE_NEAR = 1e-2
#: distance to the other multipliers below which a critical +-1 is called double
DOUBLE_GAP = 1e-4
#: the approach speed, relative to max(1, the bracket's), at which a grazing impact is
#: taken when its root lands on v = 0 exactly (no Jacobian there: eq. (30))
GRAZING_FLOOR = 1e-14


@functools.lru_cache(maxsize=None)
def _pairs(n):
    """Index pairs i < j of n multipliers (the bialternate product)."""
    return np.triu_indices(n, 1)


class Codim1Tracker(engine.Tracker):
    """The codimension-one test functions of a branch, and the location of their zeros."""

    def __init__(self, problem, coefficients=True):
        super().__init__(problem)
        self.problem = problem
        self.coefficients = coefficients      # False: NS points located, no normal form

    # ---- test functions -----------------------------------------------------------
    def _conservative(self, X):
        # the model of the point's flights (cached by the problem: no second model built)
        return self.problem.flights(X[:-1], X[-1], check=False)[1][0].conservative

    def psi(self, X, t, orbit):
        mu = np.array(orbit.multipliers)
        out = {"fold": float(t[-1]), "flip": float(np.prod(mu + 1).real)}
        if not self._conservative(X):
            iu = _pairs(len(mu))
            out["ns"] = float(np.prod(mu[iu[0]] * mu[iu[1]] - 1).real)
            out["bp"] = float(np.prod(mu - 1).real)
        else:
            # multipliers on the unit circle move along it: the strong resonances
            # lambda^3 = 1, lambda^4 = 1 are met at isolated points (codim 1 here)
            for m in (3, 4):
                out[f"R{m}"] = _unit_circle_resonance(mu, m)
        if orbit.half_multipliers is not None:
            # symmetric orbit: H^2 = M, and -1 of H is the +1 of a symmetry-breaking pitchfork
            out["sb"] = float(np.prod(np.array(orbit.half_multipliers) + 1).real)
        for i, v in enumerate(orbit.impact_velocities):
            out[f"v{i}"] = v
        return out

    def tests(self, X, t, pt):
        return self.psi(X, t, pt.orbit)

    def brackets(self, pa, pb, pta, pt):
        out = []
        graze = False
        touches = self._touches(pa, pb)
        for key in pa:
            if key.startswith("v") and sign_change(pa[key], pb.get(key)):
                graze = True
                if key not in touches:         # the exit of a touch: one point, the entry
                    out.append((key, {}))
        # through a grazing impact the map's Jacobian has a pole (eq. (30)): the
        # multiplier test functions change sign there without a bifurcation
        # at a touch the continued (virtual) branch turns back with the contact time < 0:
        # no saddle-node there
        for kind in () if touches else ("fold",) if graze else ("fold", "flip", "ns", "R3",
                                                                   "R4"):
            if sign_change(pa.get(kind), pb.get(kind)):
                out.append((kind, {}))
        # a multiplier through +1 where the branch does not turn: two branches cross; on
        # a symmetric branch, -1 of the half map says which: symmetry breaking
        sb = not graze and sign_change(pa.get("sb"), pb.get("sb"))
        if sb:
            out.append(("symmetry-breaking", {}))
        if not graze and not sb and sign_change(pa.get("bp"), pb.get("bp")) and \
                not sign_change(pa["fold"], pb["fold"]):
            out.append(("branch-point", {}))
        if pta.admissible != pt.admissible and not graze:
            out.append(("interior", {"bad": None if pta.admissible else "a",
                                     "why": (pt if pta.admissible else pta).orbit.reason}))
        return out

    def _touches(self, pa, pb):
        """The keys of exit speeds that change sign with the entry speed before them: a
        contact phase that shrinks to a touch (entry speed, contact time and exit speed
        all tend to 0), located once, as its entry (elastic stops)."""
        pr = self.problem
        if not pr.elastic:
            return set()
        out = set()
        for i in range(pr.p):
            j = (i + 1) % pr.p                 # flight i ends at event j, flight j in contact
            if pr.kinds[j] == "entry" and sign_change(pa.get(f"v{i}"), pb.get(f"v{i}")) \
                    and sign_change(pa.get(f"v{j}"), pb.get(f"v{j}")):
                out.add(f"v{j}")
        return out

    # ---- location -----------------------------------------------------------------
    def locate_event(self, kind, Xa, ta, Xb, index, bad=None, why=""):
        if kind == "interior":
            bad = Xa if bad == "a" else Xb
        return self._locate(kind, Xa, ta, Xb, index, bad=bad, why=why)

    def unlocated(self, kind, Xa, Xb, index, exc):
        lam = 0.5 * (Xa[-1] + Xb[-1])
        pr = self.problem
        orbit = orbit_of(pr, Xb[:-1], Xb[-1])
        why = ""
        if pr.mirror is not None and not orbit.symmetric and any(
                pr.half(X[:-1], pr.monodromy(X[:-1], pr.evaluate(X[:-1], X[-1])[1])[0],
                        tol=1e-3) is not None for X in (Xa, Xb)):
            why = ("; this asymmetric branch is within 1e-3 of a symmetric orbit here: the "
                   "pitchfork where it meets the symmetric branch (located on that branch as "
                   "symmetry-breaking), at which this branch's corrector is singular")
        return SpecialPoint("unlocated", float(lam), orbit, {},
                            f"a {kind} test function changes sign between "
                            f"{Xa[-1]:.12g} and {Xb[-1]:.12g}, but locating it failed: {exc}"
                            + why, index)

    def locate(self, kind, Xa, ta, Xb, index=0):
        """The special point of ``kind`` (fold, flip, ns, branch-point, R3, R4) on the arc
        from Xa (unit tangent ta) to Xb, or None when the sign change was not one."""
        return self._locate(kind, Xa, ta, Xb, index)

    def _root(self, f, Xa, ta, Xb):
        return self.root(f, Xa, ta, Xb)

    def _orbit(self, X, Gu, admissibility=True):
        m = self.problem.size
        return orbit_of(self.problem, X[:m], X[m], Gu, admissibility=admissibility)

    def _locate(self, kind, Xa, ta, Xb, index, bad=None, why=""):
        pr, m = self.problem, self.problem.size
        if kind == "fold":
            X, t, Gu = self._root(lambda X, t, Gu: t[-1], Xa, ta, Xb)
            orbit = self._orbit(X, Gu)
            A, d2, _ = orbit.jet(2)
            a, e = fold_coefficient(A, d2)
            note = (f"; +1 is a double multiplier (separation {e.gap:.1e}): the one-dimensional "
                    "normal form does not apply" if e.gap < DOUBLE_GAP else "")
            return SpecialPoint("fold", float(X[m]), orbit,
                                {"a": a, "multiplier": e.mu, "separation": e.gap},
                                "a multiplier through +1: the branch turns (saddle-node); "
                                f"eta -> eta + a eta^2 with a = {a:.6g} (||q|| = 1, "
                                "<p,q> = 1)" + note, index)
        if kind == "branch-point":
            X, spread, orbit, Gu = self._branch_root(lambda X, Gu: self._mu_prod(X, Gu, -1),
                                                     Xa, ta, Xb)
            e = real_critical(self._mono(X, Gu), 1.0)
            return SpecialPoint("branch-point", float(X[m]), orbit,
                                {"multiplier": e.mu, "separation": e.gap, "spread": float(spread)},
                                "a multiplier through +1 where the branch does not turn: "
                                "another branch of orbits crosses this one here (the orbit is "
                                "not isolated; e.g. a symmetry-breaking pitchfork, or the "
                                "period-doubled branch met on an orbit traversed twice); symvi "
                                "reports it and continues on the same branch", index)
        if kind == "symmetry-breaking":
            X, spread, orbit, Gu = self._branch_root(self._half_prod, Xa, ta, Xb)
            H = pr.half(X[:m], pr.monodromy(X[:m], Gu)[0])
            if H is None:
                return None
            e = real_critical(H, -1.0)
            return SpecialPoint("symmetry-breaking", float(X[m]), orbit,
                                {"half_multiplier": e.mu, "separation": e.gap,
                                 "spread": float(spread)},
                                "a multiplier of the half map H (H^2 = M) through -1: the "
                                "symmetric orbit's monodromy has +1 and the branch does not "
                                "turn; a pair of mirror-image asymmetric orbits branches off "
                                "here (a pitchfork; --switch follows one, the other is its "
                                "mirror image)", index)
        if kind == "flip":
            X, t, Gu = self._root(lambda X, t, Gu: self._mu_prod(X, Gu, +1), Xa, ta, Xb)
            orbit = self._orbit(X, Gu)
            A, d2, d3 = orbit.jet(3)
            c, e = flip_coefficient(A, d2, d3)
            crit = ("supercritical: a stable" if c > 0 else "subcritical: an unstable")
            if e.gap < DOUBLE_GAP:
                crit = (f"degenerate: -1 is a double multiplier (separation {e.gap:.1e}, a collision "
                        "of two multipliers at -1), so the one-dimensional flip normal form and "
                        "its c do not decide the")
            return SpecialPoint("flip", float(X[m]), orbit,
                                {"c": c, "multiplier": e.mu, "separation": e.gap},
                                f"a multiplier through -1: period doubling to a "
                                f"{2 * pr.n_periods}-{2 * pr.p} orbit, {crit} doubled orbit "
                                f"(eta -> -eta + c eta^3, c = {c:.6g}, ||q|| = 1, <p,q> = 1)",
                                index)
        if kind == "ns":
            X, t, Gu = self._root(lambda X, t, Gu: self._bialt(X, Gu), Xa, ta, Xb)
            orbit = self._orbit(X, Gu)
            mu = np.array(orbit.multipliers)
            crit = min(mu, key=lambda z: abs(abs(z) - 1))
            if abs(crit.imag) <= 1e-8:
                return None                       # a neutral saddle, not a bifurcation
            if not self.coefficients:
                return SpecialPoint("ns", float(X[m]), orbit, {}, "a complex pair through "
                                    "|lambda| = 1 (normal form left to the caller)", index)
            return self._ns(X, orbit, index, Xa, Xb)
        if kind in ("R3", "R4"):
            m_ = int(kind[1])
            X, t, Gu = self._root(
                lambda X, t, Gu: _unit_circle_resonance(
                    np.linalg.eigvals(self._mono(X, Gu)), m_), Xa, ta, Xb)
            orbit = self._orbit(X, Gu)
            # a primitive m-th root of unity: lambda^m = -1 (a weak resonance 1:2m) and a
            # pair meeting at -1 (lambda^4 = 1, but the 1:2 resonance, a flip) are not 1:m
            prim = [complex(math.cos(2 * math.pi * k / m_), math.sin(2 * math.pi * k / m_))
                    for k in range(1, m_) if math.gcd(k, m_) == 1]
            mu = min(orbit.multipliers, key=lambda z: min(abs(z - w) for w in prim))
            if min(abs(mu - w) for w in prim) > 1e-6:
                return None
            return SpecialPoint(kind, float(X[m]), orbit,
                                {"theta": float(np.angle(mu)), "distance": float(abs(mu ** m_ - 1))},
                                f"a multiplier on the unit circle passes e^(2 pi i/{m_}): the "
                                f"strong resonance 1:{m_} met on the branch of a conservative "
                                "model (its multipliers move along the unit circle)", index)
        if kind.startswith("v"):
            i = int(kind[1:])
            j = (i + 1) % pr.p
            if pr.elastic and pr.kinds[j] == "entry":
                return self._touch(i, Xa, ta, Xb, index)
            X, t, Gu = self._root(lambda X, t, Gu: self._vimp(X, i), Xa, ta, Xb)
            try:
                orbit = self._orbit(X, Gu, admissibility=False)
            except SingularCaseError:
                # the root met v = 0 exactly, where the map has no Jacobian (eq. (30)):
                # take it on the admissible side, at a speed of GRAZING_FLOOR
                floor = GRAZING_FLOOR * max(1.0, abs(self._vimp(Xa, i)))
                X, t, Gu = self._root(lambda X, t, Gu: self._vimp(X, i) - floor, Xa, ta, Xb)
                orbit = self._orbit(X, Gu, admissibility=False)
            coef = {"impact": i + 1, "impact_velocity": self._vimp(X, i)}
            if pr.several:
                coef["stop"] = int(pr.sig[(i + 1) % pr.p]) + 1
            return SpecialPoint("grazing", float(X[m]), orbit, *_nordmark(
                pr, orbit, coef, f"impact {i + 1} of the orbit arrives with zero velocity "
                "(grazing impact): the impact velocity changes sign and the orbit is not "
                "admissible beyond"), index)
        # admissibility lost inside a flight: locate the interior tangency
        i, val, tm, k = self._worst_flight(bad)
        if val is None or val < -1e-9:
            lam = 0.5 * (Xa[-1] + Xb[-1])
            return SpecialPoint("admissibility", float(lam), self._orbit(bad, None),
                                {}, f"the orbit's admissibility changes between "
                                f"{Xa[-1]:.12g} and {Xb[-1]:.12g}: {why}", index)
        X, t, Gu = self._root(lambda X, t, Gu: self._interior(X, i, k)[0], Xa, ta, Xb)
        h, tm = self._interior(X, i, k)
        orbit = self._orbit(X, Gu, admissibility=False)
        coef = {"flight": i + 1, "t": tm, "duration": orbit.times[i]}
        stop = "the stop"
        if k is not None:
            coef["stop"] = k + 1
            new = ("a new contact is born" if pr.model.constraints[k].kind == "elastic"
                   else "a new impact is born")
            stop = f"stop {k + 1}" + ("" if k in orbit.signature else
                                      f" (one the orbit does not touch yet: {new})")
        if pr.elastic and k in pr.phases[i]:
            coef["exit"] = True
            return SpecialPoint("grazing", float(X[m]), orbit, coef,
                                f"flight {i + 1}, in contact with stop {k + 1}, reaches the "
                                f"contact's edge with zero velocity at t = {tm:.9g} of "
                                f"{orbit.times[i]:.9g}: the contact splits in two beyond",
                                index)
        return SpecialPoint("grazing", float(X[m]), orbit, *_nordmark(
            pr, orbit, coef, f"flight {i + 1} touches {stop} with zero velocity at t = "
            f"{tm:.9g} of {orbit.times[i]:.9g} (grazing inside a flight): the orbit "
            f"penetrates {'the stop' if k is None else 'it'} beyond"), index)

    def _touch(self, i, Xa, ta, Xb, index):
        """Flight i arrives at an elastic stop with zero speed: the contact that follows
        shrinks to a touch (its time -> 0 with the speed) and has gone beyond.  The
        shooting system is singular at the touch (the contact flight's guard has zero
        derivative at zero time), so the point is interpolated between corrected points
        either side (:meth:`_branch_root`)."""
        pr, m = self.problem, self.problem.size
        X, spread, orbit, _ = self._branch_root(lambda X, Gu: self._vimp(X, i), Xa, ta, Xb)
        j = (i + 1) % pr.p
        k = int(pr.sig[j])
        coef = {"impact": i + 1, "impact_velocity": self._vimp(X, i), "stop": k + 1,
                "contact_time": float(pr.split(X[:m])[1][j]), "spread": spread}
        return SpecialPoint("grazing", float(X[m]), orbit, coef,
                            f"flight {i + 1} arrives at the elastic stop {k + 1} with zero "
                            f"velocity: its contact shrinks to a touch (the contact time "
                            f"tends to 0 with the speed) and the orbit has no such contact "
                            f"beyond (interpolated: the shooting system is singular at the "
                            f"touch)", index)

    def _branch_root(self, f, Xa, ta, Xb):
        """(X, spread, orbit, G_u) at the zero of f(X, G_u) on the arc: the extended system
        is singular at a branch point, so the corrector cannot sit on it and the root is
        interpolated between corrected points either side (:func:`interpolated_root`)."""
        m = self.problem.size
        X, spread = interpolated_root(self.problem, f, Xa, ta, Xb)
        return X, spread, self._orbit(X, None), self.problem.evaluate(X[:m], X[m])[1]

    def _ns(self, X, orbit, index, Xa, Xb):
        m = self.problem.size
        A, d2, d3 = orbit.jet(3)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NearSingularWarning)
            nf = normal_form(A, d2, d3, paper=False)
        # explicit pairing check: p is the adjoint vector of lambda1 itself
        res = float(np.linalg.norm(A.T @ nf.p - np.conj(nf.lam) * nf.p))
        pq = complex(np.vdot(nf.p, nf.q))
        if res > 1e-6 * np.linalg.norm(A) * np.linalg.norm(nf.p) or abs(pq - 1) > 1e-8:
            raise RuntimeError(f"adjoint eigenvector not paired with q (residual {res:.2g})")
        dmod = self._dmod(X, Xa, Xb)
        mres, dist = nf.resonance
        l1 = float(nf.l1)
        kind = "supercritical (l1 < 0: a stable invariant circle)" if l1 < 0 else \
            "subcritical (l1 > 0: an unstable invariant circle)"
        detail = (f"a complex pair through |lambda| = 1 at theta/2pi = "
                  f"{float(nf.theta) / (2 * math.pi):.9g}: Neimark-Sacker, {kind}")
        if mres <= 4 and float(dist) < STRONG_RESONANCE_NEAR:
            detail += f"; close to the strong resonance R{mres} (|lambda^{mres} - 1| = " \
                      f"{float(dist):.2g})"
        return SpecialPoint("ns", float(X[m]), orbit,
                            {"l1": l1, "theta": float(nf.theta),
                             "c1_re": float(complex(nf.c1).real),
                             "c1_im": float(complex(nf.c1).imag),
                             "dmod_dparam": dmod, "adjoint_residual": res,
                             "normalisation": "||q||_2 = 1, <p,q> = 1, l1 = Re(e^{-i theta} c1)"},
                            detail, index)

    # ---- scalar functions of a point ----------------------------------------------
    def _mono(self, X, Gu):
        return self.problem.monodromy(X[:-1], Gu)[1]

    def _mu_prod(self, X, Gu, sign):
        return float(np.linalg.det(self._mono(X, Gu) + sign * np.eye(self.problem.d)))

    def _half_prod(self, X, Gu):
        pr = self.problem
        H = pr.half(X[:-1], pr.monodromy(X[:-1], Gu)[0])
        if H is None:                  # left the symmetric orbits: no value (never a root)
            return math.nan
        return float(np.linalg.det(H + np.eye(pr.d)))

    def _bialt(self, X, Gu):
        mu = np.linalg.eigvals(self._mono(X, Gu))
        iu = _pairs(len(mu))
        return float(np.prod(mu[iu[0]] * mu[iu[1]] - 1).real)

    def _dmod(self, X, Xa, Xb):
        """d|mu|/dparam at the NS point X: a central difference over orbits corrected at
        lam +- h, h = 1e-4 of the bracket (Xa, Xb).  The secant between the bracketing
        branch points, used before, is off by the curvature of |mu| over a whole step (4 to
        8 % on the impact Duffing absorber's branch, tests/continuation/test_absorber.py);
        it remains the fallback where Newton does not converge."""
        m, lam = self.problem.size, float(X[-1])
        h = 1e-4 * abs(float(Xb[-1]) - float(Xa[-1]))
        try:
            mods = [self._crit_mod(np.append(newton(self.problem, X[:m], lam + s), lam + s))
                    for s in (-h, h)]
            return (mods[1] - mods[0]) / (2 * h)
        except ConvergenceError:
            return (self._crit_mod(Xb) - self._crit_mod(Xa)) / (Xb[-1] - Xa[-1])

    def _crit_mod(self, X):
        G, Gu, _ = self.problem.evaluate(X[:-1], X[-1])
        mu = np.linalg.eigvals(self._mono(X, Gu))
        cands = [z for z in mu if abs(z.imag) > 1e-12] or list(mu)
        return float(abs(min(cands, key=lambda z: abs(abs(z) - 1))))

    def _vimp(self, X, i):
        fl, (_, flow, _) = self.problem.flights(X[:-1], X[-1])
        return self.problem.approach_speeds(fl, flow)[i]

    def _interior(self, X, i, k=None):
        """(max over the interior of flight i of the guard h of constraint k (x_k(t) - b for
        the stop), where): its local maxima only.  ``k`` None: the flow's own guard (one
        stop); with several constraints :meth:`_worst_flight` asks each."""
        pr = self.problem
        fl, (model, flow, F) = pr.flights(X[:-1], X[-1])
        z0, tau = fl[i][0], fl[i][1]
        T = float(pr.split(X[:-1])[1][i])
        if pr.elastic:
            # the flight's contact phase; in contact with k its guard is the exit's, -h
            fi, Fi = pr.phase_flows(model, flow, F)[i]
            row = _table_row(flow, k, pr.N)
            s = -1.0 if k in pr.phases[i] else 1.0
            h = lambda t: s * (row[0] @ fi.flight(Fi, z0, tau, t)[0][:pr.N] - row[1])  # noqa: E731
            flow = fi
        elif k is None:
            mo = flow.motion(F, z0, tau)
            h = lambda t: mo.h(t)[0]              # noqa: E731
        else:
            mo = flow.motion(F, z0, tau)
            row = _table_row(flow, k, pr.N)
            h = lambda t: row[0] @ mo.state(t)[:pr.N] - row[1]   # noqa: E731
        rate = flow.nl.omega_max if pr.nonlinear else float(np.max(np.abs(flow.lam)))
        fast = max(rate, float(F.omega))
        n = int(min(20000, max(400, 20 * T * fast / (2 * math.pi))))
        ts = np.linspace(0.0, T, n + 1)
        hs = np.array([h(t) for t in ts])
        best, where = None, None
        for j in range(1, n):
            if hs[j] >= hs[j - 1] and hs[j] >= hs[j + 1]:
                from scipy.optimize import minimize_scalar   # ~0.1 s to import
                r = minimize_scalar(lambda t: -h(t), bounds=(ts[j - 1], ts[j + 1]),
                                    method="bounded", options={"xatol": 1e-13 * T})
                v = -float(r.fun)
                if best is None or v > best:
                    best, where = v, float(r.x)
        return (best if best is not None else -math.inf), where

    def _worst_flight(self, X):
        """(flight, largest interior maximum of a guard, where, constraint): the flight
        that comes closest to (or goes through) a stop inside it."""
        best = (None, None, None, None)
        several = self.problem.several
        for i in range(self.problem.p):
            for k in (range(len(self.problem.model.constraints)) if several else (None,)):
                v, t = self._interior(X, i, k)
                if math.isfinite(v) and (best[1] is None or v > best[1]):
                    best = (i, v, t, k)
        return best


def _table_row(flow, k, N):
    """(signed guard normal, level) of constraint k in the flow's order."""
    from ..flow.compiled import table
    row = table(flow)[k]
    return row[3:3 + N], row[2]


def _unit_circle_resonance(mu, m):
    """prod of Im(lambda^m) over the multipliers on the unit circle with Im > 0 (None when
    there are none): it changes sign where one of them passes e^{2 pi i k/m}."""
    on = [z for z in mu if abs(abs(z) - 1) < 1e-6 and z.imag > 1e-8]
    if not on:
        return None
    return float(np.prod([(z ** m).imag for z in on]))



def _nordmark(pr, orbit, coef, detail):
    """(coefficients, detail) of a rigid grazing point with Nordmark's map added
    (:func:`symvi.orbits.nordmark.discontinuity_map`, its normalisation there): the
    leading multiplier lambda1 of its smooth part, gamma of the 1-D reduction, the
    coefficient c_first of the first new impact's speed c sqrt(mu), and d delta / d lambda;
    the predicted scenario past grazing in the detail.  Where the map cannot be computed the
    reason is stated in the detail instead."""
    from ..orbits.nordmark import discontinuity_map
    try:
        nm = discontinuity_map(orbit, coef, param=pr.param or "omega")
    except SymviError as exc:
        return coef, detail + f"; Nordmark's map not computed: {exc}"
    lam1 = nm.multipliers[0]
    coef = dict(coef, lambda1_re=float(lam1.real), lambda1_im=float(lam1.imag),
                acceleration=nm.acceleration)
    for key in ("gamma", "c_first", "delta_rate"):
        v = getattr(nm, key)
        if v is not None and math.isfinite(v):
            coef[key] = float(v)
    return coef, detail + f"; Nordmark's map past grazing: {nm.scenario}"

# names that moved to the one engine (issue 24, item 4): they warn for one release
__getattr__ = _moved_names(__name__, __name__, {"Tracker": "Codim1Tracker"})
