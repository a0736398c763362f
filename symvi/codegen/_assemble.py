"""Compiled float64 helpers of the jet at a point, where numpy's per-call overhead
dominates a jet of a few masses in Python:

* :func:`assemble64`, twin of :func:`symvi.codegen.layout.assemble` without a parameter
  tangent (its zero slots): the same inputs in the same order, in one numba call;
* :func:`fixed_solve64`, the solve of :func:`symvi.codegen.jets.fixed_point_motion`
  with its conditioning measure, in one call (numpy's det, norm and solve cost ~15 us).
"""
import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from ..flow._steady import _lu_factor, _lu_solve


@nb.njit(cache=True)
def assemble64(lam, W, Winv, A, U, V, dU, dV, w, con, y, te, order, params):
    """E_k = Phi(te) A^k (k = 0..order, row-major), U, V, [dU, dV, 0 (pE_0, pE_1, pU, pV)],
    omega, g0, level, R[:, 0], [0, 0 (plevel, pR_i0)], y, te: the layout of
    :mod:`symvi.codegen.layout`; ``con`` is the flow's ``constraint64`` (b, level, guard g,
    R row-major), whose guard is g0 e_0 and R the identity but for column 0
    (:func:`symvi.codegen.layout.jet_constraint` checks it)."""
    d = lam.shape[0]
    n = U.shape[0]
    size = (order + 1) * d * d + 2 * n + 3 + n + d + 1
    if params:
        size += 2 * n + 2 * d * d + 2 * n + 1 + n
    out = np.zeros(size)
    e = np.empty(d, np.complex128)
    for k in range(d):
        e[k] = np.exp(lam[k] * te)
    pos = 0
    for q in range(order + 1):              # Phi A^q = Re(W e^{lambda t} lambda^q W^-1)
        for a in range(d):
            for c in range(d):
                s = 0j
                for k in range(d):
                    s += (W[a, k] * e[k]) * Winv[k, c]
                out[pos] = s.real
                pos += 1
        for k in range(d):
            e[k] = e[k] * lam[k]
    pos = _put(out, pos, U)
    pos = _put(out, pos, V)
    if params:
        pos = _put(out, pos, dU)
        pos = _put(out, pos, dV)
        pos += 2 * d * d + 2 * n            # pE_0, pE_1, pU, pV: zero
    out[pos] = w
    out[pos + 1] = con[2]                   # g0
    out[pos + 2] = con[1]                   # level
    pos += 3
    for i in range(n):                      # R[i, 0]
        out[pos + i] = con[2 + n + i * n]
    pos += n
    if params:
        pos += 1 + n                        # plevel, pR_i0: zero
    pos = _put(out, pos, y)
    out[pos] = te
    return out


@nb.njit(cache=True)
def _put(out, pos, x):
    """out[pos:pos + len(x)] = x, returning the next position; a loop, since a slice
    assignment compiles numba's shape-mismatch message (~1.8 s of first-run compiling)."""
    for k in range(x.shape[0]):
        out[pos + k] = x[k]
    return pos + x.shape[0]


@nb.njit(cache=True)
def fixed_solve64(J, dP):
    """(x, h): x = (I - J)^{-1} dP and h = |det(I - J)| / prod of its row norms (the
    Hadamard ratio, 1 for orthogonal rows, 0 when singular; x is zero then)."""
    n = J.shape[0]
    M = np.empty((n, n))
    h = 1.0
    # loops, not array expressions (each costs a compiled kernel); the same sums in the
    # same order as np.sum's
    for i in range(n):
        for j in range(n):
            M[i, j] = -J[i, j]
        M[i, i] += 1.0
        s = 0.0
        for j in range(n):
            s += M[i, j] * M[i, j]
        h /= max(np.sqrt(s), 1e-300)
    perm = np.arange(n)
    x = np.zeros(n)
    if not _lu_factor(M, perm):
        return x, 0.0
    for i in range(n):
        h *= abs(M[i, i])
        x[i] = dP[perm[i]]
    _lu_solve(M, x)
    return x, h
