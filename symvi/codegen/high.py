"""Jets of the impact map to order 4 or 5, eqs. (33)–(38) generalised: the state
derivatives the second Lyapunov coefficient l2 needs at Chenciner points (issue 13).

Raw derivatives in the section's variable order (:class:`symvi.maps.Section`),
not divided by factorials, full symmetric tensors:

* ``jacobian[i, j] = dP_i/dy_j``, ``d2[i, j, k]``, ``d3[i, j, k, l]`` as in
  :mod:`symvi.codegen.jets`,
* ``d4[i, j, k, l, m] = d^4 P_i / dy_j dy_k dy_l dy_m`` and ``d5`` likewise.

No parameter derivatives: the modules ``impact_n<N>_order4/5`` carry none.
This module is their only importer, so no other job pays for loading them.
"""
from dataclasses import dataclass

import mpmath
import numpy as np

from ..errors import ParameterError
from .jets import _at, _check_grazing, _checked, evaluate


@dataclass(frozen=True)
class HighJet:
    """Jet of P to order 4 or 5 at a section point, see the module docstring.

    Arrays are float64, or object arrays of mpf when ``digits`` is set;
    ``d5`` is None at order 4.  ``theta1 = dtheta/dy`` (eq. (37)) and
    ``g_theta = dg/dtheta`` (eq. (27)) as in :class:`symvi.codegen.jets.Jet`.
    """

    jacobian: np.ndarray
    d2: np.ndarray
    d3: np.ndarray
    d4: np.ndarray
    d5: np.ndarray
    theta1: np.ndarray
    g_theta: object
    digits: object = None


def high_jet(model, omega, y, te, *, order=5, digits=None):
    """The jet of P up to ``order`` (4 or 5) at y (flight time te), eqs. (33)–(38).

    The jet assumes g(y, te) = 0 (eq. (27)): with ``digits``, pass te to that
    precision (a float64 2 pi / omega limits d4 to about 1e-14 relative).
    """
    if order not in (4, 5):
        raise ParameterError("order", order, "4 or 5")
    y, te = _checked(model, y, te)
    if digits is None:
        flow, F = _at(model, omega, None)
        return _high(flow, F, tuple(float(v) for v in y), float(te), order, False)
    with mpmath.mp.workdps(digits):
        flow, F = _at(model, omega, digits)
        return _high(flow, F, tuple(mpmath.mpf(v) for v in y), mpmath.mpf(te), order, True)


def _high(flow, F, y, te, order, mp):
    vals = evaluate(flow, F, y, te, order)
    _check_grazing(vals, mp)
    return HighJet(jacobian=vals["J"], d2=vals["d2"], d3=vals["d3"], d4=vals["d4"],
                   d5=vals.get("d5"), theta1=vals["theta1"], g_theta=vals["g_theta"],
                   digits=flow.bk.digits)
