"""Taylor jets of the Poincaré map from the generated code, eqs. (33)–(38).

The tensors are raw derivatives in the paper's variable order
(dx1dot+, dx20, dx20dot, dtau):

* ``jacobian[i, j] = df_i/dx_j`` (= F01, eq. 36),
* ``d2[i, j, k] = d^2 f_i/dx_j dx_k`` (the paper's F02 = d2 / 2),
* ``d3[i, j, k, l]`` (F03 = d3 / 6),
* ``dA[i, j] = d/dv (df_i/dx_j)`` along the orbit branch v = omega (F11, eq. 34
  with p = q = 1): the explicit omega-derivative plus d2 · dy*/domega, where
  dy*/domega = (I - J)^{-1} dP/domega follows from P(y*(omega); omega) = y*(omega).

Order K imports ``symvi._generated.order<K>`` only: a multiplier-only job never
imports second- or third-order code.
"""
import math
from dataclasses import dataclass

import mpmath
import numpy as np

from ._backend import MP
from .errors import ParameterError, SingularCaseError
from .params import Params, _finite, check_omega
from .params import modal as _modal
from ._paper_eval import _evaluate, _gen, _inputs, _orbit_inputs  # noqa: F401
from ._paper_eval import multipliers_of as multipliers_of
from .codegen.jets import eigenvalues as eigenvalues  # one owner, any size


def jacobian_at(params, omega, y, t_e, digits=None):
    """DP at a section point y whose flight to the next impact lasts t_e, eqs. (36)–(38).

    Valid at any impact point, not only at the period-1 orbit, so it serves the
    Lyapunov exponents along a simulated orbit.
    """
    if digits is None:
        return _evaluate(1, jet_inputs(params, omega, y, t_e), False)["J"]
    with mpmath.mp.workdps(digits):
        inp = _inputs(_modal(params, MP), MP.num(omega), MP.num(params.r), MP.num(params.b),
                      tuple(MP.num(v) for v in y), MP.num(t_e))
        return _evaluate(1, inp, True)["J"]


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
    from ._compiled import f64_kernel
    mod, _ = _gen(order)
    return CompiledJet(order, f64_kernel(order), tuple(mod.INPUTS), mod.LAYOUT)


@dataclass(frozen=True)
class Jet:
    """Jet of the Poincaré map f(v, dX) at a period-1 orbit, eqs. (33)–(38).

    Arrays are numpy float64, or numpy object arrays of mpf when ``digits`` is set.
    Unrequested orders are ``None``.
    """

    orbit: object
    omega: object
    order: int
    jacobian: np.ndarray
    theta1: np.ndarray         # d(dtheta)/dx_i, eq. (37)
    g_theta: object            # dg/d(dtheta) at 0; -> 0 at grazing
    d2: np.ndarray = None
    d3: np.ndarray = None
    dA: np.ndarray = None      # F11 along the branch, eq. (34)
    dP_domega: np.ndarray = None     # explicit dP/domega at fixed y
    dy_domega: np.ndarray = None     # motion of the fixed point with omega
    digits: object = None

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
    """The admissible period-1 orbit at omega (``branch`` picks one when both are)."""
    from .orbit import period1_orbits
    if branch is not None and branch not in ("+", "-"):
        raise ParameterError("branch", branch, "'+' or '-'")
    orbits = period1_orbits(params, omega, digits=digits, multipliers=multipliers)
    cands = [o for o in orbits if o.admissible and (branch is None or o.branch == branch)]
    if not cands:
        why = "; ".join(f"branch {o.branch}: {o.reason}" for o in orbits) or \
            "conditions (10) have no solution (eq. 16)"
        raise SingularCaseError("no-admissible-orbit",
                                f"no admissible period-1 orbit at omega = {float(omega):.12g} ({why})")
    if len(cands) > 1:
        raise SingularCaseError("two-admissible-orbits",
                                f"both branches are admissible at omega = {float(omega):.12g}; "
                                "pass branch='+' or '-'")
    return cands[0]


def jet(params, omega, order=3, *, digits=None, branch=None, orbit=None):
    """Jet of the Poincaré map at the admissible period-1 orbit, eqs. (33)–(38).

    ``order`` 1 gives the Jacobian only; 2 adds d2, dA (F11), dP/domega; 3 adds d3.
    ``digits`` selects the mpmath backend at that many digits.
    """
    if order not in (1, 2, 3):
        raise ParameterError("order", order, "1, 2 or 3")
    if orbit is None:
        orbit = select_orbit(params, omega, branch, digits)
    from .model import Model
    if isinstance(params, Model):         # any model: the jet of its N-mass structure
        from .codegen.jets import jet_at
        w = orbit.omega
        T = 2 * (mpmath.pi if digits else math.pi) / w
        return jet_at(params, w, orbit.y, T, order, digits=digits)
    if digits is None:
        return _jet(params, orbit, order, False)
    with mpmath.mp.workdps(digits):
        return _jet(params, orbit, order, True)


def _jet(params, orbit, order, mp):
    vals = _evaluate(order, _orbit_inputs(params, orbit), mp)
    g_th = vals["g_theta"]
    # theta1 = -g_x / g_theta, so |theta1| |g_theta| is the scale of dg/dx
    scale = abs(g_th) * (1 + float(np.max(np.abs(vals["theta1"].astype(float)))))
    if abs(g_th) <= 1e3 * (mpmath.mp.eps if mp else 2.2e-16) * max(scale, 1):
        raise SingularCaseError("grazing", "dg/d(dtheta) = 0 at the orbit: the impact is "
                                "grazing and the implicit function theorem of eq. (30) fails")
    kw = dict(orbit=orbit, omega=orbit.omega, order=order, jacobian=vals["J"],
              theta1=vals["theta1"], g_theta=g_th, digits=orbit.digits)
    if order >= 2:
        J, d2, dwP = vals["J"], vals["d2"], vals["dwP"]
        dy = _solve(np.eye(4, dtype=object if mp else float) - J, dwP, mp)
        kw.update(d2=d2, dP_domega=dwP, dy_domega=dy,
                  dA=vals["dwJ"] + d2 @ dy)
    if order >= 3:
        kw.update(d3=vals["d3"])
    return Jet(**kw)


def _solve(M, v, mp):
    """(I - J)^{-1} v for M = I - J, with the fold checks of
    :func:`symvi.codegen.jets.fixed_point_motion` (one owner)."""
    from .codegen.jets import fixed_point_motion
    n = M.shape[0]
    return fixed_point_motion(np.eye(n, dtype=M.dtype) - M, v, mp)
