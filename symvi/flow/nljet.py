"""Jets of a nonlinear flight and of its impact map, to any order (issue 28).

The flight of :mod:`symvi.flow.nonlinear`, M x'' + C x' + K x + f(x, v) = P sin(omega t +
tau), is integrated on truncated power series (:mod:`symvi.flow.tps`) in the variables
delta: the start's free coordinates, the phase tau, and optionally omega and one named
parameter p.  The integrator is DOP853 (the coefficients :mod:`symvi.flow.nonlinear`
keeps beside its Taylor method, which runs the trajectories; a Taylor method on series
is a later step), with the error norm over every coefficient (:func:`_error`).  The
result is the flow's jet z(T; delta) at a fixed time T to order K.

The impact (eqs. (28)-(30) of the paper, generalised).  At the end the flight goes on in
the time shift s: Z(s; delta) = z(T) + int_0^s F(Z, T + sigma) d sigma by K + 1 Picard
iterations on series in (delta, s), exact to order K.  The impact time T + S(delta) solves
h(Z(S(delta); delta)) = 0 for the guard h = g . x - level of the constraint the flight
ends on, by K + 1 Newton iterations on series (each gains an order; dh/ds at delta = 0 is
the approach speed, nonzero off grazing).  Then z-(delta) = Z(S(delta); delta), the reset
v+ = R v-, and the section point on that constraint (the coordinates in its section's
layout, the phase tau + omega (T + S)).  Guards, levels, resets and layouts are the
linear part's flow's, in its (flow) order (:class:`FlowView`).  Its series are the jet of
the impact map P to order K: raw derivative tensors by
:meth:`symvi.flow.tps.Algebra.tensor`, as the generated jets of the linear flow give them
(:mod:`symvi.codegen.jets`).

Parameters.  omega enters the phase omega t + tau; a named force parameter is a variable of
the force program; a parameter of the linear part moves M, K, C, P (linearly: M(p) = M +
p dM, ...; M(p)^-1 r by K fixed-point sweeps w = M^-1 (r - p dM w)).  A gap or a
restitution is refused by name (their series would enter the start, the guard's level and
the reset: a later step).
"""
import math

import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from ..errors import ParameterError, SingularCaseError
from . import tps
from .nonlinear import (_A, _B, _C, _NS, ATOL, MAX_STACK, OP_ADD, OP_CONST, OP_MUL, OP_POW,
                        OP_POWI, OP_VAR, RTOL, _combine)
from .nonlinear import _error as _flat_error

#: steps of one series flight before it gives up
MAX_STEPS = 200_000
#: how far (relative) the flight's end may lie from the impact the series solve for (the
#: shift's series, cut at order K in s, is exact near 0 only), and how often it is moved
TIME_TOL = 1e-12
TIME_TRIES = 4


# --------------------------------------------------------------------------- the field
@nb.njit(cache=True)
def _eval(ops, lo, hi, U, stack, out, ws, c, K, MI, MJ, MK):
    """One force on series: the postfix program ops[lo:hi] at the variables U (nvar, L)
    (:func:`symvi.flow.nonlinear._eval` on numbers)."""
    tmp, tmp2, u, res = ws[0], ws[1], ws[2], ws[3]
    L = out.shape[0]
    sp = 0
    for i in range(lo, hi):
        op = int(ops[i, 0])
        arg = ops[i, 1]
        if op == OP_CONST:
            for j in range(L):
                stack[sp, j] = 0.0
            stack[sp, 0] = arg
            sp += 1
        elif op == OP_VAR:
            for j in range(L):
                stack[sp, j] = U[int(arg), j]
            sp += 1
        elif op == OP_ADD:
            m = int(arg)
            for q in range(sp - m + 1, sp):
                for j in range(L):
                    stack[sp - m, j] += stack[q, j]
            sp -= m - 1
        elif op == OP_MUL:
            m = int(arg)
            for q in range(sp - m + 1, sp):
                tps.mul(stack[sp - m], stack[q], tmp, MI, MJ, MK)
                for j in range(L):
                    stack[sp - m, j] = tmp[j]
            sp -= m - 1
        elif op == OP_POWI:
            tps.powi(stack[sp - 1], int(arg), res, tmp, tmp2, u, c, K, MI, MJ, MK)
            for j in range(L):
                stack[sp - 1, j] = res[j]
        elif op == OP_POW:                     # b^e = exp(e log b)
            tps.apply(tps.LOG, stack[sp - 2], res, u, tmp, c, K, MI, MJ, MK)
            tps.mul(stack[sp - 1], res, tmp2, MI, MJ, MK)
            tps.apply(tps.EXP, tmp2, res, u, tmp, c, K, MI, MJ, MK)
            sp -= 1
            for j in range(L):
                stack[sp - 1, j] = res[j]
        else:
            tps.apply(int(arg), stack[sp - 1], res, u, tmp, c, K, MI, MJ, MK)
            for j in range(L):
                stack[sp - 1, j] = res[j]
    for j in range(L):
        out[j] = stack[0, j]


@nb.njit(cache=True)
def _field(sy, time, Y, out):
    """Y' = (v, M(p)^-1 (P(p) sin(omega t + tau) - C(p) v - K(p) x - f(x, v))) on series;
    ``time`` the series of t (a number, or T + s)."""
    (Minv, K, C, P, dM, dK, dC, dP, ops, off, U, stack, omega, tau, pvar, moves, ws, c, Kord,
     MI, MJ, MK, r, g) = sy
    n = P.shape[0]
    L = Y.shape[1]
    tmp, u, res, ph, sn = ws[0], ws[2], ws[3], ws[4], ws[5]
    for i in range(2 * n):
        for j in range(L):
            U[i, j] = Y[i, j]
    tps.mul(omega, time, ph, MI, MJ, MK)
    for j in range(L):
        ph[j] += tau[j]
    tps.apply(tps.SIN, ph, sn, u, tmp, c, Kord, MI, MJ, MK)
    for i in range(n):
        _eval(ops, off[i], off[i + 1], U, stack, res, ws, c, Kord, MI, MJ, MK)
        for j in range(L):
            acc = P[i] * sn[j] - res[j]
            for q in range(n):
                acc -= C[i, q] * Y[n + q, j] + K[i, q] * Y[q, j]
            r[i, j] = acc
        if moves:                              # + p (dP sin - dC v - dK x)
            for j in range(L):
                acc = dP[i] * sn[j]
                for q in range(n):
                    acc -= dC[i, q] * Y[n + q, j] + dK[i, q] * Y[q, j]
                g[i, j] = acc
            tps.mul_add(g[i], pvar, r[i], MI, MJ, MK)
    for i in range(n):
        for j in range(L):
            out[i, j] = Y[n + i, j]
    _solve_mass(sy, out[n:])


@nb.njit(cache=True)
def _solve_mass(sy, dst):
    """dst = M(p)^-1 r (r in sy): M^-1 r, then K sweeps w = M^-1 (r - p dM w) when dM != 0."""
    (Minv, K, C, P, dM, dK, dC, dP, ops, off, U, stack, omega, tau, pvar, moves, ws, c, Kord,
     MI, MJ, MK, r, g) = sy
    n = P.shape[0]
    L = r.shape[1]
    _rows(Minv, r, dst)
    mass_moves = False
    for i in range(n):
        for q in range(n):
            mass_moves = mass_moves or dM[i, q] != 0.0
    if not (moves and mass_moves):
        return
    tmp = ws[0]
    for _ in range(Kord):
        _rows(dM, dst, g)
        for i in range(n):
            tps.mul(g[i], pvar, tmp, MI, MJ, MK)
            for j in range(L):
                g[i, j] = r[i, j] - tmp[j]
        _rows(Minv, g, dst)


@nb.njit(cache=True)
def _rows(A, X, out):
    """out = A X for series rows X (n, L); out distinct from X."""
    n, L = X.shape
    for i in range(n):
        for j in range(L):
            acc = 0.0
            for q in range(n):
                acc += A[i, q] * X[q, j]
            out[i, j] = acc


# --------------------------------------------------------------------------- the flight
@nb.njit(cache=True)
def _dop853(sy, t, Y, h, Kst, Ynew, tmp, tser):
    """One DOP853 step on series (:func:`symvi.flow.nonlinear._dop853` on numbers, its
    stage sums :func:`symvi.flow.nonlinear._combine` on the flattened rows)."""
    m = Y.size
    Yf, Nf, Tf = Y.reshape(m), Ynew.reshape(m), tmp.reshape(m)
    Kf = Kst.reshape((Kst.shape[0], m))
    for s in range(1, _NS):
        _combine(Yf, h, Kf, _A[s], s, Tf)
        tser[0] = t + _C[s] * h
        _field(sy, tser, tmp, Kst[s])
    _combine(Yf, h, Kf, _B, _NS, Nf)
    tser[0] = t + h
    _field(sy, tser, Ynew, Kst[_NS])


@nb.njit(cache=True)
def _error(Kst, Y, Ynew, h):
    """DOP853's error norm over every coefficient of every component
    (:func:`symvi.flow.nonlinear._error` on the flattened rows): each order of the
    variational equations to the flow's tolerance.  (On the state alone the steps were 66
    for 92 a period of the Duffing benchmark, but the third derivatives of a nonlinear map
    drifted to 1e-11 of the independent chain's; over every coefficient 1e-13.)"""
    m = Y.size
    return _flat_error(Kst.reshape((Kst.shape[0], m)), Y.reshape(m), Ynew.reshape(m), h,
                       RTOL, ATOL)


@nb.njit(cache=True)
def _integrate(sy, Y, t_end, hmax, Kst, Ynew, tmp, tser):
    """Y(t_end) from Y(0) (in place); returns the number of steps, -1 when it failed."""
    dim, L = Y.shape
    t = 0.0
    for j in range(L):
        tser[j] = 0.0
    _field(sy, tser, Y, Kst[0])
    h = hmax
    steps = 0
    while t < t_end:
        if steps >= MAX_STEPS:
            return -1
        h = min(h, hmax, t_end - t)
        _dop853(sy, t, Y, h, Kst, Ynew, tmp, tser)
        err = _error(Kst, Y, Ynew, h)
        steps += 1
        if err > 1.0 or not math.isfinite(err):
            h *= 0.2 if not math.isfinite(err) else max(0.2, 0.9 * err ** (-1.0 / 8.0))
            if h < 1e-14 * max(t_end, 1.0):
                return -1
            continue
        t = t + h if t_end - t > h else t_end
        for i in range(dim):
            for j in range(L):
                Y[i, j] = Ynew[i, j]
                Kst[0, i, j] = Kst[_NS, i, j]
        h *= 10.0 if err == 0.0 else min(10.0, max(0.2, 0.9 * err ** (-1.0 / 8.0)))
    return steps


@nb.njit(cache=True)
def _picard(sy, Z0, T, svar, Z, F, INT_SRC, INT_DST, INT_DIV, Kord):
    """Z(s; delta) = Z0 + int_0^s F(Z, T + sigma) d sigma on series in (delta, s): Kord + 1
    Picard sweeps (each exact to one more order); ``svar`` the series of s."""
    dim, L = Z0.shape
    tser = svar.copy()
    tser[0] += T
    for i in range(dim):
        for j in range(L):
            Z[i, j] = Z0[i, j]
    for _ in range(Kord + 1):
        _field(sy, tser, Z, F)
        for i in range(dim):
            for j in range(L):
                Z[i, j] = Z0[i, j]
            for q in range(INT_SRC.shape[0]):
                Z[i, INT_DST[q]] += F[i, INT_SRC[q]] / INT_DIV[q]


@nb.njit(cache=True)
def _compose(Zb, S, out, SPLIT_POW, SPLIT_IDX, Kord, tmp, cj, MI, MJ, MK):
    """out(delta) = Zb(delta, S(delta)) for one series Zb in (delta, s): Horner in s."""
    L = out.shape[0]
    for j in range(L):
        out[j] = 0.0
    for p in range(Kord, -1, -1):
        for j in range(L):
            cj[j] = 0.0
        for q in range(Zb.shape[0]):
            if SPLIT_POW[q] == p:
                cj[SPLIT_IDX[q]] += Zb[q]
        if p < Kord:
            tps.mul(out, S, tmp, MI, MJ, MK)
            for j in range(L):
                out[j] = tmp[j]
        for j in range(L):
            out[j] += cj[j]


# --------------------------------------------------------------------------- Python side
class _System:
    """The series field of one (flow, omega, tau, parameter) in an algebra of d variables."""

    def __init__(self, flow, alg, omega, tau, pvar=None, tangent=None, pslot=None):
        n, L = flow.n, alg.L
        model = flow.model
        Z = np.zeros((n, n))
        # writeable copies: numba types a read-only array apart (a second compilation)
        dM, dK, dC, dP = ((np.array(tangent.dM, float), np.array(tangent.dK, float),
                           np.array(tangent.dC, float), np.array(tangent.dP, float))
                          if tangent is not None else (Z, Z, Z, np.zeros(n)))
        nvar = 2 * n + len(flow.pars)
        U = np.zeros((nvar, L))
        for i, v in enumerate(flow.pars):
            U[2 * n + i, 0] = v
        if pslot is not None:                  # a named force parameter: a variable
            U[2 * n + pslot] += pvar
        ws = np.zeros((6, L))
        moves = tangent is not None and not (
            not dM.any() and not dK.any() and not dC.any() and not dP.any())
        self.sy = (flow.Minv, np.ascontiguousarray(model.stiffness, float),
                   np.ascontiguousarray(model.damping, float),
                   np.ascontiguousarray(model.forcing, float), dM, dK, dC, dP,
                   flow.ops, flow.off, U, np.zeros((MAX_STACK + 1, L)), omega, tau,
                   pvar if pvar is not None else np.zeros(L), bool(moves), ws,
                   np.zeros(alg.K + 1), alg.K, *alg.mul, np.zeros((n, L)), np.zeros((n, L)))


def _series(alg, value, var=None):
    a = np.zeros(alg.L)
    a[0] = value
    if var is not None:
        a[1 + var] = 1.0
    return a


def _bigger(alg):
    """The algebra with one more variable s (last), the embedding of ``alg`` into it, the
    integration in s, and the split of a big series by powers of s."""
    big = tps.algebra(alg.d + 1, alg.K)
    key = (alg.d, alg.K)
    hit = _BIG.get(key)
    if hit is None:
        emb = np.array([big.index[e + (0,)] for e in map(tuple, alg.exps)], dtype=np.int64)
        src, dst, div = [], [], []
        for q, e in enumerate(map(tuple, big.exps)):
            if sum(e) < alg.K:
                src.append(q)
                dst.append(big.index[e[:-1] + (e[-1] + 1,)])
                div.append(e[-1] + 1.0)
        spow = big.exps[:, -1].copy()
        sidx = np.array([alg.index[tuple(e[:-1])] for e in big.exps], dtype=np.int64)
        hit = _BIG[key] = (big, emb, np.array(src, np.int64), np.array(dst, np.int64),
                           np.array(div), spow, sidx)
    return hit


_BIG = {}


def flight_series(flow, omega, z0, tau, T, order, B, *, omega_var=False, param=None):
    """(alg, Y, sys, (tangent, pvar, ip)): the flow's series z(T; delta) (mass order,
    rows) from z0 + B delta_state at phase tau.

    Variables, in order: the columns of ``B`` (dim x m: how the start moves with each),
    the phase, then omega if ``omega_var``, then ``param`` (a
    :class:`symvi.model.parameters.Parameter` other than omega) if given."""
    B = np.asarray(B, dtype=float)
    m = B.shape[1]
    d = m + 1 + bool(omega_var) + (param is not None)
    alg = tps.algebra(d, order)
    dim = 2 * flow.n
    Y = np.zeros((dim, alg.L))
    Y[:, 0] = z0
    Y[:, 1:1 + m] = B
    itau = m
    iw = itau + 1 if omega_var else None
    ip = d - 1 if param is not None else None
    tau_s = _series(alg, tau, itau)
    om_s = _series(alg, omega, iw)
    tangent, pslot, pvar = None, None, None
    if param is not None:
        pvar = _series(alg, 0.0, ip)
        pslot = _force_slot(flow.model, param)
        if pslot is None:
            tangent = param.tangent(flow.model)
            if tangent.db or tangent.dr:       # they move the start, the level, the reset
                raise ParameterError("param", param.name, "omega, a parameter of the "
                                     "forces or an entry of M, K, C, P (a gap or a "
                                     "restitution with nonlinear forces: a later step of "
                                     "issue 28)")
    sys = _System(flow, alg, om_s, tau_s, pvar, tangent, pslot)
    Kst = np.zeros((_NS + 1, dim, alg.L))
    steps = _integrate(sys.sy, Y, float(T), flow.hmax(omega), Kst, np.zeros_like(Y),
                       np.zeros_like(Y), np.zeros(alg.L))
    if steps < 0 or not np.all(np.isfinite(Y)):
        raise SingularCaseError("flight", f"the series flight over t = {T:.6g} did not "
                                "finish (a non-finite state or the step limit)")
    return alg, Y, sys, (tangent, pvar, ip)


def _force_slot(model, param):
    """The index of a named force parameter among the forces' parameters, else None."""
    names = () if model._nl is None else model._nl.names
    return list(names).index(param.name) if param.name in names else None


def flight_first(flow, omega, z0, tau, T, *, omega_var=False, param=None):
    """(z, dz/dz0, dz/dtau, dz/dt, dz/dp) of the flight from z0 (mass order) over T: the
    first-order series (the variational equations); dz/dp along omega or ``param`` (None
    when neither is asked for)."""
    dim = 2 * flow.n
    alg, Y, sys, _ = flight_series(flow, omega, z0, tau, T, 1, np.eye(dim),
                                   omega_var=omega_var, param=param)
    z = Y[:, 0].copy()
    Phi = Y[:, 1:1 + dim].copy()
    dzt = Y[:, 1 + dim].copy()
    dzp = Y[:, 2 + dim].copy() if (omega_var or param is not None) else None
    dzdt = flow.rhs(omega, tau, T, z)
    return z, Phi, dzt, dzdt, dzp


def impact_series(view, omega, y, T, order, start, end, *, omega_var=False, param=None):
    """(alg, P, te, speed): the series of the impact map's section point after the flight
    from section point ``y`` of constraint ``start`` (its layout, last the phase) that ends
    on constraint ``end`` near time T (its exact time is solved here: the flight is
    integrated again to the impact when it lies farther than TIME_TOL T, at most
    TIME_TRIES times), in the variables (y, [omega], [p]); ``speed`` the approach speed
    at the impact.  ``view`` a :class:`FlowView`: the constraints' guards, resets and
    section layouts are its flow order's."""
    T = float(T)
    for _ in range(TIME_TRIES):
        out = _impact_series(view, omega, y, T, order, start, end, omega_var, param)
        if abs(out[2] - T) <= TIME_TOL * max(T, 1.0):
            return out[:4]
        T = out[2]
    raise ParameterError("te", T, "the flight's impact time (the guard is not 0 there: "
                         f"the impact is {out[2] - T:.3g} away)")


def _impact_series(view, omega, y, T, order, start, end, omega_var, param):
    flow = view.nl
    n, dim = flow.n, 2 * flow.n
    rows = view.rows
    pa, fa = view.positions[start], view.frames[start]
    # the start in flow order: x_pa on its section, the other coordinates the point's
    w0 = np.zeros(dim)
    w0[pa] = rows[start][1]
    w0[fa] = y[:-1]
    E = np.zeros((dim, dim - 1))
    E[fa, np.arange(dim - 1)] = 1.0
    S = view.S
    alg, Y, sys, (tangent, pvar, ip) = flight_series(
        flow, omega, S @ w0, float(y[-1]), T, order, S @ E, omega_var=omega_var,
        param=param)
    big, emb, src, dst, div, spow, sidx = _bigger(alg)
    # the field on series in (delta, s)
    om_b = np.zeros(big.L)
    om_b[emb] = sys.sy[12]
    tau_b = np.zeros(big.L)
    tau_b[emb] = sys.sy[13]
    pv_b = None
    if param is not None:
        pv_b = np.zeros(big.L)
        pv_b[emb] = pvar
    sysb = _System(flow, big, om_b, tau_b, pv_b, tangent,
                   None if param is None else _force_slot(flow.model, param))
    Z0 = np.zeros((dim, big.L))
    Z0[:, emb] = Y
    svar = _series(big, 0.0, big.d - 1)
    Zb, Fb = np.zeros_like(Z0), np.zeros_like(Z0)
    _picard(sysb.sy, Z0, float(T), svar, Zb, Fb, src, dst, div, alg.K)
    Zb = view.Sinv @ Zb                          # flow order from here
    # the impact time: h(Z(S(delta); delta)) = 0, h = guard . x - level
    row = rows[end]
    guard, level = row[3:3 + n], row[2]
    H = guard @ Zb[:n]
    H[0] -= level
    speed = float(H[big.index[(0,) * alg.d + (1,)]])
    if not speed > 0:
        raise SingularCaseError("grazing", f"the approach speed at the impact is {speed:.3g}: "
                                "the impact time is not a smooth function of the start "
                                "(grazing, eq. (30))")
    St = np.zeros(alg.L)
    hs = np.zeros(alg.L)
    tmp, cj = np.zeros(alg.L), np.zeros(alg.L)
    MI, MJ, MK = alg.mul
    for _ in range(alg.K + 1):
        _compose(H, St, hs, spow, sidx, alg.K, tmp, cj, MI, MJ, MK)
        St -= hs / speed
    ze = np.zeros((dim, alg.L))
    for i in range(dim):
        _compose(Zb[i], St, ze[i], spow, sidx, alg.K, tmp, cj, MI, MJ, MK)
    # the reset v+ = R v- and the section point on constraint ``end``
    R = row[3 + n:].reshape(n, n)
    ze[n:] = R @ ze[n:]
    out = np.zeros((dim, alg.L))
    out[:dim - 1] = ze[view.frames[end]]
    phase = sys.sy[13].copy()
    tser = St.copy()
    tser[0] += T
    tps.mul_add(sys.sy[12], tser, phase, MI, MJ, MK)
    out[dim - 1] = phase
    return alg, out, float(T + St[0]), speed


def map_jet(view, omega, y, T, order, start=0, end=0, *, param=None):
    """The jet of the impact map as :func:`symvi.codegen.jets.flight_jet` gives it: a dict
    with "P" (the image, phase not reduced), "J", "d2".."d<order>" (raw tensors over the
    section point), "te", "speed"; with ``param`` (a Parameter, omega included) also
    "dpP" = dP/dp and "dpJ" = dJ/dp at fixed y."""
    w = param is not None and param.is_forcing_frequency
    alg, P, te, speed = impact_series(view, omega, y, T, order, start, end, omega_var=w,
                                      param=None if (param is None or w) else param)
    m = len(y)
    ax = tuple(range(m))
    out = {"P": P[:, 0].copy(), "te": te, "speed": speed,
           "J": alg.tensor(P, 1, ax)}
    for k in range(2, order + 1):
        out[f"d{k}"] = alg.tensor(P, k, ax)
    if param is not None:
        out["dpP"] = P[:, 1 + m].copy()
        if order >= 2:
            both = alg.tensor(P, 2)
            out["dpJ"] = both[:, :m, m]
    return out


# --------------------------------------------------------------------------- the view
_VIEWS = {}


class NonlinearForcing:
    """The forcing of a nonlinear flow at omega: the frequency alone (no steady state)."""

    __slots__ = ("omega",)

    def __init__(self, omega):
        self.omega = omega


class FlowView:
    """The nonlinear flow as the shooting system of :mod:`symvi.orbits.periodic` reads a
    flow: in the linear flow's (stop-first) order, with its constraint data (guards,
    resets, levels, section frames: geometry, the same for the linear part), and the
    flights of the series (:func:`flight_first`).  Only the names in :data:`GEOMETRY`
    are taken from the linear part's flow; every flight comes from the nonlinear one."""

    GEOMETRY = frozenset(("reset", "guard", "level", "constraint_rows", "constraint64",
                          "constraint", "position", "perm", "framed", "to_mass", "to_flow",
                          "approach", "section_approach", "bk", "n", "b", "r", "_unit_guard",
                          "_constrain", "_reset_data", "_framed_reset", "_mass_key"))
    offset = None
    free = False

    def __init__(self, model):
        from .compiled import section_index
        from .linear import LinearFlow
        from .nonlinear import NonlinearFlow
        self.model = model
        lin = self.lin = LinearFlow.of(model.linear_part)
        self.nl = NonlinearFlow(model)
        dim = 2 * model.n
        #: z_mass = S z_flow (a permutation, or T^-1 on positions and on velocities)
        self.S = np.array([lin.to_mass(e) for e in np.eye(dim)]).T
        self.Sinv = np.array([lin.to_flow(e) for e in np.eye(dim)]).T
        #: per constraint: (position, gap, level, guard, reset) in flow order, its position
        #: and the flow-order index of each section coordinate
        self.rows = [np.asarray(r, dtype=float) for r in lin.constraint_rows()]
        self.positions = tuple(int(r[0]) for r in self.rows)
        self.frames = tuple(section_index(model.n, q) for q in self.positions)

    @classmethod
    def of(cls, model):
        """The view of ``model``, built once (its flows and tables; cached like
        :meth:`LinearFlow.of`)."""
        from .linear import _memo
        return _memo(_VIEWS, model, lambda: cls(model), size=64)

    def __getattr__(self, name):
        if name in FlowView.GEOMETRY:
            return getattr(self.lin, name)
        raise AttributeError(name)

    def check_omega(self, omega, name="omega", warn=True):
        from .linear import check_range
        return check_range(omega, name)

    def forcing(self, omega):
        return NonlinearForcing(float(omega))

    def flight(self, forcing, z0, tau, t, param=None):
        """(z, dz/dz0, dz/dtau, dz/dt) at t of the flight from z0 (flow order) at phase
        tau, :meth:`symvi.flow.linear.LinearFlow.flight`'s layout; with ``param`` (a
        Parameter) the derivative along it is appended."""
        S, Si = self.S, self.Sinv
        w = param is not None and param.is_forcing_frequency
        z, Phi, dzt, dzdt, dzp = flight_first(
            self.nl, forcing.omega, S @ z0, float(tau), float(t), omega_var=w,
            param=None if (param is None or w) else param)
        out = (Si @ z, Si @ Phi @ S, Si @ dzt, Si @ dzdt)
        return out if param is None else out + (Si @ dzp,)

    def motion(self, forcing, z0, tau):
        """The first contact of the flight from z0 (flow order), as
        :class:`symvi.flow.linear.Motion` gives it (``first_impact(t_max)``)."""
        return _Motion(self, forcing.omega, self.S @ z0, float(tau))

    def step(self, forcing, y, k=0):
        """(status, t, y', constraint met) of the impact map from section point y of
        constraint k, in the flow order's section layouts (:attr:`frames`)."""
        n, dim = self.n, 2 * self.n
        w = np.empty(dim)
        w[self.positions[k]] = self.rows[k][1]
        w[self.frames[k]] = y[:-1]
        st, te, c, ze = self.nl.first_impact(forcing.omega, self.S @ w, float(y[-1]),
                                             just_hit=k)
        if st != "impact":
            return st, te, None, c
        z = self.Sinv @ ze
        z[n:] = self.rows[c][3 + n:].reshape(n, n) @ z[n:]
        z[self.positions[c]] = self.rows[c][1]
        y1 = np.append(z[self.frames[c]], float(y[-1]) + forcing.omega * te)
        return st, te, y1, c


class _Motion:
    def __init__(self, view, omega, z0, tau):
        self.view, self.omega, self.z0, self.tau = view, omega, z0, tau

    def state(self, t):
        """z(t) (flow order), the constraints ignored (:meth:`NonlinearFlow.state`)."""
        return self.view.Sinv @ self.view.nl.state(self.omega, self.z0, self.tau, float(t))

    def h(self, t):
        """(h(t),): the first constraint's guard along the flight, as
        :meth:`symvi.flow.linear.Motion.h` gives it (value only)."""
        row, n = self.view.rows[0], self.view.n
        return (float(row[3:3 + n] @ self.state(t)[:n] - row[2]),)

    def first_impact(self, t_max=None, max_steps=None):
        from .linear import GRAZING, IMPACT, NO_IMPACT, FirstImpact
        view, nl = self.view, self.view.nl
        zf, k = view.Sinv @ self.z0, -1
        for c, row in enumerate(view.rows):        # the constraint z0 lies on, if any
            if abs(zf[view.positions[c]] - row[1]) <= 1e-12 * max(1.0, abs(row[1])):
                k = c
        st, te, c, ze = nl.first_impact(self.omega, self.z0, self.tau, t_max=t_max,
                                        just_hit=k)
        status = {"impact": IMPACT, "grazing": GRAZING}.get(st, NO_IMPACT)
        if status == NO_IMPACT and t_max is not None:
            te = max(te, t_max * (1 + 1e-9))   # ran to t_max: decided
        hit = FirstImpact(status, te, self.view.Sinv @ ze, 0)
        object.__setattr__(hit, "constraint", c)
        return hit
