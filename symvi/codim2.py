"""Normal-form coefficients of codimension-two bifurcations of fixed points of maps.

System-independent, like :mod:`symvi.normal_form` (whose backends, multilinear
forms and critical eigenvectors are reused here): everything takes the jet of an
n-dimensional map ``x -> f(x)`` (n >= 2) at a fixed point and knows nothing of
impacts.

Jet convention (raw derivatives, full symmetric tensors, *not* divided by factorials)::

    A = Df,  d2[i,j,k],  d3[i,j,k,l],  d4 (order 4),  d5 (order 5)

with B(u,v)_i = d2[i,j,k] u_j v_k, C, D, E the order-3, 4, 5 forms, applied to
complex vectors, so f(x) = A x + B(x,x)/2 + C(x,x,x)/6 + D(x,x,x,x)/24 + E(...)/120.

Method [Kuznetsov & Meijer 2005]: the centre manifold x = H(w) and the restricted
map w -> G(w) (in normal form) solve the homological equation f(H(w)) = H(G(w));
H = sum h_jk w^j conj(w)^k / (j! k!).  At each order the coefficient of the
monomial gives a linear system (mu I - A) h = r - (terms of G); a singular system
(mu a critical multiplier) is solved in bordered form, which fixes the component of
h along the critical eigenvector to zero (<p, h> = 0), and its solvability condition
gives the normal-form coefficient.  "<p, v> = conj(p)^T v" throughout.

Normalisations (every result repeats its own in ``normalisation``)
------------------------------------------------------------------
* Simple complex multiplier lambda (Im lambda > 0, chosen by
  :func:`symvi.normal_form._eigen`): A q = lambda q, ||q||_2 = 1, largest |q_k| real
  > 0; A^T p = conj(lambda) p, <p, q> = 1, p the row of V^{-1} of q's own column
  (explicit pairing); x = w q + conj(w q) + O(|w|^2).
* Simple real multiplier mu = +-1: q real, ||q||_2 = 1, largest |q_k| > 0;
  A^T p = mu p, <p, q> = 1 (the convention of :func:`symvi.normal_form.real_critical`).
* Jordan block at mu = +-1 (R1, R2): A q0 = mu q0, A q1 = mu q1 + q0,
  A^T p1 = mu p1, A^T p0 = mu p0 + p1, ||q0||_2 = 1 (largest |q0_k| > 0),
  <q0, q1> = 0, <p0, q0> = <p1, q1> = 1, <p0, q1> = <p1, q0> = 0;
  x = xi1 q0 + xi2 q1 + O(|xi|^2).
  The only freedom left is the common sign of (q0, q1).

Each result carries ``residuals``: ||A q - lambda q||, ||A^T p - conj(lambda) p||,
|<p, q> - 1| (and the Jordan-chain analogues), so the pairing can be audited.

Where MatContM differs
----------------------
Transcribed formulas of MatContM were re-derived; the following differ, and the
known-answer tests of ``tests/normal_form/test_codim2.py`` side with the derivation:

1. ``nf_CHm`` solves (I - A) h22 = r22; the homological equation has
   (I - A) h22 = r22 - 4 Re(conj(lambda) g21) h11 (from h11 G conj(G)).  The term
   vanishes at l1 = 0, so MatContM is right *at* a Chenciner point; we keep it, so
   c2 is right also off l1 = 0 (``test_chenciner_off_l1_zero``).
2. ``nf_LPNSm`` and ``nf_PDNSm``: h021 = C(q,q,qb) + 2B(qb,h020) + B(q,h011);
   derived: C(q,q,qb) + B(qb,h020) + 2B(q,h011) (as in the NS coefficient c1).
3. ``nf_PDNSm``: h111 uses 2 Re B(h110, q); derived: 2 Re B(h110, conj(q)) (as
   ``nf_LPNSm`` has it).
4. ``nf_LPPDm`` solves (I - A) h20 = a1 q0 - B(q0,q0) and likewise h02: the sign of
   the right-hand side is reversed (compare ``nf_CPm``, which has it right); derived:
   (I - A) h20 = B(q0,q0) - a1 q0.

The hypernormalised combinations of ``nf_LPNSm`` (s, a, b, c) and ``nf_LPPDm``
(a/e, b e, CNS) are *transcribed*, evaluated on our (corrected) critical
coefficients; they are not independently derived.  MatContM's own two versions of
nf_LPNS differ in the last term of b (f200 g021 vs f200 g021 conj(lambda)); we use
``nf_LPNSm``'s.

References
----------
[Kuznetsov, Elements] Yu. A. Kuznetsov, Elements of Applied Bifurcation Theory,
3rd ed., Springer 2004, Secs. 5.4, 9.5 (strong resonances), 9.6.
[Kuznetsov & Meijer 2005] Yu. A. Kuznetsov and H. G. E. Meijer, Numerical normal
forms for codim 2 bifurcations of fixed points with at most two critical
eigenvalues, SIAM J. Sci. Comput. 26 (2005) 1932-1954.
[MatContM] MultilinearForms/nf_*m.m of MatContM (W. Govaerts, Yu. A. Kuznetsov,
R. Khoshsiar Ghaziani, H. G. E. Meijer).
"""
import math
from dataclasses import dataclass, field

import numpy as np

from .errors import NearSingularWarning, ParameterError, SingularCaseError  # noqa: F401
from .normal_form import _B, _C, _eigen, _kuznetsov, _phase_fix, _symmetrise, _vdot, backend

#: default bound on the distance of the critical multipliers from their exact
#: codimension-two values (relative to max(1, max|multiplier|))
TOL = 1e-6


# --------------------------------------------------------------------------- small generic helpers
def _D(d4, a, b, c, e):
    """D(a, b, c, e)_i = d4[i, j, k, l, m] a_j b_k c_l e_m."""
    return np.dot(np.dot(np.dot(np.dot(d4, e), c), b), a)


def _E(d5, a, b, c, e, g):
    """E(a, b, c, e, g)_i = d5[i, j, k, l, m, r] a_j b_k c_l e_m g_r."""
    return np.dot(np.dot(np.dot(np.dot(np.dot(d5, g), e), c), b), a)


def _sym(d, first=1):
    """Average a tensor over permutations of its axes first..end, by cosets:
    Sym_m = (1/m) sum_j tau_(first, j) (Sym over the later axes); O(m^2) transposes."""
    m = d.ndim - first
    if m <= 1:
        return d
    t = _sym(d, first + 1)
    acc = t.copy()
    for j in range(first + 1, d.ndim):
        acc = acc + np.swapaxes(t, first, j)
    return acc / m


def _jet(bk, A, *ds):
    """Backend arrays of A and the symmetrised derivatives, shapes checked."""
    A = bk.arr(A)
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] < 2:
        raise ParameterError("A", A.shape, "a square n x n matrix with n >= 2")
    n = A.shape[0]
    out = [A]
    for k, d in enumerate(ds, start=2):
        d = bk.arr(d)
        if d.shape != (n,) * (k + 1):
            raise ParameterError(f"d{k}", d.shape, f"shape {(n,) * (k + 1)}")
        out.append(_symmetrise(d) if k <= 3 else _sym(d))
    return out


def _num(bk, x):
    """A Python float/complex (float64 backend) or the mpmath number itself."""
    if bk.digits is None:
        x = complex(x)
        return x.real if x.imag == 0 else x
    return x


def _real(bk, x):
    return float(np.real(x)) if bk.digits is None else bk.real(x)


def _norm(v):
    return math.sqrt(sum(float(abs(e)) ** 2 for e in v))


def _scale(vals):
    return max(1.0, max(float(abs(e)) for e in vals))


def _solve(bk, M, b, what):
    """M^{-1} b, refused when M is numerically singular (a further critical multiplier)."""
    c = bk.cond(M)
    if not c < 1e-3 / float(bk.eps):
        raise SingularCaseError("singular-solve", f"{what} is singular (cond {c:.2e}): a "
                                "further multiplier is critical (higher codimension)")
    return bk.solve(M, b)


def _bordered(bk, M, q, p, r, what):
    """The h with M h = r - s q, <p, h> = 0 (s fixed by solvability): the bordered system
    [[M, q], [conj(p)^T, 0]] [h; s] = [r; 0]  [Kuznetsov & Meijer 2005]."""
    n = M.shape[0]
    K = bk.zeros((n + 1, n + 1))
    K[:n, :n] = M
    K[:n, n] = q
    K[n, :n] = np.conj(p)
    rhs = bk.zeros(n + 1)
    rhs[:n] = r
    return _solve(bk, K, rhs, what)[:n]


def _check_dist(dist, tol, kind, message):
    if not float(dist) <= tol:
        raise SingularCaseError(kind, message)


# --------------------------------------------------------------------------- eigen-structure
def _complex_pair(bk, A, index, target, tol):
    """normal_form's critical pair (q, p paired explicitly) and its residuals.

    ``target``: None (the pair nearest the unit circle must lie on it) or the exact
    multiplier (e.g. 1j for R4), within ``tol``."""
    e = _eigen(bk, A, index)
    s = _scale(e.values)
    if target is None:
        _check_dist(abs(abs(e.lam) - 1), tol * s, "not-on-unit-circle",
                    f"|lambda| = {float(abs(e.lam)):.12g}: no complex pair on the unit circle")
    else:
        _check_dist(abs(e.lam - target), tol * s, "not-resonant",
                    f"lambda = {complex(e.lam):.12g} is not {complex(target):.6g} "
                    f"(distance {float(abs(e.lam - target)):.2e} > tol {tol:.1e})")
    res = {"|A q - lam q|": _norm(np.dot(A, e.q) - e.lam * e.q),
           "|A^T p - conj(lam) p|": _norm(np.dot(A.T, e.p) - np.conj(e.lam) * e.p),
           "|<p,q> - 1|": float(abs(_vdot(e.p, e.q) - 1)),
           "|<p,conj(q)>|": float(abs(_vdot(e.p, np.conj(e.q))))}
    return e, res


@dataclass(frozen=True)
class _Real:
    mu: object
    q: object
    p: object
    res: dict


def _real_eig(bk, A, target, tol, vals=None, V=None, tag=""):
    """Simple real multiplier nearest ``target`` (+1 or -1) and its paired vectors.

    The convention of :func:`symvi.normal_form.real_critical` (which is float64 only):
    q real, ||q||_2 = 1, largest |q_k| > 0; p the row of V^{-1} of q's column,
    scaled to <p, q> = 1 (A^T p = mu p).  Refused when the multiplier is not within
    ``tol`` of the target or is not simple."""
    if vals is None:
        vals, V = bk.eig(A)
    n = A.shape[0]
    s = _scale(vals)
    k = min(range(n), key=lambda i: (float(abs(vals[i] - target)), i))
    mu = vals[k]
    _check_dist(abs(mu - target), tol * s, f"no-multiplier{tag}",
                f"no multiplier at {target:+g} (nearest {complex(mu):.12g})")
    gap = min(float(abs(vals[i] - mu)) for i in range(n) if i != k)
    if not gap > tol * s:
        raise SingularCaseError(f"double-multiplier{tag}",
                                f"the multiplier {target:+g} is not simple (distance "
                                f"{gap:.2e} to another): a 1:{1 if target > 0 else 2} "
                                "resonance, see resonance_1_1 / resonance_1_2")
    q = bk.re(_phase_fix(bk, V[:, k].copy()))
    u = bk.inv(V)[k, :]
    u = u / np.dot(u, q)
    p = bk.re(np.conj(u))
    mu = mu.real
    res = {f"|A q{tag} - mu q{tag}|": _norm(np.dot(A, q) - mu * q),
           f"|A^T p{tag} - mu p{tag}|": _norm(np.dot(A.T, p) - mu * p),
           f"|<p{tag},q{tag}> - 1|": float(abs(_vdot(p, q) - 1))}
    return _Real(mu, q, p, res)


def _svd(bk, M):
    """(U, singular values ascending-sorted indices, V) of a real matrix M = U S V^T."""
    if bk.digits is None:
        U, S, Vt = np.linalg.svd(np.real(M).astype(float))
        return U, list(S), Vt.T
    import mpmath
    U, S, Vt = mpmath.svd_r(mpmath.matrix([[x.real for x in row] for row in M.tolist()]))
    n = M.shape[0]
    U = np.array([[U[i, j] for j in range(n)] for i in range(n)], dtype=object)
    V = np.array([[Vt[j, i] for j in range(n)] for i in range(n)], dtype=object)
    return U, [S[i] for i in range(n)], V


@dataclass(frozen=True)
class _Jordan:
    mu: object
    q0: object
    q1: object
    p0: object
    p1: object
    res: dict


def _jordan(bk, A, mu, tol):
    """Jordan chain of a double multiplier mu = +-1 (one Jordan block) and its dual basis.

    A q0 = mu q0, A q1 = mu q1 + q0, A^T p1 = mu p1, A^T p0 = mu p0 + p1;
    ||q0|| = 1 (largest component > 0), <q0, q1> = 0, <p_i, q_j> = delta_ij.
    q0, p1 are the right/left singular vectors of A - mu I for its smallest singular
    value; q1 solves [[A - mu I, p1], [q0^T, 0]] [q1; 0] = [q0; 0], p0 likewise.
    Refused: no multiplier mu; mu semisimple (two singular values ~ 0); mu simple
    (<p1, q0> != 0); a longer Jordan chain (<p1, q1> = 0)."""
    n = A.shape[0]
    M = A - mu * bk.eye(n)
    U, S, V = _svd(bk, M)
    order = sorted(range(n), key=lambda i: float(S[i]))
    s = max(1.0, float(max(S)))
    name = {1: "1", -1: "-1"}[mu]
    _check_dist(S[order[0]], tol * s, "no-multiplier",
                f"A - ({name}) I is regular (smallest singular value {float(S[order[0]]):.2e}):"
                f" no multiplier {name}")
    if float(S[order[1]]) <= tol * s:
        raise SingularCaseError("semisimple",
                                f"the multiplier {name} is semisimple (two singular values of "
                                f"A - ({name}) I vanish: {float(S[order[0]]):.1e}, "
                                f"{float(S[order[1]]):.1e}): two independent eigenvectors, "
                                "no Jordan block, not a 1:%s resonance" % ("1" if mu > 0 else "2"))
    q0 = bk.arr(V[:, order[0]])
    p1 = bk.arr(U[:, order[0]])
    q0 = bk.re(_phase_fix(bk, q0))
    overlap = float(abs(_vdot(p1, q0))) / _norm(p1)
    if overlap > tol ** 0.5:
        raise SingularCaseError("simple", f"the multiplier {name} is simple (<p, q> = "
                                f"{overlap:.2e} != 0): no Jordan block, a plain "
                                f"{'fold' if mu > 0 else 'flip'}")
    # (A - mu I) q1 = q0, <q0, q1> = 0     (bordered, solvable since <p1, q0> = 0)
    q1 = _bordered(bk, M, p1, q0, q0, "the Jordan-chain system for q1")
    # (A - mu I)^T v = p1 (any solution); p0 = v + t p1
    v = _bordered(bk, M.T, q0, p1, p1, "the Jordan-chain system for p0")
    g = _vdot(p1, q1)
    if float(abs(g)) <= tol ** 0.5 * _norm(p1) * _norm(q1):
        raise SingularCaseError("triple", f"<p1, q1> = {float(abs(g)):.2e}: the Jordan block of "
                                f"{name} is longer than 2 (codimension > 2)")
    p1 = p1 / np.conj(g)                     # <p1, q1> = 1
    v = v / np.conj(g)                       # (A - mu I)^T v = p1 still; then <v, q0> = 1
    p0 = v - np.conj(_vdot(v, q1)) * p1      # <p0, q1> = 0
    res = {"|A q0 - mu q0|": _norm(np.dot(A, q0) - mu * q0),
           "|A q1 - mu q1 - q0|": _norm(np.dot(A, q1) - mu * q1 - q0),
           "|A^T p1 - mu p1|": _norm(np.dot(A.T, p1) - mu * p1),
           "|A^T p0 - mu p0 - p1|": _norm(np.dot(A.T, p0) - mu * p0 - p1),
           "|<p0,q0> - 1|": float(abs(_vdot(p0, q0) - 1)),
           "|<p1,q1> - 1|": float(abs(_vdot(p1, q1) - 1)),
           "|<p0,q1>|": float(abs(_vdot(p0, q1))), "|<p1,q0>|": float(abs(_vdot(p1, q0))),
           "|<q0,q1>|": float(abs(_vdot(q0, q1)))}
    return _Jordan(mu, q0, q1, p0, p1, res)


def _default_tol(tol):
    if tol is None:
        return TOL
    if not (isinstance(tol, (int, float)) and tol > 0):
        raise ParameterError("tol", tol, "a positive number")
    return float(tol)


# --------------------------------------------------------------------------- Chenciner
_NORM_NS = ("A q = lambda q, Im lambda > 0, ||q||_2 = 1, largest |q_k| real > 0; "
            "A^T p = conj(lambda) p, <p,q> = conj(p)^T q = 1; x = w q + conj(w q) + O(|w|^2)")


@dataclass(frozen=True)
class Chenciner:
    """Chenciner (generalised Neimark–Sacker) point: w -> lambda w + c1 w|w|^2 + c2 w|w|^4.

    With a = conj(lambda) c1, b = conj(lambda) c2 (|lambda| = 1), i.e. the normal form
    w -> lambda w (1 + a|w|^2 + b|w|^4):  |w'| = |w| (1 + l1 |w|^2 + l2 |w|^4 + ...),
    l1 = Re a, l2 = Re b + (Im a)^2 / 2.  ``l2_matcont`` = Re(b - a^2/2) (MatContM's
    coefficient) = l2 - l1^2/2, equal to l2 at a Chenciner point (l1 = 0).
    At l1 = 0, l2 < 0: the fixed point is weakly attracting and the circle branch of
    the nearby subcritical (l1 > 0) NS points turns at a fold of circles, beyond which a
    *stable* invariant circle surrounds the unstable one; l2 > 0: the mirror case
    (an unstable outer circle).  Only Re b is invariant (Im b depends on the choice
    of normalising transformation; here <p, h21> = 0).
    """

    lam: object
    q: object
    p: object
    c1: object
    c2: object
    l1: object
    l2: object
    l2_matcont: object
    residuals: dict = field(default_factory=dict)
    backend: str = "float64"
    digits: object = None
    normalisation: str = _NORM_NS


def chenciner(A, d2, d3, d4, d5, *, index=None, tol=None, digits=None):
    """c1, c2, l1, l2 of a Chenciner point [Kuznetsov & Meijer 2005], [MatContM nf_CHm].

    The pair lambda nearest the unit circle (or ``values[index]``, Im > 0); refused
    when ||lambda| - 1| > tol, or lambda^m = 1 for m <= 4 (a singular solve).
    Normalisation: ||q||_2 = 1, <p, q> = 1 (see :class:`Chenciner`).
    """
    tol = _default_tol(tol)
    bk = backend(digits, A, d2, d3, d4, d5)
    with bk.context():
        A, d2, d3, d4, d5 = _jet(bk, A, d2, d3, d4, d5)
        n = A.shape[0]
        e, res = _complex_pair(bk, A, index, None, tol)
        lam, q, p = e.lam, e.q, e.p
        lb, qb = np.conj(lam), np.conj(q)
        I = bk.eye(n)

        def B(u, v):
            return _B(d2, u, v)

        def C(u, v, w):
            return _C(d3, u, v, w)

        def D(u, v, w, x):
            return _D(d4, u, v, w, x)

        # c1 and h11 = (I - A)^{-1} B(q, qb), h20 = (lam^2 I - A)^{-1} B(q, q) as for NS
        c1, _, h11, h20 = _kuznetsov(bk, A, d2, d3, e)
        g21 = 2 * c1
        h02 = np.conj(h20)
        # (lam I - A) h21 = r21 - g21 q, <p, h21> = 0
        r21 = C(q, q, qb) + 2 * B(q, h11) + B(qb, h20)
        h21 = _bordered(bk, A - lam * I, q, p, g21 * q - r21, "A - lambda I")
        h12 = np.conj(h21)
        # (lam^3 I - A) h30 = C(q,q,q) + 3 B(q, h20)
        h30 = _solve(bk, lam ** 3 * I - A, C(q, q, q) + 3 * B(q, h20), "lambda^3 I - A")
        # (lam^3 lb I - A) h31 = r31 - 3 lam g21 h20   (h20 G^2 / 2 of H(G))
        r31 = (D(q, q, q, qb) + 3 * C(q, q, h11) + 3 * C(q, qb, h20) + 3 * B(h20, h11)
               + B(qb, h30) + 3 * B(q, h21))
        h31 = _solve(bk, lam ** 3 * lb * I - A, r31 - 3 * lam * g21 * h20,
                     "lambda^2 I - A")
        # (|lam|^4 I - A) h22 = r22 - 4 Re(lb g21) h11   (h11 G conj(G); MatContM omits it)
        r22 = (D(q, q, qb, qb) + C(q, q, h02) + C(qb, qb, h20) + 4 * C(q, qb, h11)
               + B(h20, h02) + 2 * B(h11, h11) + 2 * B(qb, h21) + 2 * B(q, h12))
        h22 = _solve(bk, (lam * lb) ** 2 * I - A, r22 - 4 * (lb * g21).real * h11, "I - A")
        # coefficient of w^3 wb^2 / 12 in f(H); g32 = <p, r32> since <p, h21> = 0
        r32 = (_E(d5, q, q, q, qb, qb) + D(q, q, q, h02) + 6 * D(q, q, qb, h11)
               + 3 * D(q, qb, qb, h20) + 6 * C(h11, h11, q) + 6 * C(q, qb, h21)
               + 6 * C(qb, h11, h20) + 3 * C(q, h20, h02) + 3 * C(q, q, h12)
               + C(qb, qb, h30) + 6 * B(h11, h21) + 3 * B(h20, h12) + 3 * B(q, h22)
               + 2 * B(qb, h31) + B(h02, h30))
        c2 = _vdot(p, r32) / 12
        u = lb / abs(lam)                      # e^{-i theta}
        a, b = u * c1, u * c2
        l1 = a.real
        l2 = b.real + a.imag ** 2 / 2
        l2m = (b - a * a / 2).real
        return Chenciner(lam=_num(bk, lam), q=q, p=p, c1=_num(bk, c1), c2=_num(bk, c2),
                         l1=_real(bk, l1), l2=_real(bk, l2), l2_matcont=_real(bk, l2m),
                         residuals=res, backend=bk.name, digits=bk.digits)
