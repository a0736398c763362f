"""Normal-form coefficients of codimension-two bifurcations of fixed points of maps.

System-independent, like :mod:`symvi.normal_forms.normal_form` (whose backends, multilinear
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
  :func:`symvi.normal_forms.normal_form._eigen`): A q = lambda q, ||q||_2 = 1, largest |q_k| real
  > 0; A^T p = conj(lambda) p, <p, q> = 1, p the row of V^{-1} of q's own column
  (explicit pairing); x = w q + conj(w q) + O(|w|^2).
* Simple real multiplier mu = +-1: q real, ||q||_2 = 1, largest |q_k| > 0;
  A^T p = mu p, <p, q> = 1 (the convention of :func:`symvi.normal_forms.normal_form.real_critical`).
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
known-answer tests of ``tests/normal_forms/test_codim2.py`` side with the derivation:

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
import contextlib
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ParameterError, SingularCaseError
from .normal_form import _B, _C, _backend, _eigen, _kuznetsov, _phase_fix, _symmetrise, _vdot

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
    A = bk.carr(A)
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] < 2:
        raise ParameterError("A", A.shape, "a square n x n matrix with n >= 2")
    n = A.shape[0]
    out = [A]
    for k, d in enumerate(ds, start=2):
        d = bk.carr(d)
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
    return bk.real(x)


def _norm(v):
    return math.sqrt(sum(float(abs(e)) ** 2 for e in v))


def _scale(vals):
    return max(1.0, max(float(abs(e)) for e in vals))


def _solve(bk, M, b, what):
    """M^{-1} b, refused when M is numerically singular (a further critical multiplier)."""
    c = bk.cond(M)
    if not c < 1e-3 / bk.eps:
        raise SingularCaseError("singular-solve", f"{what} is singular (cond {c:.2e}): a "
                                "further multiplier is critical (higher codimension)")
    return bk.csolve(M, b)


def _bordered(bk, M, q, p, r, what):
    """The h with M h = r - s q, <p, h> = 0 (s fixed by solvability): the bordered system
    [[M, q], [conj(p)^T, 0]] [h; s] = [r; 0]  [Kuznetsov & Meijer 2005]."""
    n = M.shape[0]
    K = bk.czeros((n + 1, n + 1))
    K[:n, :n] = M
    K[:n, n] = q
    K[n, :n] = np.conj(p)
    rhs = bk.czeros(n + 1)
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

    The convention of :func:`symvi.normal_forms.normal_form.real_critical` (which is float64 only):
    q real, ||q||_2 = 1, largest |q_k| > 0; p the row of V^{-1} of q's column,
    scaled to <p, q> = 1 (A^T p = mu p).  Refused when the multiplier is not within
    ``tol`` of the target or is not simple."""
    if vals is None:
        vals, V = bk.ceig(A)
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
    q = bk.carr(bk.vreal(_phase_fix(bk, V[:, k].copy())))
    u = bk.cinv(V)[k, :]
    u = u / np.dot(u, q)
    p = bk.carr(bk.vreal(np.conj(u)))
    mu = mu.real
    res = {f"|A q{tag} - mu q{tag}|": _norm(np.dot(A, q) - mu * q),
           f"|A^T p{tag} - mu p{tag}|": _norm(np.dot(A.T, p) - mu * p),
           f"|<p{tag},q{tag}> - 1|": float(abs(_vdot(p, q) - 1))}
    return _Real(mu, q, p, res)


def _svd(bk, M):
    """(U, singular values, V) of the real part of a square M = U S V^T."""
    U, S, Vt = bk.svd(bk.vreal(M))
    return U, list(S), Vt.T


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
    M = A - mu * bk.ceye(n)
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
    q0 = bk.carr(V[:, order[0]])
    p1 = bk.carr(U[:, order[0]])
    q0 = bk.carr(bk.vreal(_phase_fix(bk, q0)))
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


@contextlib.contextmanager
def _prepared(tol, digits, A, *ds):
    """(tol, backend, [A, *ds] as the backend's arrays, the derivatives symmetrised), inside
    the backend's precision: the start of every normal form here."""
    tol = _default_tol(tol)
    bk = _backend(digits, A, *ds)
    with bk.context():
        yield tol, bk, _jet(bk, A, *ds)


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
    with _prepared(tol, digits, A, d2, d3, d4, d5) as (tol, bk, (A, d2, d3, d4, d5)):
        n = A.shape[0]
        e, res = _complex_pair(bk, A, index, None, tol)
        lam, q, p = e.lam, e.q, e.p
        lb, qb = np.conj(lam), np.conj(q)
        I = bk.ceye(n)

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


# --------------------------------------------------------------------------- 1:1 and 1:2 resonances
_NORM_JORDAN = ("A q0 = mu q0, A q1 = mu q1 + q0, A^T p1 = mu p1, A^T p0 = mu p0 + p1; "
                "||q0||_2 = 1 (largest component > 0), <q0,q1> = 0, <p_i,q_j> = delta_ij; "
                "x = xi1 q0 + xi2 q1 + O(|xi|^2)")


@dataclass(frozen=True)
class Resonance11:
    """1:1 resonance (R1): xi -> (xi1 + xi2, xi2 + a xi1^2 + b xi1 xi2) + O(|xi|^3).

    The map is approximated by the time-1 map of the Bogdanov–Takens flow
    x' = y, y' = a x^2 + (b - 2a) x y (quadratic terms of the time-1 map brought to this
    normal form give a = A, b = B + 2A for y' = A x^2 + B x y;
    ``test_r1_bt_flow``), so s = sign(a (b - 2a)) is the BT sign: s = -1, the
    invariant circle born on the nearby NS branch is stable; s = +1, unstable
    [Kuznetsov, Elements, Secs. 8.4, 9.5.1].  (a, b) change sign with (q0, q1); s does
    not.  ``s`` is 0 when |a (b - 2a)| <= 1e-13 (MatContM's cut-off).
    """

    a: object
    b: object
    s: int
    q0: object
    q1: object
    p0: object
    p1: object
    residuals: dict = field(default_factory=dict)
    backend: str = "float64"
    digits: object = None
    normalisation: str = _NORM_JORDAN


def resonance_1_1(A, d2, *, tol=None, digits=None):
    """a, b and s of a 1:1 resonance [Kuznetsov & Meijer 2005], [MatContM nf_R1m].

    a = <p1, B(q0,q0)>/2, b = <p1, B(q0,q1)> + <p0, B(q0,q0)> (solvability of the
    xi1^2 and xi1 xi2 terms of f(H) = H(G), using <p1, h20> = -<p0, B(q0,q0)>).
    Needs a double multiplier 1 with a Jordan block; a semisimple double 1, a simple 1
    or no multiplier 1 is refused (SingularCaseError).  Normalisation: see
    :class:`Resonance11`.
    """
    with _prepared(tol, digits, A, d2) as (tol, bk, (A, d2)):
        J = _jordan(bk, A, 1, tol)
        Bqq = _B(d2, J.q0, J.q0)
        a = _vdot(J.p1, Bqq) / 2
        b = _vdot(J.p1, _B(d2, J.q0, J.q1)) + _vdot(J.p0, Bqq)
        a, b = _real(bk, a), _real(bk, b)
        prod = a * (b - 2 * a)
        s = 0 if abs(float(prod)) < 1e-13 else (1 if prod > 0 else -1)
        return Resonance11(a=a, b=b, s=s, q0=J.q0, q1=J.q1, p0=J.p0, p1=J.p1,
                           residuals=J.res, backend=bk.name, digits=bk.digits)


@dataclass(frozen=True)
class Resonance12:
    """1:2 resonance (R2): xi -> (-xi1 + xi2, -xi2 + C xi1^3 + D xi1^2 xi2) + O(|xi|^4).

    ``flow`` = (4C, -2D - 6C) [Kuznetsov, Elements, Sec. 9.5.2; MatContM nf_R2m]: the
    second iterate is approximated by the time-1 map of x' = y, y' = 4C x^3 +
    (-2D - 6C) x^2 y with x = xi1, y = -2 xi2.  Checked: for F = -(time-1 map of
    x' = y, y' = C1 x^3 + D1 x^2 y) this gives C = C1, D = -D1 - 3 C1, so flow = (4 C1,
    2 D1), the time-2 field rescaled (``test_r2_flow``).  C, D do not depend on the sign
    of (q0, q1).
    """

    C: object
    D: object
    flow: tuple
    q0: object
    q1: object
    p0: object
    p1: object
    residuals: dict = field(default_factory=dict)
    backend: str = "float64"
    digits: object = None
    normalisation: str = _NORM_JORDAN


def resonance_1_2(A, d2, d3, *, tol=None, digits=None):
    """C, D of a 1:2 resonance [Kuznetsov & Meijer 2005], [MatContM nf_R2m].

    (I - A) h20 = B(q0,q0), (I - A) h11 = B(q0,q1) + h20;
    C = <p1, C(q0,q0,q0) + 3B(q0,h20)>/6,
    D = (<p1, C(q0,q0,q1) + B(q1,h20) + 2B(q0,h11)> + <p0, C(q0,q0,q0) + 3B(q0,h20)>)/2
    (the xi1^3 and xi1^2 xi2 solvability conditions, with <p1, h30> = -<p0, r30>).
    Needs a double multiplier -1 with a Jordan block (else SingularCaseError).
    """
    with _prepared(tol, digits, A, d2, d3) as (tol, bk, (A, d2, d3)):
        J = _jordan(bk, A, -1, tol)
        q0, q1, p0, p1 = J.q0, J.q1, J.p0, J.p1
        ImA = bk.ceye(A.shape[0]) - A
        h20 = _solve(bk, ImA, _B(d2, q0, q0), "I - A")
        h11 = _solve(bk, ImA, _B(d2, q0, q1) + h20, "I - A")
        r30 = _C(d3, q0, q0, q0) + 3 * _B(d2, q0, h20)
        r21 = _C(d3, q0, q0, q1) + _B(d2, q1, h20) + 2 * _B(d2, q0, h11)
        C = _real(bk, _vdot(p1, r30) / 6)
        D = _real(bk, (_vdot(p1, r21) + _vdot(p0, r30)) / 2)
        return Resonance12(C=C, D=D, flow=(4 * C, -2 * D - 6 * C), q0=q0, q1=q1, p0=p0, p1=p1,
                           residuals=J.res, backend=bk.name, digits=bk.digits)


# --------------------------------------------------------------------------- 1:3 and 1:4 resonances
@dataclass(frozen=True)
class Resonance13:
    """1:3 resonance (R3): w -> lambda w + b1 conj(w)^2 + c1 w|w|^2 + O(|w|^4), lambda^3 = 1.

    ``coef`` = (lambda^2 c1 / |b1|^2 - 1) / 3 (complex; MatContM's nondegeneracy pair is
    (Re, Im)).  b1 turns with the phase of q, |b1| does not.  Re(coef) is invariant
    under every near-identity change of coordinates; Im(coef) depends on the normalising
    transformation (here <p, h02> = 0): a resonant change w -> w + k conj(w)^2 adds
    4i Im(k lambda conj(b1)) to lambda^2 c1.
    """

    lam: object
    b1: object
    c1: object
    coef: object
    re: object
    im: object
    q: object
    p: object
    residuals: dict = field(default_factory=dict)
    backend: str = "float64"
    digits: object = None
    normalisation: str = _NORM_NS


def resonance_1_3(A, d2, d3, *, index=None, tol=None, digits=None):
    """b1, c1 and (lambda^2 c1/|b1|^2 - 1)/3 of a 1:3 resonance [MatContM nf_R3m].

    b1 = <p, B(qb,qb)>/2; (lambda I - A) h02 = B(qb,qb) - 2 b1 q with <p, h02> = 0
    (conj(lambda)^2 = lambda), h20 = conj(h02); h11 = (I - A)^{-1} B(q,qb);
    c1 = <p, C(q,q,qb) + B(qb,h20) + 2B(q,h11)>/2.  lambda (Im > 0) must be within tol
    of exp(2 pi i/3); b1 = 0 is refused.
    """
    with _prepared(tol, digits, A, d2, d3) as (tol, bk, (A, d2, d3)):
        n = A.shape[0]
        e, res = _complex_pair(bk, A, index, bk.cexp(2j * bk.pi / 3), tol)
        lam, q, p = e.lam, e.q, e.p
        qb = np.conj(q)
        I = bk.ceye(n)
        Bqbqb = _B(d2, qb, qb)
        b1 = _vdot(p, Bqbqb) / 2
        if not float(abs(b1)) > tol:
            raise SingularCaseError("degenerate", f"|b1| = {float(abs(b1)):.2e}: the quadratic "
                                    "coefficient of the 1:3 resonance vanishes")
        h02 = _bordered(bk, A - lam * I, q, p, 2 * b1 * q - Bqbqb, "A - lambda I")
        h20 = np.conj(h02)
        h11 = _solve(bk, lam * np.conj(lam) * I - A, _B(d2, q, qb), "I - A")
        c1 = _vdot(p, _C(d3, q, q, qb) + _B(d2, qb, h20) + 2 * _B(d2, q, h11)) / 2
        coef = (lam * lam * c1 / abs(b1) ** 2 - 1) / 3
        return Resonance13(lam=_num(bk, lam), b1=_num(bk, b1), c1=_num(bk, c1),
                           coef=_num(bk, coef), re=_real(bk, coef.real),
                           im=_real(bk, coef.imag), q=q, p=p, residuals=res,
                           backend=bk.name, digits=bk.digits)


@dataclass(frozen=True)
class Resonance14:
    """1:4 resonance (R4): w -> i w + c1 w|w|^2 + d1 conj(w)^3 + O(|w|^4).

    ``A`` = -i c1 / |d1| (complex; MatContM's pair is (Re A, Im A)); A does not depend on
    the phase of q (d1 turns with it, |d1| does not) nor on any near-identity change.
    """

    lam: object
    c1: object
    d1: object
    A: object
    re: object
    im: object
    q: object
    p: object
    residuals: dict = field(default_factory=dict)
    backend: str = "float64"
    digits: object = None
    normalisation: str = _NORM_NS


def resonance_1_4(A, d2, d3, *, index=None, tol=None, digits=None):
    """c1, d1 and A = -i c1/|d1| of a 1:4 resonance [MatContM nf_R4m].

    c1 is Kuznetsov's NS coefficient (:func:`symvi.normal_forms.normal_form._kuznetsov`, with
    h20 = -(A + I)^{-1} B(q,q)); d1 = <p, C(qb,qb,qb) + 3B(qb,h02)>/6, h02 = conj(h20).
    lambda (Im > 0) must be within tol of i; d1 = 0 is refused.
    """
    with _prepared(tol, digits, A, d2, d3) as (tol, bk, (A, d2, d3)):
        e, res = _complex_pair(bk, A, index, 1j, tol)
        q, p = e.q, e.p
        qb = np.conj(q)
        c1, _, _, h20 = _kuznetsov(bk, A, d2, d3, e)
        d1 = _vdot(p, _C(d3, qb, qb, qb) + 3 * _B(d2, qb, np.conj(h20))) / 6
        if not float(abs(d1)) > tol:
            raise SingularCaseError("degenerate", f"|d1| = {float(abs(d1)):.2e}: the conj(w)^3 "
                                    "coefficient of the 1:4 resonance vanishes")
        Ac = -1j * c1 / abs(d1)
        return Resonance14(lam=_num(bk, e.lam), c1=_num(bk, c1), d1=_num(bk, d1),
                           A=_num(bk, Ac), re=_real(bk, Ac.real), im=_real(bk, Ac.imag),
                           q=q, p=p, residuals=res, backend=bk.name, digits=bk.digits)


# --------------------------------------------------------------------------- fold-NS and flip-NS
_NORM_XZ = ("real multiplier: A q1 = mu q1, ||q1||_2 = 1 (largest component > 0), "
            "A^T p1 = mu p1, <p1,q1> = 1; pair: " + _NORM_NS.replace("q", "q2").replace(
                "p", "p2").replace("w ", "z ") + "; x = xi q1 + z q2 + conj(z q2) + ...")


@dataclass(frozen=True)
class FoldNS:
    """Fold–Neimark–Sacker (LPNS), critical normal form [Kuznetsov & Meijer 2005]:

        xi -> xi + f200 xi^2 + f011 |z|^2 + f300 xi^3 + f111 xi |z|^2,
        z  -> lambda z + g110 xi z + g210 xi^2 z + g021 z |z|^2   (+ O(4)).

    f200, f011, g110 are invariant; the cubic ones depend on the normalising
    transformation (here <p1, h200> = <p1, h011> = <p2, h110> = 0).  Under
    q1 -> -q1, f200, f011 and g110 change sign.  ``s, a, b, c``: the hypernormalised
    combination of MatContM nf_LPNSm, *transcribed* (s = sign(f200 f011),
    a = g110/f200, b = (f011 g210 + g110 (f111/2 + Re(conj(lambda) g021)) - f200 g021)
    / (f011 f200^2), c = f300/f200^2); not independently derived.
    """

    lam: object
    f200: object
    f011: object
    g110: object
    f300: object
    f111: object
    g210: object
    g021: object
    s: int
    a: object
    b: object
    c: object
    q1: object
    p1: object
    q2: object
    p2: object
    residuals: dict = field(default_factory=dict)
    backend: str = "float64"
    digits: object = None
    normalisation: str = _NORM_XZ


def fold_ns(A, d2, d3, *, index=None, tol=None, digits=None):
    """Critical normal form of a fold–Neimark–Sacker point (see :class:`FoldNS`).

    h200, h011 (bordered at 1), h110 (bordered at lambda), h020 = (lambda^2 I - A)^{-1}
    B(q2,q2); f300 = <p1, C(q1,q1,q1) + 3B(q1,h200)>/6,
    f111 = <p1, C(q1,q2,qb2) + B(q1,h011) + 2 Re B(h110,qb2)>,
    g210 = <p2, C(q1,q1,q2) + 2B(q1,h110) + B(q2,h200)>/2,
    g021 = <p2, C(q2,q2,qb2) + 2B(q2,h011) + B(qb2,h020)>/2 (MatContM has the factor 2
    on the other term).  Needs a simple multiplier 1 and a complex pair on the unit circle.
    """
    return _xz(A, d2, d3, 1, index, tol, digits)


@dataclass(frozen=True)
class FlipNS:
    """Flip–Neimark–Sacker (PDNS), critical normal form [Kuznetsov & Meijer 2005]:

        xi -> -xi + f300 xi^3 + f111 xi |z|^2,
        z  -> lambda z + g210 xi^2 z + g021 z |z|^2   (+ O(4)),

    all four invariant (no quadratic resonances).  ``amplitude`` = (-f300, -f111,
    Re(conj(lambda) g210), Re(conj(lambda) g021)): |xi| -> |xi| (1 + amplitude[0] xi^2 +
    amplitude[1] |z|^2), |z| -> |z| (1 + amplitude[2] xi^2 + amplitude[3] |z|^2), as
    MatContM nf_PDNSm reports it.
    """

    lam: object
    f300: object
    f111: object
    g210: object
    g021: object
    amplitude: tuple
    q1: object
    p1: object
    q2: object
    p2: object
    residuals: dict = field(default_factory=dict)
    backend: str = "float64"
    digits: object = None
    normalisation: str = _NORM_XZ


def flip_ns(A, d2, d3, *, index=None, tol=None, digits=None):
    """Critical normal form of a flip–Neimark–Sacker point (see :class:`FlipNS`).

    h200 = (I - A)^{-1} B(q1,q1), h011 = (I - A)^{-1} B(q2,qb2), h020 = (lambda^2 I -
    A)^{-1} B(q2,q2), h110 = -(lambda I + A)^{-1} B(q1,q2); f300, f111, g210, g021 as for
    LPNS (MatContM's h111 has B(h110, q2) instead of B(h110, conj(q2)), and its h021
    the factor 2 on the other term).  g021 equals normal_form's Kuznetsov c1.
    """
    return _xz(A, d2, d3, -1, index, tol, digits)


def _xz(A, d2, d3, mu, index, tol, digits):
    """The common computation of LPNS (mu = 1) and PDNS (mu = -1)."""
    with _prepared(tol, digits, A, d2, d3) as (tol, bk, (A, d2, d3)):
        n = A.shape[0]
        if n < 3:
            raise ParameterError("A", A.shape, "n >= 3 (a real and a complex critical multiplier)")
        e, res = _complex_pair(bk, A, index, None, tol)
        R = _real_eig(bk, A, mu, tol, e.values, e.vectors, tag="1")
        res = {k.replace("q", "q2").replace("p", "p2").replace("lam", "lam"): v
               for k, v in res.items()}
        res.update(R.res)
        lam, q2, p2 = e.lam, e.q, e.p
        q1, p1 = R.q, R.p
        qb2 = np.conj(q2)
        I = bk.ceye(n)

        def B(u, v):
            return _B(d2, u, v)

        B11, B22b, B22, B12 = B(q1, q1), B(q2, qb2), B(q2, q2), B(q1, q2)
        h020 = _solve(bk, lam * lam * I - A, B22, "lambda^2 I - A")
        if mu == 1:
            f200 = _vdot(p1, B11) / 2
            f011 = _vdot(p1, B22b)
            g110 = _vdot(p2, B12)
            # (I - A) h200 = B(q1,q1) - 2 f200 q1, (I - A) h011 = B(q2,qb2) - f011 q1,
            # (lambda I - A) h110 = B(q1,q2) - g110 q2; all with <p, h> = 0
            h200 = _bordered(bk, A - I, q1, p1, 2 * f200 * q1 - B11, "A - I")
            h011 = _bordered(bk, A - I, q1, p1, f011 * q1 - B22b, "A - I")
            h110 = _bordered(bk, A - lam * I, q2, p2, g110 * q2 - B12, "A - lambda I")
        else:
            h200 = _solve(bk, I - A, B11, "I - A")
            h011 = _solve(bk, I - A, B22b, "I - A")
            h110 = _solve(bk, -lam * I - A, B12, "-lambda I - A")
        h300 = _C(d3, q1, q1, q1) + 3 * B(q1, h200)
        Bh = B(h110, qb2)
        h111 = _C(d3, q1, q2, qb2) + B(q1, h011) + Bh + np.conj(Bh)
        h210 = _C(d3, q1, q1, q2) + 2 * B(q1, h110) + B(q2, h200)
        h021 = _C(d3, q2, q2, qb2) + 2 * B(q2, h011) + B(qb2, h020)
        f300 = _real(bk, _vdot(p1, h300) / 6)
        f111 = _real(bk, _vdot(p1, h111))
        g210 = _num(bk, _vdot(p2, h210) / 2)
        g021 = _num(bk, _vdot(p2, h021) / 2)
        lb = np.conj(lam)
        common = dict(lam=_num(bk, lam), f300=f300, f111=f111, g210=g210, g021=g021, q1=q1,
                      p1=p1, q2=q2, p2=p2, residuals=res, backend=bk.name, digits=bk.digits)
        if mu == -1:
            amp = (-f300, -f111, _real(bk, (lb * g210).real), _real(bk, (lb * g021).real))
            return FlipNS(amplitude=amp, **common)
        f200, f011, g110 = _real(bk, f200), _real(bk, f011), _num(bk, g110)
        prod = f200 * f011
        s = 0 if prod == 0 else (1 if prod > 0 else -1)
        a = g110 / f200
        b = (f011 * g210 + g110 * (f111 / 2 + (lb * g021).real) - f200 * g021) / (f011 * f200 ** 2)
        c = f300 / f200 ** 2
        return FoldNS(f200=f200, f011=f011, g110=g110, s=s, a=_num(bk, a), b=_num(bk, b),
                      c=_num(bk, c), **common)


# --------------------------------------------------------------------------- fold-flip, cusp, GPD
_NORM_REAL = ("A q = mu q, q real, ||q||_2 = 1 (largest component > 0); A^T p = mu p, "
              "<p,q> = 1 (normal_form.real_critical's convention); x = xi q + O(xi^2)")


@dataclass(frozen=True)
class FoldFlip:
    """Fold–flip (LPPD), critical normal form [Kuznetsov & Meijer 2005]:

        xi1 -> xi1 + a20 xi1^2 + a02 xi2^2 + a30 xi1^3 + a12 xi1 xi2^2,
        xi2 -> -xi2 + b11 xi1 xi2 + b21 xi1^2 xi2 + b03 xi2^3   (+ O(4)),

    q0, p0 belonging to 1 and q1, p1 to -1.  a20, a02, b11 are invariant (and change
    sign with q0); the cubic ones depend on the normalising transformation (here
    <p0, h20> = <p0, h02> = <p1, h11> = 0).  ``matcont`` = (a20/b11, a02 b11, CNS),
    MatContM nf_LPPDm's hypernormalised coefficients and its NS-of-the-double-period
    nondegeneracy CNS, *transcribed* (not independently derived), evaluated on our
    cubic coefficients.
    """

    a20: object
    a02: object
    b11: object
    a30: object
    a12: object
    b21: object
    b03: object
    matcont: tuple
    q0: object
    p0: object
    q1: object
    p1: object
    residuals: dict = field(default_factory=dict)
    backend: str = "float64"
    digits: object = None
    normalisation: str = _NORM_REAL + " (q0, p0 at +1; q1, p1 at -1)"


def fold_flip(A, d2, d3, *, tol=None, digits=None):
    """Critical normal form of a fold–flip point (see :class:`FoldFlip`).

    a20 = <p0,B(q0,q0)>/2, a02 = <p0,B(q1,q1)>/2, b11 = <p1,B(q0,q1)>;
    (I - A) h20 = B(q0,q0) - 2 a20 q0, (I - A) h02 = B(q1,q1) - 2 a02 q0,
    (-I - A) h11 = B(q0,q1) - b11 q1 (bordered);
    a30 = <p0, C(q0,q0,q0) + 3B(q0,h20)>/6, a12 = <p0, C(q0,q1,q1) + B(q0,h02) +
    2B(q1,h11)>/2, b21 = <p1, C(q0,q0,q1) + B(q1,h20) + 2B(q0,h11)>/2,
    b03 = <p1, C(q1,q1,q1) + 3B(q1,h02)>/6.
    """
    with _prepared(tol, digits, A, d2, d3) as (tol, bk, (A, d2, d3)):
        vals, V = bk.ceig(A)
        F = _real_eig(bk, A, 1, tol, vals, V, tag="0")
        P = _real_eig(bk, A, -1, tol, vals, V, tag="1")
        q0, p0, q1, p1 = F.q, F.p, P.q, P.p
        I = bk.ceye(A.shape[0])

        def B(u, v):
            return _B(d2, u, v)

        B00, B01, B11 = B(q0, q0), B(q0, q1), B(q1, q1)
        a20, a02, b11 = _vdot(p0, B00) / 2, _vdot(p0, B11) / 2, _vdot(p1, B01)
        # (A - I) h = 2 a q0 - B  <=>  (I - A) h = B - 2 a q0;  <p0, h> = 0
        h20 = _bordered(bk, A - I, q0, p0, 2 * a20 * q0 - B00, "A - I")
        h02 = _bordered(bk, A - I, q0, p0, 2 * a02 * q0 - B11, "A - I")
        h11 = _bordered(bk, A + I, q1, p1, b11 * q1 - B01, "A + I")
        a30 = _vdot(p0, _C(d3, q0, q0, q0) + 3 * B(q0, h20)) / 6
        a12 = _vdot(p0, _C(d3, q0, q1, q1) + B(q0, h02) + 2 * B(q1, h11)) / 2
        b21 = _vdot(p1, _C(d3, q0, q0, q1) + B(q1, h20) + 2 * B(q0, h11)) / 2
        b03 = _vdot(p1, _C(d3, q1, q1, q1) + 3 * B(q1, h02)) / 6
        a20, a02, b11, a30, a12, b21, b03 = (_real(bk, x) for x in
                                             (a20, a02, b11, a30, a12, b21, b03))
        if float(abs(b11)) > 0:
            # MatContM: a1 = 2 a20, b1 = 2 a02, e1 = b11, c1..c4 = 6 a30, 2 a12, 2 b21, 6 b03
            a1, b1, e1 = 2 * a20, 2 * a02, b11
            c = [a1 / e1 / 2, b1 * e1 / 2, 6 * a30 / e1 / e1 / 6,
                 a12 + (b1 * 2 * b21 - 6 * b03 * (a1 + e1) / 3) / e1]
            cns = c[1] * c[2] / 3 - c[0] * (c[0] * c[1] / 2 + 3 * c[1] + c[3])
            matcont = (c[0], c[1], cns)
        else:
            matcont = ()
        res = dict(F.res)
        res.update(P.res)
        return FoldFlip(a20=a20, a02=a02, b11=b11, a30=a30, a12=a12, b21=b21, b03=b03,
                        matcont=matcont, q0=q0, p0=p0, q1=q1, p1=p1, residuals=res,
                        backend=bk.name, digits=bk.digits)


@dataclass(frozen=True)
class Cusp:
    """Cusp of fixed points (CP): xi -> xi + a xi^2 + c xi^3 + O(xi^4), a = 0 at the cusp.

    a is normal_form.fold_coefficient's a (changes sign with q); c is invariant under
    every near-identity change (even for a != 0) and under q -> -q.
    """

    a: object
    c: object
    q: object
    p: object
    residuals: dict = field(default_factory=dict)
    backend: str = "float64"
    digits: object = None
    normalisation: str = _NORM_REAL


def cusp(A, d2, d3, *, tol=None, digits=None):
    """a and c of a cusp point [MatContM nf_CPm].

    a = <p, B(q,q)>/2; (I - A) h2 = B(q,q) - 2a q with <p, h2> = 0;
    c = <p, C(q,q,q) + 3B(q,h2)>/6.  Needs a simple multiplier 1.
    """
    with _prepared(tol, digits, A, d2, d3) as (tol, bk, (A, d2, d3)):
        R = _real_eig(bk, A, 1, tol)
        q, p = R.q, R.p
        Bqq = _B(d2, q, q)
        a = _vdot(p, Bqq) / 2
        h2 = _bordered(bk, A - bk.ceye(A.shape[0]), q, p, 2 * a * q - Bqq, "A - I")
        c = _vdot(p, _C(d3, q, q, q) + 3 * _B(d2, q, h2)) / 6
        return Cusp(a=_real(bk, a), c=_real(bk, c), q=q, p=p, residuals=R.res,
                    backend=bk.name, digits=bk.digits)


@dataclass(frozen=True)
class DegenerateFlip:
    """Generalised (degenerate) flip (GPD): xi -> -xi + c xi^3 + e xi^5 + O(xi^6), c = 0.

    c is normal_form.flip_coefficient's c; e is invariant under every near-identity
    change (even for c != 0) and under q -> -q.  The second iterate is
    xi -> xi - 2c xi^3 - 2e xi^5 + ...: at c = 0, e > 0 means the fixed point is weakly
    attracting and the period-2 branch of the nearby subcritical (c < 0) flips turns at a
    fold beyond which a *stable* period-2 orbit surrounds the unstable one; e < 0 is the
    mirror case.
    """

    c: object
    e: object
    q: object
    p: object
    residuals: dict = field(default_factory=dict)
    backend: str = "float64"
    digits: object = None
    normalisation: str = _NORM_REAL


def degenerate_flip(A, d2, d3, d4, d5, *, tol=None, digits=None):
    """c and e of a generalised flip point [MatContM nf_DPDm].

    h2 = (I - A)^{-1} B(q,q); r3 = C(q,q,q) + 3B(q,h2), c = <p, r3>/6;
    (-I - A) h3 = r3 - 6c q with <p, h3> = 0;
    (I - A) h4 = r4 + 24 c h2, r4 = D(q,q,q,q) + 6C(q,q,h2) + 4B(q,h3) + 3B(h2,h2)
    (the 24 c h2 from h2 G^2/2; MatContM omits it, right at c = 0);
    e = <p, E(q^5) + 10D(q,q,q,h2) + 15C(q,h2,h2) + 10C(q,q,h3) + 10B(h2,h3) + 5B(q,h4)>/120.
    """
    with _prepared(tol, digits, A, d2, d3, d4, d5) as (tol, bk, (A, d2, d3, d4, d5)):
        R = _real_eig(bk, A, -1, tol)
        q, p = R.q, R.p
        I = bk.ceye(A.shape[0])

        def B(u, v):
            return _B(d2, u, v)

        h2 = _solve(bk, I - A, B(q, q), "I - A")
        r3 = _C(d3, q, q, q) + 3 * B(q, h2)
        c = _vdot(p, r3) / 6
        h3 = _bordered(bk, A + I, q, p, 6 * c * q - r3, "A + I")
        r4 = (_D(d4, q, q, q, q) + 6 * _C(d3, q, q, h2) + 4 * B(q, h3) + 3 * B(h2, h2))
        h4 = _solve(bk, I - A, r4 + 24 * c * h2, "I - A")
        r5 = (_E(d5, q, q, q, q, q) + 10 * _D(d4, q, q, q, h2) + 15 * _C(d3, q, h2, h2)
              + 10 * _C(d3, q, q, h3) + 10 * B(h2, h3) + 5 * B(q, h4))
        e = _vdot(p, r5) / 120
        return DegenerateFlip(c=_real(bk, c), e=_real(bk, e), q=q, p=p, residuals=R.res,
                              backend=bk.name, digits=bk.digits)
