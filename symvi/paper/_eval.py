"""Evaluation of the paper's generated modal jets (``generated/order<K>.py``):
loading, the input tuple of eqs. (21)–(29) and the multipliers at a period-1 orbit.

Not on the analysis path (``Params`` runs on the N = 2 structure since issue 11):
it serves the published 16-input evaluators of :mod:`symvi.jets` and the oracle
:mod:`symvi.paper.modal_orbit`.
"""
import importlib

import mpmath
import numpy as np

from ..numerics.backend import backend
from ..codegen.jets import eigenvalues
from .params import modal as _modal


_LOADED = {}


def _gen(order):
    """The generated module of ``order`` and its layout as numpy index arrays (cached)."""
    if order not in _LOADED:
        mod = importlib.import_module(f"symvi._generated.order{order}")
        _LOADED[order] = (mod, [(k, np.asarray(v)) for k, v in mod.LAYOUT.items()])
    return _LOADED[order]


def _inputs(m, omega, r, b, y, te):
    p = m.psi
    return (p[0][0], p[0][1], p[1][0], p[1][1], m.omega1, m.omega2, m.F[0], m.F[1],
            omega, r, b, y[0], y[1], y[2], y[3], te)


def _evaluate(order, inp, mp):
    """Flat generated values -> dict of numpy arrays (object arrays of mpf when ``mp``)."""
    mod, layout = _gen(order)
    if mp:
        vals = mod.mp(inp)
        flat = np.empty(len(vals), dtype=object)
        flat[:] = vals
    else:
        flat = np.array(mod.f64(inp))
    return {name: flat[idx] for name, idx in layout}


def _orbit_inputs(params, orbit):
    lib = backend(orbit.digits)
    m = _modal(params, lib)
    te = 2 * lib.pi / orbit.omega
    return _inputs(m, orbit.omega, lib.num(params.r), lib.num(params.b), orbit.y, te)


def multipliers_of(params, orbit):
    """Multipliers (eigenvalues of DP, eq. 36) at a period-1 orbit."""
    if orbit.digits is None:
        J = _evaluate(1, _orbit_inputs(params, orbit), False)["J"]
        return eigenvalues(J)
    with mpmath.mp.workdps(orbit.digits):
        J = _evaluate(1, _orbit_inputs(params, orbit), True)["J"]
        return eigenvalues(J)
