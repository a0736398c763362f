"""High-precision re-evaluation of the Hopf chain, two independent ways (issue 4, item 6).

Chain A (the project's own chain on the mpmath backend, >= 50 digits):
period-1 orbit of eqs. (10)–(18) -> generated jets (eqs. 33–38) -> v_c by the
secant method on |lambda1(omega)|^2 - 1 -> order-3 jet, F11 -> the normal form
of :mod:`symvi.normal_forms.normal_form` (eigen-decomposition, (A1)–(A3), Kuznetsov, the
paper's reduction), all at ``digits``.

Chain B (shares no derivation code with chain A): only the numeric map P of
:mod:`symvi.paper.modal_map` (the paper's modal closed form; for a Model,
:mod:`symvi.maps.impact`) evaluated in mpmath at ``digits`` + 30 or more.  The fixed point
is found by Newton's method on P(y) - y - (0, 0, 0, 2 pi); the Jacobian, d2 and
d3 by Richardson-extrapolated central differences (steps h and 2h, h balanced
against the working precision for each order); v_c by the secant method on
|lambda1|^2 - 1 of the finite-difference Jacobian; d|lambda1|/domega by
Richardson differences of |lambda1| along the Newton-tracked branch; and l1 by
Kuznetsov's formula written out again here on mpmath matrices (no
:mod:`symvi.normal_forms.normal_form` code).

Both chains use the parameters exactly as the binary floats of ``Params``
(e.g. r = 0.8 is 0.8000000000000000444...), so they solve the same problem.

References
----------
[Kuznetsov, Elements of Applied Bifurcation Theory] Yu. A. Kuznetsov, Elements
of Applied Bifurcation Theory, 3rd ed., Springer 2004, Sec. 5.4.
"""
import itertools
import warnings
from dataclasses import dataclass

import mpmath

from ..errors import NearSingularWarning, ParameterError, SingularCaseError


@dataclass(frozen=True)
class ChainResult:
    """v_c, the fixed point, lambda1, d|lambda1|/domega and l1 from one chain (mpf/mpc)."""

    name: str
    digits: int
    omega_c: object
    y: tuple
    lam: object
    dmod_domega: object
    l1: object
    c1: object
    f1_paper: object = None
    f1_wan: object = None


@dataclass(frozen=True)
class MpCheck:
    """Chains A and B, and the digits to which they (and float64) agree."""

    params: object
    branch: str
    chain_a: ChainResult
    chain_b: ChainResult
    float_point: object
    agreement: dict        # quantity -> {"A-B": digits, "float-A": digits}

    def as_dict(self):
        def s(x):
            return mpmath.nstr(x, self.chain_a.digits) if x is not None else None

        def chain(c):
            return {"digits": c.digits, "omega_c": s(c.omega_c), "dmod_domega": s(c.dmod_domega),
                    "l1": s(c.l1), "lam": [s(mpmath.re(c.lam)), s(mpmath.im(c.lam))],
                    "y": [s(v) for v in c.y], "f1_paper": s(c.f1_paper), "f1_wan": s(c.f1_wan)}
        return {("model" if _is_model(self.params) else "params"): self.params.as_dict(),
                "branch": self.branch,
                "chain_a": chain(self.chain_a), "chain_b": chain(self.chain_b),
                "agreement_digits": self.agreement}


def digits_of_agreement(a, b):
    """-log10 of the relative difference (capped at the working precision)."""
    a, b = mpmath.mpmathify(a), mpmath.mpmathify(b)
    if not (mpmath.isfinite(a) and mpmath.isfinite(b)):
        return 0.0                       # min() and max() below would drop a NaN
    d = abs(a - b)
    s = max(abs(a), abs(b))
    if d == 0:
        return float(mpmath.mp.dps)
    return float(min(mpmath.mp.dps, -mpmath.log10(d / s)))


# --------------------------------------------------------------------------- chain A
def _secant_root(f, omega0, digits, chain, maxsteps=60):
    """v_c: the root of f(omega) = |lambda1|^2 - 1 by the secant method from the float64
    omega0, to the working precision of f.

    The stopping rule is on the steps, not on |f|: f carries the rounding of the whole
    chain (and, in chain B, the truncation of the finite differences), so a fixed
    residual tolerance such as 10^(-digits) is either unreachable at high precision
    (mpmath.findroot's ValueError from about 125 digits) or reached only after the
    secant has divided by f1 - f0 = 0 at the noise floor (ZeroDivisionError).  The
    iteration stops when the step is below 10^(-digits) relative, when f1 = f0 or
    f1 = 0 (nothing left to resolve), or when the steps stop shrinking at a level
    below 10^(-digits/2) (the noise floor of f; the secant converges superlinearly
    above it).  The agreement of the two chains then says how many digits are right."""
    x0 = mpmath.mpf(omega0)
    x1 = x0 + mpmath.mpf("1e-9")
    f0, f1 = f(x0), f(x1)
    tiny = mpmath.mpf(10) ** (-digits)
    prev = None
    for _ in range(maxsteps):
        if f1 == 0 or (f1 == f0 and prev is not None):
            return x1
        if f1 == f0:
            break                      # flat at the start: no root to follow
        step = f1 * (x1 - x0) / (f1 - f0)
        if not mpmath.isfinite(step):
            break
        x0, f0 = x1, f1
        x1 = x1 - step
        if abs(step) <= tiny * abs(x1):
            return x1
        if prev is not None and abs(step) >= prev / 2 and abs(step) < mpmath.sqrt(tiny):
            return x1 if abs(f(x1)) <= abs(f0) else x0      # at the noise floor: the better
        prev = abs(step)
        f1 = f(x1)
    raise SingularCaseError("no-convergence", f"chain {chain}: the secant method on "
                            f"|lambda1|^2 = 1 did not converge in {maxsteps} steps at "
                            f"{digits} digits")


def _is_model(params):
    from ..model import Model
    return isinstance(params, Model)


def _orbit_mp(params, omega, branch, digits):
    """The period-1 orbit of ``branch`` at an mpf omega, at ``digits`` (Params or Model)."""
    from ..paper.orbit import period1_orbits
    orbs = {o.branch: o for o in period1_orbits(params, omega, digits=digits)}
    o = orbs.get(branch)
    if o is None or not o.admissible:
        raise SingularCaseError("no-admissible-orbit", f"branch {branch} is not admissible "
                                f"at omega = {mpmath.nstr(omega, 15)}")
    return o


def chain_a(params, omega0, branch, digits, lam0):
    """The project's chain on the mpmath backend at ``digits``."""
    from ..paper.jets import jet
    from ..paper.reduction import normal_form     # Kuznetsov's l1 and the paper's f1
    with mpmath.workdps(digits):
        target = [mpmath.mpc(lam0)]

        def lam1(w):
            o = _orbit_mp(params, w, branch, digits)
            z = min(o.multipliers, key=lambda x: abs(x - target[0]))
            target[0] = z
            return z

        def f(w):
            return abs(lam1(w)) ** 2 - 1
        wc = _secant_root(f, omega0, digits, "A")
        o = _orbit_mp(params, wc, branch, digits)
        j = jet(params, wc, order=3, digits=digits, orbit=o)
        nf = normal_form(j.jacobian, j.d2, j.d3, j.dA, digits=digits)
        return ChainResult("A: orbit + generated jets + normal_form (mpmath)", digits, wc,
                           tuple(o.y), nf.lam, nf.dmod_dv, nf.l1, nf.c1,
                           nf.f1_printed, nf.f1_wan)


# --------------------------------------------------------------------------- chain B
class _MapFD:
    """Finite differences of the numeric map P in mpmath (no generated code)."""

    def __init__(self, params, dps, n=4):
        self.params, self.dps, self.n = params, dps, n

    def P(self, w, y):
        if _is_model(self.params):
            from ..maps.impact import poincare_map
        else:                                     # the paper's modal map: independent
            from ..paper.modal_map import poincare_map
        s = poincare_map(self.params, w, y, digits=self.dps)
        if s.status != "impact":
            raise SingularCaseError("grazing", f"P is not smooth here (flight ends in {s.status})")
        return [*s.y[:-1], s.tau_unwrapped]

    def residual(self, w, y):
        p = self.P(w, y)
        r = [p[i] - y[i] for i in range(self.n)]
        r[-1] -= 2 * mpmath.pi
        return r

    def _h(self, order):
        # balance truncation h^4 (after Richardson) against rounding 10^-dps / h^order
        return mpmath.mpf(10) ** (-(self.dps // (order + 4)))

    def _stencil(self, w, y, axes, h):
        """Central mixed difference d^k P / dy_axes at y (any repeated axes), step h."""
        k = len(axes)
        acc = [mpmath.mpf(0)] * self.n
        for signs in itertools.product((1, -1), repeat=k):
            z = list(y)
            for s, a in zip(signs, axes):
                z[a] += s * h
            p = self.P(w, z)
            sg = 1
            for s in signs:
                sg *= s
            for i in range(self.n):
                acc[i] += sg * p[i]
        return [v / (2 * h) ** k for v in acc]

    def derivative(self, w, y, axes, richardson=True):
        h = self._h(len(axes))
        d1 = self._stencil(w, y, axes, h)
        if not richardson:
            return d1
        d2 = self._stencil(w, y, axes, 2 * h)
        return [(4 * a - b) / 3 for a, b in zip(d1, d2)]

    def jacobian(self, w, y, richardson=True):
        n = self.n
        cols = [self.derivative(w, y, (j,), richardson) for j in range(n)]
        return mpmath.matrix([[cols[j][i] for j in range(n)] for i in range(n)])

    def fixed_point(self, w, y0):
        """Newton on P(y) - y - (0, 0, 0, 2 pi)."""
        y = [mpmath.mpf(v) for v in y0]
        tol = mpmath.mpf(10) ** (-self.dps + 8)
        for _ in range(40):
            r = self.residual(w, y)
            if all(abs(v) < tol for v in r):       # False for a NaN, unlike max()
                return y
            J = self.jacobian(w, y, richardson=False) - mpmath.eye(self.n)
            dy = mpmath.lu_solve(J, mpmath.matrix(r))
            y = [y[i] - dy[i] for i in range(self.n)]
        raise SingularCaseError("newton", "Newton on P(y) = y did not converge in chain B")

    def jets(self, w, y):
        n = self.n
        A = self.jacobian(w, y)
        d2 = [[[None] * n for _ in range(n)] for _ in range(n)]
        d3 = [[[[None] * n for _ in range(n)] for _ in range(n)] for _ in range(n)]
        for j, k in itertools.combinations_with_replacement(range(n), 2):
            v = self.derivative(w, y, (j, k))
            for i in range(n):
                d2[i][j][k] = d2[i][k][j] = v[i]
        for t in itertools.combinations_with_replacement(range(n), 3):
            v = self.derivative(w, y, t)
            for i in range(n):
                for p in set(itertools.permutations(t)):
                    d3[i][p[0]][p[1]][p[2]] = v[i]
        return A, d2, d3


def _critical(A, target):
    """(lambda1, q with ||q||_2 = 1, u = conj(p)^T with u q = 1): mpmath.eig, left and right."""
    E, EL, ER = mpmath.eig(A, left=True, right=True)
    k = min(range(A.rows), key=lambda i: abs(E[i] - target))
    q = ER[:, k]
    q = q / mpmath.norm(q)
    u = EL[k, :]
    u = u / (u * q)[0]
    return E[k], q, u


def kuznetsov_l1(A, d2, d3, target):
    """c1, l1 by Kuznetsov's formula on mpmath matrices (independent of symvi.normal_forms.normal_form)."""
    lam, q, u = _critical(A, target)
    qb = q.conjugate()
    n = A.rows

    def B(x, y):
        return mpmath.matrix([sum(d2[i][j][k] * x[j] * y[k] for j in range(n) for k in range(n))
                              for i in range(n)])

    def C(x, y, z):
        return mpmath.matrix([sum(d3[i][j][k][l] * x[j] * y[k] * z[l] for j in range(n)
                                  for k in range(n) for l in range(n)) for i in range(n)])
    I = mpmath.eye(n)
    h11 = mpmath.lu_solve(lam * mpmath.conj(lam) * I - A, B(q, qb))
    h20 = mpmath.lu_solve(lam * lam * I - A, B(q, q))
    c1 = (u * (C(q, q, qb) + 2 * B(q, h11) + B(qb, h20)))[0] / 2
    return lam, c1, mpmath.re(mpmath.conj(lam) * c1) / abs(lam)


def chain_b(params, omega0, branch, digits, lam0, y0):
    """Finite differences of P only, at ``digits`` plus guard digits for the differences:
    the Richardson-extrapolated Jacobian is good to ~4/5 of the working digits (h =
    10^(-dps/5)), so the guard grows with ``digits`` (30, or digits/4 + 10 from 80 on)
    for v_c to reach ``digits``."""
    dps = digits + max(30, digits // 4 + 10)
    with mpmath.workdps(dps):
        fd = _MapFD(params, dps, len(y0))
        state = {"y": [mpmath.mpf(v) for v in y0], "lam": mpmath.mpc(lam0)}

        def lam1(w):
            y = fd.fixed_point(w, state["y"])
            state["y"] = y
            E = mpmath.eig(fd.jacobian(w, y), left=False, right=False)
            z = min(E, key=lambda x: abs(x - state["lam"]))
            state["lam"] = z
            return z

        wc = _secant_root(lambda w: abs(lam1(w)) ** 2 - 1, omega0, digits, "B")
        y = fd.fixed_point(wc, state["y"])
        A, d2, d3 = fd.jets(wc, y)
        lam, c1, l1 = kuznetsov_l1(A, d2, d3, state["lam"])
        # d|lambda1|/domega along the branch, Richardson on central differences
        hw = mpmath.mpf(10) ** (-(dps // 5))

        def m(w):
            return abs(lam1(w))
        D1 = (m(wc + hw) - m(wc - hw)) / (2 * hw)
        D2 = (m(wc + 2 * hw) - m(wc - 2 * hw)) / (4 * hw)
        dmod = (4 * D1 - D2) / 3
        return ChainResult("B: finite differences of P + Kuznetsov (mpmath)", digits, wc,
                           tuple(y), lam, dmod, l1, c1)


def mpcheck(params, omega_min, omega_max, *, digits=50, index=0):
    """Run float64 hopf_points, then chains A and B at the ``index``-th point; compare."""
    from ..analysis.hopf import spans_text
    from ..paper.hopf import hopf_points
    _check_digits(digits)
    res = hopf_points(params, omega_min, omega_max)
    if not res.points:
        spans = spans_text(res.uncertified, 6)
        raise SingularCaseError("no-hopf-point", f"no Neimark–Sacker point found in "
                                f"[{omega_min}, {omega_max}]" + (
                                    f" (not certified on {spans}: a point there may have "
                                    "been missed)" if spans else ""))
    if not (isinstance(index, int) and 0 <= index < len(res.points)):
        raise ParameterError("index", index, f"0 .. {len(res.points) - 1}")
    pt = res.points[index]
    return check_point(params, pt, digits=digits)


def _check_digits(digits):
    if not isinstance(digits, int) or isinstance(digits, bool) or not 30 <= digits <= 500:
        raise ParameterError("digits", digits, "an integer from 30 to 500")


def check_points(params, points, *, digits=50):
    """Chains A and B at each float64 HopfPoint of ``points`` (a scan's, in its order:
    ``symvi hopf --digits``); ``digits`` from 30 to 500.  Seconds a point: a progress bar
    on stderr (:mod:`symvi.progress`) says so while it runs."""
    from ..progress import Progress
    _check_digits(digits)
    out = []
    with Progress(len(points), f"mpmath checks at {digits} digits") as bar:
        for pt in points:
            out.append(check_point(params, pt, digits=digits))
            bar.update()
    return out


def check_point(params, pt, *, digits=50):
    """Chains A and B at a float64 HopfPoint ``pt``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        a = chain_a(params, pt.omega_c, pt.branch, digits, pt.multiplier)
        b = chain_b(params, pt.omega_c, pt.branch, digits, pt.multiplier, pt.orbit.y)
    agree = {}
    with mpmath.workdps(digits):
        for name, fa, fb, ff in (("omega_c", a.omega_c, b.omega_c, pt.omega_c),
                                 ("dmod_domega", a.dmod_domega, b.dmod_domega, pt.dmod_domega),
                                 ("l1", a.l1, b.l1, pt.l1)):
            agree[name] = {"A-B": round(digits_of_agreement(fa, fb), 1),
                           "float-A": round(digits_of_agreement(ff, fa), 1)}
    return MpCheck(params, pt.branch, a, b, pt, agree)

