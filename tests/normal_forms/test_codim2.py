"""Known-answer tests of symvi.codim2: maps built with chosen codimension-two normal forms.

Each map is a critical normal form N_c in coordinates u (z = u1 + i u2 for a complex
pair), two contracting coordinates w coupled so that {w = 0} stays invariant, disguised
by a near-identity polynomial change Phi and a rational orthogonal L (see
``_codim2_maps``).  With ||q||_2 = 1 the Kuznetsov coordinate of a complex pair is
w = z / sqrt(2) (q = L (1, -i, 0..)/sqrt(2)), so a coefficient of z^j conj(z)^k
(j + k = m) in N_c is multiplied by 2^((m - 1)/2); real critical coordinates map one to
one (up to the sign of q).  Jets are exact to 60 digits; float64 results are checked to
1e-10, mpmath results (digits=50) to 1e-30.
"""
import dataclasses
import functools

import mpmath
import numpy as np
import pytest

from . import _codim2_maps as m
from symvi.errors import SingularCaseError
from symvi.normal_forms import codim2
from symvi.normal_forms.normal_form import (_kuznetsov, flip_coefficient, fold_coefficient,
                                            real_critical)

I = mpmath.mpc(0, 1)
F_TOL, MP_TOL = 1e-10, 1e-30


@pytest.fixture(autouse=True)
def _precision():
    """Expected values are formed at the maps' 60 digits (codim2 sets its own precision)."""
    with mpmath.workdps(m.DPS):
        yield


def mp(x):
    return mpmath.mpmathify(x)


def close(got, want, tol):
    """|got - want| <= tol * max(1, |want|), for float/complex/mpmath numbers."""
    with mpmath.workdps(m.DPS):
        return abs(mp(got) - mp(want)) <= tol * max(1, abs(mp(want)))


def both(fn, jet, **kw):
    """The result on float64 jets and on mpmath jets at 50 digits."""
    return [(fn(*m.to_float(jet), **kw), F_TOL), (fn(*jet, digits=50, **kw), MP_TOL)]


def sign_of(q, v):
    """+1 or -1: the sign with which the computed real vector q equals v."""
    s = float(np.real(np.dot(np.array([complex(x) for x in q]),
                             np.array([float(x) for x in v]))))
    assert abs(abs(s) - 1) < 1e-8
    return 1 if s > 0 else -1


def small_residuals(r, tol=1e-12):
    assert r.residuals and max(r.residuals.values()) < tol, r.residuals


# --------------------------------------------------------------------------- the maps
def _lam_ns():
    return mpmath.mpc(3, 4) / 5          # on the unit circle, exactly; theta not resonant


@functools.lru_cache(maxsize=None)
def ch_map(re_a, seed):
    """z -> lam z (1 + a|z|^2 + b|z|^4), generic disguise, order 5."""
    with mpmath.workdps(m.DPS):
        lam, a, b = _lam_ns(), mpmath.mpc(re_a, "0.7"), mpmath.mpc("-0.4", "0.25")

        def crit(u):
            z, r = m.complex_z(u), m.complex_z(u) * m.conj_z(u)
            Z = z * lam * (1 + r * a + r * r * b)
            return [Z.real(), Z.imag()]

        jet, L = m.build(4, 2, m.with_stable(crit, 2, 5), 5, seed=seed)
        return jet, dict(lam=lam, a=a, b=b)


@functools.lru_cache(maxsize=None)
def r1_map(seed):
    with mpmath.workdps(m.DPS):
        a, b = mp("0.6"), mp("-0.5")
        jet, L = m.build(4, 2, m.with_stable(
            lambda u: [u[0] + u[1], u[1] + u[0] * u[0] * a + u[0] * u[1] * b], 2, 3), 3, seed=seed)
        return jet, L, dict(a=a, b=b)


@functools.lru_cache(maxsize=None)
def r2_map(seed):
    with mpmath.workdps(m.DPS):
        C, D = mp("-0.7"), mp("0.4")
        jet, L = m.build(4, 2, m.with_stable(
            lambda u: [-u[0] + u[1], -u[1] + u[0] * u[0] * u[0] * C + u[0] * u[0] * u[1] * D],
            2, 3), 3, seed=seed)
        return jet, dict(C=C, D=D)


@functools.lru_cache(maxsize=None)
def r3_map(seed, generic):
    with mpmath.workdps(m.DPS):
        lam = mpmath.expjpi(mpmath.mpf(2) / 3)
        b1, c1 = mpmath.mpc("0.5", "-0.3"), mpmath.mpc("-0.2", "0.6")

        def crit(u):
            z, zb = m.complex_z(u), m.conj_z(u)
            Z = z * lam + zb * zb * b1 + z * z * zb * c1
            return [Z.real(), Z.imag()]

        jet, L = m.build(4, 2, m.with_stable(crit, 2, 3), 3, seed=seed, generic=generic)
        return jet, dict(lam=lam, b1=b1, c1=c1)


@functools.lru_cache(maxsize=None)
def r4_map(seed):
    with mpmath.workdps(m.DPS):
        c1, d1 = mpmath.mpc("-0.3", "0.5"), mpmath.mpc("0.4", "0.2")

        def crit(u):
            z, zb = m.complex_z(u), m.conj_z(u)
            Z = z * I + z * z * zb * c1 + zb * zb * zb * d1
            return [Z.real(), Z.imag()]

        jet, L = m.build(4, 2, m.with_stable(crit, 2, 3), 3, seed=seed)
        return jet, dict(c1=c1, d1=d1)


LPNS = dict(f200="0.5", f011="-0.4", g110=("0.3", "-0.2"), f300="0.25", f111="-0.35",
            g210=("-0.15", "0.45"), g021=("0.2", "-0.3"))
PDNS = dict(f300="-0.3", f111="0.45", g210=("0.2", "0.1"), g021=("-0.25", "0.35"))


def _coeffs(spec):
    return {k: (mpmath.mpc(*v) if isinstance(v, tuple) else mp(v)) for k, v in spec.items()}


@functools.lru_cache(maxsize=None)
def xz_map(mu, seed, generic):
    """xi -> mu xi + ..., z -> lam z + ... (LPNS for mu = 1, PDNS for mu = -1), n = 5."""
    with mpmath.workdps(m.DPS):
        lam = _lam_ns()
        k = _coeffs(LPNS if mu == 1 else PDNS)
        k0 = {n: k.get(n, 0) for n in ("f200", "f011", "g110")}

        def crit(u):
            xi, z, zb = u[0], m.complex_z(u[1:]), m.conj_z(u[1:])
            r = z * zb
            X = (xi * mu + xi * xi * k0["f200"] + r * k0["f011"] + xi * xi * xi * k["f300"]
                 + xi * r * k["f111"])
            Z = z * lam + xi * z * k0["g110"] + xi * xi * z * k["g210"] + z * r * k["g021"]
            return [X.real(), Z.real(), Z.imag()]

        jet, L = m.build(5, 3, m.with_stable(crit, 3, 3), 3, seed=seed, generic=generic)
        return jet, L, dict(lam=lam, **k)


LPPD = dict(a20="0.4", a02="-0.3", b11="0.6", a30="0.2", a12="-0.45", b21="0.35", b03="-0.25")


@functools.lru_cache(maxsize=None)
def lppd_map(seed, generic):
    with mpmath.workdps(m.DPS):
        k = _coeffs(LPPD)

        def crit(u):
            x, y = u
            return [x + x * x * k["a20"] + y * y * k["a02"] + x * x * x * k["a30"]
                    + x * y * y * k["a12"],
                    -y + x * y * k["b11"] + x * x * y * k["b21"] + y * y * y * k["b03"]]

        if generic:
            jet, L = m.build(4, 2, m.with_stable(crit, 2, 3), 3, seed=seed, generic=True)
        else:      # resonant: xi1^2, xi2^2 in the xi1 component, xi1 xi2 in the xi2 component
            res = lambda i, e: (e[0] == 1) == (i == 1)   # noqa: E731
            jet, L = m.build_general(4, 2, m.with_stable(crit, 2, 3), seed=seed, resonant=res)
        return jet, L, k


@functools.lru_cache(maxsize=None)
def line_map(mu, quad, cub, quint, seed):
    """xi -> mu xi + quad xi^2 + cub xi^3 + quint xi^5 (CP: mu = 1, GPD: mu = -1), n = 3."""
    order = 5 if quint else 3
    with mpmath.workdps(m.DPS):
        a, c, e = mp(quad), mp(cub), mp(quint)

        def crit(u):
            x = u[0]
            out = x * mu + x * x * a + x * x * x * c
            if order == 5:
                out = out + x * x * x * x * x * e
            return [out]

        jet, L = m.build(3, 1, m.with_stable(crit, 1, order), order, seed=seed)
        return jet, L, dict(a=a, c=c, e=e)


# --------------------------------------------------------------------------- Chenciner
@pytest.mark.parametrize("re_a", ["0", "0.3"])
def test_chenciner_known(re_a):
    """c1 = 2 lam a, Re(conj(lam) c2) = 4 Re b, l1 = 2 Re a, l2 = 4 (Re b + (Im a)^2/2),
    l2_matcont = 4 Re(b - a^2/2), under a generic disguise (quadratic and cubic Phi with
    resonant terms): Re b is invariant under w -> w + k w|w|^2 (it adds 2i Im(k conj(a))
    to b).  re_a = 0.3 (l1 != 0) needs h22's 4 Re(conj(lam) g21) h11 term."""
    jet, k = ch_map(re_a, 1)
    with mpmath.workdps(m.DPS):
        lam, a, b = k["lam"], k["a"], k["b"]
        want = dict(c1=2 * lam * a, l1=2 * a.real, l2=4 * (b.real + a.imag ** 2 / 2),
                    l2_matcont=4 * (b - a * a / 2).real, reb=4 * b.real)
    for r, tol in both(codim2.chenciner, jet):
        for name in ("c1", "l1", "l2", "l2_matcont"):
            assert close(getattr(r, name), want[name], tol), (name, r.backend)
        with mpmath.workdps(m.DPS):
            assert close((mpmath.conj(mp(r.lam)) * mp(r.c2)).real, want["reb"], tol)
        assert close(r.lam, lam, tol)
        if r.backend == "float64":
            small_residuals(r)
    if re_a == "0":
        assert abs(want["l2"] - want["l2_matcont"]) < 1e-40     # equal at l1 = 0
        assert r.l2 < 0                                          # the constructed case


def test_chenciner_wrong_pairing_detected(monkeypatch):
    """A q paired with the wrong adjoint vector is caught.  (i) p of conj(lambda), i.e.
    conj(p): <conj(p), q> = 0, so no normalisation exists; Kuznetsov's c1 formula then
    gives another number and the bordered solve refuses (never a silent NaN).
    (ii) p contaminated by it, p + conj(p) (still <p, q> = 1): c1 and l2 change, and the
    residual |A^T p - conj(lambda) p| reports it."""
    jet, _ = ch_map("0", 1)
    fj = m.to_float(jet)
    good = codim2.chenciner(*fj)
    real_eigen = codim2._eigen
    from symvi.numerics.backend import FLOAT64
    A = fj[0].astype(complex)
    e = real_eigen(FLOAT64, A, None)
    c1_wrong = _kuznetsov(FLOAT64, A, fj[1].astype(complex), fj[2].astype(complex),
                          dataclasses.replace(e, p=np.conj(e.p)))[0]
    assert abs(c1_wrong - good.c1) > 0.1
    monkeypatch.setattr(codim2, "_eigen",
                        lambda *a: dataclasses.replace(real_eigen(*a), p=np.conj(real_eigen(*a).p)))
    with pytest.raises(SingularCaseError):
        codim2.chenciner(*fj)
    monkeypatch.setattr(codim2, "_eigen", lambda *a: dataclasses.replace(
        real_eigen(*a), p=real_eigen(*a).p + np.conj(real_eigen(*a).p)))
    bad = codim2.chenciner(*fj)
    assert abs(bad.c1 - good.c1) > 0.1 and abs(bad.l2 - good.l2) > 0.1
    assert bad.residuals["|A^T p - conj(lam) p|"] > 0.1
    assert bad.residuals["|<p,q> - 1|"] < 1e-12


# --------------------------------------------------------------------------- R1, R2
def test_resonance_1_1_known():
    """(a, b) = sigma (0.6, -0.5) with sigma the sign of q0 against L e1 (a, b are odd in
    (q0, q1)); s = sign(a (b - 2a)) = -1 is sign-free; generic disguise."""
    jet, L, k = r1_map(2)
    for r, tol in both(codim2.resonance_1_1, jet[:2]):
        sg = sign_of(r.q0, L[:, 0])
        assert close(r.a, sg * k["a"], tol) and close(r.b, sg * k["b"], tol)
        assert r.s == -1
        assert max(r.residuals.values()) < (1e-12 if tol == F_TOL else 1e-40), r.residuals


def _time1(field, order):
    """Jets at 0 of the time-1 map of the planar polynomial field (x' = y, y' = field)
    by Picard iteration, truncated at ``order`` (SymPy, exact rationals)."""
    import itertools
    import sympy as sp
    x, y, t, s, eps = sp.symbols("x y t s eps")
    F = [y, field(x, y)]
    X = [x, y]
    for _ in range(2 * order + 2):
        Fx = [sp.expand(f.subs({x: X[0], y: X[1]}, simultaneous=True)) for f in F]
        X = [sp.expand(v + sp.integrate(fx.subs(t, s), (s, 0, t))) for v, fx in zip((x, y), Fx)]
        X = [sp.expand(v.subs({x: eps * x, y: eps * y}, simultaneous=True)).series(
            eps, 0, order + 1).removeO().subs(eps, 1) for v in X]
    P = [sp.expand(v.subs(t, 1)) for v in X]
    out = []
    for k in range(1, order + 1):
        T = np.zeros((2,) * (k + 1))
        for idx in itertools.product(range(2), repeat=k):
            for i in range(2):
                T[(i,) + idx] = float(sp.diff(P[i], *[(x, y)[j] for j in idx]).subs({x: 0, y: 0}))
        out.append(T)
    return out


@pytest.mark.slow
def test_r1_bt_flow():
    """The time-1 map of the Bogdanov–Takens flow x' = y, y' = A x^2 + B x y has
    a = A and b = B + 2A: MatContM's s = sign(a (b - 2a)) is the BT sign(A B)."""
    A_, B_ = 0.7, -0.4
    r = codim2.resonance_1_1(*_time1(lambda x, y: A_ * x ** 2 + B_ * x * y, 2))
    assert r.a == pytest.approx(A_, rel=1e-12) and r.b - 2 * r.a == pytest.approx(B_, rel=1e-12)
    assert r.s == np.sign(A_ * B_)


def test_resonance_1_2_known():
    """C = -0.7, D = 0.4 exactly (odd in xi, so sign-free), generic disguise."""
    jet, k = r2_map(3)
    for r, tol in both(codim2.resonance_1_2, jet):
        assert close(r.C, k["C"], tol) and close(r.D, k["D"], tol)
        assert close(r.flow[0], 4 * k["C"], tol) and close(r.flow[1], -2 * k["D"] - 6 * k["C"], tol)
        assert max(r.residuals.values()) < (1e-12 if tol == F_TOL else 1e-40), r.residuals


@pytest.mark.slow
def test_r2_flow():
    """F = -(time-1 map of x' = y, y' = C1 x^3 + D1 x^2 y) has C = C1, D = -D1 - 3 C1, so
    (4C, -2D - 6C) = (4 C1, 2 D1): the field whose time-1 map is F^2 (time-2 of the
    original, rescaled y -> 2y)."""
    C1, D1 = 0.6, -0.3
    jet = [-t for t in _time1(lambda x, y: C1 * x ** 3 + D1 * x ** 2 * y, 3)]
    r = codim2.resonance_1_2(*jet)
    assert r.C == pytest.approx(C1, rel=1e-12) and r.D == pytest.approx(-D1 - 3 * C1, rel=1e-12)
    assert r.flow == pytest.approx((4 * C1, 2 * D1), rel=1e-12)


def test_jordan_refusals():
    """A semisimple double 1, a simple 1 and no 1 are refused with their reason."""
    z2, z3 = np.zeros((4, 4, 4)), np.zeros((4, 4, 4, 4))
    M = np.array(m.cayley(4, 7), dtype=float)
    with pytest.raises(SingularCaseError, match="semisimple"):
        codim2.resonance_1_1(M @ np.diag([1, 1, 0.2, 0.3]) @ M.T, z2)
    with pytest.raises(SingularCaseError, match="simple"):
        codim2.resonance_1_1(M @ np.diag([1, 0.5, 0.2, 0.3]) @ M.T, z2)
    with pytest.raises(SingularCaseError, match="no-multiplier"):
        codim2.resonance_1_1(np.diag([0.9, 0.5, 0.2, 0.3]), z2)
    with pytest.raises(SingularCaseError, match="semisimple"):
        codim2.resonance_1_2(np.diag([-1, -1, 0.2, 0.3]), z2, z3)
    with pytest.raises(SingularCaseError, match="triple"):
        J3 = np.array([[1, 1, 0, 0], [0, 1, 1, 0], [0, 0, 1, 0], [0, 0, 0, 0.3]])
        codim2.resonance_1_1(J3, z2)


def test_jordan_wrong_pairing_detected(monkeypatch):
    """Mixing the generalised adjoint vector into the eigenvector, p1 -> p1 + p0 (so
    <p1, q1> = 1 still), changes (a, b); the residual |<p1,q0>| reports it."""
    jet, L, k = r1_map(2)
    good = codim2.resonance_1_1(*m.to_float(jet)[:2])
    real = codim2._jordan
    monkeypatch.setattr(codim2, "_jordan",
                        lambda *a: dataclasses.replace(real(*a), p1=real(*a).p1 + real(*a).p0))
    bad = codim2.resonance_1_1(*m.to_float(jet)[:2])
    assert abs(bad.a - good.a) > 0.1 or abs(bad.b - good.b) > 0.1


# --------------------------------------------------------------------------- R3, R4
def test_resonance_1_3_known():
    """|b1_K| = sqrt(2) |b1|, and coef = (lam^2 c1/|b1|^2 - 1)/3 is scale-free.  Plain
    disguise: c1_K = 2 c1 and coef exactly.  Generic disguise (resonant conj(z)^2 terms in
    Phi): Re(coef) is unchanged, Im(coef) is not (the claim of Resonance13)."""
    with mpmath.workdps(m.DPS):
        _, k = r3_map(4, False)
        lam, b1, c1 = k["lam"], k["b1"], k["c1"]
        coef = (lam * lam * c1 / abs(b1) ** 2 - 1) / 3
    jet, _ = r3_map(4, False)
    for r, tol in both(codim2.resonance_1_3, jet):
        assert close(abs(r.b1), mpmath.sqrt(2) * abs(b1), tol)
        assert close(r.c1, 2 * c1, tol) and close(r.coef, coef, tol)
        assert close(r.lam, lam, tol)
    jet, _ = r3_map(4, True)
    for r, tol in both(codim2.resonance_1_3, jet):
        assert close(r.re, coef.real, tol)
    assert abs(r.im - coef.imag) > 1e-3


def test_resonance_1_4_known():
    """c1_K = 2 c1, |d1_K| = 2 |d1|, A = -i c1/|d1| (scale- and phase-free), generic."""
    jet, k = r4_map(5)
    with mpmath.workdps(m.DPS):
        A = -I * k["c1"] / abs(k["d1"])
    for r, tol in both(codim2.resonance_1_4, jet):
        assert close(r.c1, 2 * k["c1"], tol) and close(abs(r.d1), 2 * abs(k["d1"]), tol)
        assert close(r.A, A, tol) and close(r.re, A.real, tol) and close(r.im, A.imag, tol)
    small_residuals(codim2.resonance_1_4(*m.to_float(jet)))


def test_resonance_refusals():
    """The complex pair must be at the resonance; a vanishing b1 / d1 is refused."""
    jet, _ = r4_map(5)
    with pytest.raises(SingularCaseError, match="not-resonant"):
        codim2.resonance_1_3(*m.to_float(jet))
    jet3, _ = r3_map(4, False)
    with pytest.raises(SingularCaseError, match="not-resonant"):
        codim2.resonance_1_4(*m.to_float(jet3))
    A, _, d3 = m.to_float(jet3)
    with pytest.raises(SingularCaseError, match="degenerate"):
        codim2.resonance_1_3(A, np.zeros((4, 4, 4)), d3)


# --------------------------------------------------------------------------- LPNS, PDNS
def _xz_want(k, sg):
    """Kuznetsov-normalised critical coefficients (z = sqrt(2) w, xi = sg xi_K)."""
    out = dict(f300=k["f300"], f111=2 * k["f111"], g210=k["g210"], g021=2 * k["g021"])
    if "f200" in k:
        out.update(f200=sg * k["f200"], f011=sg * 2 * k["f011"], g110=sg * k["g110"])
    return out


def test_fold_ns_known():
    """All seven critical coefficients under the plain disguise; the quadratic ones and
    s = sign(f200 f011) = -1 under the generic one, whose resonant quadratic terms do
    change the cubic coefficients (they depend on the normalising transformation)."""
    jet, L, k = xz_map(1, 6, False)
    for r, tol in both(codim2.fold_ns, jet):
        want = _xz_want(k, sign_of(r.q1, L[:, 0]))
        for name, v in want.items():
            assert close(getattr(r, name), v, tol), (name, r.backend)
        assert r.s == -1
    small_residuals(codim2.fold_ns(*m.to_float(jet)))
    jet, L, k = xz_map(1, 6, True)
    r = codim2.fold_ns(*m.to_float(jet))
    want = _xz_want(k, sign_of(r.q1, L[:, 0]))
    for name in ("f200", "f011", "g110"):
        assert close(getattr(r, name), want[name], F_TOL), name
    assert max(abs(getattr(r, n) - complex(want[n])) for n in ("f300", "f111", "g210")) > 1e-3


def test_flip_ns_known():
    """f300, f111, g210, g021 and the amplitude coefficients, generic disguise (no
    quadratic resonances: all four invariant); g021 is normal_form's Kuznetsov c1."""
    jet, L, k = xz_map(-1, 7, True)
    with mpmath.workdps(m.DPS):
        want = _xz_want(k, 1)
        lb = mpmath.conj(k["lam"])
        amp = (-want["f300"], -want["f111"], (lb * want["g210"]).real, (lb * want["g021"]).real)
    for r, tol in both(codim2.flip_ns, jet):
        for name, v in want.items():
            assert close(getattr(r, name), v, tol), (name, r.backend)
        for x, y in zip(r.amplitude, amp):
            assert close(x, y, tol)
    r = codim2.flip_ns(*m.to_float(jet))
    small_residuals(r)
    from symvi.normal_forms.normal_form import _eigen
    from symvi.numerics.backend import FLOAT64
    A, d2, d3 = m.to_float(jet)
    c1 = _kuznetsov(FLOAT64, A.astype(complex), d2.astype(complex), d3.astype(complex),
                    _eigen(FLOAT64, A.astype(complex), None))[0]
    assert abs(c1 - r.g021) < 1e-12


def test_matcont_pdns_formulas_differ():
    """MatContM's h021 = C + 2B(qb, h020) + B(q, h011) (factors swapped; nf_LPNSm and
    nf_PDNSm) and nf_PDNSm's h111 miss the constructed g021, f111 of the flip-NS map;
    the derived ones hit them (test_flip_ns_known)."""
    jet, L, k = xz_map(-1, 7, True)
    A, d2, d3 = m.to_float(jet)
    r = codim2.flip_ns(A, d2, d3)
    q, qb, p, lam = r.q2, np.conj(r.q2), r.p2, r.lam
    n = A.shape[0]
    B = lambda u, v: np.einsum("ijk,j,k->i", d2, u, v)       # noqa: E731
    h020 = np.linalg.solve(lam ** 2 * np.eye(n) - A, B(q, q))
    h011 = np.linalg.solve(np.eye(n) - A, B(q, qb))
    C = np.einsum("ijkl,j,k,l->i", d3, q, q, qb)
    g021_matcont = np.vdot(p, C + 2 * B(qb, h020) + B(q, h011)) / 2
    assert abs(g021_matcont - 2 * complex(k["g021"])) > 1e-2
    # nf_PDNSm's h111 with 2 Re B(h110, q) instead of 2 Re B(h110, conj(q)) misses f111
    q1, p1 = np.real(r.q1), np.real(r.p1)
    h110 = -np.linalg.solve(lam * np.eye(n) + A, B(q1, q))
    f111_matcont = np.real(p1 @ (np.einsum("ijkl,j,k,l->i", d3, q1, q, qb) + B(q1, h011)
                                 + 2 * np.real(B(h110, q))))
    assert abs(f111_matcont - 2 * float(k["f111"])) > 1e-2


# --------------------------------------------------------------------------- LPPD, CP, GPD
def test_fold_flip_known():
    """All seven coefficients (plain disguise), the quadratic ones (generic)."""
    jet, L, k = lppd_map(8, False)
    for r, tol in both(codim2.fold_flip, jet):
        s0 = sign_of(r.q0, L[:, 0])
        for name, v in k.items():
            want = s0 * v if name in ("a20", "a02", "b11") else v
            assert close(getattr(r, name), want, tol), (name, r.backend)
    r = codim2.fold_flip(*m.to_float(jet))
    small_residuals(r)
    c = [k["a20"] / k["b11"], k["a02"] * k["b11"]]
    assert close(r.matcont[0], c[0], F_TOL) and close(r.matcont[1], c[1], F_TOL)
    jet, L, k = lppd_map(8, True)
    r = codim2.fold_flip(*m.to_float(jet))
    s0 = sign_of(r.q0, L[:, 0])
    for name in ("a20", "a02", "b11"):
        assert close(getattr(r, name), s0 * k[name], F_TOL), name


def test_fold_flip_matcont_sign_of_h20():
    """MatContM nf_LPPDm's (I - A) h20 = a1 q0 - B(q0,q0) (sign reversed) misses a30."""
    jet, L, k = lppd_map(8, False)
    A, d2, d3 = m.to_float(jet)
    r = codim2.fold_flip(A, d2, d3)
    q0, p0 = np.real(r.q0), np.real(r.p0)
    n = A.shape[0]
    B = lambda u, v: np.einsum("ijk,j,k->i", d2, u, v)        # noqa: E731
    K = np.block([[np.eye(n) - A, q0[:, None]], [p0[None, :], np.zeros((1, 1))]])
    a1 = p0 @ B(q0, q0)
    h20 = np.linalg.solve(K, np.append(a1 * q0 - B(q0, q0), 0))[:n]
    a30_matcont = p0 @ (np.einsum("ijkl,j,k,l->i", d3, q0, q0, q0) + 3 * B(q0, h20)) / 6
    assert abs(a30_matcont - float(k["a30"])) > 1e-2


@pytest.mark.parametrize("quad", ["0", "0.5"])
def test_cusp_known(quad):
    """c = -0.6 (invariant, also for a != 0); a = sigma * quad = fold_coefficient's a."""
    jet, L, k = line_map(1, quad, "-0.6", 0, 9)
    for r, tol in both(codim2.cusp, jet):
        sg = sign_of(r.q, L[:, 0])
        assert close(r.c, k["c"], tol) and close(r.a, sg * k["a"], tol)
    r = codim2.cusp(*m.to_float(jet))
    small_residuals(r)
    a, e = fold_coefficient(*m.to_float(jet)[:2])
    assert abs(a - r.a) < 1e-12
    assert np.allclose(e.q, np.real(r.q)) and np.allclose(e.p, np.real(r.p))


@pytest.mark.parametrize("cub", ["0", "0.3"])
def test_degenerate_flip_known(cub):
    """e = 0.45 (invariant, also for c != 0: needs h4's 24 c h2 term); c = flip_coefficient.
    (A quadratic term a xi^2 in the map would not be normal form: c would be c + a^2.)"""
    jet, L, k = line_map(-1, "0", cub, "0.45", 10)
    for r, tol in both(codim2.degenerate_flip, jet):
        assert close(r.e, k["e"], tol) and close(r.c, k["c"], tol)
    r = codim2.degenerate_flip(*m.to_float(jet))
    small_residuals(r)
    assert abs(flip_coefficient(*m.to_float(jet)[:3])[0] - r.c) < 1e-12


def test_real_pairing_matches_normal_form():
    """codim2's backend-generic real eigenvectors follow real_critical's convention."""
    jet, L, k = lppd_map(8, False)
    A = m.to_float(jet)[0]
    r = codim2.fold_flip(*m.to_float(jet))
    for mu, q, p in ((1.0, r.q0, r.p0), (-1.0, r.q1, r.p1)):
        e = real_critical(A, mu)
        assert np.allclose(e.q, np.real(q), atol=1e-13) and np.allclose(e.p, np.real(p), atol=1e-12)


def test_real_wrong_pairing_detected(monkeypatch):
    """p0 contaminated by the adjoint vector of -1 (p0 + p1: <p0, q0> = 1 still) changes
    the fold-flip coefficients (pure p1 instead of p0 has <p1, q0> = 0: refused)."""
    jet, L, k = lppd_map(8, False)
    good = codim2.fold_flip(*m.to_float(jet))
    real = codim2._real_eig

    def swapped(bk, A, target, tol, vals=None, V=None, tag=""):
        other = real(bk, A, -target, tol, vals, V, tag)
        mine = real(bk, A, target, tol, vals, V, tag)
        return dataclasses.replace(mine, p=mine.p + other.p)

    monkeypatch.setattr(codim2, "_real_eig", swapped)
    bad = codim2.fold_flip(*m.to_float(jet))
    assert abs(bad.a20 - good.a20) > 1e-2 or abs(bad.b11 - good.b11) > 1e-2


def test_refusals_and_inputs():
    z3, z4 = np.zeros((4, 4, 4)), np.zeros((4, 4, 4, 4))
    with pytest.raises(SingularCaseError, match="not-on-unit-circle"):
        A = np.diag([0.5, 0.5, 0.2, 0.1])
        A[0, 1], A[1, 0] = -0.5, 0.5
        codim2.chenciner(A, z3, z4, np.zeros((4,) * 5), np.zeros((4,) * 6))
    with pytest.raises(SingularCaseError, match="no-multiplier"):
        codim2.cusp(np.diag([0.5, 0.2, 0.1, -1.0]), z3, z4)
    with pytest.raises(SingularCaseError, match="double-multiplier"):
        codim2.degenerate_flip(np.diag([-1.0, -1.0, 0.1, 0.2]), z3, z4, np.zeros((4,) * 5),
                               np.zeros((4,) * 6))
    with pytest.raises(codim2.ParameterError, match="d3"):
        codim2.cusp(np.diag([1.0, 0.5]), np.zeros((2, 2, 2)), z4)
    with pytest.raises(codim2.ParameterError, match="tol"):
        codim2.cusp(np.diag([1.0, 0.5]), np.zeros((2, 2, 2)), np.zeros((2,) * 4), tol=-1)
