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
    are ``None``.  What :func:`symvi.jet` returns for the paper's :class:`symvi.Params`
    (for a :class:`symvi.Model`, the :class:`symvi.codegen.jets.Jet` itself, the same
    fields without ``orbit`` and the F names).  Indices run over the section variables
    (x1dot+, x20, x20dot, tau) of eq. (9).

    Attributes
    ----------
    omega : float
        The forcing frequency.
    y : tuple
        The fixed point y* the jet is taken at.
    order : int
        The order computed, 1 to 3.
    jacobian : ndarray, shape (4, 4)
        ``jacobian[i, j] = df_i/dy_j`` (F01, eq. (36)); its eigenvalues are the
        multipliers.
    theta1 : ndarray, shape (4,)
        First-order coefficients of the implicit impact-phase correction theta in dy
        (the implicit function theorem of eq. (37)).
    g_theta : float
        Derivative of the impact condition g in theta at the point, eq. (37): zero at
        grazing (refused).
    d2 : ndarray, shape (4, 4, 4) or None
        ``d2[i, j, k] = d^2 f_i/dy_j dy_k`` (order >= 2).
    d3 : ndarray, shape (4, 4, 4, 4) or None
        Third derivatives (order 3).
    dA : ndarray, shape (4, 4) or None
        d/domega of the Jacobian along the orbit branch (F11, eq. (34) with p = q = 1):
        ``dJ_domega + d2 . dy_domega`` (order >= 2).
    dP_domega : ndarray, shape (4,) or None
        Explicit omega-derivative of the map at fixed y (order >= 2).
    dJ_domega : ndarray, shape (4, 4) or None
        Explicit omega-derivative of the Jacobian at fixed y (order >= 2).
    dy_domega : ndarray, shape (4,) or None
        Motion of the fixed point, dy*/domega = (I - J)^-1 dP/domega (order >= 2).
    digits : int or None
        The mpmath precision (None: float64).
    orbit : Orbit
        The period-1 orbit the jet is taken at (the paper's :class:`Orbit`).
    F01 : ndarray
        The paper's name of ``jacobian``, eq. (36).
    F02 : ndarray or None
        ``d2 / 2``: the paper's second-order coefficients.
    F03 : ndarray or None
        ``d3 / 6``: the paper's third-order coefficients.
    F11 : ndarray or None
        The paper's name of ``dA``, eq. (34).

    Examples
    --------
    >>> import numpy as np, symvi
    >>> p = symvi.Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    >>> j = symvi.jet(p, 0.72)
    >>> j.F01.shape, j.F02.shape, j.F03.shape
    ((4, 4), (4, 4, 4), (4, 4, 4, 4))
    >>> print(np.allclose(j.F02, j.d2 / 2), round(float(np.linalg.det(j.F01)), 12))
    True 0.64
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
    ``digits`` selects the mpmath backend at that many digits.  The derivatives are
    evaluated by the generated code of the model's N-mass structure (exact, not finite
    differences); the orbit is the admissible period-1 orbit at omega
    (:func:`symvi.period1_orbits`) unless ``orbit`` is given.

    Parameters
    ----------
    params : Params or Model
        The paper's parameters (a :class:`Jet` with the paper's names), or a
        :class:`symvi.Model` with one rigid upper stop on one mass (a
        :class:`symvi.codegen.jets.Jet`: raw derivatives in its section order).
    omega : float
        Forcing frequency of the orbit, 1e-4 <= omega <= 1e4; not used when ``orbit``
        is given (the orbit's own omega is).
    order : {1, 2, 3}, optional
        Highest order of derivatives computed (default 3).
    digits : int, optional
        Compute with mpmath at this many digits (16 to 10000 for the orbit).  Default
        None: float64; with ``orbit``, the orbit's point is taken at this precision.
    branch : {"+", "-"}, optional
        Which orbit, when both branches are admissible at omega (default None: the one
        admissible orbit).
    orbit : Orbit, optional
        A period-1 orbit computed by :func:`symvi.period1_orbits` (of the same model):
        the jet is taken there, without solving for the orbit again.

    Returns
    -------
    Jet
        The derivatives; unrequested orders are None.

    Raises
    ------
    ParameterError
        ``order`` not 1, 2 or 3, ``branch`` not "+" or "-", an invalid omega or
        ``digits``, or a model with several stops or a lower, elastic or between-masses
        stop.
    SingularCaseError
        ``"no-admissible-orbit"`` (none at omega), ``"two-admissible-orbits"`` (both,
        and no ``branch``), ``"grazing"`` (the impact has zero speed: eq. (30)'s
        implicit function theorem fails), ``"multiplier-one"`` or
        ``"near-singular-map"`` (order >= 2: the fixed point does not move smoothly with
        omega), and those of :func:`symvi.period1_orbits`.

    Examples
    --------
    >>> import symvi
    >>> p = symvi.Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    >>> j = symvi.jet(p, 0.72, order=1)
    >>> j.jacobian.shape, j.d2 is None
    ((4, 4), True)
    >>> o = symvi.period1_orbits(p, 0.72)[0]
    >>> j3 = symvi.jet(p, 0.72, orbit=o)       # at an orbit already computed
    >>> j3.d3.shape
    (4, 4, 4, 4)
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
