"""The one precision backend: float64 (``math`` / numpy) or mpmath at a number of digits.

The exact flow, the period-1 orbits, the paper's modal oracle and the normal forms are
written once against this interface; :data:`FLOAT64` and ``backend(digits)`` run them in
double precision or in mpmath.  ``backend(digits)`` (None: float64) is the one constructor
and :func:`is_mp` the one test for mpmath numbers.

Names say what they return (one name, one meaning):

* scalars, real: ``sin cos sqrt atan2 acos fabs`` (``math`` / mpmath), ``num(x)`` (x as
  the backend's real number), ``isfinite``, ``real(x)`` (the real part of a scalar, as a
  real number), ``pi``, ``eps`` (unit roundoff);
* scalars, complex (prefix ``c``): ``csqrt cexp`` (``cmath`` / mpmath), ``arg`` (phase);
* arrays: ``arr(x)`` real (float64, or mpf objects; an mpmath backend keeps complex
  entries as mpc), ``carr(x)``, ``ceye(n)``, ``czeros(shape)`` complex (complex128, or mpc
  objects; ``carr`` of a 0-d input is a scalar mpc in mpmath);
* elementwise on arrays (prefix ``v``): ``vexp vabs vreal``;
* linear algebra: ``eig`` (values, right eigenvectors as columns), ``eigh_pair(K, M)``
  (omega_j ascending and M-normalised modes of K psi = omega^2 M psi), ``solve``, ``inv``,
  ``svd`` (U, s, Vt; full matrices), ``cond`` (a float).  Their entries are what the
  library gives: numpy's dtype, mpmath's mpf or mpc (a real eigenvalue of a real matrix is
  an mpf).  ``ceig``, ``csolve``, ``cinv``: the same, complex (complex128, or mpc);
* ``context()``: the precision to compute in (``mp.workdps(digits)``; nothing for
  float64), ``digits`` (None for float64), ``name``.

An mpmath backend computes at the *current* ``mp.dps`` (``pi``, ``eps`` and every
operation read it): hold ``context()``, or a ``workdps`` of the same digits, around its
use.  mpmath arrays are numpy object arrays.
"""
import cmath
import contextlib
import functools
import math

import mpmath
import numpy as np

from .tolerances import EPS64

__all__ = ["FLOAT64", "backend", "is_mp"]


class _Float64:
    """float64 scalars (``math``, ``cmath``) and numpy arrays and linear algebra."""

    name = "float64"
    digits = None
    eps = EPS64
    pi = math.pi

    sin = staticmethod(math.sin)
    cos = staticmethod(math.cos)
    sqrt = staticmethod(math.sqrt)
    atan2 = staticmethod(math.atan2)
    acos = staticmethod(math.acos)
    fabs = staticmethod(math.fabs)
    isfinite = staticmethod(math.isfinite)
    csqrt = staticmethod(cmath.sqrt)
    cexp = staticmethod(cmath.exp)
    arg = staticmethod(cmath.phase)

    vexp = staticmethod(np.exp)
    vabs = staticmethod(np.abs)
    vreal = staticmethod(np.real)
    eig = staticmethod(np.linalg.eig)
    solve = staticmethod(np.linalg.solve)
    inv = staticmethod(np.linalg.inv)
    svd = staticmethod(np.linalg.svd)

    def __repr__(self):
        return "FLOAT64"

    @staticmethod
    def context():
        return contextlib.nullcontext()

    @staticmethod
    def num(x):
        return float(x)

    @staticmethod
    def real(x):
        return float(np.real(x))

    arr = staticmethod(functools.partial(np.array, dtype=float))
    carr = staticmethod(functools.partial(np.array, dtype=complex))
    ceye = staticmethod(functools.partial(np.eye, dtype=complex))
    czeros = staticmethod(functools.partial(np.zeros, dtype=complex))

    @staticmethod
    def eigh_pair(K, M):
        """omega_j ascending and M-normalised modes (columns) of K psi = omega^2 M psi."""
        L = np.linalg.cholesky(M)
        Li = np.linalg.inv(L)
        w2, Q = np.linalg.eigh(Li @ K @ Li.T)
        return np.sqrt(w2), Li.T @ Q

    @staticmethod
    def cond(M):
        return float(np.linalg.cond(M))

    @staticmethod
    def ceig(A):
        w, V = np.linalg.eig(A)
        return w.astype(complex, copy=False), V.astype(complex, copy=False)

    @staticmethod
    def csolve(A, b):
        return np.linalg.solve(A, b).astype(complex, copy=False)

    @staticmethod
    def cinv(A):
        return np.linalg.inv(A).astype(complex, copy=False)


FLOAT64 = _Float64()


def _mpf_or_mpc(v):
    if isinstance(v, (mpmath.mpf, mpmath.mpc)):
        return v
    return mpmath.mpc(v) if isinstance(v, complex) else mpmath.mpf(v)


def _matrix(A):
    return mpmath.matrix(A.tolist())


def _array(m, shape):
    """The entries of the mpmath matrix ``m`` as an object array of ``shape`` (1-D or 2-D)."""
    out = np.empty(shape, dtype=object)
    for i in range(shape[0]):
        if len(shape) == 1:
            out[i] = m[i]
        else:
            for j in range(shape[1]):
                out[i, j] = m[i, j]
    return out


class _Mp:
    """mpmath at ``digits`` significant digits (see the module docstring)."""

    name = "mpmath"

    def __init__(self, digits):
        self.digits = int(digits)

    def __repr__(self):
        return f"backend({self.digits})"

    def context(self):
        return mpmath.mp.workdps(self.digits)

    @property
    def eps(self):
        return mpmath.mp.eps

    @property
    def pi(self):
        return +mpmath.pi

    sin = staticmethod(mpmath.sin)
    cos = staticmethod(mpmath.cos)
    sqrt = staticmethod(mpmath.sqrt)
    atan2 = staticmethod(mpmath.atan2)
    acos = staticmethod(mpmath.acos)
    fabs = staticmethod(mpmath.fabs)
    isfinite = staticmethod(mpmath.isfinite)
    csqrt = staticmethod(mpmath.sqrt)
    cexp = staticmethod(mpmath.exp)
    arg = staticmethod(mpmath.arg)

    @staticmethod
    def num(x):
        return mpmath.mpf(x) if not isinstance(x, mpmath.mpf) else +x

    @staticmethod
    def real(x):
        return mpmath.mpf(mpmath.mpc(x).real)

    # ---- arrays: numpy object arrays of mpf / mpc
    _vnum = staticmethod(np.vectorize(_mpf_or_mpc, otypes=[object]))
    _to_mpc = staticmethod(np.frompyfunc(lambda e: mpmath.mpc(e), 1, 1))
    _vreal = staticmethod(np.vectorize(lambda v: mpmath.re(v), otypes=[object]))
    _vabs = staticmethod(np.vectorize(lambda v: abs(v), otypes=[object]))

    def arr(self, x):
        a = np.array(x, dtype=object)
        return self._vnum(a) if a.size else a

    def carr(self, x):
        if isinstance(x, mpmath.matrix):
            x = x.tolist()
        a = np.array(x, dtype=object)
        return self._to_mpc(a) if a.ndim else mpmath.mpc(a.item())

    def ceye(self, n):
        return self.carr(np.eye(n))

    def czeros(self, shape):
        return self.carr(np.zeros(shape))

    @staticmethod
    def vexp(v):
        return np.array([mpmath.exp(x) for x in v], dtype=object)

    def vabs(self, x):
        return self._vabs(x)

    def vreal(self, x):
        return self._vreal(x)

    # ---- linear algebra (mpmath.matrix inside, object arrays outside)
    @staticmethod
    def eig(A):
        E, ER = mpmath.eig(_matrix(A))
        n = A.shape[0]
        return np.array([E[i] for i in range(n)], dtype=object), _array(ER, (n, n))

    @staticmethod
    def eigh_pair(K, M):
        """omega_j ascending and M-normalised modes (columns) of K psi = omega^2 M psi."""
        L = mpmath.cholesky(_matrix(M))
        Li = mpmath.inverse(L)
        E, Q = mpmath.eigsy(Li * _matrix(K) * Li.T)
        n = K.shape[0]
        order = sorted(range(n), key=lambda i: E[i])
        psi = _array(Li.T * Q, (n, n))[:, order]
        return np.array([mpmath.sqrt(E[i]) for i in order], dtype=object), psi

    @staticmethod
    def solve(A, b):
        return _array(mpmath.lu_solve(_matrix(A), mpmath.matrix(list(b))), b.shape)

    @staticmethod
    def inv(A):
        return _array(mpmath.inverse(_matrix(A)), A.shape)

    @staticmethod
    def svd(G):
        """(U, s, Vt) of G, full matrices, s descending (as numpy's)."""
        U, s, V = mpmath.svd_r(_matrix(G), full_matrices=True)
        m, n = G.shape
        return _array(U, (m, m)), np.array([s[i] for i in range(len(s))], dtype=object), \
            _array(V, (n, n))

    @staticmethod
    def cond(A):
        m = _matrix(A)
        return float(mpmath.mnorm(m, 1) * mpmath.mnorm(mpmath.inverse(m), 1))

    def ceig(self, A):
        w, V = self.eig(A)
        return self.carr(w), self.carr(V)

    def csolve(self, A, b):
        return self.carr(self.solve(A, b))

    def cinv(self, A):
        return self.carr(self.inv(A))


@functools.lru_cache(maxsize=None)
def _mp(digits):
    return _Mp(digits)


def is_mp(x):
    """Whether ``x`` holds mpmath numbers: an mpf, mpc or mpmath matrix, or a numpy array,
    list or tuple whose first entry does."""
    if isinstance(x, (mpmath.mpf, mpmath.mpc, mpmath.matrix)):
        return True
    if isinstance(x, np.ndarray):
        return x.dtype == object and x.size > 0 and is_mp(x.flat[0])
    if isinstance(x, (list, tuple)):
        return len(x) > 0 and is_mp(x[0])
    return False


def backend(digits=None, *like):
    """The backend for ``digits``: :data:`FLOAT64` for None, unless one of ``like`` holds
    mpmath numbers (:func:`is_mp`), then mpmath at the current ``mp.dps``; else mpmath at
    ``digits`` (one object per number of digits).  Callers check a user's ``digits``."""
    if digits is None:
        if any(is_mp(e) for e in like):
            return _mp(mpmath.mp.dps)
        return FLOAT64
    return _mp(int(digits))
