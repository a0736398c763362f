"""The forces of a model as a postfix program, and its pointwise interpreter (issue 28).

:func:`program` compiles the forces f(x, v) (SymPy expressions over x1..xN, v1..vN and the
named parameters) once per model into a short postfix program; :func:`_eval` interprets
it at a point (the field of :mod:`symvi.flow.nonlinear`'s DOP853) and
:mod:`symvi.flow.taylor` on univariate Taylor series.  No code is generated or compiled per
model, and ``x**3`` at x = 0 is 0 (integer powers are products).
"""
import math

import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from ..errors import ParameterError

OP_CONST, OP_VAR, OP_ADD, OP_MUL, OP_POWI, OP_POW, OP_FUNC = range(7)
FUNCS = ("sin", "cos", "tan", "exp", "log", "sqrt", "sinh", "cosh", "tanh", "atan")
#: the deepest stack a program may need
MAX_STACK = 64


def program(exprs, names):
    """(ops (L, 2), offsets (N + 1,), stack depth): the postfix program of the forces
    ``exprs`` (SymPy) over the variables ``names`` (x1..xN, v1..vN, the parameters; a
    variable's index in ``names`` is its slot)."""
    import sympy
    index = {s: i for i, s in enumerate(names)}
    ops, offsets = [], [0]
    depth = [0, 0]

    def push(op, arg, change):
        ops.append((float(op), float(arg)))
        depth[0] += change
        depth[1] = max(depth[1], depth[0])

    def emit(e):
        if isinstance(e, sympy.Symbol):
            push(OP_VAR, index[e.name], 1)
        elif e.is_Number or isinstance(e, sympy.NumberSymbol):
            push(OP_CONST, float(e), 1)
        elif isinstance(e, (sympy.Add, sympy.Mul)):
            for a in e.args:
                emit(a)
            push(OP_ADD if isinstance(e, sympy.Add) else OP_MUL, len(e.args), 1 - len(e.args))
        elif isinstance(e, sympy.Pow):
            emit(e.base)
            if e.exp.is_Integer:
                push(OP_POWI, int(e.exp), 0)
            elif e.exp == sympy.Rational(1, 2):
                push(OP_FUNC, FUNCS.index("sqrt"), 0)
            else:
                emit(e.exp)
                push(OP_POW, 0, -1)
        elif isinstance(e, sympy.Function) and type(e).__name__ in FUNCS and len(e.args) == 1:
            emit(e.args[0])
            push(OP_FUNC, FUNCS.index(type(e).__name__), 0)
        else:
            raise ParameterError("nonlinear", str(e), "a smooth elementary expression",
                                 f"{type(e).__name__} cannot be evaluated")

    for e in exprs:
        emit(sympy.Integer(e) if isinstance(e, int) else e)
        depth[0] = 0
        offsets.append(len(ops))
    if depth[1] > MAX_STACK:
        raise ParameterError("nonlinear", f"nesting {depth[1]}", f"at most {MAX_STACK} "
                             "nested operations")
    return (np.array(ops, dtype=np.float64).reshape(-1, 2),
            np.array(offsets, dtype=np.int64), depth[1])


@nb.njit(cache=True)
def _func(k, a):
    if k == 0:
        return math.sin(a)
    if k == 1:
        return math.cos(a)
    if k == 2:
        return math.tan(a)
    if k == 3:
        return math.exp(a)
    if k == 4:
        return math.log(a) if a > 0.0 else math.nan
    if k == 5:
        return math.sqrt(a) if a >= 0.0 else math.nan
    if k == 6:
        return math.sinh(a)
    if k == 7:
        return math.cosh(a)
    if k == 8:
        return math.tanh(a)
    return math.atan(a)


@nb.njit(cache=True)
def _eval(ops, lo, hi, u, stack):
    """One force: the postfix program ops[lo:hi] at the variables u."""
    sp = 0
    for i in range(lo, hi):
        op = int(ops[i, 0])
        arg = ops[i, 1]
        if op == OP_CONST:
            stack[sp] = arg
            sp += 1
        elif op == OP_VAR:
            stack[sp] = u[int(arg)]
            sp += 1
        elif op == OP_ADD or op == OP_MUL:
            m = int(arg)
            acc = stack[sp - m]
            for j in range(sp - m + 1, sp):
                acc = acc + stack[j] if op == OP_ADD else acc * stack[j]
            sp -= m
            stack[sp] = acc
            sp += 1
        elif op == OP_POWI:
            m = int(arg)
            b = stack[sp - 1]
            p = 1.0
            for _ in range(abs(m)):
                p *= b
            stack[sp - 1] = p if m >= 0 else 1.0 / p
        elif op == OP_POW:
            e = stack[sp - 1]
            sp -= 1
            b = stack[sp - 1]
            stack[sp - 1] = b ** e if b > 0.0 or e == int(e) else math.nan
        else:
            stack[sp - 1] = _func(int(arg), stack[sp - 1])
    return stack[0]
