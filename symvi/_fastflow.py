"""Compiled twin of :mod:`symvi.flow` and :mod:`symvi.poincare`: the exact flow
between impacts, the first-impact finder and the map P, eqs. (7)–(8), (19)–(31).

The finder is :func:`symvi.flow.first_impact` with a tighter, still provably
safe step.  Along h(t) = x1(t) - b < 0, for any horizon S > 0 and s in [0, S]

    h''(t + s) <= K(S) = h2 + max(h3 S, 0) + max(h4, 0) S^2/2 + M5 S^3/6,

(h_k the current k-th derivative, M5 >= |h'''''| from the known amplitudes),
so h(t + s) <= h + h1 s + K s^2/2 on [0, S]: no crossing occurs before
min(S, first positive root of that quadratic).  The global bound of
:mod:`symvi.flow` (K = M2 for every S) is also safe; the step taken is the
largest of these lower bounds, with S tuned by a few trig-free fixed-point
iterations.  Iterates never pass the first crossing; a crossing with
h' below the grazing speed of :mod:`symvi.flow` is reported as grazing, with
the same thresholds, so the twin and the reference agree.

Kernels take the constants of one (params, omega) as a float64 array made by
:func:`constants`; ``cache=True`` keeps compiled code on disk.
"""
import math

import numba as nb
import numpy as np

from .flow import forcing_amplitudes
from .params import modal as _modal

#: finder statuses, as in :mod:`symvi.flow`
IMPACT, GRAZING, NO_IMPACT = 0, 1, 2
STATUS_NAMES = ("impact", "grazing", "no-impact")

#: run stop codes
COMPLETED, STOP_GRAZING, STOP_CHATTER, STOP_STICKING, STOP_NO_IMPACT, STOP_NONFINITE = range(6)
STOP_NAMES = ("completed", "grazing", "chatter", "sticking", "no-impact", "non-finite")

#: a run stops as chatter after this many consecutive flights ...
CHATTER_COUNT = 16
#: ... each shorter than this fraction of the forcing period
CHATTER_FLIGHT = 1e-3

_EPS = 2.0 ** -52
_TWO_PI = 2.0 * math.pi
_MAX_STEPS = 1_000_000

# layout of the constants array
_W1, _W2, _P11, _P12, _P21, _P22, _A1, _A2, _D, _OM, _B, _R, _TMAX = range(13)
NCONST = 13


def constants(params, omega, t_max=None):
    """Float64 constants of one (params, omega) for the kernels, eqs. (5)–(7).

    ``t_max`` (default 1000 forcing periods, as in :func:`symvi.flow.first_impact`)
    bounds one flight.
    """
    m = _modal(params)
    A = forcing_amplitudes(m, omega)
    if t_max is None:
        t_max = 2000 * math.pi / omega
    return np.array([m.omega1, m.omega2, m.psi[0][0], m.psi[0][1], m.psi[1][0], m.psi[1][1],
                     A[0], A[1], m.D, omega, params.b, params.r, t_max], dtype=np.float64)


@nb.njit(cache=True, inline="always")
def _motion(c, v1, x2, v2, tau):
    """Integration constants (a1, b1, a2, b2) after an impact, eqs. (21)–(24)."""
    w1, w2, p11, p12, p21, p22 = c[_W1], c[_W2], c[_P11], c[_P12], c[_P21], c[_P22]
    A1, A2, D, om, b = c[_A1], c[_A2], c[_D], c[_OM], c[_B]
    xi1 = (p22 * b - p12 * x2) / D
    xi2 = (-p21 * b + p11 * x2) / D
    xd1 = (p22 * v1 - p12 * v2) / D
    xd2 = (-p21 * v1 + p11 * v2) / D
    st, ct = math.sin(tau), math.cos(tau)
    return (xi1 - A1 * st, (xd1 - A1 * om * ct) / w1,
            xi2 - A2 * st, (xd2 - A2 * om * ct) / w2)


@nb.njit(cache=True, inline="always")
def _eval(c, a1, b1, a2, b2, tau, t):
    """h = x1 - b and its first four derivatives, plus x2, x2dot at t, eqs. (7)–(8)."""
    w1, w2, p11, p12, p21, p22 = c[_W1], c[_W2], c[_P11], c[_P12], c[_P21], c[_P22]
    A1, A2, om = c[_A1], c[_A2], c[_OM]
    c1, s1 = math.cos(w1 * t), math.sin(w1 * t)
    c2, s2 = math.cos(w2 * t), math.sin(w2 * t)
    ph = om * t + tau
    sp, cp = math.sin(ph), math.cos(ph)
    u1 = a1 * c1 + b1 * s1
    u2 = a2 * c2 + b2 * s2
    d1 = w1 * (-a1 * s1 + b1 * c1)
    d2 = w2 * (-a2 * s2 + b2 * c2)
    xi1 = u1 + A1 * sp
    xi2 = u2 + A2 * sp
    xd1 = d1 + A1 * om * cp
    xd2 = d2 + A2 * om * cp
    q = p11 * A1 + p12 * A2
    k1, k2, ko = w1 * w1, w2 * w2, om * om
    h = p11 * xi1 + p12 * xi2 - c[_B]
    h1 = p11 * xd1 + p12 * xd2
    h2 = -(p11 * k1 * u1 + p12 * k2 * u2 + q * ko * sp)
    h3 = -(p11 * k1 * d1 + p12 * k2 * d2 + q * ko * om * cp)
    h4 = p11 * k1 * k1 * u1 + p12 * k2 * k2 * u2 + q * ko * ko * sp
    return h, h1, h2, h3, h4, p21 * xi1 + p22 * xi2, p21 * xd1 + p22 * xd2


@nb.njit(cache=True, inline="always")
def _root(h, h1, K):
    """First positive root of h + h1 s + K s^2/2 (h < 0), or inf if none."""
    disc = h1 * h1 - 2.0 * K * h
    if disc < 0.0:
        return np.inf
    den = h1 + math.sqrt(disc)
    if den <= 0.0:
        return np.inf
    return -2.0 * h / den


@nb.njit(cache=True)
def _near_max(c, a1, b1, a2, b2, tau, ta, ha, da, tb, hb, db, L):
    """Location of the max of h in (ta, tb) (h' > 0 at ta, <= 0 at tb) when it may
    come within 1e-3 L of the stop; else -1.  Safeguarded Newton on h'."""
    s = tb - ta
    u = s * da / (da - db)            # linear h' between the ends
    if max(ha + 0.5 * da * u, hb - 0.5 * db * (s - u)) < -1e-3 * L:
        return -1.0
    t = ta + u
    for _ in range(60):
        h, h1, h2, h3, h4, x2, v2 = _eval(c, a1, b1, a2, b2, tau, t)
        if h1 > 0.0:
            ta = t
        else:
            tb = t
        tn = t - h1 / h2 if h2 < 0.0 else 0.5 * (ta + tb)
        if not ta < tn < tb:
            tn = 0.5 * (ta + tb)
        if abs(tn - t) <= 4.0 * _EPS * t:
            return tn
        t = tn
    return t


@nb.njit(cache=True)
def first_impact(c, a1, b1, a2, b2, tau, t_max):
    """First t > 0 with x1(t) = b; the compiled twin of :func:`symvi.flow.first_impact`.

    Returns (status, t, x1dot, x2, x2dot, x1ddot, steps); x1ddot at the stop
    separates grazing (< 0) from sticking (> 0).
    """
    w1, w2, om = c[_W1], c[_W2], c[_OM]
    p11, p12 = c[_P11], c[_P12]
    amp1 = abs(p11) * math.sqrt(a1 * a1 + b1 * b1)
    amp2 = abs(p12) * math.sqrt(a2 * a2 + b2 * b2)
    q = abs(p11 * c[_A1] + p12 * c[_A2])
    L = amp1 + amp2 + q + abs(c[_B])
    M2 = amp1 * w1 ** 2 + amp2 * w2 ** 2 + q * om ** 2
    M5 = amp1 * w1 ** 5 + amp2 * w2 ** 5 + q * om ** 5
    eps_h = 64.0 * _EPS * L
    v_graze = 8.0 * math.sqrt(2.0 * M2 * eps_h)
    h, h1, h2, h3, h4, x2, v2 = _eval(c, a1, b1, a2, b2, tau, 0.0)
    if not h1 < 0.0:
        return GRAZING, 0.0, h1, x2, v2, h2, 0
    t = -h1 / M2                      # vertex of the global bound: h < 0 up to here
    S = 0.5 / max(w1, w2, om)         # first horizon; adapted below
    tp, hp, dp = 0.0, h, h1
    for n in range(1, _MAX_STEPS + 1):
        h, h1, h2, h3, h4, x2, v2 = _eval(c, a1, b1, a2, b2, tau, t)
        if dp > 0.0 and h1 <= 0.0 and h < -eps_h:
            # a local max of h was stepped over; the reference (smaller steps)
            # lands within eps_h of a near-tangency and calls it grazing: so do we
            tm = _near_max(c, a1, b1, a2, b2, tau, tp, hp, dp, t, h, h1, L)
            if tm >= 0.0:
                hm, hm1, hm2, _, _, xm2, vm2 = _eval(c, a1, b1, a2, b2, tau, tm)
                if hm >= -eps_h:
                    return GRAZING, tm, hm1, xm2, vm2, hm2, n
        tp, hp, dp = t, h, h1
        if h >= -eps_h:
            if h1 <= v_graze:
                return GRAZING, t, h1, x2, v2, h2, n
            for _ in range(3):        # Newton polish of a transversal root
                dt = -h / h1
                t += dt
                h, h1, h2, h3, h4, x2, v2 = _eval(c, a1, b1, a2, b2, tau, t)
                if abs(dt) <= 4.0 * _EPS * t:
                    break
            return IMPACT, t, h1, x2, v2, h2, n
        if t > t_max or not math.isfinite(h):
            return NO_IMPACT, t, h1, x2, v2, h2, n
        step = _root(h, h1, M2)       # the reference step: K = M2 for all s
        g3 = max(h3, 0.0)
        g4 = 0.5 * max(h4, 0.0)
        for _ in range(3):            # S -> fixed point of S = root(K(S))
            K = min(M2, h2 + S * (g3 + S * (g4 + S * M5 / 6.0)))
            r = _root(h, h1, K)
            step = max(step, min(S, r))
            S = 4.0 * S if r == np.inf else math.sqrt(S * r)
        t += step
        S = max(S, 2.0 * step)
    return NO_IMPACT, t, h1, x2, v2, h2, _MAX_STEPS


@nb.njit(cache=True)
def step(c, v1, x2, v2, tau):
    """One application of P, eqs. (26) and (31).

    Returns (status, t_e, x1dot+', x2', x2dot', tau' in [0, 2 pi), x1dot-, x1ddot, steps).
    """
    a1, b1, a2, b2 = _motion(c, v1, x2, v2, tau)
    st, t, v1m, x2n, v2n, acc, n = first_impact(c, a1, b1, a2, b2, tau, c[_TMAX])
    tau_u = tau + c[_OM] * t
    tau_n = tau_u - _TWO_PI * math.floor(tau_u / _TWO_PI)
    return st, t, -c[_R] * v1m, x2n, v2n, tau_n, v1m, acc, n


@nb.njit(cache=True)
def _run_into(c, y0, n_keep, transient, sec, times, vimp):
    """Iterate P from y0: drop ``transient`` images, store the next ``n_keep``.

    Returns (stop code, number stored, total finder steps).  Times are
    cumulative from the start, transient included.
    """
    v1, x2, v2, tau = y0[0], y0[1], y0[2], y0[3]
    T = 0.0
    short = 0
    t_chat = CHATTER_FLIGHT * _TWO_PI / c[_OM]
    steps = 0
    for k in range(transient + n_keep):
        st, te, v1, x2, v2, tau, vm, acc, n = step(c, v1, x2, v2, tau)
        steps += n
        kept = k - transient
        if st == NO_IMPACT:
            return STOP_NO_IMPACT, max(kept, 0), steps
        if st == GRAZING:
            # x1'' > 0 at a contact with ~zero speed: the stop holds the mass
            return (STOP_STICKING if acc > 0.0 else STOP_GRAZING), max(kept, 0), steps
        if not (math.isfinite(v1) and math.isfinite(x2) and math.isfinite(v2)):
            return STOP_NONFINITE, max(kept, 0), steps
        T += te
        short = short + 1 if te < t_chat else 0
        if kept >= 0:
            sec[kept, 0] = v1
            sec[kept, 1] = x2
            sec[kept, 2] = v2
            sec[kept, 3] = tau
            times[kept] = T
            vimp[kept] = vm
        if short >= CHATTER_COUNT:
            return STOP_CHATTER, max(kept + 1, 0), steps
    return COMPLETED, n_keep, steps


def run(c, y0, n_keep, transient=0):
    """Python entry to :func:`_run_into`: (code, section (n,4), t (n,), x1dot- (n,), steps)."""
    sec = np.empty((n_keep, 4))
    times = np.empty(n_keep)
    vimp = np.empty(n_keep)
    code, n, steps = _run_into(c, np.asarray(y0, dtype=np.float64), n_keep, transient,
                               sec, times, vimp)
    return code, sec[:n], times[:n], vimp[:n], steps


@nb.njit(cache=True, parallel=True)
def _run_batch(C, Y0, n_keep, transient, sec, times, codes, counts, steps):
    for i in nb.prange(C.shape[0]):
        vimp = np.empty(n_keep)
        codes[i], counts[i], steps[i] = _run_into(C[i], Y0[i], n_keep, transient,
                                                  sec[i], times[i], vimp)


def run_batch(C, Y0, n_keep, transient=0):
    """Many independent runs in parallel (one per row of C and Y0).

    Returns (codes (m,), counts (m,), section (m, n_keep, 4), t (m, n_keep),
    steps (m,)); rows past ``counts[i]`` are NaN.
    """
    C = np.ascontiguousarray(C, dtype=np.float64)
    Y0 = np.ascontiguousarray(Y0, dtype=np.float64)
    m = C.shape[0]
    sec = np.full((m, n_keep, 4), np.nan)
    times = np.full((m, n_keep), np.nan)
    codes = np.empty(m, dtype=np.int64)
    counts = np.empty(m, dtype=np.int64)
    steps = np.empty(m, dtype=np.int64)
    _run_batch(C, Y0, n_keep, transient, sec, times, codes, counts, steps)
    return codes, counts, sec, times, steps
