"""Compiled (numba) evaluators of the generated jets, eqs. (33)–(38).

A kernel is the machine-written ``f64`` of ``generated/order<K>.py`` compiled
as it is, with its ``_jet`` body compiled too: no second copy of the
expressions exists.  ``cache=True`` keeps the machine code on disk (beside
the generated module, or in numba's user cache when that is read-only); it is
invalidated when ``symvi regenerate`` rewrites the module.  Order K is
imported and compiled only when first asked for.
"""
import hashlib
import importlib
import math
import types

import numba as nb
import numpy as np

_KERNELS = {}


def f64_kernel(order):
    """The numba-compiled ``f64(inp) -> flat tuple`` of generated order ``order``."""
    return kernel_of(importlib.import_module(f"symvi._generated.order{order}"))


def kernel_of(mod):
    """The numba-compiled ``f64`` of any generated module (``_jet`` compiled as it is)."""
    if mod.__name__ not in _KERNELS:
        # f64 calls _jet(inp, math.sin, math.cos, Q_F64); let it call the compiled body
        env = dict(vars(mod), _jet=nb.njit(cache=True)(mod._jet))
        f64 = types.FunctionType(mod.f64.__code__, env, "f64")
        _KERNELS[mod.__name__] = nb.njit(cache=True)(f64)
    return _KERNELS[mod.__name__]


# --------------------------------------------------------------------------- Lyapunov QR loop
_J1 = None            # the order-1 kernel, bound before _qr_logs is first compiled
# Stamp of generated/order1.py, frozen into _qr_logs when it is compiled.  numba's cache
# tracks _qr_logs' own file only, so after `symvi regenerate` a cached _qr_logs could
# still hold the old Jacobian; the stamp it returns exposes that and forces a recompile.
_STAMP = 0

#: the input order _qr_logs assembles; checked against the generated INPUTS
_QR_INPUTS = ('psi11', 'psi12', 'psi21', 'psi22', 'w1', 'w2', 'F1', 'F2', 'omega', 'r', 'b',
              'v1', 'x20', 'x20d', 'tau', 'te')


@nb.njit(cache=True)
def _qr_logs(const, sec, te, jidx):
    """log |R_k[i, i]| of Q_{k+1} R_k = DP(y_k) Q_k along the section (QR method)."""
    m = len(te)
    logs = np.empty((m, 4))
    Q = np.eye(4)
    JQ = np.empty((4, 4))
    for k in range(m):
        y = sec[k]
        flat = _J1((const[0], const[1], const[2], const[3], const[4], const[5], const[6],
                    const[7], const[8], const[9], const[10], y[0], y[1], y[2], y[3], te[k]))
        for i in range(4):
            for j in range(4):
                s = 0.0
                for l in range(4):
                    s += flat[jidx[i, l]] * Q[l, j]
                JQ[i, j] = s
        Q, R = np.linalg.qr(JQ)
        for i in range(4):
            d = R[i, i]
            logs[k, i] = math.log(abs(d))
            if d < 0.0:               # keep Q's columns continuous
                Q[:, i] = -Q[:, i]
    return logs, _STAMP


def qr_logs(const, sec, te):
    """Compiled QR-method logs along a section; ``const`` = the first 11 jet inputs."""
    global _J1, _STAMP
    mod = importlib.import_module("symvi._generated.order1")
    if _J1 is None:
        if tuple(mod.INPUTS) != _QR_INPUTS:
            raise RuntimeError("generated INPUTS changed; update symvi._compiled._QR_INPUTS")
        _J1 = f64_kernel(1)
        with open(mod.__file__, "rb") as f:
            _STAMP = int.from_bytes(hashlib.sha256(f.read()).digest()[:7], "big")
    args = (np.asarray(const, dtype=np.float64), np.ascontiguousarray(sec, dtype=np.float64),
            np.ascontiguousarray(te, dtype=np.float64), np.array(mod.LAYOUT["J"]))
    logs, stamp = _qr_logs(*args)
    if stamp != _STAMP:           # compiled against another generated/order1.py
        _qr_logs.recompile()
        logs, stamp = _qr_logs(*args)
    return logs
