"""Compiled float64 twin of :func:`symvi.codegen.layout.assemble` without a parameter
tangent (its zero slots): the same inputs in the same order, in one numba call, since
the exponential Phi(t_e) and the copies dominate a low-order jet in Python."""
import numba as nb
import numpy as np


@nb.njit(cache=True)
def assemble64(lam, W, Winv, A, U, V, dU, dV, w, r, b, y, te, order, params):
    """E_k = Phi(te) A^k (k = 0..order, row-major), U, V, [dU, dV, 0 (pE_0, pE_1, pU, pV)],
    omega, r, b, [0, 0 (pr, pb)], y, te: the layout of :mod:`symvi.codegen.layout`."""
    d = lam.shape[0]
    n = U.shape[0]
    size = (order + 1) * d * d + 2 * n + 3 + d + 1
    if params:
        size += 2 * n + 2 * d * d + 2 * n + 2
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
    out[pos:pos + n] = U
    pos += n
    out[pos:pos + n] = V
    pos += n
    if params:
        out[pos:pos + n] = dU
        pos += n
        out[pos:pos + n] = dV
        pos += n
        pos += 2 * d * d + 2 * n            # pE_0, pE_1, pU, pV: zero
    out[pos] = w
    out[pos + 1] = r
    out[pos + 2] = b
    pos += 3
    if params:
        pos += 2                            # pr, pb: zero
    out[pos:pos + d] = y
    out[pos + d] = te
    return out
