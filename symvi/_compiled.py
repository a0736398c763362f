"""Compiled (numba) evaluators of the generated jets, eqs. (33)–(38).

A kernel is the machine-written ``f64`` of ``generated/order<K>.py`` compiled
as it is, with its ``_jet`` body compiled too: no second copy of the
expressions exists.  ``cache=True`` keeps the machine code on disk (beside
the generated module, or in numba's user cache when that is read-only); it is
invalidated when ``symvi regenerate`` rewrites the module.  Order K is
imported and compiled only when first asked for.
"""
import importlib
import types

import numba as nb

_KERNELS = {}


def f64_kernel(order):
    """The numba-compiled ``f64(inp) -> flat tuple`` of generated order ``order``."""
    if order not in _KERNELS:
        mod = importlib.import_module(f"symvi._generated.order{order}")
        # f64 calls _jet(inp, math.sin, math.cos, Q_F64); let it call the compiled body
        env = dict(vars(mod), _jet=nb.njit(cache=True)(mod._jet))
        f64 = types.FunctionType(mod.f64.__code__, env, "f64")
        _KERNELS[order] = nb.njit(cache=True)(f64)
    return _KERNELS[order]
