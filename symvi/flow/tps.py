"""Truncated power series (jets) in d variables to total order K, in numba (issue 28).

A series a(delta) = sum_m a_m delta^m over the monomials of total degree <= K is stored as
its coefficient vector (graded order: degree 0, then the d of degree 1, ...).  The
arithmetic is the algebra R[delta_1..delta_d] / (degree > K): a product keeps the pairs
of monomials whose degrees add to at most K (:func:`mul`, one table of index pairs grouped
by the monomial they make),
and a smooth function of a series is its Taylor polynomial in the nilpotent part,
f(a_0 + u) = sum_k f^(k)(a_0) u^k / k! (:func:`apply`; the coefficients f^(k)(a_0) / k!
from the function's own recurrence, :func:`_coefficients`).  Evaluating a vector field on
series so gives its jet, and integrating a flight on series gives the flow's jet in its
initial values and parameters to order K exactly as the variational equations of order
K would [Berz, Modern Map Methods in Particle Beam Physics, Academic Press 1999, ch. 2;
the "jet transport" of Alessi, Farres, Vieiro, Jorba & Simo, Celest. Mech. 104 (2009)].

The raw derivative tensors are read back by :func:`tensor`: d^k a / d delta_{j1}..d
delta_{jk} = a_m prod_i m_i! with m the multi-index of (j1..jk).
"""
import math
from functools import lru_cache

import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)


class Algebra:
    """The tables of the series in ``d`` variables to order ``K`` (built once per (d, K))."""

    def __init__(self, d, K):
        self.d, self.K = int(d), int(K)
        exps = []
        for deg in range(K + 1):
            exps.extend(_monomials(d, deg))
        self.exps = np.array(exps, dtype=np.int64).reshape(-1, d)
        self.L = len(exps)
        self.index = {e: i for i, e in enumerate(exps)}
        self.deg = self.exps.sum(axis=1)
        # the product's pairs grouped by the monomial they make: out[m] sums a[MI[t]] b[MJ[t]]
        # over t in OFF[m]..OFF[m + 1] (a gather: no scattered stores)
        pairs = [[] for _ in range(self.L)]
        for i, a in enumerate(exps):
            for j, b in enumerate(exps):
                if self.deg[i] + self.deg[j] <= K:
                    pairs[self.index[tuple(x + y for x, y in zip(a, b))]].append((i, j))
        self.mul = (np.array([i for p in pairs for i, _ in p], dtype=np.int64),
                    np.array([j for p in pairs for _, j in p], dtype=np.int64),
                    np.cumsum([0] + [len(p) for p in pairs]).astype(np.int64))
        #: factor prod m_i! of each monomial (coefficient -> raw derivative)
        self.fact = np.array([math.prod(math.factorial(x) for x in e) for e in exps], float)

    def var(self, j, value=0.0):
        """The series value + delta_j."""
        a = np.zeros(self.L)
        a[0] = value
        a[1 + j] = 1.0
        return a

    def tensor(self, a, k, axes=None):
        """The raw derivative tensor of order k of series ``a`` (shape (..., L)) over the
        variables ``axes`` (default all): shape (..., len(axes) x k)."""
        axes = tuple(range(self.d)) if axes is None else tuple(axes)
        idx, fac = _tensor_index(self, k, axes)
        return a[..., idx] * fac


def _monomials(d, deg):
    """Exponent tuples of total degree deg in d variables, in lexicographic descending
    order (delta_1^deg first)."""
    if d == 1:
        return [(deg,)]
    out = []
    for first in range(deg, -1, -1):
        out.extend((first,) + rest for rest in _monomials(d - 1, deg - first))
    return out


@lru_cache(maxsize=64)
def algebra(d, K):
    return Algebra(d, K)


_TENSOR = {}


def _tensor_index(alg, k, axes):
    key = (alg.d, alg.K, k, axes)
    hit = _TENSOR.get(key)
    if hit is None:
        m = len(axes)
        shape = (m,) * k
        idx = np.empty(shape, dtype=np.int64)
        fac = np.empty(shape)
        for multi in np.ndindex(*shape):
            e = [0] * alg.d
            for a in multi:
                e[axes[a]] += 1
            i = alg.index[tuple(e)]
            idx[multi] = i
            fac[multi] = alg.fact[i]
        hit = _TENSOR[key] = (idx, fac)
    return hit


# --------------------------------------------------------------------------- arithmetic
@nb.njit(cache=True, error_model="numpy")
def mul(a, b, out, MI, MJ, OFF):
    """out = a b (out distinct from a and b)."""
    for m in range(out.shape[0]):
        acc = 0.0
        for t in range(OFF[m], OFF[m + 1]):
            acc += a[MI[t]] * b[MJ[t]]
        out[m] = acc


@nb.njit(cache=True, error_model="numpy")
def mul_add(a, b, out, MI, MJ, OFF):
    """out += a b (out distinct from a and b)."""
    for m in range(out.shape[0]):
        acc = 0.0
        for t in range(OFF[m], OFF[m + 1]):
            acc += a[MI[t]] * b[MJ[t]]
        out[m] += acc


#: the functions of :data:`symvi.flow.nonlinear.FUNCS`, by index
SIN, COS, TAN, EXP, LOG, SQRT, SINH, COSH, TANH, ATAN = range(10)
#: the reciprocal (a tape's inverse rows; a division by a series' first coefficient)
RECIP = 10


@nb.njit(cache=True, error_model="numpy")
def _coefficients(k, a0, K, c):
    """c[j] = f^(j)(a0) / j!, j = 0..K, of function k; NaN outside its domain."""
    if k == SIN or k == COS:
        s, co = math.sin(a0), math.cos(a0)
        f = 1.0
        for j in range(K + 1):
            if j > 0:
                f /= j
            r = (j + (1 if k == COS else 0)) % 4   # d^j sin = sin, cos, -sin, -cos
            c[j] = f * (s if r == 0 else co if r == 1 else -s if r == 2 else -co)
    elif k == EXP or k == SINH or k == COSH:
        e, em = math.exp(a0), math.exp(-a0)
        f = 1.0
        for j in range(K + 1):
            if j > 0:
                f /= j
            if k == EXP:
                c[j] = e * f
            else:
                odd = (j % 2 == 1) != (k == COSH)      # sinh: even j sinh, odd j cosh
                c[j] = f * 0.5 * (e + em if odd else e - em)
    elif k == LOG:
        if not a0 > 0.0:
            for j in range(K + 1):
                c[j] = math.nan
            return
        c[0] = math.log(a0)
        p = 1.0
        for j in range(1, K + 1):
            p *= a0
            c[j] = (1.0 if j % 2 == 1 else -1.0) / (j * p)
    elif k == SQRT:
        if not a0 > 0.0:
            for j in range(K + 1):
                c[j] = math.nan
            return
        b = 1.0                                  # binom(1/2, j)
        for j in range(K + 1):
            if j > 0:
                b *= (0.5 - (j - 1)) / j
            c[j] = b * a0 ** (0.5 - j)
    elif k == RECIP:
        if a0 == 0.0:
            for j in range(K + 1):
                c[j] = math.nan
            return
        p = 1.0 / a0
        for j in range(K + 1):
            c[j] = p if j % 2 == 0 else -p
            p /= a0
    elif k == TAN or k == TANH:
        # T' = 1 + T^2 (tan), 1 - T^2 (tanh): T_{j+1} = (delta_j0 +- sum T_i T_{j-i}) / (j+1)
        sg = 1.0 if k == TAN else -1.0
        c[0] = math.tan(a0) if k == TAN else math.tanh(a0)
        for j in range(K):
            acc = 0.0
            for i in range(j + 1):
                acc += c[i] * c[j - i]
            c[j + 1] = ((1.0 if j == 0 else 0.0) + sg * acc) / (j + 1)
    else:                                        # atan: A' = 1 / q, q = 1 + (a0 + t)^2
        q0, q1 = 1.0 + a0 * a0, 2.0 * a0
        r = np.empty(K + 1)
        for j in range(K + 1):
            acc = (1.0 if j == 0 else 0.0)
            if j >= 1:
                acc -= q1 * r[j - 1]
            if j >= 2:
                acc -= r[j - 2]
            r[j] = acc / q0
        c[0] = math.atan(a0)
        for j in range(K):
            c[j + 1] = r[j] / (j + 1)


@nb.njit(cache=True, error_model="numpy")
def apply(k, a, out, u, tmp, c, K, MI, MJ, OFF):
    """out = f_k(a) (see :func:`_coefficients`): Horner in u = a - a_0."""
    _coefficients(k, a[0], K, c)
    L = a.shape[0]
    for i in range(L):
        u[i] = a[i]
        out[i] = 0.0
    u[0] = 0.0
    out[0] = c[K]
    for j in range(K - 1, -1, -1):
        mul(out, u, tmp, MI, MJ, OFF)
        for i in range(L):
            out[i] = tmp[i]
        out[0] += c[j]
