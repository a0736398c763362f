"""Compiled twin of :mod:`symvi.flow.linear` and :mod:`symvi.maps.impact` for any model:
the exact modal flow, the first-impact finder, the map P and long runs.

Modal form.  z(t) = Re(W (c * e^{lambda t})) + zp(t), c = W^-1 (z0 - zp(0)), as in
:mod:`symvi.flow.linear`.  A is real, so its eigenvalues come in conjugate pairs
whose terms are conjugate: only one of each pair is kept, with weight 2
(``Re(a) + Re(conj a) = 2 Re(a)``); real (overdamped) eigenvalues keep weight 1.
Along a flight only the guard h = g . x - level of the model's constraint
(:class:`symvi.model.Constraint`; x_k - b for the stop on mass k) and its
derivatives are needed::

    h^(m)(t) = sum_j w_j Re(d_j lambda_j^m e^{lambda_j t}) + d^m/dt^m g . x_p - level [m = 0],
    d_j = (g . W[:N, j]) c_j         (W[0, j] c_j for the stop: g = e_0 in the stop-first order);

the full state is rebuilt only at the impact.  With free modes (a mass on no spring:
:meth:`symvi.flow.linear.LinearFlow._free_modal`) the flight gains the drift t NIL w,
NIL = [[0, G], [0, 0]]: positions only, so h gains delta_g t (delta_g = g . G w_v),
h' gains delta_g, and h'' and every higher derivative, hence the bounds below, are
unchanged; a guard whose h is linear (M2 = 0: a free mass that nothing forces) and falling
never meets its stop, and the finder ends past t_max.  Models without free modes carry no
G block (the header's offset is 0) and run exactly as before.

Finder.  :meth:`symvi.flow.linear.Motion.first_impact` with a tighter, still
provably safe step.  For s >= 0,
|h''(t + s)| <= M2(t) = sum_j w_j |d_j| |lambda_j|^2 e^{Re lambda_j t} + |X_k| omega^2
(Re lambda_j <= 0: M positive definite, K, C semi-definite), and likewise
M5(t) >= |h'''''(t + s)|.  With a horizon S and s in [0, S]

    h''(t + s) <= K(S) = h2 + max(h3 S, 0) + max(h4, 0) S^2/2 + M5 S^3/6,

so h(t + s) <= h + h1 s + min(K, M2) s^2/2 and no crossing occurs before the
first root of that quadratic (capped at S).  The reference step of
:meth:`symvi.flow.linear.Motion.first_impact` (K = M2(0) for every s) is one of
these lower bounds, so the twin never steps further than is safe.  Grazing uses
the reference's thresholds (eps_h, v_graze from the amplitudes at t = 0), and a
local maximum of h stepped over within eps_h of the stop is reported as grazing,
as the reference (smaller steps) would land on it.

Kernels take the constants of one (model, omega) as one float64 array made by
:func:`constants` (complex numbers as (re, im) pairs); section points are 2N
vectors in the layout of :mod:`symvi.maps.section`.  This module owns the one
run loop (:func:`_run_into`: simulate, sweep, the plane and the classifier share it,
the tangent map and the escape test chosen by its arguments), and the statuses,
stop codes and chatter thresholds of every compiled run.  The paper's model
(:class:`symvi.Params`) runs here too, as :meth:`symvi.model.Model.luo_xie`: its section layout is the
paper's (x1dot+, x20, x20dot, tau0), eq. (9).
"""
import math

import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from ..numerics.tolerances import CONTACT_TIME_ULPS, CONTACT_ULPS, GRAZING_SPEED_FACTOR
from ..numerics.tolerances import EPS64 as _EPS
from .linear import LinearFlow

__all__ = ["constants", "size", "pack", "first_impact_from", "state_from", "step", "step_tangent",
           "jacobian_tangent", "run", "run_batch",
           "IMPACT", "GRAZING", "NO_IMPACT", "STATUS_NAMES", "COMPLETED", "STOP_GRAZING",
           "STOP_CHATTER", "STOP_STICKING", "STOP_NO_IMPACT", "STOP_NONFINITE", "STOP_NAMES",
           "CHATTER_COUNT", "CHATTER_FLIGHT"]

#: finder status codes; their names are the statuses of :mod:`symvi.flow.linear`
IMPACT, GRAZING, NO_IMPACT = 0, 1, 2
STATUS_NAMES = ("impact", "grazing", "no-impact")

#: run stop codes
COMPLETED, STOP_GRAZING, STOP_CHATTER, STOP_STICKING, STOP_NO_IMPACT, STOP_NONFINITE = range(6)
STOP_NAMES = ("completed", "grazing", "chatter", "sticking", "no-impact", "non-finite")

#: a run stops as chatter after this many consecutive flights ...
CHATTER_COUNT = 16
#: ... each shorter than this fraction of the forcing period
CHATTER_FLIGHT = 1e-3

_TWO_PI = 2.0 * math.pi
_MAX_STEPS = 1_000_000

# The constants array, typed against the constraint interface (symvi.model.Constraint).
# Header: N, kept modes, omega, t_max, max(|lambda|, omega), the growth factor, the
# number of constraints, and the offset of the free modes' drift block G (0: none).
# Then, for a model of N masses (capacity 2N modes), in the flow's order:
#   modes   [_HDR, +6N)            (Re lambda_j, Im lambda_j, weight w_j)
#   W cols  [ow, +8N^2)            W[i, j] at ow + 2 (2N j + i), (re, im)
#   W^-1    [ov, +8N^2)            W^-1[j, i] at ov + 2 (2N j + i)
#   U, V    [ou, +2N)              steady-state amplitudes
#   constraint table [oc, ...)     one block of _CB + N + N^2 per constraint k, in the
#       model's order: the position p of its coordinate in the flow's order (its section is
#       x_p = gap), the gap, the guard level (h = guard . x - level < 0 off it), the guard's
#       steady amplitudes (guard . U, guard . V, |guard . X|), the signed guard normal (N),
#       the reset R (N^2, R[i, j] at + N i + j: v+ = R v-, the impact law)
#   G       [c[_FREE], +N^2)       only with free modes: NIL = [[0, G], [0, 0]], G[i, j] at
#       + N i + j (:meth:`LinearFlow._free_modal`; the flight gains t G (v0 - v_p(0)) in x)
_NN, _NM, _OM, _TMAX, _LMAX, _GROW, _NC, _FREE = range(8)
_HDR = 8
#: the fields at the head of a constraint's block
_P, _GAP, _LEVEL, _US, _VS, _XS = range(6)
_CB = 6


def size(n, m=1, free=False):
    """Length of the constants array of a model with n masses and m constraints (and a
    drift block when it has ``free`` modes)."""
    return _HDR + 6 * n + 16 * n * n + 2 * n + m * (_CB + n + n * n) + (n * n if free else 0)


def _modes(lam):
    """Indices and weights of the kept modes: one of each conjugate pair (weight 2),
    every real eigenvalue (weight 1); all 2N with weight 1 if the pairing fails."""
    keep, used = [], set()
    for j, lj in enumerate(lam):
        if j in used:
            continue
        if lj.imag == 0.0:
            keep.append((j, 1.0))
            continue
        # partner: the closest conjugate among the rest
        rest = [p for p in range(len(lam)) if p != j and p not in used]
        if not rest:
            break
        p = min(rest, key=lambda q: abs(lam[q] - np.conj(lj)))
        if abs(lam[p] - np.conj(lj)) > 1e-12 * max(abs(lj), 1e-300):
            break
        used.update((j, p))
        keep.append((j if lj.imag > 0 else p, 2.0))
    else:
        if sum(w for _, w in keep) == len(lam):
            return keep
    return [(j, 1.0) for j in range(len(lam))]


def constants(model, omega, t_max=None):
    """Float64 constants of one (model, omega) for the kernels (layout in the source).

    ``omega`` is validated by :meth:`LinearFlow.check_omega` (no warning here);
    ``t_max`` (default 1000 forcing periods, as the reference finder) bounds one
    flight.  Every constraint of the model is in the table (:meth:`LinearFlow.constraint_rows`).
    """
    flow = LinearFlow.of(model)
    omega = flow.check_omega(omega, warn=False)
    fo = flow.forcing(omega)
    n = flow.n
    dim = 2 * n
    if t_max is None:
        t_max = 2000 * math.pi / omega
    keep = _modes(np.asarray(flow.lam, dtype=complex))
    W = np.asarray(flow.W, dtype=complex)
    Winv = np.asarray(flow.Winv, dtype=complex)
    rows = table(flow)
    c = np.zeros(size(n, len(rows), flow.free))
    U, V = np.asarray(fo.U, dtype=float), np.asarray(fo.V, dtype=float)
    c[_NN], c[_NM], c[_OM] = n, len(keep), omega
    c[_TMAX] = t_max
    c[_NC] = len(rows)
    ow, ov, ou, oc, cb = offsets(n)
    set_constraints(c, n, rows)
    set_guard_forcing(c, flow, U, V)
    c[_LMAX] = max(max(abs(flow.lam)), omega)
    # Re lambda <= 0 holds up to rounding; a rounding-sized Re lambda > 0 inflates
    # the bounds M2, M5 by its growth over a flight (> t_max only by a last step)
    c[_GROW] = math.exp(max(0.0, float(np.max(flow.lam.real))) * 4 * t_max)
    for q, (j, w) in enumerate(keep):
        lj = complex(flow.lam[j])
        c[_HDR + 3 * q:_HDR + 3 * q + 3] = (lj.real, lj.imag, w)
        c[ow + 2 * dim * q:ow + 2 * dim * (q + 1)] = np.column_stack(
            [W[:, j].real, W[:, j].imag]).ravel()
        c[ov + 2 * dim * q:ov + 2 * dim * (q + 1)] = np.column_stack(
            [Winv[j].real, Winv[j].imag]).ravel()
    c[ou:ou + n], c[ou + n:ou + 2 * n] = U, V
    if flow.free:
        NIL = np.asarray(flow.NIL, dtype=float)
        G = NIL[:n, n:]
        # the finder's bounds take the drift in positions only (module docstring)
        assert not NIL[:, :n].any() and not NIL[n:].any()
        o = size(n, len(rows))
        c[_FREE] = o
        c[o:o + n * n] = G.ravel()
    return c


#: the constraint as the kernels take it (:attr:`LinearFlow.constraint64`): the section's
#: level b, the guard's level, then the guard (N) and the reset R (N x N, row-major)
CONSTRAINT = ("b", "level", "guard", "reset")


def set_constraint(c, flow):
    """Write the flow's constraint (gap, guard, reset: :meth:`LinearFlow._constrain`) into
    the first block of the constants array ``c`` (a flow copied for a new gap or
    restitution shares the rest)."""
    n = flow.n
    k = flow.constraint64
    oc = offsets(n)[3]
    c[oc + _GAP], c[oc + _LEVEL] = k[0], k[1]
    c[oc + _CB:oc + _CB + n + n * n] = k[2:]


def table(flow):
    """The flow's constraint rows (:meth:`LinearFlow.constraint_rows`) as one C array, kept
    on the flow for its model and constraint (a flow copied for a new gap makes its own)."""
    c = flow.__dict__.get("_table")
    if c is None or c[0] is not flow.model or c[1] is not flow.constraint64:
        tab = np.ascontiguousarray(np.array(flow.constraint_rows(), dtype=float))
        c = flow.__dict__["_table"] = (flow.model, flow.constraint64, tab)
    return c[2]


def set_constraints(c, n, rows):
    """Write every constraint's row (:meth:`LinearFlow.constraint_rows`: position, gap,
    level, guard, reset) into its block of the table; the steady amplitudes of the guards
    are :func:`set_guard_forcing`'s."""
    _, _, _, oc, cb = offsets(n)
    for k, row in enumerate(rows):
        c[oc + k * cb + _P:oc + k * cb + _P + 3] = row[:3]
        c[oc + k * cb + _CB:oc + (k + 1) * cb] = row[3:]


def set_guard_forcing(c, flow, U, V):
    """Each guard's steady amplitudes guard . U, guard . V and |guard . X| (U[0], V[0],
    |X_k| for the stop on mass k)."""
    n = flow.n
    _, _, _, oc, cb = offsets(n)
    for k in range(int(c[_NC])):
        o = oc + k * cb
        if k == 0 and flow._unit_guard:       # the stop on the flow's first mass, read off
            us, vs = U[0], V[0]
        else:
            g = c[o + _CB:o + _CB + n]
            us, vs = g @ U, g @ V
        c[o + _US], c[o + _VS], c[o + _XS] = us, vs, math.sqrt(us ** 2 + vs ** 2)


def offsets(n):
    """:func:`_offsets` for Python callers (a dispatcher call costs microseconds)."""
    o = _OFFSETS.get(n)
    if o is None:
        o = _OFFSETS[n] = _offsets.py_func(n)
    return o


_OFFSETS = {}


# --------------------------------------------------------------------------- kernels
@nb.njit(cache=True, inline="always")
def _offsets(n):
    """(ow, ov, ou, oc, cb): the blocks of the constants array (layout above); cb is the
    length of one constraint's block."""
    dim = 2 * n
    ow = _HDR + 3 * dim
    ov = ow + 2 * dim * dim
    ou = ov + 2 * dim * dim
    oc = ou + 2 * n
    return ow, ov, ou, oc, _CB + n + n * n


@nb.njit(cache=True, inline="always")
def _slot(i, p):
    """Where coordinate i (flow order, i != p) sits in a section point of the constraint
    at position p: x_i at y[slot], v_i at y[n - 1 + slot]; y[0] is v_p."""
    return i + 1 if i < p else i


def section_index(n, p):
    """The flow-order state index of each of y[:2N-1] on the section of the constraint at
    position p (:func:`_slot`): y[0] is v_p, y[slot] is x_i, y[n - 1 + slot] is v_i."""
    idx = np.empty(2 * n - 1, dtype=np.int64)
    idx[0] = n + p
    for i in range(n):
        if i != p:
            q = _slot.py_func(i, p)
            idx[q], idx[n - 1 + q] = i, n + i
    return idx


@nb.njit(cache=True, inline="always")
def _response(c, ou, n, i, sp, cp):
    """(U_i sin + V_i cos, U_i cos - V_i sin) at the phase (sp, cp): the steady response
    zp_i of mass i (eq. (7)) and its velocity over omega, = d_tau zp_i."""
    U, V = c[ou + i], c[ou + n + i]
    return U * sp + V * cp, U * cp - V * sp


@nb.njit(cache=True, inline="always")
def _put_section(c, orr, n, p, x, xo, u, uo, y):
    """y[:2N-1] <- the section point of the constraint at position p whose reset R sits at
    ``orr``: v+ = R u (u = u[uo:uo+N], the velocities before the impact; v_k+ = -r v_k-,
    eq. (2), for the stop), y[0] = v+_p, and the positions x[xo:xo+N] and the other v+ at
    their slots (:func:`_slot`)."""
    for i in range(n):
        sv = 0.0
        for j in range(n):
            sv += c[orr + n * i + j] * u[uo + j]
        if i == p:
            y[0] = sv
        else:
            q = _slot(i, p)
            y[q] = x[xo + i]
            y[n - 1 + q] = sv


@nb.njit(cache=True)
def _start(c, y, k, cc, d, amp, w):
    """Weighted mode coefficients w_j c_j, c = W^-1 (z0 - zp(0)), of the flight from the
    point y of constraint k's section into cc; per guard g and mode j, into d (12 floats
    at 12 (2N g + j)): w_j d_j lambda_j^k for k = 0..4 (re, im), then w_j |d_j|
    |lambda_j|^2 and w_j |d_j| |lambda_j|^5 (times the growth factor of the header, 1 when
    every Re lambda <= 0); sum_j w_j |d_j| per guard into amp.  With free modes, the drift
    G (v0 - v_p(0)) into cc[4N:5N] and its rate along guard g into d[24 N nc + g].
    Returns tau.  ``w`` is scratch (2N)."""
    n, m, om = int(c[_NN]), int(c[_NM]), c[_OM]
    dim = 2 * n
    ow, ov, ou, oc, cb = _offsets(n)
    nc = int(c[_NC])
    ob = oc + k * cb
    p = int(c[ob + _P])
    tau = y[dim - 1]
    sp, cp = math.sin(tau), math.cos(tau)
    # z0 = (x_p = gap, the others from y) in the flow's order, minus zp(0)
    for i in range(n):
        s0, s1 = _response(c, ou, n, i, sp, cp)
        if i == p:
            xi, vi = c[ob + _GAP], y[0]
        else:
            s = _slot(i, p)
            xi, vi = y[s], y[n - 1 + s]
        w[i] = xi - s0
        w[n + i] = vi - om * s1
    for g in range(nc):
        amp[g] = 0.0
    of = int(c[_FREE])
    if of > 0:                                  # free modes: the drift G (v0 - v_p(0))
        for i in range(n):
            a = 0.0
            for j in range(n):
                a += c[of + n * i + j] * w[n + j]
            cc[4 * n + i] = a
        for g in range(nc):                     # its rate along each guard, delta_g
            og = oc + g * cb + _CB
            a = 0.0
            for i in range(n):
                a += c[og + i] * cc[4 * n + i]
            d[24 * n * nc + g] = a
    else:                                       # none: a zero rate, added without a branch
        for g in range(nc):
            d[24 * n * nc + g] = 0.0
    for j in range(m):
        lr, li, wt = c[_HDR + 3 * j], c[_HDR + 3 * j + 1], c[_HDR + 3 * j + 2]
        ar, ai = 0.0, 0.0
        for i in range(dim):
            o = ov + 2 * (dim * j + i)
            ar += c[o] * w[i]
            ai += c[o + 1] * w[i]
        ar, ai = wt * ar, wt * ai               # the weight is 1 or 2: exact
        cc[2 * j], cc[2 * j + 1] = ar, ai
        l2 = lr * lr + li * li
        for g in range(nc):
            og = oc + g * cb + _CB
            gr, gi = 0.0, 0.0                   # guard . W[:n, j] (W[0, j] for the stop)
            for i in range(n):
                o = ow + 2 * (dim * j + i)
                gr += c[og + i] * c[o]
                gi += c[og + i] * c[o + 1]
            dr = gr * ar - gi * ai
            di = gr * ai + gi * ar
            q = 12 * (dim * g + j)
            for kk in range(5):
                d[q + 2 * kk], d[q + 2 * kk + 1] = dr, di
                dr, di = dr * lr - di * li, dr * li + di * lr
            a = math.sqrt(d[q] * d[q] + d[q + 1] * d[q + 1])
            amp[g] += a
            d[q + 10] = a * l2 * c[_GROW]
            d[q + 11] = a * l2 * l2 * math.sqrt(l2) * c[_GROW]
    return tau


@nb.njit(cache=True, inline="always")
def _modes_at(c, e, x, m, tau, t):
    """The modes' factors at t: e^{lambda_j t} (re, im) into e[2j:2j+2], e^{Re lambda_j t}
    into x[j] (1 for an undamped mode), (sin, cos) of the phase into e[2m:2m+2], t into
    e[2m+2]; what
    :func:`_guard_at` and :func:`_state` read."""
    for j in range(m):
        lr, li = c[_HDR + 3 * j], c[_HDR + 3 * j + 1]
        cs, sn = math.cos(li * t), math.sin(li * t)
        if lr == 0.0:                            # undamped mode: no decay
            x[j] = 1.0
        else:
            ex = math.exp(lr * t)
            cs, sn = ex * cs, ex * sn
            x[j] = ex
        e[2 * j], e[2 * j + 1] = cs, sn
    ph = c[_OM] * t + tau
    e[2 * m], e[2 * m + 1] = math.sin(ph), math.cos(ph)
    e[2 * m + 2] = t


@nb.njit(cache=True, inline="always")
def _guard_at(c, d, e, x, n, m, g):
    """h = guard . x - level of guard g (x_k - b for the stop), its first four derivatives,
    and the bounds M2(t), M5(t), at the time of the last :func:`_modes_at`."""
    h = h1 = h2 = h3 = h4 = 0.0
    M2 = M5 = 0.0
    q0 = 12 * (2 * n * g)
    for j in range(m):
        q = q0 + 12 * j
        cs, sn = e[2 * j], e[2 * j + 1]
        M2 += x[j] * d[q + 10]
        M5 += x[j] * d[q + 11]
        # Re(w_j d_j lambda_j^k e^{lambda_j t})
        h += d[q] * cs - d[q + 1] * sn
        h1 += d[q + 2] * cs - d[q + 3] * sn
        h2 += d[q + 4] * cs - d[q + 5] * sn
        h3 += d[q + 6] * cs - d[q + 7] * sn
        h4 += d[q + 8] * cs - d[q + 9] * sn
    ob = _offsets(n)[3] + g * (_CB + n + n * n)
    om = c[_OM]
    sp, cp = e[2 * m], e[2 * m + 1]
    s0 = c[ob + _US] * sp + c[ob + _VS] * cp
    s1 = om * (c[ob + _US] * cp - c[ob + _VS] * sp)
    o2 = om * om
    h += s0 - c[ob + _LEVEL]
    h1 += s1
    h2 -= o2 * s0
    h3 -= o2 * s1
    h4 += o2 * o2 * s0
    # the free modes' drift delta_g t (h'' and on: 0); delta_g = 0 without free modes
    dl = d[24 * n * int(c[_NC]) + g]
    h += dl * e[2 * m + 2]
    h1 += dl
    X = c[ob + _XS]
    return h, h1, h2, h3, h4, M2 + X * o2, M5 + X * o2 * o2 * om


@nb.njit(cache=True)
def _eval(c, d, e, x, n, m, tau, t, g):
    """Guard g's h and derivatives and bounds at t (:func:`_modes_at`, :func:`_guard_at`)."""
    _modes_at(c, e, x, m, tau, t)
    return _guard_at(c, d, e, x, n, m, g)


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


@nb.njit(cache=True, inline="always")
def _safe_dt(h, h1, h2, h3, h4, M2, M5, S):
    """A step along which guard h provably stays < 0, and the next horizon S (module
    docstring: the reference step, then S -> fixed point of S = root(K(S)))."""
    step = _root(h, h1, M2)           # the reference step (M2 decays with the motion)
    g3 = max(h3, 0.0)
    g4 = 0.5 * max(h4, 0.0)
    for _ in range(3):
        K = min(M2, h2 + S * (g3 + S * (g4 + S * M5 / 6.0)))
        r = _root(h, h1, K)
        step = max(step, min(S, r))
        S = 4.0 * S if r == np.inf else math.sqrt(S * r)
    return step, S


@nb.njit(cache=True, inline="always")
def _release_time(h1, h2, h3, M4, eps_h):
    """How long a start with h = 0, h' = 0 (to rounding) stays provably off the stop: a
    release from sticking (:mod:`symvi.flow.sticking`), where the contact force vanished:
    h'' = 0 (to rounding) and h3 = h'(3) < 0, or h'' < 0.  With |h'(4)| <= M4
    (= M2 max(|lambda|, omega)^2), h''(s) <= min(h2, 0) + h3 s + M4 s^2/2 < 0 for
    0 < s < s*, so h' < 0 and h < 0 on (0, s*/2], which is returned.  A rounding-sized
    h2 > 0 is dropped: its penetration, ~h2^3/h3^2, is below eps_h.  0 when the start is
    no release (h'' clearly > 0, or h'' = 0 and h3 >= 0): the finder then reports
    grazing at t = 0 as before."""
    if M4 <= 0.0:
        return 0.0
    s_star = (-h3 + math.sqrt(h3 * h3 - 2.0 * M4 * min(h2, 0.0))) / M4
    if not s_star > 0.0:
        return 0.0
    if h2 > 0.0 and (h2 * (h2 / h3) ** 2 > eps_h or 6.0 * h2 / -h3 > 0.5 * s_star):
        return 0.0
    return 0.5 * s_star


@nb.njit(cache=True)
def _near_max(c, d, e, x, n, m, tau, g, ta, ha, da, tb, hb, db, L):
    """Location of the max of guard g's h in (ta, tb) (h' > 0 at ta, <= 0 at tb) when it
    may come within 1e-3 L of the stop; else -1.  Safeguarded Newton on h'."""
    s = tb - ta
    u = s * da / (da - db)            # linear h' between the ends
    if max(ha + 0.5 * da * u, hb - 0.5 * db * (s - u)) < -1e-3 * L:
        return -1.0
    t = ta + u
    for _ in range(60):
        h, h1, h2, _, _, _, _ = _eval(c, d, e, x, n, m, tau, t, g)
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


#: per guard, the finder's state in its scratch array (8 floats a guard)
_SL, _SEPS, _SVG, _SS, _STP, _SHP, _SDP = range(7)


@nb.njit(cache=True)
def _first_impact(c, d, e, x, amp, s, tau, t_max, k):
    """First t > 0 with h_g(t) = 0 for some guard g, from a point on guard k: the twin of
    :meth:`Motion.first_impact`, over every constraint.

    Every step is provably safe for every guard (module docstring), so no contact is
    stepped over, grazing ones included.  Returns (status, t, h_g'' at t, steps, g);
    h_g'' at a contact separates grazing (< 0) from sticking (> 0).  ``s`` is scratch
    (8 a guard).
    """
    n, m, nc = int(c[_NN]), int(c[_NM]), int(c[_NC])
    _, _, _, oc, cb = _offsets(n)
    _modes_at(c, e, x, m, tau, 0.0)
    t = np.inf
    t_rel = 0.0                               # a release start: guard k safe up to here
    for g in range(nc):
        ob = oc + g * cb
        h, h1, h2, h3, h4, M2, M5 = _guard_at(c, d, e, x, n, m, g)
        q = 8 * g
        L = amp[g] + c[ob + _XS] + abs(c[ob + _LEVEL])
        eps_h = CONTACT_ULPS * _EPS * L
        s[q + _SL], s[q + _SEPS] = L, eps_h
        s[q + _SVG] = GRAZING_SPEED_FACTOR * math.sqrt(2.0 * M2 * eps_h)
        s[q + _SS] = 0.5 / c[_LMAX]           # first horizon; adapted below
        s[q + _STP], s[q + _SHP], s[q + _SDP] = 0.0, h, h1
        if g == k:
            if not h1 < -eps_h * c[_LMAX]:
                # leaving at no speed (to rounding): a release, or grazing at t = 0
                t_rel = _release_time(h1, h2, h3, M2 * c[_LMAX] * c[_LMAX], eps_h)
                if t_rel <= 0.0 or h1 > eps_h * c[_LMAX]:
                    if not h1 < 0.0:
                        return GRAZING, 0.0, h2, 0, g
                    t_rel = 0.0               # a slow departure: as before
                    tg = -h1 / M2 if M2 > 0.0 else t_max + 1.0 / c[_LMAX]
                else:
                    tg = t_rel
                    s[q + _SDP] = 0.0         # h' < 0 from here: no maximum behind
            else:
                # vertex of the global bound: h < 0 up to here (h linear if M2 = 0: a
                # free mass, unforced, leaving: never back)
                tg = -h1 / M2 if M2 > 0.0 else t_max + 1.0 / c[_LMAX]
        elif h >= -eps_h:
            # the start touches another stop too (a corner): no safe way on
            return GRAZING, 0.0, h2, 0, g
        else:
            tg, s[q + _SS] = _safe_dt(h, h1, h2, h3, h4, M2, M5, s[q + _SS])
        t = min(t, tg)
    for it in range(1, _MAX_STEPS + 1):
        _modes_at(c, e, x, m, tau, t)
        step = np.inf
        stale = False
        for g in range(nc):
            if stale:                         # _near_max moved the factors away from t
                _modes_at(c, e, x, m, tau, t)
                stale = False
            h, h1, h2, h3, h4, M2, M5 = _guard_at(c, d, e, x, n, m, g)
            q = 8 * g
            eps_h = s[q + _SEPS]
            if g == k and t < t_rel:          # still inside the release's safe start
                s[q + _STP], s[q + _SHP], s[q + _SDP] = t, h, h1
                step = min(step, t_rel - t)
                continue
            if s[q + _SDP] > 0.0 and h1 <= 0.0 and h < -eps_h:
                # a local max of h was stepped over; the reference (smaller steps)
                # lands within eps_h of a near-tangency and calls it grazing: so do we
                tm = _near_max(c, d, e, x, n, m, tau, g, s[q + _STP], s[q + _SHP],
                               s[q + _SDP], t, h, h1, s[q + _SL])
                if tm >= 0.0:
                    hm, _, hm2, _, _, _, _ = _eval(c, d, e, x, n, m, tau, tm, g)
                    if hm >= -eps_h:
                        return GRAZING, tm, hm2, it, g
                    stale = True
            s[q + _STP], s[q + _SHP], s[q + _SDP] = t, h, h1
            if h >= -eps_h:
                if h1 <= s[q + _SVG]:
                    return GRAZING, t, h2, it, g
                for _ in range(3):            # Newton polish of a transversal root
                    dt = -h / h1
                    t += dt
                    h, h1, h2, h3, h4, M2, M5 = _eval(c, d, e, x, n, m, tau, t, g)
                    if abs(dt) <= CONTACT_TIME_ULPS * _EPS * t:
                        break
                return IMPACT, t, h2, it, g
            if t > t_max or not math.isfinite(h):
                return NO_IMPACT, t, h2, it, g
            sg, s[q + _SS] = _safe_dt(h, h1, h2, h3, h4, M2, M5, s[q + _SS])
            step = min(step, sg)
        if step == np.inf:                    # every h linear and falling (M2 = 0): no
            step = max(t_max - t, 0.0) + 1.0 / c[_LMAX]     # contact ever; end past t_max
        t += step
        for g in range(nc):
            s[8 * g + _SS] = max(s[8 * g + _SS], 2.0 * step)
    h, h1, h2, h3, h4, M2, M5 = _eval(c, d, e, x, n, m, tau, t, 0)
    return NO_IMPACT, t, h2, _MAX_STEPS, 0


@nb.njit(cache=True)
def phi_into(lam, W, Winv, NIL, t, out):
    """out <- Phi(t) = e^{A t} = Re(W e^{Lambda t} W^-1) + t NIL, real 2N x 2N, from
    :attr:`LinearFlow.modal_nil64` (NIL = 0 without free modes; with them the modal sum
    alone misses the drift of the Jordan block at lambda = 0: :meth:`LinearFlow.phis`)."""
    m = lam.shape[0]
    e = np.exp(lam * t)
    for i in range(m):
        for k in range(m):
            a = 0.0
            for j in range(m):
                a += (W[i, j] * e[j] * Winv[j, k]).real
            out[i, k] = a + t * NIL[i, k]


@nb.njit(cache=True)
def _state(c, cc, e, z):
    """The full state z(t) (flow order) of the flight with coefficients cc, at the time
    of the last :func:`_modes_at` (its factors ``e``)."""
    n, m, om = int(c[_NN]), int(c[_NM]), c[_OM]
    dim = 2 * n
    ow, ov, ou, _, _ = _offsets(n)
    for i in range(dim):
        z[i] = 0.0
    for j in range(m):
        cs, sn = e[2 * j], e[2 * j + 1]
        er = cc[2 * j] * cs - cc[2 * j + 1] * sn      # w_j c_j e^{lambda_j t}
        ei = cc[2 * j] * sn + cc[2 * j + 1] * cs
        for i in range(dim):
            q = ow + 2 * (dim * j + i)
            z[i] += c[q] * er - c[q + 1] * ei
    sp, cp = e[2 * m], e[2 * m + 1]
    for i in range(n):
        s0, s1 = _response(c, ou, n, i, sp, cp)
        z[i] += s0
        z[n + i] += om * s1
    if c[_FREE] > 0.0:                            # + t NIL (z0 - zp(0)): positions only
        t = e[2 * m + 2]
        for i in range(n):
            z[i] += t * cc[4 * n + i]


@nb.njit(cache=True, inline="always")
def _work(c):
    """Scratch of one flight for the constants c: (cc, d, e, x, amp, s, z, w)."""
    n, nc = int(c[_NN]), int(c[_NC])
    return (np.empty(5 * n), np.empty(24 * n * nc + nc), np.empty(4 * n + 3), np.empty(2 * n),
            np.empty(nc), np.empty(8 * nc), np.empty(2 * n), np.empty(8 * n))


@nb.njit(cache=True)
def _step_into(c, y, k, cc, d, e, x, amp, s, z):
    """One application of P on y, a point of constraint k's section, in place: y <- P(y)
    on the section of the constraint hit, eq. (31) generalised.

    Returns (status, t_e, guard . v- at the contact (v_k-), h'' there (x_k''), finder
    steps, the constraint hit)."""
    n = int(c[_NN])
    tau = _start(c, y, k, cc, d, amp, z)
    st, t, acc, steps, g = _first_impact(c, d, e, x, amp, s, tau, c[_TMAX], k)
    _state(c, cc, e, z)
    tau_u = tau + c[_OM] * t
    _, _, _, oc, cb = _offsets(n)
    og = oc + g * cb + _CB
    orr = og + n
    p = int(c[oc + g * cb + _P])
    vm = 0.0
    for i in range(n):
        vm += c[og + i] * z[n + i]
    _put_section(c, orr, n, p, z, 0, z, n, y)
    y[2 * n - 1] = tau_u - _TWO_PI * math.floor(tau_u / _TWO_PI)
    return st, t, vm, acc, steps, g


@nb.njit(cache=True)
def _first_impact_from(c, y, t_max, k):
    n = int(c[_NN])
    cc, d, e, x, amp, s, z, _ = _work(c)
    tau = _start(c, y, k, cc, d, amp, z)
    st, t, acc, steps, g = _first_impact(c, d, e, x, amp, s, tau, t_max, k)
    _state(c, cc, e, z)
    return st, t, z, acc, steps, g


def first_impact_from(c, y, t_max=None, k=0):
    """The finder from point y of constraint k's section: (status, t, state z(t) in the
    flow's order, h'' of the guard met, steps, the constraint met)."""
    c = np.ascontiguousarray(c, dtype=np.float64)
    return _first_impact_from(c, np.ascontiguousarray(y, dtype=np.float64),
                              c[_TMAX] if t_max is None else float(t_max), k)


@nb.njit(cache=True)
def _state_from(c, y, k, t):
    n, m = int(c[_NN]), int(c[_NM])
    cc, d, e, x, amp, s, z, _ = _work(c)
    tau = _start(c, y, k, cc, d, amp, z)
    _modes_at(c, e, x, m, tau, t)
    _state(c, cc, e, z)
    return z


def state_from(c, y, t, k=0):
    """The state z(t) (flow order) of the free flight from point y of constraint k's
    section, at time t (no finder: the caller knows the flight stays off every stop)."""
    return _state_from(np.ascontiguousarray(c, dtype=np.float64),
                       np.ascontiguousarray(y, dtype=np.float64), np.int64(k), float(t))


@nb.njit(cache=True)
def _step(c, y, k):
    y = y.copy()
    cc, d, e, x, amp, s, z, _ = _work(c)
    st, t, vm, acc, steps, g = _step_into(c, y, k, cc, d, e, x, amp, s, z)
    return st, t, y, vm, acc, steps, g


def step(c, y, k=0):
    """One application of P from y on constraint k's section: (status, t_e, P(y) with tau
    in [0, 2 pi) on the section of the constraint hit, its approach speed guard . v-,
    h'' at the contact, finder steps, the constraint hit)."""
    return _step(np.ascontiguousarray(c, dtype=np.float64),
                 np.ascontiguousarray(y, dtype=np.float64), np.int64(k))


@nb.njit(cache=True)
def _tangent(c, tau, v, cc, e, z, w, k, g):
    """v <- DP v for the flight just done by :func:`_step_into` from phase ``tau`` on
    constraint k's section to constraint g's (its coefficients ``cc``, factors ``e`` at
    t = t_e and state ``z`` there).

    Variation of z(t) = Phi(t) (z0 - zp(0; tau)) + zp(t; tau) at fixed t, then of
    the impact time from h_g(t_e) = 0 (x_k = b), then of the reset (formulas in
    :func:`step_tangent`).  O(dim^2): W^-1 then W per kept mode.  ``w`` is
    scratch (2 dim)."""
    n, m, om = int(c[_NN]), int(c[_NM]), c[_OM]
    dim = 2 * n
    ow, ov, ou, oc, cb = _offsets(n)
    pk = int(c[oc + k * cb + _P])
    og = oc + g * cb + _CB
    orr = og + n
    pg = int(c[oc + g * cb + _P])
    dtau = v[dim - 1]
    sp, cp = math.sin(tau), math.cos(tau)
    # u = dz0 - d_tau zp(0) dtau; d_tau zp = zp' / omega (zp depends on omega t + tau)
    for i in range(n):
        s0, s1 = _response(c, ou, n, i, sp, cp)
        if i == pk:
            dx, dv = 0.0, v[0]
        else:
            q = _slot(i, pk)
            dx, dv = v[q], v[n - 1 + q]
        w[i] = dx - s1 * dtau
        w[n + i] = dv + om * s0 * dtau
    # dz = Phi(t) u = Re sum_j W_j w_j (W^-1_j u) e^{lambda_j t}, into w[dim:]
    for i in range(dim):
        w[dim + i] = 0.0
    for j in range(m):
        wt = c[_HDR + 3 * j + 2]
        ar, ai = 0.0, 0.0
        for i in range(dim):
            o = ov + 2 * (dim * j + i)
            ar += c[o] * w[i]
            ai += c[o + 1] * w[i]
        cs, sn = e[2 * j], e[2 * j + 1]
        gr = wt * (ar * cs - ai * sn)            # w_j (W^-1_j u) e^{lambda_j t}
        gi = wt * (ar * sn + ai * cs)
        for i in range(dim):
            o = ow + 2 * (dim * j + i)
            w[dim + i] += c[o] * gr - c[o + 1] * gi
    of = int(c[_FREE])
    if of > 0:                                    # + t NIL u = (t G u_v, 0)
        t = e[2 * m + 2]
        for i in range(n):
            a = 0.0
            for j in range(n):
                a += c[of + n * i + j] * w[n + j]
            w[dim + i] += t * a
    # accelerations into w[:n] (u is spent): Re sum_j W[n + i, j] lambda_j w_j c_j
    # e^{lambda_j t} (rows n.. of W are the velocities) plus zp''
    for i in range(n):
        w[i] = 0.0
    for j in range(m):
        lr, li = c[_HDR + 3 * j], c[_HDR + 3 * j + 1]
        cs, sn = e[2 * j], e[2 * j + 1]
        er = cc[2 * j] * cs - cc[2 * j + 1] * sn
        ei = cc[2 * j] * sn + cc[2 * j + 1] * cs
        er, ei = er * lr - ei * li, er * li + ei * lr
        for i in range(n):
            o = ow + 2 * (dim * j + n + i)
            w[i] += c[o] * er - c[o + 1] * ei
    sp, cp = e[2 * m], e[2 * m + 1]
    o2 = om * om
    for i in range(n):
        s0, s1 = _response(c, ou, n, i, sp, cp)
        w[i] -= o2 * s0
        # + d_tau zp(t_e) dtau
        w[dim + i] += s1 * dtau
        w[dim + n + i] -= om * s0 * dtau
    # h(t_e + dte) = 0: dte = -guard . dx / guard . v- (-dx_k / v_k- for the stop)
    gx, gv = 0.0, 0.0
    for i in range(n):
        gx += c[og + i] * w[dim + i]
        gv += c[og + i] * z[n + i]
    dte = -gx / gv
    # Dz = dz + zdot dte; zdot = (z velocities, accelerations w[0:n]); Dv- into w[n:dim]
    for i in range(n):
        w[n + i] = w[dim + n + i] + w[i] * dte
    for i in range(n):                            # Dx = dx + xdot dte
        w[dim + i] = w[dim + i] + z[n + i] * dte
    _put_section(c, orr, n, pg, w, dim, w, n, v)  # Dv+ = R Dv-
    v[dim - 1] = dtau + om * dte


@nb.njit(cache=True)
def _step_tangent_into(c, y, k, v, cc, d, e, x, amp, s, z, w):
    """:func:`_step_into` and, on an impact, v <- DP(y) v at the old y, in place.

    Same return value as :func:`_step_into`; v is left unchanged when the
    status is not an impact.  ``w`` is scratch (2 dim)."""
    tau = y[2 * int(c[_NN]) - 1]
    st, t, vm, acc, steps, g = _step_into(c, y, k, cc, d, e, x, amp, s, z)
    if st == IMPACT:
        _tangent(c, tau, v, cc, e, z, w, k, g)
    return st, t, vm, acc, steps, g


@nb.njit(cache=True)
def _step_tangent(c, y, v, k):
    y, v = y.copy(), v.copy()
    cc, d, e, x, amp, s, z, w = _work(c)
    st, t, vm, acc, steps, g = _step_tangent_into(c, y, k, v, cc, d, e, x, amp, s, z, w)
    return st, t, y, v, g


def step_tangent(c, y, v, k=0):
    """One application of P and of its tangent map from y on constraint k's section:
    (status, t_e, P(y), DP(y) v, the constraint hit g).

    Variation of the flight z(t) = Phi(t) (z0 - zp(0; tau)) + zp(t; tau), with
    z0 = (x_p = gap, the rest from y) (p the position of constraint k's coordinate) and
    d_tau zp = zp' / omega::

        dz(t_e) = Phi(t_e) (dz0 - d_tau zp(0) dtau) + d_tau zp(t_e) dtau,
        dt_e = -g . dx(t_e) / g . v-,  Dz = dz(t_e) + zdot(t_e) dt_e,   Dv+ = R Dv-,
        DP v = (Dv+_q, Dx_i, Dv+_i (i != q), dtau + omega dt_e),

    g the guard of the constraint hit (coordinate q) and R its reset (-dx_k / v_k- and
    Dv_k+ = -r Dv_k- for the stop on mass k), with dz0 = (0 at p, the rest from v) and
    dtau = v[2n-1].  DP v is only meaningful when the status is an impact (v is returned
    unchanged otherwise).
    """
    c = np.ascontiguousarray(c, dtype=np.float64)
    return _step_tangent(c, np.ascontiguousarray(y, dtype=np.float64),
                         np.ascontiguousarray(v, dtype=np.float64), np.int64(k))


def jacobian_tangent(c, y, k=0):
    """DP(y) (2N x 2N) column by column from :func:`step_tangent` (for tests)."""
    c = np.ascontiguousarray(c, dtype=np.float64)
    y = np.ascontiguousarray(y, dtype=np.float64)
    dim = len(y)
    J = np.empty((dim, dim))
    for j in range(dim):
        st, _, _, J[:, j], _ = step_tangent(c, y, np.eye(dim)[j], k)
        if st != IMPACT:
            raise ValueError(f"no impact from y (status {STATUS_NAMES[st]}): DP undefined")
    return J


@nb.njit(cache=True)
def _run_into(c, y, k, n_keep, transient, sec, times, vimp, hits, v, glog, y_max):
    """The run loop: iterate P from y (in place), a point of constraint k's section, drop
    ``transient`` images, store the next ``n_keep``: section points, cumulative times
    (transient included), approach speeds guard . v- (v_k-), and, when ``hits`` is not
    empty, the constraint each impact hit (each section point lies on its section).

    Optional, chosen by the arguments (one body for every caller):

    * tangent map: when ``v`` is not empty, v <- DP v / |DP v| at every step (from the
      caller's v) and log |DP v| of each kept step into ``glog`` (the largest Lyapunov
      exponent is their mean);
    * escape test: a state with |y_i| > ``y_max`` (inf: off) stops the run as
      non-finite.

    Stops as the module docstring says (no impact, grazing, sticking, chatter,
    non-finite); on a stop y is left at the last section point accepted.  Returns
    (stop code, number stored, total finder steps, time at the start of the kept steps,
    the constraint of y's section at the end, the images accepted (transient included),
    the time of y since the start).
    """
    n = int(c[_NN])
    dim = 2 * n
    tangent = v.shape[0] > 0
    record = hits.shape[0] > 0
    cc, d, e, x, amp, s, z, w = _work(c)
    y_prev = np.empty(dim)
    T = 0.0
    T0 = 0.0
    short = 0
    t_chat = CHATTER_FLIGHT * _TWO_PI / c[_OM]
    steps = 0
    g_prev, vm_prev = -1, np.inf
    for it in range(transient + n_keep):
        kept = it - transient
        if kept == 0:
            T0 = T
        for i in range(dim):
            y_prev[i] = y[i]
        tau = y[dim - 1]
        st, te, vm, acc, ns, g = _step_into(c, y, k, cc, d, e, x, amp, s, z)
        steps += ns
        if st != IMPACT:
            for i in range(dim):
                y[i] = y_prev[i]
            if st == NO_IMPACT:
                return STOP_NO_IMPACT, max(kept, 0), steps, T0, k, it, T
            # h'' > 0 at a contact with ~zero speed: the stop holds the mass
            return ((STOP_STICKING if acc > 0.0 else STOP_GRAZING), max(kept, 0), steps, T0, k,
                    it, T)
        ok = True
        for i in range(dim):
            ok = ok and math.isfinite(y[i]) and abs(y[i]) <= y_max
        nv = 1.0
        if tangent:
            _tangent(c, tau, v, cc, e, z, w, k, g)
            nv = 0.0
            for i in range(dim):
                nv += v[i] * v[i]
            nv = math.sqrt(nv)
            ok = ok and math.isfinite(nv) and nv > 0.0
        if not ok:
            for i in range(dim):
                y[i] = y_prev[i]
            return STOP_NONFINITE, max(kept, 0), steps, T0, k, it, T
        k = g
        if tangent:
            for i in range(dim):
                v[i] /= nv
        T += te
        # a short flight counts toward a chatter stop unless the sequence converges: the
        # same constraint, pushed into it (h'' > 0), a smaller approach speed; that one
        # is followed to its grazing impact, whose sticking the caller continues
        # (:func:`symvi.flow.sticking.run_through`)
        conv = g == g_prev and acc > 0.0 and vm < vm_prev
        short = short + 1 if te < t_chat and not conv else 0
        g_prev, vm_prev = g, vm
        if kept >= 0:
            for i in range(dim):
                sec[kept, i] = y[i]
            times[kept] = T
            vimp[kept] = vm
            if record:
                hits[kept] = g
            if tangent:
                glog[kept] = math.log(nv)
        if short >= CHATTER_COUNT:
            return STOP_CHATTER, max(kept + 1, 0), steps, T0, k, it + 1, T
    return COMPLETED, n_keep, steps, T0, k, transient + n_keep, T


_NONE = np.empty(0)
_NO_HITS = np.empty(0, dtype=np.int64)


def run(c, y0, n_keep, transient=0, k=0, hits=False):
    """Python entry to the run loop from y0 on constraint k's section: (code, section
    (n, 2N), t (n,), approach speeds (n,), steps), and with ``hits`` the constraint each
    stored impact hit (n,) last."""
    c = np.ascontiguousarray(c, dtype=np.float64)
    dim = 2 * int(c[_NN])
    sec = np.empty((n_keep, dim))
    times = np.empty(n_keep)
    vimp = np.empty(n_keep)
    which = np.empty(n_keep if hits else 0, dtype=np.int64)
    y = np.array(np.asarray(y0, dtype=np.float64)[:dim])
    code, kk, steps, _, _, _, _ = _run_into(c, y, np.int64(k), n_keep, transient, sec, times,
                                            vimp, which, _NONE, _NONE, np.inf)
    out = (code, sec[:kk], times[:kk], vimp[:kk], steps)
    return out + (which[:kk],) if hits else out


@nb.njit(cache=True, parallel=True)
def _run_batch(C, Y0, n_keep, transient, sec, times, vimp, codes, counts, steps):
    none = np.empty(0)
    no_hits = np.empty(0, dtype=np.int64)
    for i in nb.prange(C.shape[0]):
        y = Y0[i, :2 * int(C[i, _NN])].copy()
        codes[i], counts[i], steps[i], _, _, _, _ = _run_into(
            C[i], y, 0, n_keep, transient, sec[i], times[i], vimp[i], no_hits, none, none,
            np.inf)


def run_batch(C, Y0, n_keep, transient=0):
    """Many independent runs in parallel, one per row of C and Y0.

    Rows may belong to models of different N: C is padded to the longest
    constants array and Y0 to the widest section point (padding ignored).
    Returns (codes (m,), counts (m,), section (m, n_keep, D), t (m, n_keep),
    v_k- (m, n_keep), steps (m,)); D = Y0.shape[1]; entries past a run's
    ``counts[i]`` rows or 2N columns are NaN.
    """
    C = np.ascontiguousarray(C, dtype=np.float64)
    Y0 = np.ascontiguousarray(Y0, dtype=np.float64)
    m = C.shape[0]
    sec = np.full((m, n_keep, Y0.shape[1]), np.nan)
    times = np.full((m, n_keep), np.nan)
    vimp = np.full((m, n_keep), np.nan)
    codes = np.empty(m, dtype=np.int64)
    counts = np.empty(m, dtype=np.int64)
    steps = np.empty(m, dtype=np.int64)
    _run_batch(C, Y0, n_keep, transient, sec, times, vimp, codes, counts, steps)
    return codes, counts, sec, times, vimp, steps


def pack(rows):
    """Stack constants arrays of possibly different N into one zero-padded 2-D array."""
    width = max(len(r) for r in rows)
    out = np.zeros((len(rows), width))
    for i, r in enumerate(rows):
        out[i, :len(r)] = r
    return out
