"""Compiled steady-state response of the float64 flow: U, V and their omega-derivatives.

The forcing of :meth:`symvi.flow.linear.LinearFlow.forcing` solves, at each omega,

    (K - omega^2 M + i omega C) X = P,         U + i V = X,
    (K - omega^2 M + i omega C) dX = (2 omega M - i C) X,    dU + i dV = dX

(the omega-derivative of the first).  A continuation in omega asks for a new
omega at every corrector iterate; two numpy solves of an N x N complex system
cost ~20 us of Python overhead each time.  Here one LU factorisation with
partial pivoting (LAPACK's zgetrf pivot rule, |Re| + |Im|) serves both right-hand
sides, compiled by numba (cached on disk).  Agrees with numpy's solve to
rounding (the test: tests/continuation/test_compiled_shooting.py).
"""
import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)

@nb.njit(cache=True)
def _steady(K, M, C, P, w):
    n = P.shape[0]
    D = np.empty((n, n), np.complex128)
    for i in range(n):
        for j in range(n):
            D[i, j] = complex(K[i, j] - w * w * M[i, j], w * C[i, j])
    perm = np.arange(n)
    if not _lu_factor(D, perm):
        return False, np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    X = np.empty(n, np.complex128)
    for i in range(n):
        X[i] = P[perm[i]]
    _lu_solve(D, X)
    R = np.empty(n, np.complex128)               # (2 omega M - i C) X
    for i in range(n):
        s = 0j
        for j in range(n):
            s += complex(2.0 * w * M[i, j], -C[i, j]) * X[j]
        R[i] = s
    dX = np.empty(n, np.complex128)
    for i in range(n):
        dX[i] = R[perm[i]]
    _lu_solve(D, dX)
    return True, X.real.copy(), X.imag.copy(), dX.real.copy(), dX.imag.copy()


@nb.njit(cache=True)
def _lu_factor(D, perm):
    """D <- L\\U in place by partial pivoting (LAPACK's getrf rule, |Re| + |Im|; real
    or complex D), the row swaps recorded in perm; False on an exactly zero pivot."""
    n = D.shape[0]
    for k in range(n):
        p, best = k, -1.0
        for i in range(k, n):
            a = abs(D[i, k].real) + abs(D[i, k].imag)
            if a > best:
                p, best = i, a
        if best == 0.0:
            return False
        if p != k:
            for j in range(n):
                D[k, j], D[p, j] = D[p, j], D[k, j]
            perm[k], perm[p] = perm[p], perm[k]
        inv = 1.0 / D[k, k]
        for i in range(k + 1, n):
            D[i, k] *= inv
            for j in range(k + 1, n):
                D[i, j] -= D[i, k] * D[k, j]
    return True


@nb.njit(cache=True)
def _lu_solve(LU, x):
    """x <- U^-1 L^-1 x in place (x already permuted)."""
    n = x.shape[0]
    for i in range(n):
        for j in range(i):
            x[i] -= LU[i, j] * x[j]
    for i in range(n - 1, -1, -1):
        for j in range(i + 1, n):
            x[i] -= LU[i, j] * x[j]
        x[i] = x[i] / LU[i, i]


def steady_state(K, M, C, P, omega):
    """(U, V, dU, dV) at omega for float64 K, M, C (N x N) and P (N); LinAlgError if the
    system is exactly singular (an undamped forcing resonance)."""
    ok, U, V, dU, dV = _steady(K, M, C, P, float(omega))
    if not ok:
        raise np.linalg.LinAlgError("Singular matrix")
    return U, V, dU, dV
