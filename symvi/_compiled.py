"""Compiled (numba) evaluators of the generated jets, eqs. (33)–(38).

A kernel is the machine-written ``f64`` of ``generated/order<K>.py`` compiled
as it is, with its ``_jet`` body compiled too: no second copy of the
expressions exists.  ``cache=True`` keeps the machine code on disk (beside
the generated module, or in numba's user cache when that is read-only); it is
invalidated when ``symvi regenerate`` rewrites the module.  Order K is
imported and compiled only when first asked for.  These serve the published
16-input evaluators of the paper's modal structure (:func:`symvi.jets.compiled`) and
any generated module (:func:`kernel_of`); the analysis itself runs on the compiled
kernels of :mod:`symvi.orbits._shooting` and :mod:`symvi.flow.compiled`.
"""
import importlib
import types

import numba as nb

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

