"""The Taylor method on truncated power series: a nonlinear flight's jet (issue 28).

The flight M x'' + C x' + K x + f(x, v) = P sin(omega t + tau) is integrated as
:mod:`symvi.flow.taylor` integrates it, Taylor in time of order ORDER with Jorba & Zou's
step, but every Taylor coefficient y_k is a truncated power series in the variables delta
(:mod:`symvi.flow.tps`: the start, the phase, omega, a parameter).  The recurrences are
the same [Jorba & Zou, Exp. Math. 14 (2005) 99-117, sec. 2; Griewank & Walther,
Evaluating Derivatives, ch. 13] with the numbers' products made series products::

    x_{k+1} = v_k / (k + 1),   v_{k+1} = M(p)^-1 (P(p) s_k - C(p) v_k - K(p) x_k - f_k) / (k + 1)

f_k from the forces' tape (:func:`symvi.flow.taylor.tape`, one row a binary operation)
interpreted on series of series, s_k the coefficients of sin(omega t + tau) (s_k = omega
c_{k-1} / k, c_k = -omega s_{k-1} / k; omega a series when it is a variable).  A division
by a row's first coefficient is a product by its reciprocal series (computed once a step).
One cached kernel interprets every model's tape: nothing is generated per model.

The step [Jorba & Zou, sec. 3.2]: h = rho_m / e^2 exp(-0.7 / (p - 1)) with rho_m taken
over every coefficient of the series (the smallest over the monomials of delta, each with
its own rho = max(1, |y_0|)): each order of the variational equations to the method's
accuracy, as the error norm over every coefficient did for the Runge-Kutta steps this
method replaced (the third derivatives of a nonlinear map drifted to 1e-11 of the
independent chain's when only the state was controlled).  Bounded by STEP_CAP of the
shortest period, as the trajectories' steps.

At the flight's end the Taylor coefficients there, y_0..y_K, are the series of the flight
in the time shift s, Z(T + s; delta) = sum_k y_k(delta) s^k, exact to order K in (delta,
s): the impact time's Newton iteration of :mod:`symvi.flow.nljet` composes them.
"""
import math

import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from . import tps
from .taylor import (ORDER, T_ADD, T_ATAN, T_CONST, T_COS, T_COSH, T_EXP, T_INV, T_LOG,
                     T_MUL, T_POWC, T_SCALE, T_SIN, T_SINH, T_SQRT, T_TAN, T_TANH, T_VAR)

#: steps of one series flight before it gives up
MAX_STEPS = 200_000

@nb.njit(cache=True, error_model="numpy")
def _conv2(Sa, a, Sb, b, jlo, jhi, k, out, wt, MI, MJ, OFF):
    """out = sum_{j=jlo}^{jhi} wt[j] Sa[a, j] Sb[b, k - j] (series products; the time
    sum innermost, so each coefficient of out is stored once)."""
    for m in range(out.shape[0]):
        acc = 0.0
        for t in range(OFF[m], OFF[m + 1]):
            ia = MI[t]
            ib = MJ[t]
            for j in range(jlo, jhi + 1):
                acc += wt[j] * Sa[a, j, ia] * Sb[b, k - j, ib]
        out[m] = acc


@nb.njit(cache=True, error_model="numpy")
def _func_order(S, A, R, F, wt, u, tmp, c, Kord, MI, MJ, OFF, code, i, a, k, e):
    """Time order k of row i, a function of row a (e: a real power's exponent); A the
    partner series (cos of a sin, 1 +- q^2 of a tan, 1 + a^2 of an atan), R the reciprocal
    of a first coefficient (taken at k = 0)."""
    L = S.shape[2]
    Si = S[i, k]
    if k == 0:
        if code == T_INV:
            tps.apply(tps.RECIP, S[a, 0], Si, u, tmp, c, Kord, MI, MJ, OFF)
        elif code == T_POWC:                   # a^e = exp(e log a)
            tps.apply(tps.LOG, S[a, 0], F, u, tmp, c, Kord, MI, MJ, OFF)
            for q in range(L):
                F[q] *= e
            tps.apply(tps.EXP, F, Si, u, tmp, c, Kord, MI, MJ, OFF)
            tps.apply(tps.RECIP, S[a, 0], R[i], u, tmp, c, Kord, MI, MJ, OFF)
        elif code == T_SIN or code == T_COS or code == T_SINH or code == T_COSH:
            hyp = code == T_SINH or code == T_COSH
            first = code == T_SIN or code == T_SINH
            fs = tps.SINH if hyp else tps.SIN
            fc = tps.COSH if hyp else tps.COS
            tps.apply(fs if first else fc, S[a, 0], Si, u, tmp, c, Kord, MI, MJ, OFF)
            tps.apply(fc if first else fs, S[a, 0], A[i, 0], u, tmp, c, Kord, MI, MJ, OFF)
        elif code == T_TAN or code == T_TANH:
            sg = 1.0 if code == T_TAN else -1.0
            tps.apply(tps.TAN if code == T_TAN else tps.TANH, S[a, 0], Si, u, tmp, c, Kord,
                      MI, MJ, OFF)
            tps.mul(Si, Si, A[i, 0], MI, MJ, OFF)
            for q in range(L):
                A[i, 0, q] *= sg
            A[i, 0, 0] += 1.0
        elif code == T_ATAN:
            tps.mul(S[a, 0], S[a, 0], A[i, 0], MI, MJ, OFF)
            A[i, 0, 0] += 1.0
            tps.apply(tps.ATAN, S[a, 0], Si, u, tmp, c, Kord, MI, MJ, OFF)
            tps.apply(tps.RECIP, A[i, 0], R[i], u, tmp, c, Kord, MI, MJ, OFF)
        else:                                  # exp, log, sqrt
            f = tps.EXP if code == T_EXP else tps.LOG if code == T_LOG else tps.SQRT
            tps.apply(f, S[a, 0], Si, u, tmp, c, Kord, MI, MJ, OFF)
            if code == T_LOG:
                tps.apply(tps.RECIP, S[a, 0], R[i], u, tmp, c, Kord, MI, MJ, OFF)
            elif code == T_SQRT:
                for q in range(L):
                    F[q] = 2.0 * Si[q]
                tps.apply(tps.RECIP, F, R[i], u, tmp, c, Kord, MI, MJ, OFF)
        return
    if code == T_INV:                          # q a = 1: q_k = -q_0 sum_{j>=1} a_j q_{k-j}
        for j in range(k + 1):
            wt[j] = 1.0
        _conv2(S, a, S, i, 1, k, k, F, wt, MI, MJ, OFF)
        tps.mul(S[i, 0], F, Si, MI, MJ, OFF)
        for q in range(L):
            Si[q] = -Si[q]
    elif code == T_POWC:                       # a q' = e a' q
        for j in range(k + 1):
            wt[j] = ((e + 1.0) * j - k) / k
        _conv2(S, a, S, i, 1, k, k, F, wt, MI, MJ, OFF)
        tps.mul(R[i], F, Si, MI, MJ, OFF)
    elif code == T_EXP:                        # q' = a' q
        for j in range(k + 1):
            wt[j] = j / k
        _conv2(S, a, S, i, 1, k, k, Si, wt, MI, MJ, OFF)
    elif code == T_LOG:                        # a q' = a'
        for j in range(k + 1):
            wt[j] = j / k
        _conv2(S, i, S, a, 1, k - 1, k, F, wt, MI, MJ, OFF)
        for q in range(L):
            F[q] = S[a, k, q] - F[q]
        tps.mul(R[i], F, Si, MI, MJ, OFF)
    elif code == T_SIN or code == T_COS or code == T_SINH or code == T_COSH:
        # (s, c)' = a' (c, -+s); S holds the function, A its partner
        hyp = code == T_SINH or code == T_COSH
        first = code == T_SIN or code == T_SINH
        for j in range(k + 1):
            wt[j] = j / k
        sk = S[i, k] if first else A[i, k]
        ck = A[i, k] if first else S[i, k]
        # s_k = sum j a_j c_{k-j} / k, c_k = -+ sum j a_j s_{k-j} / k
        if first:
            _conv2(S, a, A, i, 1, k, k, sk, wt, MI, MJ, OFF)
            _conv2(S, a, S, i, 1, k, k, ck, wt, MI, MJ, OFF)
        else:
            _conv2(S, a, S, i, 1, k, k, sk, wt, MI, MJ, OFF)
            _conv2(S, a, A, i, 1, k, k, ck, wt, MI, MJ, OFF)
        if not hyp:
            for q in range(L):
                ck[q] = -ck[q]
    elif code == T_TAN or code == T_TANH:      # q' = a' w, w = 1 +- q^2
        sg = 1.0 if code == T_TAN else -1.0
        for j in range(k + 1):
            wt[j] = j / k
        _conv2(S, a, A, i, 1, k, k, Si, wt, MI, MJ, OFF)
        for j in range(k + 1):
            wt[j] = sg
        _conv2(S, i, S, i, 0, k, k, A[i, k], wt, MI, MJ, OFF)
    elif code == T_SQRT:                       # q^2 = a
        for j in range(k + 1):
            wt[j] = 1.0
        _conv2(S, i, S, i, 1, k - 1, k, F, wt, MI, MJ, OFF)
        for q in range(L):
            F[q] = S[a, k, q] - F[q]
        tps.mul(R[i], F, Si, MI, MJ, OFF)
    else:                                      # atan: w q' = a', w = 1 + a^2
        for j in range(k + 1):
            wt[j] = 1.0
        _conv2(S, a, S, a, 0, k, k, A[i, k], wt, MI, MJ, OFF)
        for j in range(k + 1):
            wt[j] = j / k
        _conv2(S, i, A, i, 1, k - 1, k, F, wt, MI, MJ, OFF)
        for q in range(L):
            F[q] = S[a, k, q] - F[q]
        tps.mul(R[i], F, Si, MI, MJ, OFF)


@nb.njit(cache=True, error_model="numpy")
def _coefficients(sy, tj, t, Y, kmax):
    """X[:, 0..kmax] <- the Taylor coefficients (series in delta) of the flight through
    (t, Y) (the module docstring)."""
    (Minv, Km, Cm, P, dM, dK, dC, dP, W, U, omega, tau, pvar, moves, mass_moves,
     wvar) = sy
    (tp, vals, roots, S, A, R, F, wt, u, tmp, c, Kord, MI, MJ, OFF, X, sn, cs, r) = tj
    dim, L = Y.shape
    n = dim // 2
    w0 = omega[0]
    # the phase omega t + tau, its sine and cosine
    for q in range(L):
        F[q] = omega[q] * t + tau[q]
    tps.apply(tps.SIN, F, sn[0], u, tmp, c, Kord, MI, MJ, OFF)
    tps.apply(tps.COS, F, cs[0], u, tmp, c, Kord, MI, MJ, OFF)
    for i in range(dim):
        for q in range(L):
            X[i, 0, q] = Y[i, q]
    for k in range(kmax):
        if k > 0:
            if wvar:
                tps.mul(omega, cs[k - 1], sn[k], MI, MJ, OFF)
                tps.mul(omega, sn[k - 1], cs[k], MI, MJ, OFF)
                for q in range(L):
                    sn[k, q] /= k
                    cs[k, q] /= -k
            else:
                for q in range(L):
                    sn[k, q] = w0 * cs[k - 1, q] / k
                    cs[k, q] = -w0 * sn[k - 1, q] / k
        # time order k of every row of the tape (rows before it known to order k, every
        # row to order k - 1): :func:`symvi.flow.taylor._series` on series.  Inline, and
        # no array views: a call or a view costs two reference counts per array, which
        # took 4 times the polynomial rows' arithmetic.
        for i in range(tp.shape[0]):
            code = tp[i, 0]
            a = tp[i, 1]
            b = tp[i, 2]
            if code == T_VAR:
                if a < dim:
                    for q in range(L):
                        S[i, k, q] = X[a, k, q]
                else:                          # a parameter: constant in time
                    for q in range(L):
                        S[i, k, q] = U[a, q] if k == 0 else 0.0
            elif code == T_MUL and a == b:    # a square: the terms j, k - j pair up
                h2 = (k + 1) // 2                # (the pairs of a monomial are symmetric)
                for m in range(L):
                    acc = 0.0
                    mid = 0.0
                    for t in range(OFF[m], OFF[m + 1]):
                        ia = MI[t]
                        ib = MJ[t]
                        for j in range(h2):
                            acc += S[a, j, ia] * S[a, k - j, ib]
                        if k % 2 == 0:
                            mid += S[a, h2, ia] * S[a, h2, ib]
                    S[i, k, m] = 2.0 * acc + mid
            elif code == T_MUL:
                for m in range(L):
                    acc = 0.0
                    for t in range(OFF[m], OFF[m + 1]):
                        ia = MI[t]
                        ib = MJ[t]
                        for j in range(k + 1):
                            acc += S[a, j, ia] * S[b, k - j, ib]
                    S[i, k, m] = acc
            elif code == T_SCALE:              # S[b] constant in time
                for m in range(L):
                    acc = 0.0
                    for t in range(OFF[m], OFF[m + 1]):
                        acc += S[b, 0, MI[t]] * S[a, k, MJ[t]]
                    S[i, k, m] = acc
            elif code == T_ADD:
                for q in range(L):
                    S[i, k, q] = S[a, k, q] + S[b, k, q]
            elif code == T_CONST:
                for q in range(L):
                    S[i, k, q] = vals[i] if k == 0 and q == 0 else 0.0
            else:
                _func_order(S, A, R, F, wt, u, tmp, c, Kord, MI, MJ, OFF, code, i, a, k,
                            vals[i])
        # (no array views in this loop: each costs two reference counts)
        for i in range(n):
            ii = roots[i]
            for q in range(L):
                acc = P[i] * sn[k, q] - S[ii, k, q]
                for j in range(n):
                    acc -= Cm[i, j] * X[n + j, k, q] + Km[i, j] * X[j, k, q]
                r[i, q] = acc
            if moves:                          # + p (dP sin - dC v - dK x)
                for q in range(L):
                    acc = dP[i] * sn[k, q]
                    for j in range(n):
                        acc -= dC[i, j] * X[n + j, k, q] + dK[i, j] * X[j, k, q]
                    F[q] = acc
                tps.mul_add(F, pvar, r[i], MI, MJ, OFF)
        for i in range(n):
            if mass_moves:                     # M(p)^-1 as series (W)
                vi = X[n + i, k + 1]
                for q in range(L):
                    vi[q] = 0.0
                for j in range(n):
                    tps.mul_add(W[i, j], r[j], vi, MI, MJ, OFF)
                for q in range(L):
                    vi[q] /= k + 1
            else:
                for q in range(L):
                    acc = 0.0
                    for j in range(n):
                        acc += Minv[i, j] * r[j, q]
                    X[n + i, k + 1, q] = acc / (k + 1)
            for q in range(L):
                X[i, k + 1, q] = X[n + i, k, q] / (k + 1)


@nb.njit(cache=True, error_model="numpy")
def _jorba_zou_h(X, p, hmax):
    """Jorba & Zou's step from the last two coefficients, over every monomial of delta
    (the module docstring), at most hmax."""
    dim, _, L = X.shape
    rm = math.inf
    for q in range(L):
        rho = 1.0
        n1 = 0.0
        n2 = 0.0
        for i in range(dim):
            rho = max(rho, abs(X[i, 0, q]))
            n1 = max(n1, abs(X[i, p - 1, q]))
            n2 = max(n2, abs(X[i, p, q]))
        if n1 > 0.0:
            rm = min(rm, (rho / n1) ** (1.0 / (p - 1)))
        if n2 > 0.0:
            rm = min(rm, (rho / n2) ** (1.0 / p))
    return min(hmax, rm * math.exp(-0.7 / (p - 1)) / (math.e * math.e))


@nb.njit(cache=True, error_model="numpy")
def _at(X, p, h, Y):
    """Y = sum_{k <= p} X[:, k] h^k (Horner)."""
    dim, _, L = X.shape
    for i in range(dim):
        for q in range(L):
            acc = X[i, p, q]
            for k in range(p - 1, -1, -1):
                acc = acc * h + X[i, k, q]
            Y[i, q] = acc


@nb.njit(cache=True, error_model="numpy")
def integrate(sy, tj, Y, t_end, hmax):
    """Y(t_end) from Y(0) (in place) by steps of order ORDER, the last one cut to end
    there; returns the number of steps, -1 when it failed (a non-finite step or the
    step limit)."""
    p = ORDER
    X = tj[15]
    t = 0.0
    steps = 0
    while t < t_end:
        if steps >= MAX_STEPS:
            return -1
        _coefficients(sy, tj, t, Y, p)
        h = _jorba_zou_h(X, p, hmax)
        if not (math.isfinite(h) and h > 0.0):
            return -1
        h = min(h, t_end - t)
        _at(X, p, h, Y)
        t = t + h if t_end - t > h else t_end
        steps += 1
    return steps


@nb.njit(cache=True, error_model="numpy")
def _mass_inverse(Minv, dM, pvar, Kord, W, tmp, MI, MJ, OFF):
    """W = M(p)^-1 = (M + p dM)^-1 as series: column by column, Kord sweeps
    w = M^-1 (e - p dM w) (each exact to one more order in p)."""
    n = Minv.shape[0]
    L = W.shape[2]
    col = np.zeros((n, L))
    rhs = np.zeros((n, L))
    for e in range(n):
        for i in range(n):
            for q in range(L):
                col[i, q] = 0.0
            col[i, 0] = Minv[i, e]
        for _ in range(Kord):
            for i in range(n):
                for q in range(L):
                    rhs[i, q] = 0.0
                rhs[i, 0] = 1.0 if i == e else 0.0
                for j in range(n):
                    if dM[i, j] != 0.0:
                        tps.mul(col[j], pvar, tmp, MI, MJ, OFF)
                        for q in range(L):
                            rhs[i, q] -= dM[i, j] * tmp[q]
            for i in range(n):
                for q in range(L):
                    acc = 0.0
                    for j in range(n):
                        acc += Minv[i, j] * rhs[j, q]
                    col[i, q] = acc
        for i in range(n):
            for q in range(L):
                W[i, e, q] = col[i, q]


def system(flow, alg, omega, tau, pvar=None, tangent=None, dpars=None, wvar=False):
    """(sy, tj): the field and the scratch of one series flight of ``flow`` (a
    :class:`symvi.flow.nonlinear.NonlinearFlow` or a contact phase,
    :class:`symvi.flow.nlcontact.NonlinearPhase`) in ``alg``: omega, tau the series of the
    frequency and the phase (``wvar``: omega is a variable), ``pvar`` the series of a
    parameter p that moves M, K, C, P (``tangent``: their derivatives, the flow's own
    K and C) and the parameters of the forces' program (``dpars``: the rate of each slot,
    a force's parameter or a phase's -f_S), each linearly."""
    n, L, K = flow.n, alg.L, alg.K
    model = flow.model
    Z = np.zeros((n, n))
    # writeable copies: numba types a read-only array apart (a second compilation)
    dM, dK, dC, dP = ((np.array(tangent.dM, float), np.array(tangent.dK, float),
                       np.array(tangent.dC, float), np.array(tangent.dP, float))
                      if tangent is not None else (Z, Z, Z, np.zeros(n)))
    moves = bool(tangent is not None and (dM.any() or dK.any() or dC.any() or dP.any()))
    mass_moves = bool(moves and dM.any())
    nvar = 2 * n + len(flow.pars)
    U = np.zeros((nvar, L))
    U[2 * n:, 0] = flow.pars
    if dpars is not None:                      # the program's parameters move: U = u + p du
        for j in np.flatnonzero(dpars):
            U[2 * n + j] += dpars[j] * pvar
    pvar = pvar if pvar is not None else np.zeros(L)
    MI, MJ, OFF = alg.mul
    W = np.zeros((n, n, L))
    if mass_moves:
        _mass_inverse(flow.Minv, dM, pvar, K, W, np.zeros(L), MI, MJ, OFF)
    sy = (flow.Minv, np.ascontiguousarray(model.stiffness, float),
          np.ascontiguousarray(model.damping, float),
          np.ascontiguousarray(model.forcing, float), dM, dK, dC, dP, W, U, omega, tau,
          pvar, moves, mass_moves, bool(wvar))
    tp, vals, roots = flow.tape
    q = max(ORDER, K) + 1
    Lt = tp.shape[0]
    tj = (tp, vals, roots, np.zeros((Lt, q, L)), np.zeros((Lt, q, L)), np.zeros((Lt, L)),
          np.zeros(L), np.zeros(q), np.zeros(L), np.zeros(L), np.zeros(K + 1), K, MI, MJ,
          OFF, np.zeros((2 * n, q, L)), np.zeros((q, L)), np.zeros((q, L)), np.zeros((n, L)))
    return sy, tj


def expansion(sy, tj, t, Y, K):
    """(dim, K + 1, L): the flight's series in the time shift s at t, Z(t + s; delta) =
    sum_k out[:, k] s^k, from the state's series Y at t (the Taylor coefficients there)."""
    _coefficients(sy, tj, float(t), Y, K)
    return tj[15][:, :K + 1].copy()
