"""Centre-manifold reduction and Neimark–Sacker normal form of a map, eqs. (39)–(60), (A1)–(A17).

System-independent: everything here takes the jet of an n-dimensional map
``x -> f(x)`` at a fixed point (n >= 2) and knows nothing about impacts.

Jet convention (raw derivatives, *not* divided by factorials)::

    A[i, j]        = df_i / dx_j                  (the paper's F01)
    d2[i, j, k]    = d^2 f_i / dx_j dx_k          (the paper's F02 = d2 / 2)
    d3[i, j, k, l] = d^3 f_i / dx_j dx_k dx_l     (the paper's F03 = d3 / 6)
    dA[i, j]       = d/dv (df_i / dx_j) along the fixed-point branch  (the paper's F11)

so that f(x) = A x + B(x, x) / 2 + C(x, x, x) / 6 + O(|x|^4) with
B(u, v)_i = d2[i, j, k] u_j v_k and C(u, v, w)_i = d3[i, j, k, l] u_j v_k w_l.

Three computations of the same cubic coefficient are provided:

1. the paper's reduction (eqs. 39–55, A4–A17) in the real eigenbasis P of
   eq. (39), giving g_ij and f1(0) by eq. (60) as printed (``f1_printed``) and
   by the corrected eq. (60) (``f1_wan``, Wan's formula in the paper's sign
   convention);
2. Wan's planar formula applied to the same g_ij (``wan_a``);
3. Kuznetsov's n-dimensional formula (``c1``, ``l1``), which needs no
   eigenbasis and no centre-manifold coordinates.

Normalisations (every output states its own)
--------------------------------------------
* ``q``: right eigenvector, A q = lambda1 q, Im lambda1 > 0, ||q||_2 = 1, phase
  fixed so that the component of largest modulus is real and positive (the
  first such component on ties).  The paper's r1 is the same vector.
* ``p``: adjoint eigenvector, A^T p = conj(lambda1) p, <p, q> = conj(p)^T q = 1.
  It is the paper's zeta_0^* of eq. (A1) (and q is zeta_0).
* Kuznetsov: x = z q + conj(z q) + O(|z|^2); the restricted map is
  z -> lambda z + c1 z |z|^2 + ...; ``l1 = Re(exp(-i theta) c1)``.  The circle
  is stable (supercritical) when l1 < 0.
* Paper: x = P y with P = (Re r1, -Im r1, ...), z = y1 + i y2, so
  x = Re(r1 z) = (z q + conj(z q)) / 2, i.e. z_paper = 2 z_Kuznetsov and every
  cubic coefficient in the paper's normalisation is 1/4 of Kuznetsov's.  With
  ||r1|| = 1:  ``wan_a = l1 / 4`` and ``f1_wan = -l1 / 4``.
* f1 (eqs. 58–60) uses the opposite sign: r -> |lambda| r - f1 r^3, so f1 > 0
  means an attracting circle.

Predicted invariant circle (leading order)
------------------------------------------
For v = v_c + mu, with d = d|lambda1|/dv: |lambda(mu)| = 1 + d mu + O(mu^2) and
|z'| = |z| (1 + d mu + l1 |z|^2 + ...), so the circle has Kuznetsov radius
rho^2 = -d mu / l1 (it exists on the side where d mu / l1 < 0), paper radius
2 rho, and x - x*(v) = 2 Re(z q_k) + O(rho^2), |z| = rho, so the half-width of
the circle's projection on state variable k is 2 rho |q_k| (the O(rho^2) terms
W_20 z^2 + W_11 |z|^2 shift the centre and change the half-width only at
O(rho^3)).

Discrepancies with the paper
----------------------------
Each was found by a known-answer test in ``tests/normal_form/``; the printed
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
4. **Eq. (A3)** writes ``Re(\\tilde\\lambda_1 e^{-i\\omega_0})``; omega_0 must be
   the argument theta_0 of lambda_0 (d|lambda|/dv = Re(conj(lambda) dlambda/dv)
   on |lambda| = 1), not omega = Im lambda_1 of eq. (41).  We implement the
   argument reading; ``test_planar.py::test_dmod_A3`` checks it against a
   family with known d|lambda|/dv.

Checked and found right as printed: eqs. (A4)–(A9), (A11), (A12), (A14)–(A16)
(equal to the Wirtinger derivatives d/dz = (d/dy1 - i d/dy2)/2 applied to
F1 + i F2 and F_k, ``test_manifold.py::test_printed_appendix_matches_wirtinger``),
eq. (54), (A13), (A17), W_20, W_11, W_02 and W_21 of eq. (46).

References
----------
[Kuznetsov, Elements of Applied Bifurcation Theory] Yu. A. Kuznetsov, Elements
of Applied Bifurcation Theory, 3rd ed., Springer 2004, Sec. 5.4 (Neimark–Sacker
bifurcation in n-dimensional maps; c1 formula) and Sec. 4.7 (planar normal form).
[Wan 1978] Y.-H. Wan, Computation of the stability condition for the Hopf
bifurcation of diffeomorphisms on R^2, SIAM J. Appl. Math. 34 (1978) 167–175;
as restated in J. Guckenheimer & P. Holmes, Nonlinear Oscillations, Dynamical
Systems, and Bifurcations of Vector Fields, Springer 1983, eq. (3.5.11).
"""
import cmath
import contextlib
import math
import warnings
from dataclasses import dataclass

import mpmath
import numpy as np

from ..errors import NearSingularWarning, ParameterError, SingularCaseError
# |lambda^m - 1| (m = 1..5) below which the reduction is refused / warned about: the strong
# resonances of the multiplier, not the forcing resonance of symvi.flow.linear's names
from ..numerics.tolerances import STRONG_RESONANCE_REFUSE as RESONANCE_REFUSE
from ..numerics.tolerances import STRONG_RESONANCE_WARN as RESONANCE_WARN
#: |Im lambda1| / ||A|| below which the complex pair is said to collide
COLLISION_WARN = 1e-6


# --------------------------------------------------------------------------- backends
class _NumpyBackend:
    """float64 / complex128 linear algebra."""

    name = "float64"
    digits = None
    eps = 2.0 ** -52

    def context(self):
        return contextlib.nullcontext()

    def arr(self, x):
        return np.array(x, dtype=complex)

    def eye(self, n):
        return np.eye(n, dtype=complex)

    def zeros(self, shape):
        return np.zeros(shape, dtype=complex)

    def eig(self, A):
        return np.linalg.eig(A)

    def solve(self, M, b):
        return np.linalg.solve(M, b)

    def inv(self, M):
        return np.linalg.inv(M)

    def re(self, x):
        return np.real(x).astype(complex)

    sqrt = staticmethod(cmath.sqrt)
    exp = staticmethod(cmath.exp)
    arg = staticmethod(cmath.phase)
    pi = math.pi

    def real(self, x):
        return float(np.real(x))

    def cond(self, M):
        return float(np.linalg.cond(M))


class _MpBackend:
    """mpmath at ``digits`` significant digits; arrays are numpy object arrays of mpc."""

    name = "mpmath"

    def __init__(self, digits):
        self.digits = int(digits)

    def context(self):
        return mpmath.mp.workdps(self.digits)

    @property
    def eps(self):
        return mpmath.mp.eps

    _to_mpc = staticmethod(np.frompyfunc(lambda e: mpmath.mpc(e), 1, 1))

    def arr(self, x):
        if isinstance(x, mpmath.matrix):
            x = x.tolist()
        a = np.array(x, dtype=object)
        return self._to_mpc(a) if a.ndim else mpmath.mpc(a.item())

    def eye(self, n):
        return self.arr(np.eye(n))

    def zeros(self, shape):
        return self.arr(np.zeros(shape))

    def _mat(self, M):
        return mpmath.matrix(M.tolist())

    def eig(self, A):
        E, ER = mpmath.eig(self._mat(A))
        n = A.shape[0]
        vals = np.array([mpmath.mpc(e) for e in E], dtype=object)
        vecs = np.array([[mpmath.mpc(ER[i, j]) for j in range(n)] for i in range(n)], dtype=object)
        return vals, vecs

    def solve(self, M, b):
        x = mpmath.lu_solve(self._mat(M), mpmath.matrix(list(b)))
        return np.array([mpmath.mpc(x[i]) for i in range(M.shape[0])], dtype=object)

    def inv(self, M):
        Mi = mpmath.inverse(self._mat(M))
        n = M.shape[0]
        return np.array([[mpmath.mpc(Mi[i, j]) for j in range(n)] for i in range(n)], dtype=object)

    _re = staticmethod(np.frompyfunc(lambda e: mpmath.mpc(e.real), 1, 1))

    def re(self, x):
        return self._re(x)

    sqrt = staticmethod(mpmath.sqrt)
    exp = staticmethod(mpmath.exp)
    arg = staticmethod(mpmath.arg)

    @property
    def pi(self):
        return +mpmath.pi

    def real(self, x):
        return mpmath.mpf(mpmath.mpc(x).real)

    def cond(self, M):
        Mm = self._mat(M)
        return float(mpmath.mnorm(Mm, 1) * mpmath.mnorm(mpmath.inverse(Mm), 1))


FLOAT64 = _NumpyBackend()


def _is_mp(x):
    if isinstance(x, (mpmath.mpf, mpmath.mpc, mpmath.matrix)):
        return True
    if isinstance(x, np.ndarray):
        return x.dtype == object and x.size > 0 and _is_mp(x.flat[0])
    if isinstance(x, (list, tuple)):
        return len(x) > 0 and _is_mp(x[0])
    return False


def backend(digits=None, *example):
    """The backend for ``digits`` (None: float64, unless an ``example`` holds mpmath numbers,
    in which case the current ``mp.dps`` is used)."""
    if digits is None:
        if any(_is_mp(e) for e in example):
            return _MpBackend(mpmath.mp.dps)
        return FLOAT64
    if not isinstance(digits, int) or isinstance(digits, bool) or not 16 <= digits <= 10000:
        raise ParameterError("digits", digits, "an integer from 16 to 10000")
    return _MpBackend(digits)


# --------------------------------------------------------------------------- multilinear forms
def _B(d2, u, v):
    """B(u, v)_i = d2[i, j, k] u_j v_k."""
    return np.dot(np.dot(d2, v), u)


def _C(d3, u, v, w):
    """C(u, v, w)_i = d3[i, j, k, l] u_j v_k w_l."""
    return np.dot(np.dot(np.dot(d3, w), v), u)


def _vdot(p, q):
    """<p, q> = conj(p)^T q."""
    return np.dot(np.conj(p), q)


def transform_jet(Pinv, P, d):
    """Jet of F(Y) = P^{-1} f(P Y) from the jet d of f (any order), eq. (40)."""
    t = np.tensordot(Pinv, d, axes=(1, 0))
    for _ in range(d.ndim - 1):
        t = np.tensordot(t, P, axes=(1, 0))
    return t


def _symmetrise(d):
    """Average a derivative tensor over its (interchangeable) lower indices."""
    if d.ndim == 3:
        return (d + d.transpose(0, 2, 1)) / 2
    perms = [(0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 1, 3), (0, 2, 3, 1), (0, 3, 1, 2), (0, 3, 2, 1)]
    return sum(d.transpose(p) for p in perms) / 6


# --------------------------------------------------------------------------- eigen-structure
@dataclass(frozen=True)
class Eigen:
    """Critical eigen-structure of A, eqs. (39), (A1).

    ``k`` indexes ``values``; ``q`` (= r1 = zeta_0) has ||q||_2 = 1 and its
    largest-modulus component real positive; ``p`` (= zeta_0^*) satisfies
    A^T p = conj(lambda1) p and <p, q> = conj(p)^T q = 1.
    """

    values: object     # all eigenvalues (backend array)
    vectors: object    # matching right eigenvectors as columns
    k: int             # index of lambda1 (Im > 0)
    kbar: int          # index of conj(lambda1)
    lam: object
    q: object
    p: object


def _phase_fix(bk, v):
    """Scale v to unit 2-norm with its largest-modulus component real positive."""
    mags = [abs(e) for e in v]
    j = max(range(len(v)), key=lambda i: (mags[i], -i))
    nrm = abs(bk.sqrt(sum(m * m for m in mags)))
    return v * (abs(v[j]) / (v[j] * nrm))


def eigen(A, *, index=None, digits=None):
    """Right and adjoint critical eigenvectors of A, eqs. (39), (A1).

    lambda1 is the eigenvalue with Im > 0 whose modulus is nearest 1, or
    ``values[index]`` when ``index`` is given.  Raises SingularCaseError when
    there is no non-real eigenvalue or lambda1 is not simple.
    """
    bk = backend(digits, A)
    with bk.context():
        return _eigen(bk, bk.arr(A), index)


def _eigen(bk, A, index):
    n = A.shape[0]
    vals, V = bk.eig(A)
    scale = max(1.0, float(max(abs(e) for e in vals)))
    tol = 1e3 * bk.eps * scale          # in the backend: float(eps) is 0 past ~320 digits
    if index is None:
        cands = [i for i in range(n) if vals[i].imag > tol]
        if not cands:
            raise SingularCaseError("no-complex-pair",
                                    "the Jacobian has no non-real multiplier: no Neimark–Sacker "
                                    "pair (H1) to reduce to")
        k = min(cands, key=lambda i: (abs(abs(vals[i]) - 1), i))
    else:
        if not (isinstance(index, int) and 0 <= index < n):
            raise ParameterError("index", index, f"an integer from 0 to {n - 1}")
        k = index
        if not vals[k].imag > tol:
            raise SingularCaseError("real-multiplier",
                                    f"multiplier {complex(vals[k]):.6g} is real or has Im < 0; "
                                    "choose the member of the pair with Im > 0")
    lam = vals[k]
    kbar = min((i for i in range(n) if i != k), key=lambda i: abs(vals[i] - lam.conjugate()))
    others = [abs(vals[i] - lam) for i in range(n) if i != k]
    gap = min(others) if others else scale
    if float(gap) <= tol:
        raise SingularCaseError("collision",
                                f"multiplier {complex(lam):.6g} is not simple (distance "
                                f"{float(gap):.2e} to another multiplier): the pair collides")
    if float(abs(lam.imag)) < COLLISION_WARN * scale:
        warnings.warn(f"Im lambda1 = {float(lam.imag):.2e}: the complex pair is about to collide "
                      "on the real axis; the eigenbasis P of eq. (39) is ill-conditioned",
                      NearSingularWarning, stacklevel=3)
    q = _phase_fix(bk, V[:, k].copy())
    # the adjoint vector is the k-th row of V^{-1}: u A = lambda u, u V = e_k
    u = bk.inv(V)[k, :]
    u = u / np.dot(u, q)
    p = np.conj(u)
    return Eigen(vals, V, k, kbar, lam, q, p)


def resonance(lam, m_max=5):
    """(m, |lambda^m - 1|) for the m in 1..m_max with the smallest distance, (H2)."""
    best = None
    for m in range(1, m_max + 1):
        dist = abs(lam ** m - 1)
        if best is None or dist < best[1]:
            best = (m, dist)
    return best


# --------------------------------------------------------------------------- paper's reduction
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
    bk = backend(digits, A)
    with bk.context():
        A = bk.arr(A)
        e = _eigen(bk, A, index)
        P = _eigenmatrix(bk, A, e)
        return P, bk.inv(P)


def _eigenmatrix(bk, A, e):
    n = A.shape[0]
    r1 = e.q
    cols = [bk.re(r1), -bk.re(-1j * r1)]  # Im r1 = Re(-i r1)
    vals, V = e.values, e.vectors
    scale = max(1.0, float(max(abs(x) for x in vals)))
    tol = 1e3 * bk.eps * scale          # in the backend: float(eps) is 0 past ~320 digits
    used = {e.k, e.kbar}
    for i in range(n):
        if i in used:
            continue
        r = _phase_fix(bk, V[:, i].copy())
        if abs(vals[i].imag) <= tol:
            cols.append(bk.re(r))
            used.add(i)
        elif vals[i].imag > 0:
            j = min((m for m in range(n) if m not in used and m != i),
                    key=lambda m: abs(vals[m] - vals[i].conjugate()))
            cols.extend([bk.re(r), -bk.re(-1j * r)])
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
    a = bk.zeros(n)
    a[0], a[1] = 0.5, -0.5j
    ab = np.conj(a)
    wG = bk.zeros(n)
    wG[0], wG[1] = 1, 1j
    E = bk.eye(n)

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
    H["10"] = np.stack([b[2:] for b in Bz], axis=1) if n > 2 else bk.zeros((0, 0))
    H["01"] = np.stack([b[2:] for b in Bzb], axis=1) if n > 2 else bk.zeros((0, 0))
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
    Pinv = bk.inv(P)
    AY = np.dot(Pinv, np.dot(A, P))
    D = AY[2:, 2:]
    lam = e.lam
    d2Y = transform_jet(Pinv, P, d2)
    d3Y = transform_jet(Pinv, P, d3)
    G, H = _wirtinger(bk, (d2Y, d3Y), n)
    lb = lam.conjugate()
    I = bk.eye(n - 2)
    W = {}
    if n > 2:
        # (lambda^i conj(lambda)^j I - D) W_ij = H_ij, i + j = 2    eq. (46)
        W["W20"] = bk.solve(lam * lam * I - D, H["H20"])
        W["W11"] = bk.solve(lam * lb * I - D, H["H11"])
        W["W02"] = bk.solve(lb * lb * I - D, H["H02"])
        W20, W11, W02 = W["W20"], W["W11"], W["W02"]
        G20, G11, G02 = G["G20"], G["G11"], G["G02"]
        H10, H01 = H["H10"], H["H01"]
        # eq. (46), W30 corrected (as printed: symvi.paper.audit.printed_W, the errata)
        W["W30"] = bk.solve(lam ** 3 * I - D, H["H30"] + 3 * np.dot(H10, W20)
                            - 3 * lam * G20 * W20 - 3 * lam * G02.conjugate() * W11)
        # eq. (46), W21 (right as printed)
        W["W21"] = bk.solve(lam * lam * lb * I - D,
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


# --------------------------------------------------------------------------- Kuznetsov
def _kuznetsov(bk, A, d2, d3, e):
    """Kuznetsov's c1 = 1/2 <p, C(q,q,qb) + 2 B(q, h11) + B(qb, h20)> and l1.

    h11 = (|lambda|^2 I - A)^{-1} B(q, qb), h20 = (lambda^2 I - A)^{-1} B(q, q)
    (|lambda| = 1 at the Neimark–Sacker point).
    """
    n = A.shape[0]
    q, p, lam = e.q, e.p, e.lam
    qb = np.conj(q)
    I = bk.eye(n)
    # (I - A) h11 = B(q, qb);  (e^{2 i theta} I - A) h20 = B(q, q)   [Kuznetsov, NS normal form]
    h11 = bk.solve(lam * lam.conjugate() * I - A, _B(d2, q, qb))
    h20 = bk.solve(lam * lam * I - A, _B(d2, q, q))
    c1 = _vdot(p, _C(d3, q, q, qb) + 2 * _B(d2, q, h11) + _B(d2, qb, h20)) / 2
    l1 = (lam.conjugate() / abs(lam) * c1).real
    return c1, l1, h11, h20


def kuznetsov(A, d2, d3, *, index=None, digits=None):
    """(c1, l1) by Kuznetsov's n-dimensional formula; ||q||_2 = 1, <p, q> = 1.

    l1 = Re(exp(-i theta) c1); the circle is stable (supercritical) when l1 < 0.
    """
    bk = backend(digits, A, d2, d3)
    with bk.context():
        A, d2, d3 = bk.arr(A), _symmetrise(bk.arr(d2)), _symmetrise(bk.arr(d3))
        e = _eigen(bk, A, index)
        c1, l1, _, _ = _kuznetsov(bk, A, d2, d3, e)
        return c1, l1


def kuznetsov_resolved(A, d2, d3):
    """(c1, l1, noise, lambda1), float64: ``noise`` bounds the rounding error of l1 (forward error
    of the sums of products in c1, with the absolute tensors |d2|, |d3|, times the
    condition numbers of the two solves).  Near grazing the jets of an impact map
    grow like powers of 1/v and l1 drowns in rounding: |l1| < noise decides nothing."""
    bk = backend(None, A, d2, d3)
    A, d2, d3 = np.asarray(A, float), _symmetrise(np.asarray(d2, float)), \
        _symmetrise(np.asarray(d3, float))
    e = _eigen(bk, A, None)
    c1, l1, h11, h20 = _kuznetsov(bk, A, d2, d3, e)
    n = A.shape[0]
    aq, a11, a20, ap = np.abs(e.q), np.abs(h11), np.abs(h20), np.abs(e.p)
    D2, D3 = np.abs(d2), np.abs(d3)
    cond = max(np.linalg.cond(np.eye(n) * abs(e.lam) ** 2 - A),
               np.linalg.cond(e.lam ** 2 * np.eye(n) - A))
    size = np.dot(ap, _C(D3, aq, aq, aq) + cond * (2 * _B(D2, aq, a11) + _B(D2, aq, a20))) / 2
    return c1, float(l1), float(16 * np.finfo(float).eps * n * size), complex(e.lam)


# --------------------------------------------------------------------------- transversality
def dmod_A3(A, dA, *, index=None, digits=None):
    """d|lambda1|/dv by eqs. (A1)–(A3): Re(exp(-i theta0) (F11 zeta0, zeta0^*)) / ... .

    (zeta0, zeta0^*) = conj(zeta0^*)^T zeta0 = 1, so dlambda/dv = <p, dA q> and
    d|lambda|/dv = Re(conj(lambda) dlambda/dv) / |lambda| (= the printed (A3) on |lambda| = 1).
    Returns (dlambda_dv, dmod_dv).
    """
    bk = backend(digits, A, dA)
    with bk.context():
        A, dA = bk.arr(A), bk.arr(dA)
        e = _eigen(bk, A, index)
        return _dmod(e, dA)


def _dmod(e, dA):
    dlam = _vdot(e.p, np.dot(dA, e.q))          # eq. (A2)
    return dlam, (e.lam.conjugate() * dlam).real / abs(e.lam)   # eq. (A3)


# --------------------------------------------------------------------------- circle
@dataclass(frozen=True)
class Circle:
    """Leading-order invariant circle for v = v_c + mu, from l1 and d|lambda1|/dv.

    Kuznetsov radius rho = sqrt(-d mu / l1) (||q||_2 = 1 normalisation); the
    paper's radius (z = y1 + i y2, ||r1||_2 = 1) is 2 rho; the half-width of the
    circle's projection on state variable k is 2 rho |q_k|, to O(rho^3).
    """

    l1: float
    dmod_dv: float
    q_abs: tuple
    names: tuple = ("x1dot+", "x20", "x20dot", "tau")
    normalisation: str = "rho: ||q||_2 = 1, <p,q> = 1; paper radius = 2 rho"

    @property
    def side(self):
        """+1 if the circle exists for mu > 0 (v > v_c), -1 if for mu < 0."""
        return 1 if -self.dmod_dv / self.l1 > 0 else -1

    @property
    def stable(self):
        return self.l1 < 0

    @property
    def coefficient(self):
        """k with rho = k sqrt(|mu|)."""
        return math.sqrt(abs(self.dmod_dv / self.l1))

    def exists(self, mu):
        return float(mu) * self.side >= 0

    def radius(self, mu):
        """Kuznetsov radius rho(mu) = sqrt(-d mu / l1)."""
        mu = float(mu)
        if not math.isfinite(mu):
            raise ParameterError("mu", mu, "a finite real number")
        if not self.exists(mu):
            rng = "mu >= 0" if self.side > 0 else "mu <= 0"
            raise ParameterError("mu", mu, rng, "the invariant circle exists only on the side "
                                 "where d|lambda1|/dv * mu / l1 < 0")
        return self.coefficient * math.sqrt(abs(mu))

    def radius_paper(self, mu):
        """Radius in the paper's z = y1 + i y2 (||r1||_2 = 1): 2 rho."""
        return 2 * self.radius(mu)

    def half_widths(self, mu):
        """Half-width 2 rho |q_k| of the circle in each state variable (numpy array)."""
        return 2 * self.radius(mu) * np.array(self.q_abs, dtype=float)

    def as_dict(self):
        return {"side": "v > v_c" if self.side > 0 else "v < v_c", "stable": bool(self.stable),
                "radius_coefficient": self.coefficient,
                "half_width_coefficients": dict(zip(self.names, (2 * self.coefficient * a
                                                                 for a in self.q_abs))),
                "q_abs": list(self.q_abs), "formula": "rho = k sqrt(|mu|); half-width_k = "
                "2 rho |q_k|; mu = omega - omega_c", "normalisation": self.normalisation}


# --------------------------------------------------------------------------- driver
@dataclass(frozen=True)
class NormalForm:
    """Everything of the Neimark–Sacker reduction at one fixed point.

    Numbers are Python complex/float or numpy arrays (float64 backend), or mpc/mpf
    and object arrays (mpmath backend).  See the module docstring for the
    normalisations; ``normalisation`` repeats them.
    """

    lam: object
    theta: object
    multipliers: object
    q: object
    p: object
    c1: object
    l1: object
    wan_a: object
    f1_wan: object
    f1_printed: object
    resonance: tuple          # (m, |lambda^m - 1|), m in 1..5
    dlam_dv: object = None
    dmod_dv: object = None
    paper: PaperReduction = None
    h11: object = None
    h20: object = None
    backend: str = "float64"
    digits: object = None
    normalisation: str = ("q = r1: A q = lambda1 q, Im lambda1 > 0, ||q||_2 = 1, largest |q_k| "
                          "real > 0; <p,q> = conj(p)^T q = 1; l1 = Re(e^{-i theta} c1) "
                          "(l1 < 0: stable circle); f1 = paper's (58)-(60) normalisation "
                          "(||r1|| = 1, f1 > 0: attracting), f1_wan = -l1/4")
    circle: Circle = None     # the predicted invariant circle (needs dA), or None

    @property
    def kind(self):
        """'supercritical' (stable circle, l1 < 0) or 'subcritical' (l1 > 0)."""
        return "supercritical" if self.l1 < 0 else "subcritical"

    @property
    def theta_over_2pi(self):
        return self.theta / (2 * math.pi) if self.digits is None else self.theta / (2 * mpmath.pi)


def normal_form(A, d2, d3, dA=None, *, index=None, digits=None, names=None, paper=True):
    """Neimark–Sacker normal form of a map with jet (A, d2, d3) and F11 = dA, eqs. (39)–(60).

    Computes Kuznetsov's c1, l1; the paper's reduction (P, G, H, W_ij, g_ij,
    f1 by eq. (60) printed and corrected); Wan's a; (A1)–(A3) when ``dA`` is
    given, and then the predicted circle.  ``digits`` (or mpmath inputs)
    selects the mpmath backend.  ``paper=False`` skips the paper's own reduction
    (its f1 of eq. (60), Wan's a): only l1, c1 and the circle are computed.  Raises SingularCaseError near lambda^m = 1
    (m = 1..3, where the formulas divide by zero) and warns for m = 4, 5.
    """
    bk = backend(digits, A, d2, d3, dA)
    with bk.context():
        A = bk.arr(A)
        if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] < 2:
            raise ParameterError("A", A.shape, "a square n x n matrix with n >= 2")
        n = A.shape[0]
        d2, d3 = bk.arr(d2), bk.arr(d3)
        if d2.shape != (n,) * 3 or d3.shape != (n,) * 4:
            raise ParameterError("d2/d3", (d2.shape, d3.shape),
                                 f"shapes {(n,) * 3} and {(n,) * 4}")
        d2, d3 = _symmetrise(d2), _symmetrise(d3)
        e = _eigen(bk, A, index)
        lam = e.lam
        m, dist = resonance(lam)
        if float(dist) < RESONANCE_REFUSE and m <= 3:
            raise SingularCaseError("strong-resonance",
                                    f"lambda1^{m} = 1 (distance {float(dist):.2e}): the normal "
                                    "form of eqs. (56)-(60) divides by lambda^m - 1")
        if float(dist) < RESONANCE_WARN:
            warnings.warn(f"lambda1 is within {float(dist):.1e} of a strong resonance "
                          f"lambda^{m} = 1: (H2) nearly fails, the cubic normal form is not "
                          "valid in a small neighbourhood", NearSingularWarning, stacklevel=2)
        c1, l1, h11, h20 = _kuznetsov(bk, A, d2, d3, e)
        red = _paper(bk, A, d2, d3, e)[0] if paper else None
        dlam = dmod = circle = None
        if dA is not None:
            dlam, dmod = _dmod(e, bk.arr(dA))
            if float(l1) != 0 and float(dmod) != 0:
                circle = Circle(float(l1), float(dmod), tuple(float(abs(x)) for x in e.q),
                                **({"names": tuple(names)} if names else {}))
        return NormalForm(lam=lam, theta=bk.arg(lam), multipliers=e.values, q=e.q, p=e.p,
                          c1=c1, l1=l1, wan_a=red and red.wan_a, f1_wan=red and red.f1_wan,
                          f1_printed=red and red.f1_printed, resonance=(m, dist), dlam_dv=dlam,
                          dmod_dv=dmod, paper=red, h11=h11, h20=h20, backend=bk.name,
                          digits=bk.digits, circle=circle)


# --------------------------------------------------------------------------- fold and flip
@dataclass(frozen=True)
class RealCritical:
    """A real critical multiplier mu (= +1 or -1) of A with its paired eigenvectors:
    A q = mu q, ||q||_2 = 1, largest |q_k| positive; A^T p = mu p, <p, q> = 1.
    ``p`` is the row of V^-1 belonging to mu's own column of V (explicit pairing).
    ``gap`` is the distance from mu to the other multipliers."""

    mu: float
    q: np.ndarray
    p: np.ndarray
    gap: float


def real_critical(A, target):
    """The multiplier of A nearest ``target`` (+1 fold, -1 flip) and its eigenvectors."""
    A = np.asarray(A, dtype=float)
    vals, V = np.linalg.eig(A)
    k = int(np.argmin(np.abs(vals - target)))
    q = V[:, k].real.copy()
    u = np.linalg.inv(V)[k].real
    j = int(np.argmax(np.abs(q)))
    q /= np.linalg.norm(q) * np.sign(q[j])
    p = u / np.dot(u, q)
    others = np.delete(vals, k)
    gap = float(np.min(np.abs(others - vals[k]))) if len(others) else math.inf
    return RealCritical(float(vals[k].real), q, p, gap)


def fold_coefficient(A, d2):
    """Quadratic coefficient a = <p, B(q, q)> / 2 of the fold normal form
    eta -> eta + a eta^2 + ... (Kuznetsov, Elements, Sec. 5.4 for maps); q, p of
    :func:`real_critical` at +1.  a != 0: a nondegenerate fold."""
    e = real_critical(A, 1.0)
    return float(np.dot(e.p, _B(_symmetrise(np.asarray(d2, float)), e.q, e.q)) / 2), e


def flip_coefficient(A, d2, d3):
    """Period-doubling coefficient of eta -> -eta + c eta^3 + ... (Kuznetsov, Elements,
    Sec. 5.4): c = <p, C(q,q,q)>/6 + <p, B(q, (I - A)^-1 B(q, q))>/2, q, p of
    :func:`real_critical` at -1.  c > 0: supercritical (the period-2 orbit is born
    stable within the centre manifold, on the side where the fixed point is unstable);
    c < 0: subcritical.  For x -> -x + a x^2 + b x^3 it is b + a^2."""
    A = np.asarray(A, dtype=float)
    d2, d3 = _symmetrise(np.asarray(d2, float)), _symmetrise(np.asarray(d3, float))
    e = real_critical(A, -1.0)
    Bqq = _B(d2, e.q, e.q)
    h = np.linalg.solve(np.eye(A.shape[0]) - A, Bqq)
    c = np.dot(e.p, _C(d3, e.q, e.q, e.q)) / 6 + np.dot(e.p, _B(d2, e.q, h)) / 2
    return float(c), e
