"""Taylor jets of the Poincaré map of the paper's model, eqs. (33)–(38).

Since issue 11 :func:`jet` and :func:`jacobian_at` evaluate the generated jets of the
N = 2 structure (:mod:`symvi.codegen.jets`) on ``Model.luo_xie``, the chain of every
model; this module presents them in the paper's terms (:class:`Jet` with F01 … F11).
The paper's own modal evaluators (``generated/order<K>.py``, 16 inputs psi11 … t_e)
stay as a published interface, :func:`jet_inputs` and :func:`compiled`, and as the
independent oracle the tests hold the N = 2 structure to.

The tensors are raw derivatives in the paper's variable order
(dx1dot+, dx20, dx20dot, dtau):

* ``jacobian[i, j] = df_i/dx_j`` (= F01, eq. 36),
* ``d2[i, j, k] = d^2 f_i/dx_j dx_k`` (the paper's F02 = d2 / 2),
* ``d3[i, j, k, l]`` (F03 = d3 / 6),
* ``dA[i, j] = d/dv (df_i/dx_j)`` along the orbit branch v = omega (F11, eq. 34
  with p = q = 1): the explicit omega-derivative plus d2 · dy*/domega, where
  dy*/domega = (I - J)^{-1} dP/domega follows from P(y*(omega); omega) = y*(omega).

Order K imports the generated order K only: a multiplier-only job never imports
second- or third-order code.
"""
import contextlib
import math
from dataclasses import dataclass, fields

import mpmath
import numpy as np

from ..errors import ParameterError, SingularCaseError
from .params import Params, _finite, check_omega
from .params import modal as _modal
from ._eval import _gen, _inputs
from ..codegen.jets import eigenvalues as eigenvalues  # one owner, any size
from ..codegen.jets import Jet as _AnyJet
from ..codegen.jets import jet_at, jet_of_orbit
from ..codegen.jets import jacobian_at as _any_model_jacobian
from ..model import Model
from .orbit import Orbit as _PaperOrbit


def jacobian_at(params, omega, y, t_e, digits=None):
    """DP at a section point y whose flight to the next impact lasts t_e, eqs. (36)–(38).

    Valid at any impact point, not only at the period-1 orbit, so it serves the
    Lyapunov exponents along a simulated orbit.
    """
    return _any_model_jacobian(Model.of(params), omega, y, t_e, digits=digits)


def multipliers_of(params, orbit):
    """Multipliers (eigenvalues of DP, eq. 36) at a period-1 orbit, at its precision."""
    J = jet_of_orbit(Model.of(params), orbit, 1).jacobian
    with mpmath.mp.workdps(orbit.digits) if orbit.digits else contextlib.nullcontext():
        return eigenvalues(J)


def jet_inputs(params, omega, y, t_e):
    """The float64 input tuple of the generated evaluators (order ``INPUTS``) at a section
    point y = (x1dot+, x20, x20dot, tau) whose flight lasts t_e, eqs. (21)–(29)."""
    if not isinstance(params, Params):
        raise ParameterError("params", params, "a symvi.Params")
    omega = check_omega(params, omega, warn=False)
    try:
        y = tuple(y)
    except TypeError:
        raise ParameterError("y", y, "4 finite numbers (x1dot+, x20, x20dot, tau)") from None
    if len(y) != 4:
        raise ParameterError("y", y, "4 finite numbers (x1dot+, x20, x20dot, tau)")
    y = tuple(_finite(f"y[{i}]", v) for i, v in enumerate(y))
    t_e = _finite("t_e", t_e)
    if not t_e > 0:
        raise ParameterError("t_e", t_e, "a flight time > 0")
    return _inputs(_modal(params), omega, params.r, params.b, y, t_e)


@dataclass(frozen=True)
class CompiledJet:
    """A numba-compiled generated evaluator, eqs. (33)–(38).

    ``kernel(inp)`` takes the tuple of :func:`jet_inputs` (16 floats, order
    ``inputs``) and returns the flat tuple the module's ``layout`` indexes
    (``layout["J"][i][j]`` is the position of dP_i/dy_j).  It is a numba
    dispatcher: call it from your own ``numba.njit`` code (no call overhead)
    or from Python (~0.6 µs for order 1); calling the CompiledJet itself
    checks ``inp`` first.  numba's on-disk cache of *your* function tracks your
    file only: after ``symvi regenerate`` clear it (or compile without cache).
    """

    order: int
    kernel: object
    inputs: tuple
    layout: dict

    def __call__(self, inp):
        """``kernel(inp)`` after checking ``inp``: 16 finite numbers in the order ``inputs``."""
        valid = f"a tuple of {len(self.inputs)} finite numbers in the order {self.inputs}"
        try:
            vals = tuple(float(v) for v in inp)
        except (TypeError, ValueError):
            raise ParameterError("inp", inp, valid) from None
        if len(vals) != len(self.inputs) or not all(math.isfinite(v) for v in vals):
            raise ParameterError("inp", inp, valid)
        return self.kernel(vals)


def compiled(order):
    """The numba-compiled float64 evaluator of the generated jet of ``order``, eqs. (33)–(38).

    The kernel is the generated code itself, compiled on first use and cached
    on disk; asking for order 1 never imports or compiles orders 2 and 3.
    """
    if order not in (1, 2, 3):
        raise ParameterError("order", order, "1, 2 or 3")
    from .._compiled import f64_kernel
    mod, _ = _gen(order)
    return CompiledJet(order, f64_kernel(order), tuple(mod.INPUTS), mod.LAYOUT)


@dataclass(frozen=True)
class Jet(_AnyJet):
    """Jet of the Poincaré map f(v, dX) at a period-1 orbit, eqs. (33)–(38).

    A :class:`symvi.codegen.jets.Jet` (raw derivatives in the section order of
    ``Model.luo_xie``) with its orbit and the paper's names F01 … F11.  Arrays are numpy
    float64, or numpy object arrays of mpf when ``digits`` is set.  Unrequested orders
    are ``None``.
    """

    orbit: object = None

    @property
    def F01(self):
        return self.jacobian

    @property
    def F02(self):
        return None if self.d2 is None else self.d2 / 2

    @property
    def F03(self):
        return None if self.d3 is None else self.d3 / 6

    @property
    def F11(self):
        return self.dA


def select_orbit(params, omega, branch=None, digits=None, multipliers=False):
    """The admissible period-1 orbit at omega (``branch`` picks one when both are):
    :func:`symvi.orbits.select_orbit`, in the paper's view for a Params."""
    from ..orbits import select_orbit as select
    o = select(Model.of(params), omega, branch, digits, multipliers)
    return o if isinstance(params, Model) else _PaperOrbit.of(params, o)


def jet(params, omega, order=3, *, digits=None, branch=None, orbit=None):
    """Jet of the Poincaré map at the admissible period-1 orbit, eqs. (33)–(38).

    ``order`` 1 gives the Jacobian only; 2 adds d2, dA (F11), dP/domega; 3 adds d3.
    ``digits`` selects the mpmath backend at that many digits.
    """
    if order not in (1, 2, 3):
        raise ParameterError("order", order, "1, 2 or 3")
    if orbit is None:
        orbit = select_orbit(params, omega, branch, digits)
    model, w = Model.of(params), orbit.omega
    if digits == orbit.digits:            # our own orbit, checked already
        jt = jet_of_orbit(model, orbit, order)
    else:
        with mpmath.mp.workdps(digits) if digits else contextlib.nullcontext():
            T = 2 * (mpmath.pi if digits else math.pi) / w      # at the jet's precision
            jt = jet_at(model, w, orbit.y, T, order, digits=digits)
    if isinstance(params, Model):         # any model: the jet of its N-mass structure
        return jt
    return Jet(**{f.name: getattr(jt, f.name) for f in fields(_AnyJet)}, orbit=orbit)
