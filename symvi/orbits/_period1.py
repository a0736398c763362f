"""Compiled float64 twin of the period-1 solver of :mod:`symvi.orbits.period1`.

One numba call (cached on disk) does, at one omega, what the numpy reference does
in ~60 small numpy calls: min_j |1 - e^{lambda_j T}| (the isolation test), the
solution line of the period-1 conditions (the equilibrated (2N + 1) x (2N + 2)
system, its SVD, the particular solution and the kernel), its orientation
(with the limit r -> 1- where b no longer moves the line), both branches' points
y and impact velocities, and for each branch the monodromy matrix of the
shooting problem with u = (y, T) (:func:`symvi.orbits._shooting.shoot` and
:func:`~symvi.orbits._shooting.monodromy`, eq. (30)), whose eigenvalues are the
multipliers.  The formulas and their order of operations are those of
:class:`symvi.orbits.period1._Line` (the reference, ``period1.COMPILED = False``),
so the two agree to rounding (tests/orbits/test_period1_compiled.py).
"""
import math

import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from ..numerics.tolerances import EPS64
from ._shooting import monodromy, shoot1

#: status codes of :func:`period1`
OK, NOT_ISOLATED, DEGENERATE, NO_PHASE, NO_ORBIT = range(5)

_TWO_PI = 2.0 * math.pi


@nb.njit(cache=True)
def _line(lam, W, Winv, U, V, w, g, level, R):
    # R: the reset, row-major (N x N); g: the signed guard (N)
    """(Phi(T), Pc, Ps, sigma, kernel vector, Xp, p1, phase share) of the period-1
    conditions with the reset R (v+ = R v-) and the guard g . x = level of the
    constraint (flow order; x_k = b, v_k+ = -r v_k- for the stop):
    :class:`symvi.orbits.period1._Line`."""
    n2 = lam.shape[0]
    n = n2 // 2
    T = _TWO_PI / w
    e = np.exp(lam * T)
    Phi = np.empty((n2, n2))
    for a in range(n2):                     # Re((W e) W^-1): LinearFlow.phis
        for c in range(n2):
            s = 0j
            for k in range(n2):
                s += (W[a, k] * e[k]) * Winv[k, c]
            Phi[a, c] = s.real
    Pc = np.empty(n2)
    Ps = np.empty(n2)
    for i in range(n):
        Pc[i], Pc[n + i] = V[i], w * U[i]
        Ps[i], Ps[n + i] = U[i], -w * V[i]
    G = np.zeros((n2 + 1, n2 + 2))
    for a in range(n2):                     # I - E Phi, (I - E) Pc, (I - E) Ps; E = diag(I, R)
        for c in range(n2):
            if a < n:
                s = 1.0 * Phi[a, c]
            else:
                s = 0.0
                for k in range(n):
                    s += R[(a - n) * n + k] * Phi[n + k, c]
            G[a, c] = (1.0 if a == c else 0.0) - s
        if a < n:
            G[a, n2] = 0.0 * Pc[a]
            G[a, n2 + 1] = 0.0 * Ps[a]
        else:
            sc = 0.0
            ss = 0.0
            for k in range(n):
                f = (1.0 if k == a - n else 0.0) - R[(a - n) * n + k]
                sc += f * Pc[n + k]
                ss += f * Ps[n + k]
            G[a, n2] = sc
            G[a, n2 + 1] = ss
    sc = 0.0
    ss = 0.0
    for k in range(n):                      # the impact condition g . x(0) = level
        G[n2, k] = g[k]
        sc += g[k] * Pc[k]
        ss += g[k] * Ps[k]
    G[n2, n2] = sc
    G[n2, n2 + 1] = ss
    D = np.empty(n2 + 2)                    # column equilibration
    for c in range(n2 + 2):
        s2 = 0.0
        for a in range(n2 + 1):
            s2 += G[a, c] * G[a, c]
        # a zero column (no steady forcing on the stop's mass) stays zero: NO_PHASE below
        D[c] = math.sqrt(s2) if s2 > 0.0 else 1.0
    for a in range(n2 + 1):
        for c in range(n2 + 2):
            G[a, c] /= D[c]
    Uq, sig, Vt = np.linalg.svd(G)
    null = np.empty(n2 + 2)
    for c in range(n2 + 2):                 # a loop: an array expression costs ~1 s to compile
        null[c] = Vt[n2 + 1, c] / D[c]
    share = Vt[n2 + 1, n2] ** 2 + Vt[n2 + 1, n2 + 1] ** 2
    # pseudo-inverse solutions of G x = e b and G x = e (e the last unit vector)
    q = np.empty(n2 + 1)
    for k in range(n2 + 1):                 # sig[k] = 0 only when DEGENERATE (rank gap 0)
        q[k] = Uq[n2, k] / sig[k] if sig[k] > 0.0 else 0.0
    p1 = np.empty(n2 + 2)
    Xp = np.empty(n2 + 2)
    for c in range(n2 + 2):
        s1 = 0.0
        sb = 0.0
        for k in range(n2 + 1):
            s1 += Vt[k, c] * q[k]
            if sig[k] > 0.0:
                sb += Vt[k, c] * ((Uq[n2, k] * level) / sig[k])
        p1[c] = s1 / D[c]
        Xp[c] = sb / D[c]
    return Phi, Pc, Ps, sig, null, Xp, p1, share


@nb.njit(cache=True)
def _normal(null, n2):
    """The unit normal of the line in (cos tau, sin tau), along the gradient of x_k(0)
    up to sign."""
    nc, ns = null[n2], null[n2 + 1]
    nrm = math.sqrt(nc * nc + ns * ns)
    if nrm == 0.0:                          # only on the reference line of a NO_PHASE case
        return 0.0, 0.0
    return ns / nrm, -nc / nrm


@nb.njit(cache=True)
def _oriented(n0, n1, side):
    """nu in the paper's orientation (module doc of :mod:`symvi.orbits.period1`)."""
    if side < 0:
        n0, n1 = -n0, -n1
    return -n0, -n1


@nb.njit(cache=True)
def period1(lam, W, Winv, A, U, V, w, con, R_ref, refuse, noise, want_mult):
    """Both period-1 orbits at omega = w; see the module docstring.

    The constraint as the flow holds it (``con`` = :attr:`LinearFlow.constraint64`): b the
    section's level, g . x = level the impact condition, R the reset; R_ref (row-major)
    the reset at restitution r - ORIENT_DR.

    Returns (status, d, j, rank gap, phase share, Y, vimp, M, ok): d, j the isolation
    measure and its mode; per branch ("+", "-") the section point Y[i] (tau in
    [0, 2 pi)), the impact velocity, the monodromy M[i] (if ``want_mult``) and whether
    it exists (the impact velocity not exactly 0).  ``status`` is :data:`OK` or the
    first refusal met (then the later outputs are not filled)."""
    n2 = lam.shape[0]
    n = n2 // 2
    b, level = con[0], con[1]
    g = con[2:2 + n]
    R = con[2 + n:2 + n + n * n]
    T = _TWO_PI / w
    Y = np.zeros((2, n2))
    vimp = np.zeros(2)
    M = np.zeros((2, n2, n2))
    ok = np.zeros(2, np.bool_)
    dmin, jmin = np.inf, 0
    for k in range(n2):                     # LinearFlow.one_minus_exp
        dk = abs(1.0 - np.exp(lam[k] * T))
        if dk < dmin:
            dmin, jmin = dk, k
    jmin = jmin % n
    if dmin < refuse:
        return NOT_ISOLATED, dmin, jmin, 0.0, 0.0, Y, vimp, M, ok
    Phi, Pc, Ps, sig, null, Xp, p1, share = _line(lam, W, Winv, U, V, w, g, level, R)
    gap = sig[n2] / sig[0]
    scale = 64 * EPS64
    if not gap > scale:
        return DEGENERATE, dmin, jmin, gap, share, Y, vimp, M, ok
    if not share > scale:
        return NO_PHASE, dmin, jmin, gap, share, Y, vimp, M, ok
    a = null[n2] * null[n2] + null[n2 + 1] * null[n2 + 1]
    n0, n1 = _normal(null, n2)
    side = n0 * p1[n2] + n1 * p1[n2 + 1]
    if not abs(side) > noise * (abs(p1[n2]) + abs(p1[n2 + 1])):
        # r = 1 with no damping: b no longer moves the line; orient as the limit r -> 1-
        ref = _line(lam, W, Winv, U, V, w, g, level, R_ref)
        rnull, rp1 = ref[4], ref[6]
        r0, r1 = _normal(rnull, n2)
        r0, r1 = _oriented(r0, r1, r0 * rp1[n2] + r1 * rp1[n2 + 1])
        side = -(n0 * r0 + n1 * r1)
    nu0, nu1 = _oriented(n0, n1, side)
    ratio = nu0 * Xp[n2] + nu1 * Xp[n2 + 1]
    if abs(ratio) > 1:
        return NO_ORBIT, dmin, jmin, gap, share, Y, vimp, M, ok
    phase = math.atan2(nu1, nu0)
    ac = math.acos(ratio)
    wv = np.empty(n2)
    z0 = np.empty(n2)
    u = np.empty(n2 + 1)
    # typed int64 and boolean, not literals: shoot and monodromy are then the ones the
    # Hopf scan calls (compiled once, not a second specialisation for Literal[int](1))
    one, yes, no = np.int64(1), np.bool_(True), np.bool_(False)
    for i in range(2):
        tau = (phase + ac if i == 0 else phase - ac) % _TWO_PI
        c, s = math.cos(tau), math.sin(tau)
        mu = ((c - Xp[n2]) * null[n2] + (s - Xp[n2 + 1]) * null[n2 + 1]) / a
        for k in range(n2):
            wv[k] = Xp[k] + mu * null[k]
        for k in range(n2):
            z0[k] = wv[k] + c * Pc[k] + s * Ps[k]
        z0[0] = b                           # exact by construction
        vi = 0.0                            # g . (Phi w + (z0 - w))[n:]: the impact velocity
        for q in range(n):
            zn = 0.0
            for k in range(n2):
                zn += Phi[n + q, k] * wv[k]
            vi += g[q] * (zn + (z0[n + q] - wv[n + q]))
        vimp[i] = vi
        Y[i, 0] = z0[n]                     # Section.point
        for q in range(1, n):
            Y[i, q] = z0[q]
            Y[i, n - 1 + q] = z0[n + q]
        Y[i, n2 - 1] = tau
        if want_mult:
            # element loops, not slice assignment: that compiles numba's shape-mismatch
            # message (string formatting, ~2.6 s) into the kernel
            for k in range(n2):
                u[k] = Y[i, k]
            u[n2] = T
            Gu = shoot1(lam, W, Winv, A, U, V, U, V, w, con, one, u, one, yes, no)[1]
            _, Mi, oki = monodromy(Gu, one, np.int64(n2))
            for ra in range(n2):
                for rc in range(n2):
                    M[i, ra, rc] = Mi[ra, rc]
            ok[i] = oki
    return OK, dmin, jmin, gap, share, Y, vimp, M, ok
