"""A Taylor method for the flow with nonlinear forces, its events on the solution's polynomial.

Between impacts (mass order, y = (x, v))::

    x' = v,   v' = M^-1 (P sin(omega t + tau) - C v - K x - f(x, v))

The Taylor coefficients y_k of the solution at t_n come from automatic differentiation:
given y_0..y_k, the k-th coefficient of f(x(t), v(t)) follows from the forces' postfix
program (:func:`symvi.flow._program.program`) interpreted on univariate series (a *tape*
of binary operations, :func:`tape`; products by convolution, exp, log, sin, cos, tan,
sqrt, sinh, cosh, tanh, atan and real powers by their recurrences [Jorba & Zou, Exp. Math.
14 (2005) 99-117, sec. 2; Griewank & Walther, Evaluating Derivatives, ch. 13]), then::

    x_{k+1} = v_k / (k + 1),   v_{k+1} = M^-1 (P s_k - C v_k - K x_k - f_k) / (k + 1)

with s_k the coefficients of sin(omega t + tau) (s_k = omega c_{k-1} / k, c_k = -omega
s_{k-1} / k).  One cached kernel interprets every model's tape, and x**3 at x = 0 is 0
(integer powers are products); a long run compiles the tape's own kernel, the same
arithmetic written out (:mod:`symvi.flow.taylor_kernel`: its series 1.6 times as fast),
which the cached flights call through a function pointer (:func:`_series_of`).

Order and step [Jorba & Zou, sec. 3.2]: the step h = exp(-0.7 / (p - 1)) min_{j = p-1, p}
(TOL rho / |y_j|_inf)^(1/j), rho = max(1, |y_0|_inf): a step's last terms are TOL relative
to rho.  TOL = EPS, the unit roundoff: the truncation, the series' tail past the last
terms (about their size times (h/R) / (1 - h/R), R the radius of convergence), stays below
the rounding of the step's sum.  Jorba & Zou's order for double precision, 20, with their
step rho_m / e^2 gives e^-40 (EPS / 50): with it the impact Duffing oscillator of
``benchmarks/bench_nonlinear_flow.py`` took 11 steps an impact and met mpmath to 2.8e-16,
with EPS 10 steps and 3.1e-16.  Their order minimizes the p^2 products of the convolutions
per unit time; the interpreted step's time grows about linearly in p (the recurrences'
latency, order after order, and the step's fixed cost), and the compiled kernel's is
flat over orders 24-32 at this TOL: FLOW_ORDER = 28 by measurement (11 steps an impact
against 21 at order 20 with e^-40).  The step is also bounded by STEP_CAP of the shortest
period (a polynomial state, whose coefficients vanish, would have no bound).

The work: the state's series are the tape's first rows (no copies), the constant rows
(parameters, numbers) are set at order 0 only, and the linear part is one map Q = M^-1 (K |
C | P | I) (:func:`_prepare`, once a flight).

Events.  Over a step the guard h_c = sign (c . x - g) of each constraint is a polynomial
of degree p in theta = (t - t_n) / h: the solution's own, since c . x is a linear
combination of the components.  Its Bernstein coefficients bound it
(:func:`symvi.flow._hull._first_bracket`): a step whose hull stays below 0 has no contact;
otherwise the search halves until the first sub-interval either starts at a contact, or
holds exactly one root (one sign change of the hull) and none before it, or is ROOT_THETA
wide (a touch, taken as a contact).  So no contact is stepped over.  The event time is
then refined by Newton on the same polynomial, safeguarded by the bracket: it IS the
solution over the step, so the refinement costs no further steps and carries the
integration's accuracy.  Just after an impact on constraint c its guard starts at 0 and
the first step looks at h_c / theta.
"""
import math

import numba as nb
import numpy as np
from numba import types
from numba.extending import overload

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from . import compiled as cf
from ._hull import _bernstein, _first_bracket
from ._program import FUNCS, OP_ADD, OP_CONST, OP_MUL, OP_POW, OP_POWI, OP_VAR

#: double precision's unit roundoff
EPS = 2.0 ** -52
#: the size of a step's last terms relative to rho (module docstring): the unit roundoff,
#: so the truncation is below a step's rounding (Jorba & Zou's order and step give EPS/50)
TOL = EPS
#: Jorba & Zou's order for EPS, ceil(-log(EPS) / 2 + 1) = 20 (the series flights of
#: :mod:`symvi.flow.jet_taylor` take it)
ORDER = int(math.ceil(-math.log(EPS) / 2.0 + 1.0))
#: the order p of the flow's steps: by measurement (module docstring)
FLOW_ORDER = 28
#: a step is at most this fraction of the shortest period (forcing, linear modes)
STEP_CAP = 0.25
#: steps of one flight before it gives up (as no impact)
MAX_STEPS = 2_000_000

# --- the tape: the program as binary operations on series ---------------------------------
(T_CONST, T_VAR, T_ADD, T_MUL, T_SCALE, T_INV, T_POWC, T_EXP, T_LOG, T_SIN, T_COS, T_TAN,
 T_SQRT, T_SINH, T_COSH, T_TANH, T_ATAN) = range(17)
_FUNC_CODE = {"sin": T_SIN, "cos": T_COS, "tan": T_TAN, "exp": T_EXP, "log": T_LOG,
              "sqrt": T_SQRT, "sinh": T_SINH, "cosh": T_COSH, "tanh": T_TANH,
              "atan": T_ATAN}


def tape(ops, off, nstate):
    """(tape (L, 3), values (L,), roots (N,)): the postfix program (ops, off) of
    :func:`symvi.flow._program.program` as binary operations on series, each row (code, a,
    b) writing the series of its own index from those of rows a and b (values: a
    constant's value, a real power's exponent); roots[i] the row of force i.  Variables
    below ``nstate`` are the state's series, the others parameters (constant series).

    Rows 0..nstate-1 are the state's series (variable i at row i: the Taylor kernel keeps
    the state in them), then the constant rows (parameters, numbers and what only they
    give: a series with coefficient 0 only, set once), then the rest."""
    rows, const = [], []

    def add(code, a=-1, b=-1, value=0.0, is_const=False):
        rows.append((code, a, b, float(value)))
        const.append(is_const)
        return len(rows) - 1

    for i in range(nstate):
        add(T_VAR, i)

    def binary(code, a, b):
        if code == T_MUL and (const[a] or const[b]):
            s, c = (b, a) if const[a] else (a, b)     # a product by a constant: a scaling
            return add(T_SCALE, s, c, is_const=const[s])
        return add(code, a, b, is_const=const[a] and const[b])

    def power(a, m):
        if m == 0:
            return add(T_CONST, value=1.0, is_const=True)
        r, sq, e = -1, a, abs(m)
        while e:                                      # square and multiply
            if e & 1:
                r = sq if r < 0 else binary(T_MUL, r, sq)
            e >>= 1
            if e:
                sq = binary(T_MUL, sq, sq)
        return r if m > 0 else add(T_INV, r, is_const=const[r])

    roots = []
    for i in range(len(off) - 1):
        stack = []
        for op, arg in ops[off[i]:off[i + 1]]:
            op = int(op)
            if op == OP_CONST:
                stack.append(add(T_CONST, value=arg, is_const=True))
            elif op == OP_VAR and int(arg) < nstate:
                stack.append(int(arg))
            elif op == OP_VAR:
                stack.append(add(T_VAR, int(arg), is_const=True))
            elif op in (OP_ADD, OP_MUL):
                args = stack[len(stack) - int(arg):]
                del stack[len(stack) - int(arg):]
                r = args[0]
                for a in args[1:]:
                    r = binary(T_ADD if op == OP_ADD else T_MUL, r, a)
                stack.append(r)
            elif op == OP_POWI:
                stack.append(power(stack.pop(), int(arg)))
            elif op == OP_POW:
                e = stack.pop()
                b = stack.pop()
                code, _, _, value = rows[e]
                if code == T_CONST and value == int(value) and abs(value) < 64:
                    stack.append(power(b, int(value)))
                elif code == T_CONST:
                    stack.append(add(T_POWC, b, value=value, is_const=const[b]))
                else:                                 # b^e = exp(e log b)
                    lb = add(T_LOG, b, is_const=const[b])
                    stack.append(add(T_EXP, binary(T_MUL, e, lb),
                                     is_const=const[b] and const[e]))
            else:
                a = stack.pop()
                stack.append(add(_FUNC_CODE[FUNCS[int(arg)]], a, is_const=const[a]))
        roots.append(stack[-1])
    # the state, the constants, the rest (a constant row reads constant rows only)
    order = (list(range(nstate)) + [i for i in range(nstate, len(rows)) if const[i]]
             + [i for i in range(nstate, len(rows)) if not const[i]])
    new = {old: k for k, old in enumerate(order)}
    out = [(c, a if c == T_VAR else new.get(a, -1), new.get(b, -1), v)   # a T_VAR's a: a slot
           for c, a, b, v in (rows[i] for i in order)]
    if not out:
        out.append((T_CONST, -1, -1, 0.0))
    return (np.array([r[:3] for r in out], dtype=np.int64).reshape(-1, 3),
            np.array([r[3] for r in out], dtype=np.float64),
            np.array([new[r] for r in roots], dtype=np.int64))


def _constants(tp, nstate):
    """The number of constant rows, which follow the state's (:func:`tape`)."""
    end = nstate

    def const(r):
        return nstate <= r < end
    while end < tp.shape[0]:
        code, a, b = (int(v) for v in tp[end])
        if not (code in (T_CONST, T_VAR) or (const(a) and (b < 0 or code == T_SCALE
                                                             or const(b)))):
            break
        end += 1
    return end - nstate


@nb.njit(cache=True, inline="always", error_model="numpy")
def _conv(S, a, b, lo, k):
    """sum_{j=lo}^{k-lo} S[a, j] S[b, k - j]."""
    acc = 0.0
    for j in range(lo, k - lo + 1):
        acc += S[a, j] * S[b, k - j]
    return acc


@nb.njit(cache=True, inline="always", error_model="numpy")
def _dconv(S, a, W, b, k):
    """sum_{j=1}^k j S[a, j] W[b, k - j] / k: the k-th coefficient of the primitive of
    a' w."""
    acc = 0.0
    for j in range(1, k + 1):
        acc += j * S[a, j] * W[b, k - j]
    return acc / k


@nb.njit(cache=True, inline="always", error_model="numpy")
def _series(tp, vals, k, S, A, X, u, nstate, lo=0):
    """Coefficient k of the rows lo.. of the tape tp, rows before it known to order k and
    every row to order k - 1; S the series, X the state's series, u the parameters (at
    their slots), vals the constants' values and the exponents.  Inlined in its callers
    (a call per order was a tenth of a step).  A square (a product of a row by itself)
    pairs its terms j, k - j: half the products.  The functions' rows (A: a row's second
    series, the cos of a sin, 1 + t^2 of a tan, ...) in :func:`_series_func`; A is None
    when the tape has none, and :func:`_function_row` then compiles to nothing: the loop
    over polynomial forces runs four times faster without that code."""
    for i in range(lo, tp.shape[0]):
        code = tp[i, 0]
        a = tp[i, 1]
        b = tp[i, 2]
        if code == T_MUL:
            acc = 0.0
            if a == b:
                for j in range((k + 1) // 2):
                    acc += S[a, j] * S[a, k - j]
                acc += acc
                if k % 2 == 0:
                    acc += S[a, k // 2] * S[a, k // 2]
            else:
                for j in range(k + 1):
                    acc += S[a, j] * S[b, k - j]
            S[i, k] = acc
        elif code == T_SCALE:
            S[i, k] = S[b, 0] * S[a, k]
        elif code == T_ADD:
            S[i, k] = S[a, k] + S[b, k]
        elif code == T_VAR:
            if a < nstate:
                S[i, k] = X[a, k]
            else:
                S[i, k] = u[a] if k == 0 else 0.0
        elif code == T_CONST:
            S[i, k] = vals[i] if k == 0 else 0.0
        else:
            _function_row(code, i, a, k, S, A, vals[i])


def _function_row(code, i, a, k, S, A, e):
    """:func:`_series_func`, or nothing when A is None (a tape with no functions): chosen
    by A's type when compiled (:func:`_function_row_impl`), so the functions' code is not
    in the inlined loop of a polynomial tape."""


@overload(_function_row, inline="always")
def _function_row_impl(code, i, a, k, S, A, e):
    if isinstance(A, types.NoneType):
        return lambda code, i, a, k, S, A, e: None
    return lambda code, i, a, k, S, A, e: _series_func(code, i, a, k, S, A, e)


@nb.njit(cache=True, error_model="numpy")
def _series_func(code, i, a, k, S, A, e):
    """Coefficient k of row i of the tape, a function of row a (e: a real power's
    exponent)."""
    if code == T_INV:                         # q p = 1
        if k == 0:
            S[i, 0] = 1.0 / S[a, 0]
        else:
            acc = 0.0
            for j in range(1, k + 1):
                acc += S[a, j] * S[i, k - j]
            S[i, k] = -acc / S[a, 0]
    elif code == T_POWC:                      # a q' = e a' q
        if k == 0:
            a0 = S[a, 0]
            S[i, 0] = a0 ** e if a0 > 0.0 else (0.0 if a0 == 0.0 and e > 0.0 else math.nan)
        else:
            acc = 0.0
            for j in range(1, k + 1):
                acc += ((e + 1.0) * j - k) * S[a, j] * S[i, k - j]
            S[i, k] = acc / (k * S[a, 0])
    elif code == T_EXP:                       # q' = a' q
        S[i, k] = math.exp(S[a, 0]) if k == 0 else _dconv(S, a, S, i, k)
    elif code == T_LOG:                       # a q' = a'
        if k == 0:
            S[i, 0] = math.log(S[a, 0]) if S[a, 0] > 0.0 else math.nan
        else:
            acc = 0.0
            for j in range(1, k):
                acc += j * S[i, j] * S[a, k - j]
            S[i, k] = (S[a, k] - acc / k) / S[a, 0]
    elif code == T_SIN or code == T_COS or code == T_SINH or code == T_COSH:
        # (s, c)' = a' (c, -+s); S holds the function, A its partner
        hyp = code == T_SINH or code == T_COSH
        first = code == T_SIN or code == T_SINH
        if k == 0:
            x = S[a, 0]
            s0 = math.sinh(x) if hyp else math.sin(x)
            c0 = math.cosh(x) if hyp else math.cos(x)
            S[i, 0] = s0 if first else c0
            A[i, 0] = c0 if first else s0
        else:
            sk = 0.0
            ck = 0.0
            for j in range(1, k + 1):
                s_ = S[i, k - j] if first else A[i, k - j]
                c_ = A[i, k - j] if first else S[i, k - j]
                sk += j * S[a, j] * c_
                ck += j * S[a, j] * s_
            sk /= k
            ck = ck / k if hyp else -ck / k
            S[i, k] = sk if first else ck
            A[i, k] = ck if first else sk
    elif code == T_TAN or code == T_TANH:     # q' = a' w, w = 1 +- q^2
        sgn = 1.0 if code == T_TAN else -1.0
        if k == 0:
            S[i, 0] = math.tan(S[a, 0]) if code == T_TAN else math.tanh(S[a, 0])
            A[i, 0] = 1.0 + sgn * S[i, 0] * S[i, 0]
        else:
            S[i, k] = _dconv(S, a, A, i, k)
            A[i, k] = sgn * _conv(S, i, i, 0, k)
    elif code == T_SQRT:                      # q^2 = a
        if k == 0:
            S[i, 0] = math.sqrt(S[a, 0]) if S[a, 0] >= 0.0 else math.nan
        else:
            S[i, k] = (S[a, k] - _conv(S, i, i, 1, k)) / (2.0 * S[i, 0])
    else:                                     # atan: w q' = a', w = 1 + a^2
        A[i, k] = 1.0 + S[a, 0] * S[a, 0] if k == 0 else _conv(S, a, a, 0, k)
        if k == 0:
            S[i, 0] = math.atan(S[a, 0])
        else:
            acc = 0.0
            for j in range(1, k):
                acc += j * S[i, j] * A[i, k - j]
            S[i, k] = (k * S[a, k] - acc) / (k * A[i, 0])


@nb.njit(cache=True, inline="always", error_model="numpy")
def _prepare(sy, tj):
    """The linear part as one map, once a flight: Q = M^-1 (K | C | P | I) (tj's Q, M^-1
    in its last n columns); with a model's own kernel also the constant rows' coefficient 0
    (the kernel computes the others)."""
    Minv, K, C, P = sy[0], sy[1], sy[2], sy[3]
    Q = tj[7]
    n = P.shape[0]
    if _has_kernel(tj[18]):
        S, X = tj[3], tj[8]
        _series(tj[0], tj[1], 0, S, tj[4], X, sy[6], 2 * n, 2 * n)
    for i in range(n):
        for j in range(n):
            Q[i, 2 * n + 1 + j] = Minv[i, j]
        for j in range(n):
            ak = 0.0
            ac = 0.0
            for m in range(n):
                ak += Minv[i, m] * K[m, j]
                ac += Minv[i, m] * C[m, j]
            Q[i, j] = ak
            Q[i, n + j] = ac
        ap = 0.0
        for m in range(n):
            ap += Minv[i, m] * P[m]
        Q[i, 2 * n] = ap


def _has_kernel(kern):
    """Whether the work has a model's own kernel (:mod:`symvi.flow.taylor_kernel`): kern's
    type, known when compiled."""


@overload(_has_kernel, inline="always")
def _has_kernel_impl(kern):
    none = isinstance(kern, types.NoneType)
    return lambda kern: not none


def _series_of(kern, ad, w, tau, sy, tj, t, y, X):
    """X[:, 0..p] <- the Taylor coefficients of the solution through (t, y): by the model's
    own kernel when the work has one (kern, ad: the work's last two entries; w, tau: the
    forcing's; all taken out of the tuples once a flight, as each array taken out costs a
    reference count), else by :func:`_coefficients`.  Chosen by kern's type when
    compiled, so each compiled flight holds one of the two: with both, the kernel's path
    paid the interpreter's reference counts (a run at 1.45e5 impacts a second against
    1.8e5)."""


@overload(_series_of, inline="always")
def _series_of_impl(kern, ad, w, tau, sy, tj, t, y, X):
    if isinstance(kern, types.NoneType):
        return lambda kern, ad, w, tau, sy, tj, t, y, X: _coefficients(sy, tj, t, y, X)

    def own(kern, ad, w, tau, sy, tj, t, y, X):
        for i in range(y.shape[0]):
            X[i, 0] = y[i]
        kern(ad[0], ad[1], ad[2], ad[3], ad[4], ad[5], ad[6], w, t, tau)
    return own


@nb.njit(cache=True, inline="always", error_model="numpy")
def _coefficients(sy, tj, t, y, X):
    """X[:, 0..p] <- the Taylor coefficients of the solution through (t, y) (module
    docstring), p = X.shape[1] - 1, by interpreting the tape; the linear part Q of
    :func:`_prepare`."""
    Minv = sy[0]
    u, w, tau = sy[6], sy[8][0], sy[9][0]
    tp, vals, roots, S, A, sn, cs, Q = tj[0], tj[1], tj[2], tj[3], tj[4], tj[5], tj[6], tj[7]
    dim = y.shape[0]
    n = dim // 2
    p = X.shape[1] - 1
    L = tp.shape[0] if roots.shape[0] > 0 else 0
    nf = n if L > 0 else 0
    first, inv = tj[16], tj[17]
    for i in range(dim):
        X[i, 0] = y[i]
    sn[0] = math.sin(w * t + tau)
    cs[0] = math.cos(w * t + tau)
    for k in range(p):
        if k > 0:
            sn[k] = w * cs[k - 1] * inv[k]
            cs[k] = -w * sn[k - 1] * inv[k]
        # X is S's first rows; the constant rows have a coefficient at k = 0 only
        if L:
            _series(tp, vals, k, S, A, X, u, dim, dim if k == 0 else first)
        if n == 1:                      # one mass: no loops over n (a quarter of the time)
            acc = Q[0, 2] * sn[k] - Q[0, 0] * X[0, k] - Q[0, 1] * X[1, k]
            if nf:
                acc -= Minv[0, 0] * S[roots[0], k]
            X[1, k + 1] = acc * inv[k + 1]
            X[0, k + 1] = X[1, k] * inv[k + 1]
        else:
            for i in range(n):
                X[n + i, k + 1] = _acceleration(Q, Minv, X, S, roots, sn, k, i, nf) * inv[k + 1]
                X[i, k + 1] = X[n + i, k] * inv[k + 1]


@nb.njit(cache=True, inline="always", error_model="numpy")
def _acceleration(Q, Minv, X, S, roots, sn, k, i, nf):
    """Coefficient k of mass i's acceleration M^-1 (P s - C v - K x - f) (module
    docstring), from Q = M^-1 (K | C | P | I) of :func:`_prepare`, the state's coefficients X
    and the forces' rows of S (nf: 0 without forces)."""
    dim = X.shape[0]
    acc = Q[i, dim] * sn[k]
    for j in range(dim):
        acc -= Q[i, j] * X[j, k]
    for j in range(nf):
        acc -= Minv[i, j] * S[roots[j], k]
    return acc


@nb.njit(cache=True, error_model="numpy")
def _jorba_zou_h(X, hmax):
    """Jorba & Zou's step from the last two coefficients (module docstring), at most hmax."""
    p = X.shape[1] - 1
    rho = 1.0
    n1 = 0.0
    n2 = 0.0
    for i in range(X.shape[0]):
        rho = max(rho, abs(X[i, 0]))
        n1 = max(n1, abs(X[i, p - 1]))
        n2 = max(n2, abs(X[i, p]))
    # the two roots and the factor by one exp (a power is a log and an exp)
    lt = math.log(TOL * rho)
    e = math.inf
    if n1 > 0.0:
        e = (lt - math.log(n1)) / (p - 1)
    if n2 > 0.0:
        e = min(e, (lt - math.log(n2)) / p)
    return min(hmax, math.exp(e - 0.7 / (p - 1)))


@nb.njit(cache=True, error_model="numpy")
def _at(X, h, out, dout):
    """out = y(t_n + h) and dout = y'(t_n + h) from the coefficients X; dout None: the
    value only (a step's end).  The value by Horner in h^2 on the even and the odd
    coefficients, y = E(h^2) + h O(h^2): two chains of p/2 products instead of one of p
    (the chain's latency was a tenth of a step), the derivative by Horner."""
    p = X.shape[1] - 1
    h2 = h * h
    top = p - (p % 2)                        # the highest even power
    for i in range(X.shape[0]):
        e = X[i, top]
        k = top - 2
        while k >= 0:
            e = e * h2 + X[i, k]
            k -= 2
        o = X[i, top - 1] if top == p else X[i, p]
        k = top - 3 if top == p else p - 2
        while k >= 1:
            o = o * h2 + X[i, k]
            k -= 2
        out[i] = e + h * o
    if dout is not None:
        for i in range(X.shape[0]):
            dacc = p * X[i, p]
            for k in range(p - 1, 0, -1):
                dacc = dacc * h + k * X[i, k]
            dout[i] = dacc


@nb.njit(cache=True, error_model="numpy")
def _poly(g, th):
    """(g(th), g'(th)) of the monomial coefficients g (Horner)."""
    p = g.shape[0] - 1
    v = g[p]
    d = 0.0
    for k in range(p - 1, -1, -1):
        d = d * th + v
        v = v * th + g[k]
    return v, d


@nb.njit(cache=True, error_model="numpy")
def _refine(g, lo, hi, scale):
    """The root of g in (lo, hi], g(lo) < 0 <= g(hi): Newton, kept in the bracket by
    bisection, to 4e-16 scale in theta."""
    glo, _ = _poly(g, lo)
    ghi, _ = _poly(g, hi)
    th = lo - glo * (hi - lo) / (ghi - glo) if ghi != glo else 0.5 * (lo + hi)
    for _ in range(60):
        v, d = _poly(g, th)
        if v == 0.0:
            return th
        if v < 0.0:
            lo = th
        else:
            hi = th
        nt = th - v / d if d != 0.0 else 0.5 * (lo + hi)
        if not (lo < nt < hi):
            nt = 0.5 * (lo + hi)
        if abs(nt - th) <= 4e-16 * scale or hi - lo <= 4e-16 * scale:
            return nt
        th = nt
    return th


@nb.njit(cache=True, error_model="numpy")
def _guard_coeffs(X, normals, c, gap, sign, h, g, mass=-1):
    """g[k] = sign (c . x_k) h^k, less sign gap at k = 0: the guard's polynomial in theta;
    returns its bound on [0, 1], g_0 + sum_k max(g_k, 0) (below 0: no contact), summed in
    the same pass.  ``mass`` >= 0: c is that mass's unit vector (a stop on it: the
    coefficients read without the product)."""
    n = normals.shape[1]
    hk = 1.0
    ub = 0.0
    for k in range(g.shape[0]):
        if mass >= 0:
            acc = X[mass, k]
        else:
            acc = 0.0
            for i in range(n):
                if normals[c, i] != 0.0:
                    acc += normals[c, i] * X[i, k]
        g[k] = sign * acc * hk
        ub += max(g[k], 0.0)
        hk *= h
    ub -= max(g[0], 0.0)
    g[0] -= sign * gap
    return ub + g[0]


@nb.njit(cache=True, error_model="numpy")
def _taylor_flight(sy, tj, cons, normals, z, just_hit, t_max, hmax):
    """Integrate from z (mass order, time 0) to the first contact of any constraint, or
    t_max.  On an impact z is the state just before it.  Returns (status, t_e, constraint,
    approach speed, h'' at the contact, steps).

    cons: one row per constraint (mass index or -1, gap, sign); normals: its c (mass
    order; a mass index >= 0 says c is that mass's unit vector)."""
    X, g, b, stackb, lo_hi, br, ye, yd = tj[8], tj[9], tj[10], tj[11], tj[12], tj[13], \
        tj[14], tj[15]
    dim = z.shape[0]
    n = dim // 2
    m = cons.shape[0]
    p = X.shape[1] - 1
    _prepare(sy, tj)
    kern, ad, w, tau = tj[18], tj[19], sy[8][0], sy[9][0]
    for i in range(dim):
        ye[i] = z[i]
    t = 0.0
    steps = 0
    first = True
    while steps < MAX_STEPS:
        if t >= t_max:
            return cf.NO_IMPACT, t, -1, 0.0, 0.0, steps
        _series_of(kern, ad, w, tau, sy, tj, t, ye, X)
        h = _jorba_zou_h(X, hmax)
        steps += 1
        if not (math.isfinite(h) and h > 0.0):
            return cf.NO_IMPACT, t, -2, 0.0, 0.0, steps
        best = 2.0
        bc = -1
        for c in range(m):
            ub = _guard_coeffs(X, normals, c, cons[c, 1], cons[c, 2], h, g, int(cons[c, 0]))
            if first and c == just_hit:
                for k in range(p):              # the guard starts at 0: look at g / theta
                    g[k] = g[k + 1]
                g[p] = 0.0
                ub = g[0]
                for k in range(1, p + 1):
                    ub += max(g[k], 0.0)
            if not math.isfinite(ub):
                return cf.NO_IMPACT, t, -2, 0.0, 0.0, steps
            if ub < 0.0:                        # below 0 on [0, 1]: no contact
                continue
            _bernstein(g, b)
            st = _first_bracket(b, stackb, lo_hi, br)
            if st == 0 or br[0] >= best:
                continue
            if st == 1:
                th = br[0]
            elif st == 2:
                th = _refine(g, br[0], br[1], 1.0 + t / h)
            else:
                th = 0.5 * (br[0] + br[1])
            if th < best:
                best = th
                bc = c
        if bc >= 0:
            te = best * h
            _at(X, te, z, yd)
            vm = 0.0
            acc = 0.0
            for i in range(n):
                vm += normals[bc, i] * z[n + i]
                acc += normals[bc, i] * yd[n + i]
            s = cons[bc, 2]
            return cf.IMPACT, t + te, bc, s * vm, s * acc, steps
        _at(X, h, ye, None)
        t += h
        first = False
    return cf.NO_IMPACT, t, -2, 0.0, 0.0, steps


@nb.njit(cache=True, error_model="numpy")
def _taylor_integrate(sy, tj, z, t_end, hmax):
    """z(t_end) by the steps of :func:`_taylor_flight`, the last one cut to end there."""
    X, ye, yd = tj[8], tj[14], tj[15]
    _prepare(sy, tj)
    kern, ad, w, tau = tj[18], tj[19], sy[8][0], sy[9][0]
    for i in range(z.shape[0]):
        ye[i] = z[i]
    t = 0.0
    while t < t_end:
        _series_of(kern, ad, w, tau, sy, tj, t, ye, X)
        h = min(_jorba_zou_h(X, hmax), t_end - t)
        _at(X, h, ye, None)
        t = t + h if t_end - t > h else t_end
    return ye.copy()


def _reciprocals(q):
    """[0, 1, 1/2, ..., 1/(q - 1)]: the recurrences multiply by 1/k (a division on the
    linear recurrence's critical path cost a third of its time)."""
    inv = np.zeros(q)
    inv[1:] = 1.0 / np.arange(1.0, q)
    return inv


def work(tape_, values, roots, dim, order=FLOW_ORDER, kernel=None):
    """The tape (:func:`tape`) and the scratch of the Taylor kernels: (tape, values, roots,
    S, A (None without functions), sin and cos series, Q, X (S's first rows), g, Bernstein
    b, its stack, bracket, y, y', the first row past the constants, 1 / k, the model's
    own kernel or None (:mod:`symvi.flow.taylor_kernel`), the addresses of S, the sin and
    cos series, Q and 1 / k for it)."""
    L = tape_.shape[0]
    q = order + 1
    A = np.zeros((L, q)) if (tape_[:, 0] >= T_INV).any() else None
    S = np.zeros((L, q))
    sn, cs, Q, inv = np.empty(q), np.empty(q), np.empty((dim // 2, dim + 1 + dim // 2)), \
        _reciprocals(q)
    # the kernel's arrays by address, read once here: the kernels pass them on with no
    # reference counting (a tenth of a step)
    ad = np.array([a.ctypes.data for a in (S, sn, cs, Q, inv)] + [L, q], dtype=np.int64)
    return (tape_, values, roots, S, A, sn, cs, Q, S[:dim], np.empty(q), np.empty(q),
            np.empty((96, q)), np.empty((96, 2)), np.empty(2), np.empty(dim), np.empty(dim),
            dim + _constants(tape_, dim), inv, kernel, ad)
