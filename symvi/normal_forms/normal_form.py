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

The cubic coefficient is Kuznetsov's n-dimensional formula (``c1``, ``l1``), which needs
no eigenbasis and no centre-manifold coordinates.  The paper's own reduction (eqs. 39–55,
A4–A17, its f1 of eq. (60) and the errata found in it) is the paper's:
:mod:`symvi.paper.reduction`.

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
* The paper's normalisation (||r1|| = 1, z_paper = 2 z_Kuznetsov, f1 = -l1/4 > 0
  attracting) is stated in :mod:`symvi.paper.reduction`.

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
Eq. (60), (A10) and (46)'s W_30 as printed, with the corrected forms and the tests that
show the difference: :mod:`symvi.paper.reduction`.  **Eq. (A3)** writes
``Re(\\tilde\\lambda_1 e^{-i\\omega_0})``; omega_0 must be the argument theta_0 of
lambda_0 (d|lambda|/dv = Re(conj(lambda) dlambda/dv) on |lambda| = 1), not
omega = Im lambda_1 of eq. (41).  We implement the argument reading;
``test_planar.py::test_dmod_A3`` checks it against a family with known d|lambda|/dv.

References
----------
[Kuznetsov, Elements of Applied Bifurcation Theory] Yu. A. Kuznetsov, Elements
of Applied Bifurcation Theory, 3rd ed., Springer 2004, Sec. 5.4 (Neimark–Sacker
bifurcation in n-dimensional maps; c1 formula) and Sec. 4.7 (planar normal form).
"""
import math
import warnings
from dataclasses import dataclass

import mpmath
import numpy as np

from .._deprecated import moved_call, moved_names
from ..errors import NearSingularWarning, ParameterError, SingularCaseError
from ..numerics.backend import backend
from ..numerics.tolerances import EPS64
# |lambda^m - 1| (m = 1..5) below which the reduction is refused / warned about: the strong
# resonances of the multiplier, not the forcing resonance of symvi.flow.linear's names
from ..numerics.tolerances import STRONG_RESONANCE_REFUSE as RESONANCE_REFUSE
from ..numerics.tolerances import STRONG_RESONANCE_WARN as RESONANCE_WARN
#: |Im lambda1| / ||A|| below which the complex pair is said to collide
COLLISION_WARN = 1e-6


def _backend(digits=None, *like):
    """The backend (:func:`symvi.numerics.backend.backend`) for a caller's ``digits``, checked:
    None (float64, or mpmath at the current precision when ``like`` holds mpmath numbers) or
    an integer from 16 to 10000."""
    if digits is not None and (not isinstance(digits, int) or isinstance(digits, bool)
                               or not 16 <= digits <= 10000):
        raise ParameterError("digits", digits, "an integer from 16 to 10000")
    return backend(digits, *like)


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
    bk = _backend(digits, A)
    with bk.context():
        return _eigen(bk, bk.carr(A), index)


def _eigen(bk, A, index):
    n = A.shape[0]
    vals, V = bk.ceig(A)
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
    u = bk.cinv(V)[k, :]
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
# --------------------------------------------------------------------------- Kuznetsov
def _kuznetsov(bk, A, d2, d3, e):
    """Kuznetsov's c1 = 1/2 <p, C(q,q,qb) + 2 B(q, h11) + B(qb, h20)> and l1.

    h11 = (|lambda|^2 I - A)^{-1} B(q, qb), h20 = (lambda^2 I - A)^{-1} B(q, q)
    (|lambda| = 1 at the Neimark–Sacker point).
    """
    n = A.shape[0]
    q, p, lam = e.q, e.p, e.lam
    qb = np.conj(q)
    I = bk.ceye(n)
    # (I - A) h11 = B(q, qb);  (e^{2 i theta} I - A) h20 = B(q, q)   [Kuznetsov, NS normal form]
    h11 = bk.csolve(lam * lam.conjugate() * I - A, _B(d2, q, qb))
    h20 = bk.csolve(lam * lam * I - A, _B(d2, q, q))
    c1 = _vdot(p, _C(d3, q, q, qb) + 2 * _B(d2, q, h11) + _B(d2, qb, h20)) / 2
    l1 = (lam.conjugate() / abs(lam) * c1).real
    return c1, l1, h11, h20


def kuznetsov(A, d2, d3, *, index=None, digits=None):
    """(c1, l1) by Kuznetsov's n-dimensional formula; ||q||_2 = 1, <p, q> = 1.

    l1 = Re(exp(-i theta) c1); the circle is stable (supercritical) when l1 < 0.
    """
    bk = _backend(digits, A, d2, d3)
    with bk.context():
        A, d2, d3 = bk.carr(A), _symmetrise(bk.carr(d2)), _symmetrise(bk.carr(d3))
        e = _eigen(bk, A, index)
        c1, l1, _, _ = _kuznetsov(bk, A, d2, d3, e)
        return c1, l1


def kuznetsov_resolved(A, d2, d3):
    """(c1, l1, noise, lambda1), float64: ``noise`` bounds the rounding error of l1 (forward error
    of the sums of products in c1, with the absolute tensors |d2|, |d3|, times the
    condition numbers of the two solves).  Near grazing the jets of an impact map
    grow like powers of 1/v and l1 drowns in rounding: |l1| < noise decides nothing."""
    bk = _backend(None, A, d2, d3)
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
    return c1, float(l1), float(16 * EPS64 * n * size), complex(e.lam)


# --------------------------------------------------------------------------- transversality
def dmod_A3(A, dA, *, index=None, digits=None):
    """d|lambda1|/dv by eqs. (A1)–(A3): Re(exp(-i theta0) (F11 zeta0, zeta0^*)) / ... .

    (zeta0, zeta0^*) = conj(zeta0^*)^T zeta0 = 1, so dlambda/dv = <p, dA q> and
    d|lambda|/dv = Re(conj(lambda) dlambda/dv) / |lambda| (= the printed (A3) on |lambda| = 1).
    Returns (dlambda_dv, dmod_dv).
    """
    bk = _backend(digits, A, dA)
    with bk.context():
        A, dA = bk.carr(A), bk.carr(dA)
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
    names: tuple = ()          # of the state variables; x1 ... xn when the caller gives none
    normalisation: str = "rho: ||q||_2 = 1, <p,q> = 1; paper radius = 2 rho"

    def __post_init__(self):
        if not self.names:
            object.__setattr__(self, "names", tuple(f"x{k + 1}" for k in range(len(self.q_abs))))

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
    resonance: tuple          # (m, |lambda^m - 1|), m in 1..5
    dlam_dv: object = None
    dmod_dv: object = None
    h11: object = None
    h20: object = None
    backend: str = "float64"
    digits: object = None
    normalisation: str = ("q = r1: A q = lambda1 q, Im lambda1 > 0, ||q||_2 = 1, largest |q_k| "
                          "real > 0; <p,q> = conj(p)^T q = 1; l1 = Re(e^{-i theta} c1) "
                          "(l1 < 0: stable circle)")
    circle: Circle = None     # the predicted invariant circle (needs dA), or None

    @property
    def kind(self):
        """'supercritical' (stable circle, l1 < 0) or 'subcritical' (l1 > 0)."""
        return "supercritical" if self.l1 < 0 else "subcritical"

    @property
    def theta_over_2pi(self):
        return self.theta / (2 * math.pi) if self.digits is None else self.theta / (2 * mpmath.pi)


def normal_form(A, d2, d3, dA=None, *, index=None, digits=None, names=None, paper=None):
    """Neimark–Sacker normal form of a map with jet (A, d2, d3) and F11 = dA, eqs. (39)–(60).

    Computes Kuznetsov's c1, l1; (A1)–(A3) when ``dA`` is given, and then the predicted
    circle.  ``digits`` (or mpmath inputs) selects the mpmath backend.  Raises
    SingularCaseError near lambda^m = 1 (m = 1..3, where the formulas divide by zero) and
    warns for m = 4, 5.  The paper's own reduction and its f1 of eq. (60):
    :func:`symvi.paper.reduction.normal_form` (``paper=True`` still returns it, with a
    DeprecationWarning, for one release; ``paper=False`` is the default and a no-op).
    """
    if paper:
        red = moved_call("normal_form(paper=True)", "symvi.paper.reduction", "normal_form")
        return red(A, d2, d3, dA, index=index, digits=digits, names=names)
    bk = _backend(digits, A, d2, d3, dA)
    with bk.context():
        A = bk.carr(A)
        if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] < 2:
            raise ParameterError("A", A.shape, "a square n x n matrix with n >= 2")
        n = A.shape[0]
        d2, d3 = bk.carr(d2), bk.carr(d3)
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
        dlam = dmod = circle = None
        if dA is not None:
            dlam, dmod = _dmod(e, bk.carr(dA))
            if float(l1) != 0 and float(dmod) != 0:
                circle = Circle(float(l1), float(dmod), tuple(float(abs(x)) for x in e.q),
                                **({"names": tuple(names)} if names else {}))
        return NormalForm(lam=lam, theta=bk.arg(lam), multipliers=e.values, q=e.q, p=e.p,
                          c1=c1, l1=l1, resonance=(m, dist), dlam_dv=dlam,
                          dmod_dv=dmod, h11=h11, h20=h20, backend=bk.name,
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


#: the paper's reduction moved to symvi.paper.reduction (issue 24): the old names warn
__getattr__ = moved_names(__name__, "symvi.paper.reduction", (
    "PaperReduction", "eigenmatrix", "appendix_printed", "f1_eq60_printed", "wan_a", "f1_eq60"))
