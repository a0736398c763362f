"""The paper's centre-manifold reduction, eqs. (39)–(60), (A4)–(A17), and its f1 of eq. (60).

Luo & Xie reduce the map to its centre manifold in the real eigenbasis P of eq. (39) and
compute f1(0) by eq. (60).  This is their own route to the cubic coefficient, kept beside
the general one (Kuznetsov's c1 and l1, :mod:`symvi.normal_forms.normal_form`, which every
analysis uses) so that each printed formula can be set beside the derived one:

1. the paper's reduction in the basis P, giving g_ij and f1(0) by eq. (60) as printed
   (``f1_printed``) and by the corrected eq. (60) (``f1_wan``, Wan's formula in the
   paper's sign convention);
2. Wan's planar formula applied to the same g_ij (``wan_a``).

Normalisation: x = P y with P = (Re r1, -Im r1, ...), ||r1||_2 = 1 (r1 = Kuznetsov's q),
z = y1 + i y2, so x = Re(r1 z) = (z q + conj(z q)) / 2: z_paper = 2 z_Kuznetsov and every
cubic coefficient here is 1/4 of Kuznetsov's: ``wan_a = l1 / 4``, ``f1_wan = -l1 / 4``.
f1 (eqs. 58–60) has the opposite sign: r -> |lambda| r - f1 r^3, f1 > 0 attracting.

Discrepancies with the paper
----------------------------
Each was found by a known-answer test in ``tests/normal_forms/``; the printed
form is kept beside the corrected one and named ``*_printed``.

1. **Eq. (60)**, first term.  Printed:
   ``f_1(0) = Re[(1 - 2\\lambda_0)\\bar\\lambda_0 / (2(1 - \\lambda_0)) g_{20} g_{11}]
   + |g_{11}|^2/2 + |g_{02}|^2/4 - Re(\\bar\\lambda_0 g_{21}/2)``.
   Corrected (Wan 1978 / Guckenheimer–Holmes eq. (3.5.11) with factorial-scaled
   g_ij, sign flipped to the paper's f1 > 0 = attracting):
   ``f_1(0) = Re[(1 - 2\\lambda_0)\\bar\\lambda_0^2 / (2(1 - \\lambda_0)) g_{20} g_{11}]
   + |g_{11}|^2/2 + |g_{02}|^2/4 - Re(\\bar\\lambda_0 g_{21}/2)``
   (\\bar\\lambda_0 squared).  Derivation: expand Kuznetsov's planar
   ``c_1 = g_{20}g_{11}(1-2\\lambda)/(2(\\lambda^2-\\lambda)) + |g_{11}|^2/(1-\\bar\\lambda)
   + |g_{02}|^2/(2(\\lambda^2-\\bar\\lambda)) + g_{21}/2`` in
   Re(\\bar\\lambda c_1) with |lambda| = 1.  The sign convention of the printed
   (60) is the paper's own (f1 > 0 attracting, consistent with eq. (58)); only
   the power of \\bar\\lambda_0 is wrong.  Shown by
   ``test_planar.py::test_eq60_printed_misses_quadratic_terms`` (a planar map
   conjugated by a quadratic change of variables: the corrected form returns
   the constructed value, the printed one does not) and
   ``test_planar.py::test_eq60_sign_convention`` (pure cubic map: both agree and
   are positive for an attracting circle).
2. **Eq. (A10)**, second equation.  Printed:
   ``(\\bar\\lambda I - D) W_{02} = H_{02}``.  Corrected:
   ``(\\bar\\lambda^2 I - D) W_{02} = H_{02}`` (the z-bar^2 coefficient of the
   invariance equation (44); eq. (46) itself has it right).  W_02 does not
   enter g_21, so f1 is unaffected; it enters g_03 (eq. A17).  Shown by
   ``test_manifold.py::test_invariance_residual_order`` (the printed W_02
   leaves an O(|z|^2) residual in eq. (44)).
3. **Eq. (46)**, W_30.  Printed:
   ``W_{30} = (\\lambda^3 - D)^{-1}(H_{30} + 3H^1_{10}W_{20} - 3\\lambda G_{20}W_{11}
   - 3\\lambda G_{20}W_{20})``.  Corrected:
   ``W_{30} = (\\lambda^3 - D)^{-1}(H_{30} + 3H^1_{10}W_{20} - 3\\lambda G_{20}W_{20}
   - 3\\lambda \\bar G_{02}W_{11})`` (the z^3 term of W_11 z' conj(z') comes
   from conj(g) whose z^2 coefficient is conj(g_02)/2).  W_30 enters only
   quartic terms, not f1.  Shown by the same invariance-residual test
   (printed W_30 leaves an O(|z|^3) residual).
(Eq. (A3)'s reading is in :mod:`symvi.normal_forms.normal_form`, which computes it.)

Checked and found right as printed: eqs. (A4)–(A9), (A11), (A12), (A14)–(A16)
(equal to the Wirtinger derivatives d/dz = (d/dy1 - i d/dy2)/2 applied to
F1 + i F2 and F_k, ``test_manifold.py::test_printed_appendix_matches_wirtinger``),
eq. (54), (A13), (A17), W_20, W_11, W_02 and W_21 of eq. (46).

References
----------
[Kuznetsov, Elements of Applied Bifurcation Theory]: see
:mod:`symvi.normal_forms.normal_form` (Sec. 4.7, the planar c1 expanded above).
[Wan 1978] Y.-H. Wan, Computation of the stability condition for the Hopf
bifurcation of diffeomorphisms on R^2, SIAM J. Appl. Math. 34 (1978) 167–175;
as restated in J. Guckenheimer & P. Holmes, Nonlinear Oscillations, Dynamical
Systems, and Bifurcations of Vector Fields, Springer 1983, eq. (3.5.11).
"""
from dataclasses import dataclass, fields

import numpy as np

from ..errors import SingularCaseError
from ..normal_forms.normal_form import (NormalForm, _B, _C, _backend, _eigen, _phase_fix,
                                        _symmetrise, transform_jet)
from ..normal_forms.normal_form import normal_form as _normal_form


@dataclass(frozen=True)
class PaperReduction:
    """The paper's reduction, eqs. (39)–(55), (A4)–(A17), in its own normalisation.

    P = (Re r1, -Im r1, <real basis of the rest>), ||r1||_2 = 1 (r1 = q);
    z = y1 + i y2; every cubic coefficient here is 1/4 of Kuznetsov's.
    Dict entries are named as in the paper (``G20``, ``H11`` ...); ``G10``,
    ``G01`` are vectors over w, ``H10``, ``H01`` matrices (eqs. 49, 55).
    """

    P: object
    Pinv: object
    D: object
    alpha: object
    omega: object
    G: dict
    H: dict
    W: dict
    g: dict
    f1_printed: object
    f1_wan: object
    wan_a: object
    normalisation: str = ("x = P y, P = (Re r1, -Im r1, rest), ||r1||_2 = 1, largest component "
                          "of r1 real > 0, z = y1 + i y2 (z = 2 z_Kuznetsov)")


def eigenmatrix(A, *, index=None, digits=None):
    """The real eigenmatrix P of eq. (39) and its inverse.

    Columns: Re r1, -Im r1, then a real basis of the complementary invariant
    subspace (real eigenvectors; Re r, -Im r for each further complex pair).
    """
    bk = _backend(digits, A)
    with bk.context():
        A = bk.carr(A)
        e = _eigen(bk, A, index)
        P = _eigenmatrix(bk, A, e)
        return P, bk.cinv(P)


def _eigenmatrix(bk, A, e):
    n = A.shape[0]
    r1 = e.q
    cols = [bk.carr(bk.vreal(r1)), -bk.carr(bk.vreal(-1j * r1))]  # Im r1 = Re(-i r1)
    vals, V = e.values, e.vectors
    scale = max(1.0, float(max(abs(x) for x in vals)))
    tol = 1e3 * bk.eps * scale          # in the backend: float(eps) is 0 past ~320 digits
    used = {e.k, e.kbar}
    for i in range(n):
        if i in used:
            continue
        r = _phase_fix(bk, V[:, i].copy())
        if abs(vals[i].imag) <= tol:
            cols.append(bk.carr(bk.vreal(r)))
            used.add(i)
        elif vals[i].imag > 0:
            j = min((m for m in range(n) if m not in used and m != i),
                    key=lambda m: abs(vals[m] - vals[i].conjugate()))
            cols.extend([bk.carr(bk.vreal(r)), -bk.carr(bk.vreal(-1j * r))])
            used.update({i, j})
    if len(cols) != n:
        raise SingularCaseError("defective", "the multipliers do not give a real eigenbasis "
                                "(a complex pair without its conjugate)")
    P = np.stack(cols, axis=1)
    c = bk.cond(P)
    if not c < 1e-3 / bk.eps:
        raise SingularCaseError("defective",
                                f"the eigenmatrix P of eq. (39) is singular (cond {c:.2e}): "
                                "A is not diagonalisable (colliding multipliers)")
    return P


def _wirtinger(bk, dY, n):
    """Complex coefficients of G = F1 + i F2 - lambda z and H = (F3..Fn) - D W from the
    real jets in Y, using d/dz = (d/dy1 - i d/dy2)/2: the generic form of (A4)–(A16)."""
    d2Y, d3Y = dY
    a = bk.czeros(n)
    a[0], a[1] = 0.5, -0.5j
    ab = np.conj(a)
    wG = bk.czeros(n)
    wG[0], wG[1] = 1, 1j
    E = bk.ceye(n)

    def cG(v):
        return np.dot(wG, v)

    G, H = {}, {}
    pairs = {"20": (a, a), "11": (a, ab), "02": (ab, ab)}
    for key, (u, v) in pairs.items():
        b = _B(d2Y, u, v)
        G[key] = cG(b)
        H[key] = b[2:]
    triples = {"30": (a, a, a), "21": (a, a, ab), "12": (a, ab, ab), "03": (ab, ab, ab)}
    for key, (u, v, w) in triples.items():
        c = _C(d3Y, u, v, w)
        G[key] = cG(c)
        H[key] = c[2:]
    # mixed z-w and zbar-w second derivatives, eqs. (49), (55)
    Bz = [_B(d2Y, a, E[:, k]) for k in range(2, n)]
    Bzb = [_B(d2Y, ab, E[:, k]) for k in range(2, n)]
    G["10"] = np.array([cG(b) for b in Bz], dtype=a.dtype)
    G["01"] = np.array([cG(b) for b in Bzb], dtype=a.dtype)
    H["10"] = np.stack([b[2:] for b in Bz], axis=1) if n > 2 else bk.czeros((0, 0))
    H["01"] = np.stack([b[2:] for b in Bzb], axis=1) if n > 2 else bk.czeros((0, 0))
    return {("G" + k): v for k, v in G.items()}, {("H" + k): v for k, v in H.items()}


def appendix_printed(d2Y, d3Y):
    """G_ij, H_ij, g_11, g_20, g_02 by eqs. (A4)–(A9), (A11), (A12), (A14)–(A16) literally.

    ``d2Y``, ``d3Y``: raw second and third derivatives of F(Y) = P^{-1} f(P Y)
    (real).  Returns a dict keyed like the paper (``G10`` is the vector over
    k = 3..n of eq. (A11), etc.).
    """
    F = lambda k, a, b: d2Y[k - 1, a - 1, b - 1]            # noqa: E731
    T = lambda k, a, b, c: d3Y[k - 1, a - 1, b - 1, c - 1]  # noqa: E731
    n = d2Y.shape[0]
    i = 1j
    out = {}
    # eq. (A4)
    out["g11"] = (F(1, 1, 1) + F(1, 2, 2) + i * (F(2, 1, 1) + F(2, 2, 2))) / 4
    # eq. (A5)
    out["g02"] = (F(1, 1, 1) - F(1, 2, 2) - 2 * F(2, 1, 2)
                  + i * (F(2, 1, 1) - F(2, 2, 2) + 2 * F(1, 1, 2))) / 4
    # eq. (A6)
    out["g20"] = (F(1, 1, 1) - F(1, 2, 2) + 2 * F(2, 1, 2)
                  + i * (F(2, 1, 1) - F(2, 2, 2) - 2 * F(1, 1, 2))) / 4
    # eq. (A7)
    out["G21"] = (T(1, 1, 1, 1) + T(1, 1, 2, 2) + T(2, 1, 1, 2) + T(2, 2, 2, 2)
                  + i * (T(2, 1, 1, 1) + T(2, 1, 2, 2) - T(1, 1, 1, 2) - T(1, 2, 2, 2))) / 8
    ks = range(3, n + 1)
    # eq. (A8), (A9)
    out["H11"] = [(F(k, 1, 1) + F(k, 2, 2)) / 4 for k in ks]
    out["H20"] = [(F(k, 1, 1) - F(k, 2, 2) - 2 * i * F(k, 1, 2)) / 4 for k in ks]
    # eq. (A11), (A12)
    out["G10"] = [(F(1, 1, k) + F(2, 2, k) + i * (F(2, 1, k) - F(1, 2, k))) / 2 for k in ks]
    out["G01"] = [(F(1, 1, k) - F(2, 2, k) + i * (F(2, 1, k) + F(1, 2, k))) / 2 for k in ks]
    # eq. (A14), (A15)
    out["G30"] = (T(1, 1, 1, 1) - 3 * T(1, 1, 2, 2) + 3 * T(2, 1, 1, 2) - T(2, 2, 2, 2)
                  + i * (T(2, 1, 1, 1) - 3 * T(2, 1, 2, 2) - 3 * T(1, 1, 1, 2)
                         + T(1, 2, 2, 2))) / 8
    out["G03"] = (T(1, 1, 1, 1) - 3 * T(1, 1, 2, 2) - 3 * T(2, 1, 1, 2) + T(2, 2, 2, 2)
                  + i * (T(2, 1, 1, 1) - 3 * T(2, 1, 2, 2) + 3 * T(1, 1, 1, 2)
                         - T(1, 2, 2, 2))) / 8
    # eq. (A16)
    out["H30"] = [(T(k, 1, 1, 1) - 3 * T(k, 1, 2, 2)
                   + i * (T(k, 2, 2, 2) - 3 * T(k, 1, 1, 2))) / 8 for k in ks]
    return out


def f1_eq60_printed(lam, g20, g11, g02, g21):
    """f1(0) by eq. (60) exactly as printed (single conj(lambda0) in the first term)."""
    lb = lam.conjugate()
    return (((1 - 2 * lam) * lb / (2 * (1 - lam)) * g20 * g11).real
            + abs(g11) ** 2 / 2 + abs(g02) ** 2 / 4 - (lb * g21 / 2).real)


def wan_a(lam, g20, g11, g02, g21):
    """Wan's planar coefficient a [Wan 1978], GH eq. (3.5.11) with g_ij of eq. (56).

    a = -Re[(1 - 2 lambda) conj(lambda)^2 / (1 - lambda) g20 g11 / 2] - |g11|^2 / 2
        - |g02|^2 / 4 + Re(conj(lambda) g21) / 2
    (GH's xi_20 = g20/2, xi_11 = g11, xi_02 = g02/2, xi_21 = g21/2).  a < 0: the
    circle is attracting.  Equals Re(conj(lambda) c1) of the planar c1 when |lambda| = 1.
    """
    lb = lam.conjugate()
    return (-((1 - 2 * lam) * lb * lb / (1 - lam) * g20 * g11 / 2).real
            - abs(g11) ** 2 / 2 - abs(g02) ** 2 / 4 + (lb * g21).real / 2)


def f1_eq60(lam, g20, g11, g02, g21):
    """f1(0) by eq. (60) corrected (conj(lambda0)^2 in the first term) = -wan_a."""
    return -wan_a(lam, g20, g11, g02, g21)


def _paper(bk, A, d2, d3, e):
    n = A.shape[0]
    P = _eigenmatrix(bk, A, e)
    Pinv = bk.cinv(P)
    AY = np.dot(Pinv, np.dot(A, P))
    D = AY[2:, 2:]
    lam = e.lam
    d2Y = transform_jet(Pinv, P, d2)
    d3Y = transform_jet(Pinv, P, d3)
    G, H = _wirtinger(bk, (d2Y, d3Y), n)
    lb = lam.conjugate()
    I = bk.ceye(n - 2)
    W = {}
    if n > 2:
        # (lambda^i conj(lambda)^j I - D) W_ij = H_ij, i + j = 2    eq. (46)
        W["W20"] = bk.csolve(lam * lam * I - D, H["H20"])
        W["W11"] = bk.csolve(lam * lb * I - D, H["H11"])
        W["W02"] = bk.csolve(lb * lb * I - D, H["H02"])
        W20, W11, W02 = W["W20"], W["W11"], W["W02"]
        G20, G11, G02 = G["G20"], G["G11"], G["G02"]
        H10, H01 = H["H10"], H["H01"]
        # eq. (46), W30 corrected (as printed: symvi.paper.audit.printed_W, the errata)
        W["W30"] = bk.csolve(lam ** 3 * I - D, H["H30"] + 3 * np.dot(H10, W20)
                            - 3 * lam * G20 * W20 - 3 * lam * G02.conjugate() * W11)
        # eq. (46), W21 (right as printed)
        W["W21"] = bk.csolve(lam * lam * lb * I - D,
                            np.dot(H01, W20) + 2 * np.dot(H10, W11) - lb * G20 * W11
                            - 2 * lam * G11 * W20 - 2 * lam * G11.conjugate() * W11
                            - lb * G02.conjugate() * W02 + H["H21"])
        g21 = G["G21"] + 2 * np.dot(G["G10"], W11) + np.dot(G["G01"], W20)   # eq. (54)
        g30 = G["G30"] + 3 * np.dot(G["G10"], W20)                          # eq. (A17)
        g03 = G["G03"] + 3 * np.dot(G["G01"], W02)                          # eq. (A17)
        # z zbar^2 coefficient (not printed; by the same expansion as eq. 54)
        g12 = G["G12"] + 2 * np.dot(G["G01"], W11) + np.dot(G["G10"], W02)
    else:
        g21, g30, g03, g12 = G["G21"], G["G30"], G["G03"], G["G12"]
    g = {"g20": G["G20"], "g11": G["G11"], "g02": G["G02"], "g21": g21, "g30": g30,
         "g12": g12, "g03": g03}
    args = (lam, g["g20"], g["g11"], g["g02"], g["g21"])
    return PaperReduction(P=P, Pinv=Pinv, D=D, alpha=lam.real, omega=lam.imag, G=G, H=H, W=W,
                          g=g, f1_printed=f1_eq60_printed(*args), f1_wan=f1_eq60(*args),
                          wan_a=wan_a(*args)), (d2Y, d3Y)


@dataclass(frozen=True)
class PaperNormalForm(NormalForm):
    """A :class:`symvi.normal_forms.normal_form.NormalForm` with the paper's reduction:
    ``f1_printed`` (eq. (60) as printed), ``f1_wan`` (corrected, = -l1/4), ``wan_a``
    (= l1/4) and the reduction itself (``paper``: P, G, H, W, g of eqs. (39)–(55))."""

    wan_a: object = None
    f1_wan: object = None
    f1_printed: object = None
    paper: PaperReduction = None


def reduction(A, d2, d3, *, index=None, digits=None):
    """The paper's reduction of the map with jet (A, d2, d3), eqs. (39)–(55), (A4)–(A17):
    a :class:`PaperReduction` in the paper's normalisation (see the module docstring)."""
    bk = _backend(digits, A, d2, d3)
    with bk.context():
        A = bk.carr(A)
        d2, d3 = _symmetrise(bk.carr(d2)), _symmetrise(bk.carr(d3))
        return _paper(bk, A, d2, d3, _eigen(bk, A, index))[0]


def normal_form(A, d2, d3, dA=None, *, index=None, digits=None, names=None):
    """:func:`symvi.normal_forms.normal_form.normal_form` (Kuznetsov's c1, l1, (A1)–(A3), the
    circle) with the paper's reduction and its f1 of eq. (60) added: a
    :class:`PaperNormalForm`.  The same checks (strong resonance refused) come first."""
    nf = _normal_form(A, d2, d3, dA, index=index, digits=digits, names=names)
    red = reduction(A, d2, d3, index=index, digits=digits)
    base = {f.name: getattr(nf, f.name) for f in fields(NormalForm)}
    return PaperNormalForm(**base, wan_a=red.wan_a, f1_wan=red.f1_wan,
                           f1_printed=red.f1_printed, paper=red)
