"""Independent high-precision check of a codimension-two point of a curve (issue 13, item 3).

:func:`check_codim2` takes a point of ``Curve.special`` (float64: located by the
minimally augmented system of :mod:`symvi.curves` on the generated jets, its normal form
by :mod:`symvi.normal_forms.codim2` on the generated jets composed over the orbit's impacts) and
re-solves it at ``digits`` (>= 40) by a chain that shares neither the generated code nor
the continuation code, the way ``chain_b`` of :mod:`symvi.studies.mpcheck` checks l1:

1. **The map.**  P^p of the curve's n-p orbit, in mpmath: :func:`symvi.maps.impact.step`
   p times on a :class:`symvi.flow.linear.LinearFlow` whose model data carry the two
   curve parameters as mpf numbers (the :class:`symvi.Model` stores floats; its other
   data are taken as the binary floats they are, and a named parameter moves the data
   along ``Model.tangent``, exact since every named parameter enters M, K, C, P, b, r
   affinely), tau unwrapped, minus 2 pi n.
2. **The fixed point** y(a, b) by Newton's method on P^p(y) - y
   (:class:`symvi.studies.mpcheck._MapFD`, finite-difference Jacobian).  Where the point has a
   multiplier 1 (every point of a fold curve; R1, LPNS, LPPD) y is a double root at fixed
   (a, b): there (y, a, b) are solved together, P^p(y) - y = 0 with the two equations
   of item 4.
3. **All derivatives** d^k P^p / dy^k, k <= 5, by central mixed differences: for the
   multiset of axes with multiplicities m_i the stencil is
   prod_i sum_j (-1)^j C(m_i, j) P(y + (m_i - 2j) h e_i) / (2h)^k, every order drawn from
   one cached grid y + h d (d integer, |d|_1 <= k); Richardson between h and 2h (error
   O(h^4)).  The working precision of an order-K jet is chosen so that truncation h^4 and
   rounding 10^-dps / h^K both stay below 10^-(digits + 10): dps = max(digits + 30,
   (digits + 10)(K + 4)/4), h = 10^(-dps/(K + 4)) (80, 105, 135 at digits = 50 for
   K = 1, 3, 5).
4. **The location**: Newton's method with Broyden updates in the two curve parameters on
   two defining equations g(a, b) = 0, their Jacobian first by forward differences of g.
   With mu_1, mu_2 the critical multipliers (followed by continuity from the float
   point's), kappa = (mu_1 + mu_2)/2 and chi(z) = det(z I - A) = prod (z - mu_i):

   ============  =====================  =============================================
   curve, point  g1                     g2
   ============  =====================  =============================================
   NS: R1..R4    Re(mu_1 mu_2) - 1      kappa - cos(2 pi/m)   (lambda^m = 1)
   NS: CH        Re(mu_1 mu_2) - 1      l1 (Kuznetsov, :func:`symvi.studies.mpcheck.kuznetsov_l1`)
   NS: LPNS      Re(mu_1 mu_2) - 1      chi(1) = det(I - A)
   NS: PDNS      Re(mu_1 mu_2) - 1      chi(-1) = det(-I - A)
   NS: NSNS      Re(mu_1 mu_2) - 1      Re(mu_3 mu_4) - 1 (the other pair)
   flip: R2      chi(-1)                chi'(-1) (a double multiplier -1)
   flip: LPPD    chi(-1)                chi(1)
   flip: PDNS    chi(-1)                prod_{i<j} (mu_i mu_j - 1) over the others
   flip: GPD     chi(-1)                c = <p, C(q,q,q) + 3 B(q, (I - A)^-1 B(q,q))>/6
   fold: R1      chi(1)                 chi'(1)
   fold: LPPD    chi(1)                 chi(-1)
   fold: LPNS    chi(1)                 prod_{i<j} (mu_i mu_j - 1) over the others
   fold: CP      chi(1)                 a = <p, B(q, q)>/2
   ============  =====================  =============================================

   (chi and its derivative as symmetric functions of the eigenvalues, smooth through a
   double multiplier).  Only the order the equations need is differenced while locating
   (order 1; order 3 for CH and GPD, 2 for CP); orders 4-5 once, at the end.
5. **The coefficients**: :mod:`symvi.normal_forms.codim2` with the mpmath backend (``digits``) on the
   finite-difference jets at the located point; for CH and GPD from the order-5 jet.
   For points with a simple complex pair (CH, R4, PDNS, NSNS) also Kuznetsov's c1 and l1
   by :func:`symvi.studies.mpcheck.kuznetsov_l1`, an independent transcription.

What is independent of what.  The chain uses neither the generated jets (``derivations/``,
``generated/``, :mod:`symvi.codegen`) nor the continuation code (:mod:`symvi.curves`,
:mod:`symvi.continuation`, the shooting of :mod:`symvi.orbits`): a wrong generated
derivative, a wrong composition over impacts, a wrong parameter derivative, or a test
function located at the wrong place would show as a disagreement.  The defining
equations above are its own.  It shares with the float64 chain (a) the numeric map:
the exact flow and the first-impact finder of :mod:`symvi.flow.linear` and the impact
law of :mod:`symvi.maps.impact`, here on their mpmath branch; (b) the normal-form
formulas of :mod:`symvi.normal_forms.codim2`: a wrong formula there would appear in both chains
alike; only c1 and l1 are also checked against the independent transcription
``kuznetsov_l1`` (and l1 = 0 at CH holds by Kuznetsov's formula while locating, by
codim2's at the end).  The known-answer tests of ``tests/normal_forms/test_codim2.py``
check the formulas themselves.

Vanishing quantities (l1 at CH, c at GPD, a at CP) are compared relative to the point's
next coefficient (|c1|, |e|, |c|): digits of |x_float - x_chain| / scale.

References
----------
[Kuznetsov, Elements] Yu. A. Kuznetsov, Elements of Applied Bifurcation Theory, 3rd ed.,
Springer 2004, Sec. 5.4.
[Kuznetsov & Meijer 2005] Yu. A. Kuznetsov and H. G. E. Meijer, Numerical normal forms for
codim 2 bifurcations of fixed points with at most two critical eigenvalues, SIAM J. Sci.
Comput. 26 (2005) 1932-1954.
"""
import itertools
import math
import time
import warnings
from collections import Counter
from dataclasses import dataclass, field

import mpmath
import numpy as np

from ..errors import NearSingularWarning, ParameterError, SingularCaseError
from ..model import Stop
from ..numerics.backend import backend
from .mpcheck import _MapFD, digits_of_agreement, kuznetsov_l1

#: kinds of point the chain can re-solve, per curve kind
KINDS = {"ns": ("R1", "R2", "R3", "R4", "CH", "LPNS", "PDNS", "NSNS"),
         "flip": ("R2", "LPPD", "PDNS", "GPD"),
         "fold": ("R1", "LPPD", "LPNS", "CP")}
#: the jet order the defining equations need (default 1: the Jacobian)
_LOC_ORDER = {"CH": 3, "GPD": 3, "CP": 2}
#: the jet order of the coefficients (default 3)
_NF_ORDER = {"CH": 5, "GPD": 5, "R1": 2}
#: coefficients that vanish at the point, and the coefficient that scales them
_VANISHING = {"CH": {"l1": "c1", "l2_matcont": None}, "GPD": {"c": "e"}, "CP": {"a": "c"}}
#: points with a multiplier 1 on NS and flip curves (all points of fold curves have one)
_ONE = ("R1", "LPNS", "LPPD")
#: guard digits of the differences beyond ``digits`` (truncation and rounding)
GUARD = 10


@dataclass(frozen=True)
class Codim2Check:
    """The point re-solved at ``digits`` and its agreement with the float64 curve point.

    ``params``: the located parameter values (mpf); ``y`` the fixed point of P^p there
    (tau unwrapped); ``tests``: the two defining equations at ``params`` (see the module
    docstring); ``coefficients``: the scalar fields of the :mod:`symvi.normal_forms.codim2` result on
    the finite-difference jets; ``kuznetsov``: c1, l1 of the independent transcription;
    ``location``: parameter name -> digits of agreement of the float64 point's value with
    ``params``; ``agreement``: coefficient name -> digits of agreement of the float64
    point's coefficient with ``coefficients``; ``internal``: digits of agreement
    of codim2 with ``kuznetsov`` inside the chain (and, with ``verify``, of the
    coefficients with a second step size); ``dps``: working precisions; ``times``:
    seconds per stage; ``evaluations``: calls of the mpmath map.
    """

    kind: str
    curve_kind: str
    names: tuple
    digits: int
    params: dict
    y: tuple
    multipliers: tuple
    tests: dict
    coefficients: dict
    kuznetsov: dict
    location: dict
    agreement: dict
    internal: dict
    dps: dict
    times: dict
    evaluations: int
    iterations: int
    float_point: object = field(repr=False, default=None)

    def as_dict(self, n=20):
        def s(x):
            if isinstance(x, mpmath.mpc):
                return [mpmath.nstr(x.real, n), mpmath.nstr(x.imag, n)]
            return mpmath.nstr(x, n) if isinstance(x, mpmath.mpf) else x
        return {"kind": self.kind, "curve": self.curve_kind, "digits": self.digits,
                "params": {k: s(v) for k, v in self.params.items()},
                "tests": {k: s(v) for k, v in self.tests.items()},
                "coefficients": {k: s(v) for k, v in self.coefficients.items()},
                "kuznetsov": {k: s(v) for k, v in self.kuznetsov.items()},
                "location": dict(self.location), "agreement": dict(self.agreement),
                "internal": dict(self.internal),
                "dps": dict(self.dps), "times": dict(self.times),
                "evaluations": self.evaluations, "iterations": self.iterations}


# --------------------------------------------------------------------------- the map
class _MpModel:
    """What :class:`LinearFlow` reads of a model, with mpf data (the curve's parameters)."""

    def __init__(self, model, values):
        self.n, self.stop = model.n, _MpStop(model.stop.mass, None, None)
        M, K, C, P = (np.array([mpmath.mpf(float(v)) for v in np.ravel(a)], dtype=object)
                      .reshape(np.shape(a)) for a in
                      (model.mass, model.stiffness, model.damping, model.forcing))
        gap, r = mpmath.mpf(model.stop.gap), mpmath.mpf(model.stop.restitution)
        for name, v in values.items():
            dv = v - mpmath.mpf(model.value(name))
            t = model.tangent(name)
            # every named parameter enters the data affinely: data(v) = data + dv * tangent
            M, K, C, P = (X + dv * np.asarray(T, dtype=float)
                          for X, T in ((M, t.dM), (K, t.dK), (C, t.dC), (P, t.dP)))
            gap, r = gap + dv * t.db, r + dv * t.dr
        self.mass, self.stiffness, self.damping, self.forcing = M, K, C, P
        self.stop = _MpStop(model.stop.mass, gap, r)
        self.damped = any(x != 0 for x in np.ravel(C))
        self._model = model

    def require_one_rigid_stop(self):
        """The checked model's answer (:meth:`symvi.model.Model.require_one_rigid_stop`)."""
        self._model.require_one_rigid_stop()
        return self

    def require_rigid_stops(self):
        """The checked model's answer (:meth:`symvi.model.Model.require_rigid_stops`)."""
        self._model.require_rigid_stops()
        return self

    def require_linear(self):
        """The checked model's answer (:meth:`symvi.model.Model.require_linear`)."""
        self._model.require_linear()
        return self

    @property
    def constraints(self):
        """The stop as the flow reads it (:meth:`symvi.model.Stop.constraint`), mpf gap and r."""
        return (Stop.constraint(self.stop, self.n),)


@dataclass(frozen=True)
class _MpStop:
    mass: int
    gap: object
    restitution: object
    between: tuple = None
    side: str = "upper"
    stiffness: object = None
    damping: object = None


class CurveMapFD(_MapFD):
    """P^p - 2 pi n e_tau of a curve's n-p orbit in mpmath at ``dps``, as a function of the
    two curve parameters w = (a, b) (mpf) and y; finite differences of it to order 5.

    ``_MapFD`` supplies Newton's method for the fixed point; :meth:`jet` the derivatives."""

    def __init__(self, model, names, omega, n, p, dps):
        super().__init__(model, dps, 2 * model.n)
        self.model, self.names, self.omega, self.n_periods, self.p = model, names, omega, n, p
        self._pars = tuple(model.parameter(nm) for nm in names)      # parsed once
        self._flows = {}
        self.calls = 0

    def _flow(self, w):
        from ..flow.linear import LinearFlow
        hit = self._flows.get(w)
        if hit is None:
            vals = {par.name: v for par, v in zip(self._pars, w) if not par.is_forcing_frequency}
            omega = next((v for par, v in zip(self._pars, w) if par.is_forcing_frequency),
                         self.omega)
            flow = LinearFlow(_MpModel(self.model, vals), backend(self.dps))
            if len(self._flows) > 8:
                self._flows.clear()
            hit = self._flows[w] = (flow, flow.forcing(mpmath.mpf(omega)))
        return hit

    def P(self, w, y):
        from ..maps.impact import IMPACT, step
        with mpmath.workdps(self.dps):
            flow, F = self._flow(w)
            y = [mpmath.mpf(v) for v in y]
            for _ in range(self.p):
                s = step(flow, F, np.array(y, dtype=object))
                self.calls += 1
                if s.status != IMPACT:
                    raise SingularCaseError("grazing", "P is not smooth here (flight ends in "
                                            f"{s.status})")
                y = [*s.y[:-1], s.tau_unwrapped]
            return y

    def residual(self, w, y):
        p = self.P(w, y)
        r = [p[i] - y[i] for i in range(self.n)]
        r[-1] -= 2 * mpmath.pi * self.n_periods
        return r

    def jet(self, w, y, order, shrink=0):
        """(A, d2, ..., d_order) at y: numpy object arrays of mpf (module docstring, item 3),
        every order from one grid of evaluations; ``shrink``: a step 10^-shrink smaller."""
        n = self.n
        with mpmath.workdps(self.dps):
            h = mpmath.mpf(10) ** (-(self.dps // (order + 4)) - shrink)
            y = [mpmath.mpf(v) for v in y]
            cache = {}

            def at(d):
                if d not in cache:
                    cache[d] = self.P(w, [y[i] + h * d[i] for i in range(n)])
                return cache[d]
            return _jet_on(at, n, order, h)


def _stencil(axes, n):
    """[(d, weight)]: prod over the axes of (E^{h e_i} - E^{-h e_i}), d in units of h."""
    per = []
    for ax, m in Counter(axes).items():
        per.append([(ax, m - 2 * j, (-1) ** j * math.comb(m, j)) for j in range(m + 1)])
    out = []
    for combo in itertools.product(*per):
        d = [0] * n
        wt = 1
        for ax, dd, c in combo:
            d[ax] = dd
            wt *= c
        out.append((tuple(d), wt))
    return out


def working_dps(digits, order):
    """dps of an order-``order`` jet good to ``digits`` + GUARD (module docstring, item 3)."""
    return max(digits + 30, -(-(digits + GUARD) * (order + 4) // 4))


# --------------------------------------------------------------------------- test functions
def _mat(A):
    n = A.shape[0]
    return mpmath.matrix([[A[i, j] for j in range(n)] for i in range(n)])


def _eig(A):
    return list(mpmath.eig(_mat(A), left=False, right=False))


def _chi(mu, z, deriv=False):
    """det(z I - A) = prod (z - mu_i), or its z-derivative, from the eigenvalues."""
    if not deriv:
        return mpmath.re(mpmath.fprod(z - m for m in mu))
    return mpmath.re(mpmath.fsum(mpmath.fprod(z - m for j, m in enumerate(mu) if j != i)
                                 for i in range(len(mu))))


def _pick(mu, targets):
    """The eigenvalues nearest the targets, in order, each used once; and the rest."""
    rest = list(mu)
    crit = []
    for t in targets:
        k = min(range(len(rest)), key=lambda i: abs(rest[i] - t))
        crit.append(rest.pop(k))
    return crit, rest


def _real_pair(A, mu0):
    """(q, p) of a simple real multiplier nearest mu0: A q = mu q, A^T p = mu p, <p,q> = 1."""
    E, EL, ER = mpmath.eig(_mat(A), left=True, right=True)
    k = min(range(len(E)), key=lambda i: abs(E[i] - mu0))
    q = [mpmath.re(ER[i, k]) for i in range(A.shape[0])]
    p = [mpmath.re(EL[k, i]) for i in range(A.shape[0])]
    s = mpmath.fsum(a * b for a, b in zip(p, q))
    return np.array(q, dtype=object), np.array([x / s for x in p], dtype=object)


def _B(d2, u, v):
    return np.dot(np.dot(d2, v), u)


def _C(d3, u, v, w):
    return np.dot(np.dot(np.dot(d3, w), v), u)


class _Tests:
    """The two defining equations of a ``kind`` point on a ``curve_kind`` curve."""

    def __init__(self, curve_kind, kind, targets):
        self.curve_kind, self.kind = curve_kind, kind
        self.targets = [mpmath.mpc(t) for t in targets]

    def __call__(self, jets):
        A = jets[0]
        mu = _eig(A)
        if self.curve_kind == "ns":
            crit, others = _pick(mu, self.targets)
        else:
            crit, others = _pick(mu, self.targets[:1])
        self.targets = crit if self.curve_kind == "ns" else crit * 2
        kind = self.kind
        if self.curve_kind == "ns":
            g1 = mpmath.re(crit[0] * crit[1]) - 1
            kappa = mpmath.re(crit[0] + crit[1]) / 2
            if kind in ("R1", "R2", "R3", "R4"):
                g2 = kappa - mpmath.cos(2 * mpmath.pi / int(kind[1]))
            elif kind == "CH":
                up = crit[0] if mpmath.im(crit[0]) > 0 else crit[1]
                g2 = kuznetsov_l1(_mat(A), jets[1], jets[2], up)[2]
            elif kind == "LPNS":
                g2 = _chi(mu, 1)
            elif kind == "PDNS":
                g2 = _chi(mu, -1)
            else:                                        # NSNS: the other pair
                z = min(((a, b) for i, a in enumerate(others) for b in others[i + 1:]),
                        key=lambda ab: abs(ab[0] * ab[1] - 1))
                g2 = mpmath.re(z[0] * z[1]) - 1
            return (g1, g2), mu
        s = 1 if self.curve_kind == "fold" else -1
        g1 = _chi(mu, s)
        if kind in ("R1", "R2"):
            g2 = _chi(mu, s, deriv=True)
        elif kind == "LPPD":
            g2 = _chi(mu, -s)
        elif kind in ("PDNS", "LPNS"):
            g2 = mpmath.re(mpmath.fprod(a * b - 1 for i, a in enumerate(others)
                                        for b in others[i + 1:]))
        else:
            q, p = _real_pair(A, s)
            Bqq = _B(jets[1], q, q)
            if kind == "CP":
                g2 = np.dot(p, Bqq) / 2
            else:                                        # GPD: the flip coefficient c
                n = A.shape[0]
                h = mpmath.lu_solve(mpmath.eye(n) - _mat(A), mpmath.matrix(list(Bqq)))
                h = np.array([h[i] for i in range(n)], dtype=object)
                g2 = np.dot(p, _C(jets[2], q, q, q) + 3 * _B(jets[1], q, h)) / 6
        return (g1, g2), mu


# --------------------------------------------------------------------------- the check
def check_codim2(curve, point, *, digits=50, verify=False, maxit=20):
    """Re-solve the codimension-two ``point`` of ``curve`` at ``digits`` by finite
    differences of the mpmath map and compare (see the module docstring).

    ``point``: an element of ``curve.special`` (or its index).  ``verify``: evaluate the
    coefficients a second time with a step 10^-3 times smaller at 20 more digits and
    report the digits to which the two agree (``internal["verify:<name>"]``).
    Returns a :class:`Codim2Check`.
    """
    if isinstance(point, int) and not isinstance(point, bool):
        if not 0 <= point < len(curve.special):
            raise ParameterError("point", point, f"0 .. {len(curve.special) - 1}")
        point = curve.special[point]
    if not isinstance(digits, int) or isinstance(digits, bool) or not 30 <= digits <= 500:
        raise ParameterError("digits", digits, "an integer from 30 to 500")
    if point.kind not in KINDS.get(curve.kind, ()):
        raise ParameterError("point", point.kind, f"a codimension-two point of a {curve.kind} "
                             f"curve: {', '.join(KINDS.get(curve.kind, ()))}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        return _check(curve, point, digits, verify, maxit)


def _check(curve, point, digits, verify, maxit):
    kind, names = point.kind, tuple(curve.names)
    orbit = point.orbit
    omega = curve.fixed.get("omega") if "omega" not in names else None
    times, dps = {}, {}
    k_loc = _LOC_ORDER.get(kind, 1)
    k_nf = max(_NF_ORDER.get(kind, 3), k_loc)
    dps["locate"] = working_dps(digits, k_loc)
    dps["coefficients"] = working_dps(digits, k_nf)
    tests = _Tests(curve.kind, kind, _critical_start(point, curve.kind))

    # ---- location: Newton-Broyden on g(a, b) = 0 ----------------------------------
    t0 = time.perf_counter()
    fd = CurveMapFD(curve.model, names, omega, orbit.n, orbit.p, dps["locate"])
    d = fd.n
    y = _unwrapped(orbit)
    # a multiplier 1 at the point: y(a, b) is a double root there, so solve (y, a, b) jointly
    joint = curve.kind == "fold" or kind in _ONE
    with mpmath.workdps(dps["locate"]):
        state = {"y": y}
        x0 = [mpmath.mpf(point.params[nm]) for nm in names]
        if joint:
            def F(X):
                w, yy = (X[d], X[d + 1]), [X[i] for i in range(d)]
                state["y"] = yy
                vals, _ = tests(fd.jet(w, yy, k_loc))
                return mpmath.matrix(fd.residual(w, yy) + list(vals))
            x0 = y + x0
        else:
            def F(X):
                w = (X[0], X[1])
                state["y"] = fd.fixed_point(w, state["y"])
                vals, _ = tests(fd.jet(w, state["y"], k_loc))
                return mpmath.matrix(list(vals))
        x, G, its = _broyden(F, mpmath.matrix(x0), state, digits, maxit, kind)
        w = (x[len(x) - 2], x[len(x) - 1])
        y = state["y"]
        G = [G[len(G) - 2], G[len(G) - 1]]
    times["locate"] = time.perf_counter() - t0
    calls = fd.calls

    # ---- the coefficients at the located point ----------------------------------
    t0 = time.perf_counter()
    coeffs, kz, jets, y, mu = _coefficients(curve, point, names, omega, w, y, k_nf,
                                            dps["coefficients"], digits, tests, joint)
    times["coefficients"] = time.perf_counter() - t0
    calls += coeffs.pop("_calls")
    internal = {}
    if verify:
        t0 = time.perf_counter()
        dps["verify"] = dps["coefficients"] + 20
        c2, _, _, _, _ = _coefficients(curve, point, names, omega, w, y, k_nf,
                                       dps["verify"], digits, tests, joint, shrink=3)
        calls += c2.pop("_calls")
        with mpmath.workdps(digits):
            for k, v in coeffs.items():
                if k in c2:
                    internal[f"verify:{k}"] = _agree(kind, k, v, c2[k], coeffs, digits)
        times["verify"] = time.perf_counter() - t0

    # ---- agreement --------------------------------------------------------------
    agreement, location = {}, {}
    with mpmath.workdps(digits):
        for nm, v in zip(names, w):
            location[nm] = round(digits_of_agreement(point.params[nm], v), 1)
        for k, fv in point.coefficients.items():
            if k in coeffs and isinstance(fv, (float, complex, int)) and \
                    not isinstance(fv, bool) and _VANISHING.get(kind, {}).get(k, 1):
                agreement[k] = _agree(kind, k, fv, coeffs[k], coeffs, digits)
        if kz:
            c1 = coeffs.get("c1", coeffs.get("g021"))
            if c1 is not None:
                internal["c1: codim2 vs kuznetsov_l1"] = round(digits_of_agreement(c1, kz["c1"]), 1)
            if "l1" in coeffs:
                diff = abs(coeffs["l1"] - kz["l1"])
                internal["l1: codim2 vs kuznetsov_l1 (rel. |c1|)"] = round(
                    float(min(digits, -mpmath.log10(diff / abs(kz["c1"])))) if diff
                    else float(digits), 1)
    times["total"] = times["locate"] + times["coefficients"] + times.get("verify", 0.0)
    with mpmath.workdps(digits):
        G = [+v for v in G]
        params = {nm: +v for nm, v in zip(names, w)}
        yv = tuple(+v for v in y)
    return Codim2Check(kind, curve.kind, names, digits, params, yv, tuple(mu),
                       {"g1": G[0], "g2": G[1]}, coeffs, kz, location, agreement, internal, dps,
                       {k: round(v, 2) for k, v in times.items()}, calls, its, point)


def _broyden(F, x, state, digits, maxit, kind):
    """F(x) = 0 by Newton's method, the Jacobian by forward differences at the start (steps
    balancing truncation and F's accuracy 10^-(digits + GUARD)), then Broyden's updates;
    converged when a step is below 10^-(digits + 5) relative, or below 10^-digits and no
    longer shrinking (the noise floor of F).  (x, F(x), steps)."""
    m = len(x)
    G = F(x)
    y0 = state["y"]
    J = mpmath.matrix(m, m)
    for j in range(m):
        dx = mpmath.mpf(10) ** (-(digits + GUARD) // 2) * max(1, abs(x[j]))
        xp = x.copy()
        xp[j] += dx
        Gp = F(xp)
        state["y"] = y0
        for i in range(m):
            J[i, j] = (Gp[i] - G[i]) / dx
    tol = mpmath.mpf(10) ** (-(digits + 5))
    last = None
    for its in range(1, maxit + 1):
        dx = -mpmath.lu_solve(J, G)
        x = x + dx
        Gn = F(x)
        # Broyden's update J += (dG - J dx) dx^T / |dx|^2
        J = J + (Gn - G - J * dx) * dx.T / (dx.T * dx)[0]
        G = Gn
        step = max(abs(dx[i]) / max(1, abs(x[i])) for i in range(m))
        if step < tol or (last is not None and step < tol * 10 ** 5 and step > last / 10):
            return x, G, its
        last = step
    raise SingularCaseError("newton", f"the {kind} point did not converge in {maxit} "
                            "Newton-Broyden steps of the finite-difference chain")


def _critical_start(point, curve_kind):
    """The float point's critical multipliers (the pair whose product is nearest 1 on an NS
    curve, the multiplier nearest -1 or 1 on a flip or fold curve), to follow them."""
    crit = point.coefficients.get("multipliers_critical")
    if crit:
        return [complex(z) for z in crit]
    mu = [complex(z) for z in point.orbit.multipliers]
    if curve_kind == "ns":
        return list(min(itertools.combinations(mu, 2), key=lambda ab: abs(ab[0] * ab[1] - 1)))
    z = min(mu, key=lambda m: abs(m - (1 if curve_kind == "fold" else -1)))
    return [z, z]


def _agree(kind, name, a, b, coeffs, digits):
    """Digits of agreement of a and b: relative, or for a coefficient that vanishes at the
    point relative to the coefficient that scales it (``_VANISHING``)."""
    scale = _VANISHING.get(kind, {}).get(name)
    if scale is None:
        return round(digits_of_agreement(a, b), 1)
    diff = abs(mpmath.mpmathify(a) - b)
    return round(float(min(digits, -mpmath.log10(diff / abs(coeffs[scale])))) if diff
                 else float(digits), 1)


def _unwrapped(orbit):
    """The orbit's first section point (tau in [0, 2 pi)) as mpf: the Newton start."""
    return [mpmath.mpf(float(v)) for v in orbit.y]


def _coefficients(curve, point, names, omega, w, y, order, dps, digits, tests, joint,
                  shrink=0):
    """The codim2 scalars (mpf/mpc) and Kuznetsov's c1, l1 at w, from FD jets at dps; the
    fixed point polished at dps unless ``joint`` (a double root: y of the location kept)."""
    from ..normal_forms import codim2
    fd = CurveMapFD(curve.model, names, omega, point.orbit.n, point.orbit.p, dps)
    with mpmath.workdps(dps):
        y = y if joint else fd.fixed_point(w, y)
        jets = fd.jet(w, y, order, shrink)
        mu = _eig(jets[0])
    A, d2, d3 = jets[0], jets[1], jets[2] if len(jets) > 2 else None
    kind = point.kind
    fn = {"CH": lambda: codim2.chenciner(*jets[:5], digits=digits),
          "GPD": lambda: codim2.degenerate_flip(*jets[:5], digits=digits),
          "R1": lambda: codim2.resonance_1_1(A, d2, digits=digits),
          "R2": lambda: codim2.resonance_1_2(A, d2, d3, digits=digits),
          "R3": lambda: codim2.resonance_1_3(A, d2, d3, digits=digits),
          "R4": lambda: codim2.resonance_1_4(A, d2, d3, digits=digits),
          "LPNS": lambda: codim2.fold_ns(A, d2, d3, digits=digits),
          "PDNS": lambda: codim2.flip_ns(A, d2, d3, digits=digits),
          "LPPD": lambda: codim2.fold_flip(A, d2, d3, digits=digits),
          "CP": lambda: codim2.cusp(A, d2, d3, digits=digits)}.get(kind)
    out = _scalars(fn()) if fn is not None else {}
    kz = {}
    if kind in ("CH", "R4", "PDNS", "NSNS"):      # a simple pair, no singular solve
        with mpmath.workdps(digits):
            # the pair codim2 chose (on a flip or fold curve the critical multiplier is real)
            up = out.get("lam") or max(tests.targets, key=lambda z: mpmath.im(z))
            lam, c1, l1 = kuznetsov_l1(_mat(A), d2, d3, up)
            kz = {"lam": lam, "c1": c1, "l1": l1}
    out["_calls"] = fd.calls
    return out, kz, jets, y, mu


def _jet_on(at, n, order, h):
    """The symmetric derivative tensors of orders 1..order from P on the grid y + h d."""
    out = []
    for k in range(1, order + 1):
        T = np.empty((n,) * (k + 1), dtype=object)
        for axes in itertools.combinations_with_replacement(range(n), k):
            sten = _stencil(axes, n)
            v = []
            for s in (1, 2):
                acc = [mpmath.mpf(0)] * n
                for d, c in sten:
                    p = at(tuple(s * x for x in d))
                    for i in range(n):
                        acc[i] += c * p[i]
                v.append([x / (2 * s * h) ** k for x in acc])
            val = [(4 * a - b) / 3 for a, b in zip(*v)]      # Richardson: O(h^4)
            for perm in set(itertools.permutations(axes)):
                for i in range(n):
                    T[(i,) + perm] = val[i]
        out.append(T)
    return out


def _scalars(res):
    """The numeric scalar fields of a codim2 result (mpf, mpc; vectors, flags left out)."""
    import dataclasses
    out = {}
    for f in dataclasses.fields(res):
        v = getattr(res, f.name)
        if isinstance(v, (mpmath.mpf, mpmath.mpc)):
            out[f.name] = v
        elif isinstance(v, (float, complex)) and not isinstance(v, bool):
            out[f.name] = mpmath.mpmathify(v)
    return out
