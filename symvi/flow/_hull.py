"""The Bernstein hull of a polynomial over one step: where a guard may reach 0.

A polynomial p(theta) = sum_i p_i theta^i of degree d on [0, 1] has Bernstein coefficients
b_k = sum_{i <= k} C(k, i) / C(d, i) p_i; p lies in their convex hull (so max b < 0 means
no root), and p has at most as many roots in (0, 1) as b has sign changes, with the same
parity (variation diminishing) [Farouki & Rajan, CAGD 5 (1988) 1-26].  Halving by de
Casteljau's algorithm narrows both.  The flows' events (:mod:`symvi.flow.nonlinear`,
:mod:`symvi.flow.taylor`) read the guard's polynomial over each step with these two
searches, so no contact of the polynomial is stepped over, however short the excursion.
"""
import math

import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)

#: the width in theta down to which the searches halve
ROOT_THETA = 1e-13
#: the highest degree a polynomial may have
MAX_DEGREE = 40


def _binom():
    B = np.zeros((MAX_DEGREE + 1, MAX_DEGREE + 1))
    for k in range(MAX_DEGREE + 1):
        for i in range(k + 1):
            B[k, i] = math.comb(k, i)
    return B


_BINOM = _binom()


@nb.njit(cache=True)
def _bernstein(p, b):
    """Bernstein coefficients b (degree d = len(p) - 1, on [0, 1]) of the monomial
    coefficients p."""
    d = p.shape[0] - 1
    for i in range(d + 1):                  # p_i / C(d, i) once (b as scratch)
        b[i] = p[i] / _BINOM[d, i]
    for k in range(d, -1, -1):              # b_k reads b_i, i <= k, not yet overwritten
        acc = 0.0
        for i in range(k + 1):
            acc += _BINOM[k, i] * b[i]
        b[k] = acc


@nb.njit(cache=True)
def _halve(stackb, lo_hi, top):
    """Split entry ``top`` of the stack at its middle by de Casteljau: the right half stays
    at ``top``, the left half goes to ``top + 1`` (examined first)."""
    d = stackb.shape[1] - 1
    w = stackb[top].copy()
    for i in range(d + 1):
        stackb[top + 1, i] = 0.0
    stackb[top + 1, 0] = w[0]
    stackb[top, d] = w[d]
    for r in range(1, d + 1):
        for i in range(d + 1 - r):
            w[i] = 0.5 * (w[i] + w[i + 1])
        stackb[top + 1, r] = w[0]
        stackb[top, d - r] = w[d - r]
    lo, hi = lo_hi[top, 0], lo_hi[top, 1]
    mid = 0.5 * (lo + hi)
    lo_hi[top, 0] = mid
    lo_hi[top + 1, 0] = lo
    lo_hi[top + 1, 1] = mid


@nb.njit(cache=True)
def _push(b0, stackb, lo_hi):
    for i in range(b0.shape[0]):
        stackb[0, i] = b0[i]
    lo_hi[0, 0] = 0.0
    lo_hi[0, 1] = 1.0


@nb.njit(cache=True)
def _first_root(b0, stackb, lo_hi):
    """The leftmost theta in [0, 1] where the polynomial with Bernstein coefficients b0 may
    reach 0 (its hull does, down to ROOT_THETA), or -1.0 when its hull stays below 0."""
    out = np.empty(2)
    st = _first_bracket(b0, stackb, lo_hi, out, False)
    if st == 0:
        return -1.0
    return out[0] if st == 1 else 0.5 * (out[0] + out[1])


@nb.njit(cache=True)
def _first_bracket(b0, stackb, lo_hi, out, one_root=True):
    """The first place in [0, 1] where the polynomial with Bernstein coefficients b0 may
    reach 0: 0 when it stays below 0; else out = (lo, hi) and 1 when p(lo) >= 0 (a contact
    at lo), 2 (with ``one_root``) when exactly one root lies in (lo, hi] and none before
    (p(lo) < 0 <= p(hi) and one sign change of the hull), 3 when the hull reaches 0 on
    [lo, hi] of width ROOT_THETA without deciding (a touch, taken as a contact)."""
    d = b0.shape[0] - 1
    _push(b0, stackb, lo_hi)
    top = 1
    while top > 0:
        top -= 1
        lo = lo_hi[top, 0]
        hi = lo_hi[top, 1]
        out[0] = lo
        out[1] = hi
        mx = -math.inf
        changes = 0
        for i in range(d + 1):
            mx = max(mx, stackb[top, i])
            if i and (stackb[top, i] >= 0.0) != (stackb[top, i - 1] >= 0.0):
                changes += 1
        if mx < 0.0:
            continue
        if stackb[top, 0] >= 0.0:
            return 1
        if one_root and changes == 1:       # b0 < 0 <= bd: one root, the hull says so
            return 2
        if hi - lo <= ROOT_THETA or top + 2 >= stackb.shape[0]:
            return 3
        _halve(stackb, lo_hi, top)
        top += 2
    return 0
