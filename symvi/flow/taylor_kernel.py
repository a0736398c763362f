"""A model's own Taylor kernel: its tape as straight-line code, compiled once a process.

:func:`symvi.flow.taylor._coefficients` interprets the forces' tape (one loop over the
tape's rows at every order, a branch on each row's code).  For a long run that dispatch is
a third of a step: on the impact Duffing oscillator (order 28) the interpreted series take
554 ns a step, the same recurrences written out for its tape 337 ns, and a run goes from
1.34e5 to 2.04e5 impacts a second (``benchmarks/bench_nonlinear_flow.py``).  :func:`kernel`
writes the recurrences of :mod:`symvi.flow.taylor` (module docstring: x_{k+1} = v_k /
(k + 1), v_{k+1} = M^-1 (P s_k - C v_k - K x_k - f_k) / (k + 1), f_k by the tape's rows) as
Python source with the rows' indices fixed, and compiles it with numba as a C callback:
the cached kernels call it through a function pointer (``tj``'s last entries,
:func:`symvi.flow.taylor.work`), so they are compiled once for every model and only this
function is compiled per model (0.6 to 1 s, so :class:`symvi.flow.nonlinear.NonlinearFlow`
takes it for long runs only: :func:`for_run`).

The source is machine-written from the tape and deterministic: the same tape gives the same
text.  Only polynomial tapes are written (sums, products, squares, scalings, constants and
parameters); a tape with functions (exp, sin, powers with real exponents, ...) has no
kernel and stays interpreted.  The arithmetic is the interpreter's, term for term and in the
same order, so both give the same coefficients to the last bit (a test checks it).
"""
import hashlib
import math
import threading

import numpy as np
from numba import cfunc, types
from numba.extending import intrinsic

from .taylor import T_ADD, T_CONST, T_MUL, T_SCALE, T_VAR, _constants

#: the C signature of a kernel: (S, sin series, cos series, Q, 1/k) as addresses of
#: float64 arrays, S's shape (L, q) (:func:`symvi.flow.taylor.work`), (omega, t, tau)
SIGNATURE = types.void(*([types.int64] * 7), types.float64, types.float64, types.float64)
_POLY = (T_CONST, T_VAR, T_ADD, T_MUL, T_SCALE)
#: impacts a process runs on one tape, interpreted, before it compiles the tape's kernel
#: (:func:`for_run`): the compiler takes 0.6 to 1 s and the kernel saves ~2.6 us an
#: impact (7.5 against 4.9, ``benchmarks/bench_nonlinear_flow.py``), so a run this long
#: takes about as long either way and every later run of the process gains
KERNEL_IMPACTS = 250_000
_CACHE = {}                 # tape -> its kernel (None: a tape with functions)
_RAN = {}                   # tape -> impacts run interpreted
_LOCK = threading.RLock()


@intrinsic
def _as_ptr(typingctx, addr):
    """A float64 pointer from an array's address (what ``a.ctypes.data`` gives)."""
    sig = types.CPointer(types.float64)(types.int64)

    def codegen(context, builder, signature, args):
        return builder.inttoptr(args[0], context.get_value_type(signature.return_type))
    return sig, codegen


def source(tape, roots, dim):
    """The kernel's Python source for this tape (:func:`symvi.flow.taylor.tape`), or None
    when the tape has a function's row."""
    codes = tape[:, 0]
    if not np.isin(codes, _POLY).all():
        return None
    n = dim // 2
    L = tape.shape[0]
    first = dim + _constants(tape, dim)
    lines = ["def kernel(S_, sn_, cs_, Q_, inv_, L, q, w, t, tau):",
             "    S = carray(_as_ptr(S_), (L, q))",
             "    sn = carray(_as_ptr(sn_), (q,))",
             "    cs = carray(_as_ptr(cs_), (q,))",
             f"    Q = carray(_as_ptr(Q_), ({n}, {dim + 1 + n}))",
             "    inv = carray(_as_ptr(inv_), (q,))",
             "    p = q - 1",
             "    sn[0] = math.sin(w * t + tau)",
             "    cs[0] = math.cos(w * t + tau)"]
    # S[:, 0] holds the state and the constant rows' values (symvi.flow.taylor._prepare);
    # the linear part's entries (Q = M^-1 (K | C | P | I)) and the constants as locals: the
    # stores into S could alias them, so read in the loop they would be loaded at every order
    lines += [f"    q{i}_{j} = Q[{i}, {j}]" for i in range(n) for j in range(dim + 1 + n)]
    lines += [f"    c{i} = S[{i}, 0]" for i in range(dim, first)]
    lines += ["    for k in range(p):",
              "        if k > 0:",
              "            sn[k] = w * cs[k - 1] * inv[k]",
              "            cs[k] = -w * sn[k - 1] * inv[k]"]
    for i in range(first, L):
        lines += _row(tape, i, "k", "        ")
    forces = [int(r) for r in roots] if len(roots) else []
    for i in range(n):                          # the linear part, the interpreter's order
        terms = [f"q{i}_{dim} * sn[k]"] + [f" - q{i}_{j} * S[{j}, k]" for j in range(dim)]
        if forces:
            terms += [f" - q{i}_{dim + 1 + j} * S[{forces[j]}, k]" for j in range(n)]
        lines += [f"        acc = {''.join(terms)}",
                  f"        S[{n + i}, k + 1] = acc * inv[k + 1]",
                  f"        S[{i}, k + 1] = S[{n + i}, k] * inv[k + 1]"]
    return "\n".join(lines) + "\n"


def _row(tape, i, k, pad):
    """Row i's coefficient k as the interpreter computes it
    (:func:`symvi.flow.taylor._series`)."""
    code, a, b = (int(v) for v in tape[i])
    head = [pad + "# row %d" % i]
    if code == T_ADD:
        return head + [f"{pad}S[{i}, {k}] = S[{a}, {k}] + S[{b}, {k}]"]
    if code == T_SCALE:                         # by a constant row (a local)
        return head + [f"{pad}S[{i}, {k}] = c{b} * S[{a}, {k}]"]
    if a == b:                                  # a square: the pairs j, k - j once
        return head + [f"{pad}acc = 0.0",
                       f"{pad}for j in range(({k} + 1) // 2):",
                       f"{pad}    acc += S[{a}, j] * S[{a}, {k} - j]",
                       f"{pad}acc += acc",
                       f"{pad}if {k} % 2 == 0:",
                       f"{pad}    acc += S[{a}, {k} // 2] * S[{a}, {k} // 2]",
                       f"{pad}S[{i}, {k}] = acc"]
    return head + [f"{pad}acc = 0.0",
                   f"{pad}for j in range({k} + 1):",
                   f"{pad}    acc += S[{a}, j] * S[{b}, {k} - j]",
                   f"{pad}S[{i}, {k}] = acc"]


def for_run(tape, roots, dim, planned):
    """The tape's kernel for a run of ``planned`` impacts, or None (the tape stays
    interpreted): compiled once the process has run KERNEL_IMPACTS impacts of flights on
    this tape, counting this run (:func:`ran` counts them), so a long run or a sweep of
    short ones takes it and a short run does not wait for the compiler."""
    key = _key(tape, roots, dim)
    with _LOCK:
        done = _CACHE.get(key, False)
        if done is not False:
            return done
        if _RAN.get(key, 0) + planned < KERNEL_IMPACTS:
            return None
    return kernel(tape, roots, dim)


def ran(tape, roots, dim, impacts):
    """Count ``impacts`` run on this tape by the interpreter (:func:`for_run`)."""
    key = _key(tape, roots, dim)
    with _LOCK:
        _RAN[key] = _RAN.get(key, 0) + int(impacts)


def _key(tape, roots, dim):
    return tape.tobytes(), np.asarray(roots).tobytes(), dim


def kernel(tape, roots, dim):
    """The compiled kernel of this tape (a numba C callback, :data:`SIGNATURE`), or None
    for a tape with functions; compiled once a process for each tape."""
    key = _key(tape, roots, dim)
    with _LOCK:
        if key not in _CACHE:
            text = source(tape, roots, dim)
            if text is None:
                _CACHE[key] = None
            else:
                from numba import carray
                env = {"math": math, "carray": carray, "_as_ptr": _as_ptr}
                name = hashlib.sha256(text.encode()).hexdigest()[:12]
                exec(compile(text, f"<symvi taylor kernel {name}>", "exec"), env)
                _CACHE[key] = cfunc(SIGNATURE, error_model="numpy")(env["kernel"])
        return _CACHE[key]
