"""Jets of the impact map of any model from the generated code, eqs. (33)–(38) generalised.

Raw derivatives in the section's variable order (:class:`symvi.maps.Section`):

* ``jacobian[i, j] = dP_i/dy_j`` (F01),
* ``d2[i, j, k]``, ``d3[i, j, k, l]`` (F02 = d2 / 2, F03 = d3 / 6),
* ``dP_domega``, ``dJ_domega``: explicit omega-derivatives at fixed y;
  ``dA = dJ/domega + d2 . dy*/domega`` along the orbit branch (F11 of eq. (34)),
  dy*/domega = (I - J)^{-1} dP/domega from P(y*(omega); omega) = y*(omega);
* the same two for any named parameter p (:func:`parameter_derivatives`), exact.

Order K imports ``impact_n<N>_order<K>`` only: a multiplier-only job never
imports second- or third-order code.
"""
import contextlib
import math
import warnings
from dataclasses import dataclass

import mpmath
import numpy as np

from ..errors import NearSingularWarning, ParameterError, SingularCaseError
from ..flow.linear import LinearFlow
from ..model import Model
from ._assemble import fixed_solve64
from .layout import assemble, module


def evaluate(flow, forcing, y, te, order, tangent=None):
    """Flat generated values -> dict of numpy arrays (object arrays of mpf on mpmath)."""
    mod, layout = module(flow.n, order)
    inp = assemble(flow, forcing, y, te, order, tangent)
    if flow.bk.digits is None:
        vals = mod.f64(inp)
        flat = np.fromiter(vals, float, len(vals))
    else:
        vals = mod.mp(inp)
        flat = np.empty(len(vals), dtype=object)
        flat[:] = vals
    return {name: flat[idx] for name, idx in layout.items()}


def flight_jet(flow, forcing, y, te, order, start, end, tangent=None):
    """The jet of the flight from point y of constraint ``start``'s section (its layout,
    :func:`symvi.flow.compiled.section_index`) that ends on constraint ``end``, as a dict
    like :func:`evaluate`'s (float64): the generated variant ``impact_n<N>_s<s>``
    (:func:`symvi.codegen.layout.assemble_flight`) with its input axes put back in the
    start section's layout; the output is in the end section's layout (issue 25)."""
    from .layout import assemble_flight
    inp, s, pi, dzs = assemble_flight(flow, forcing, y, te, order, start, end, tangent)
    mod, layout = module(flow.n, order, s)
    vals = mod.f64(inp)
    flat = np.fromiter(vals, float, len(vals))
    back = np.argsort(pi)              # d/dy_a[c] = d/dy_var[back[c]] (y_var = y_a[pi])
    out = {}
    for name, idx in layout.items():
        a = flat[idx]
        if name in ("J", "dwJ", "dpJ", "theta1") or name.startswith("d") and name[1:].isdigit():
            for ax in range(1 if name != "theta1" else 0, a.ndim):
                a = np.take(a, back, axis=ax)
        out[name] = a
    if dzs is not None:
        # a contact phase's map is P(y) = P~(y - ys_a) + ys_b with the offset's section
        # parts ys moving along the tangent: dJ/dp = dpJ~ - d2~ . dys_a and
        # dP/dp = dpP~ - J~ dys_a + dys_b (symvi.codegen.layout.phase_tangent)
        from ..flow.compiled import section_index, table
        rows = table(flow)
        ya, yb = (np.append(dzs[np.asarray(section_index(flow.n, int(rows[k][0])))], 0.0)
                  for k in (start, end))
        out["dpJ"] = out["dpJ"] - np.einsum("abc,c->ab", out["d2"], ya)
        out["dpP"] = out["dpP"] - out["J"] @ ya + yb
    return out


def eigenvalues(J):
    """Eigenvalues of a Jacobian sorted by modulus descending, then imaginary part
    descending (float or mpmath).  J is real, so complex eigenvalues come in conjugate
    pairs: a pair shares one modulus for the sort, so its order (Im > 0 first) does not
    depend on rounding (LAPACK returns exact conjugates; mpmath's eig does not)."""
    if J.dtype == object:
        ev = list(mpmath.eig(mpmath.matrix(J.tolist()), left=False, right=False))
        mods = [abs(z) for z in ev]
        for i, z in enumerate(ev):
            if mpmath.im(z) > 0:          # its partner: the nearest conjugate
                j = min(range(len(ev)), key=lambda k: abs(ev[k] - mpmath.conj(z)))
                mods[i] = mods[j] = (mods[i] + mods[j]) / 2
        order = sorted(range(len(ev)), key=lambda i: (-mods[i], -mpmath.im(ev[i])))
        return tuple(ev[i] for i in order)
    ev = np.linalg.eigvals(J)
    return tuple(sorted((complex(z) for z in ev), key=lambda z: (-abs(z), -z.imag)))


def _at(model, omega, digits, checked=False):
    flow = LinearFlow.of(model, digits)
    if not checked:                   # an orbit symvi computed was checked at its omega
        LinearFlow.of(model).check_omega(float(omega), warn=False)
    if digits is None:
        return flow, flow.forcing(float(omega))
    return flow, flow.forcing(mpmath.mpf(omega))


def _checked(model, y, te):
    """(y, te) validated: 2N finite numbers in the section layout, te > 0."""
    from ..maps.section import Section
    if not isinstance(model, Model):
        raise ParameterError("model", model, "a symvi.Model")
    y = Section.of(model).check(y)
    try:
        ok = math.isfinite(float(te)) and float(te) > 0
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ParameterError("te", te, "a finite flight time > 0")
    return y, te


def jacobian_at(model, omega, y, te, *, digits=None):
    """DP at a section point y whose flight to the next impact lasts te (any point)."""
    y, te = _checked(model, y, te)
    if digits is None:
        flow, F = _at(model, omega, None)
        return evaluate(flow, F, tuple(float(v) for v in y), float(te), 1)["J"]
    with mpmath.mp.workdps(digits):
        flow, F = _at(model, omega, digits)
        return evaluate(flow, F, tuple(mpmath.mpf(v) for v in y), mpmath.mpf(te), 1)["J"]


def multipliers_at(model, omega, y, te, *, digits=None):
    """Eigenvalues of DP at y (|.| descending)."""
    if digits is None:
        return eigenvalues(jacobian_at(model, omega, y, te))
    with mpmath.mp.workdps(digits):
        return eigenvalues(jacobian_at(model, omega, y, te, digits=digits))


def multipliers_of(flow, forcing, y, te):
    """Eigenvalues of DP at y for a flow and forcing already at hand (no checks: the
    period-1 solver's own call, in the flow's backend and precision)."""
    return eigenvalues(evaluate(flow, forcing, y, te, 1)["J"])


@dataclass(frozen=True)
class Jet:
    """Jet of the impact map at a fixed point y* (flight time te), see the module docstring.

    Arrays are float64, or object arrays of mpf when ``digits`` is set;
    unrequested orders are None.
    """

    omega: object
    y: tuple
    order: int
    jacobian: np.ndarray
    theta1: np.ndarray
    g_theta: object
    d2: np.ndarray = None
    d3: np.ndarray = None
    dA: np.ndarray = None            # F11 along the branch
    dP_domega: np.ndarray = None
    dJ_domega: np.ndarray = None
    dy_domega: np.ndarray = None
    digits: object = None


def jet_at(model, omega, y, te, order=3, *, digits=None):
    """The jet of P at a fixed point y (flight time te) of ``model``; see :class:`Jet`."""
    if order not in (1, 2, 3):
        raise ParameterError("order", order, "1, 2 or 3")
    y, te = _checked(model, y, te)
    return _jet_in(model, omega, y, te, order, digits)


def jet_of_orbit(model, orbit, order):
    """:func:`jet_at` at a period-1 orbit symvi computed (its omega, y and digits),
    without re-validating them; te = 2 pi / omega at the orbit's own precision."""
    digits = orbit.digits
    with mpmath.mp.workdps(digits) if digits else contextlib.nullcontext():
        te = 2 * (mpmath.pi if digits else math.pi) / orbit.omega
        return _jet_in(model, orbit.omega, orbit.y, te, order, digits, checked=True)


def _jet_in(model, omega, y, te, order, digits, checked=False):
    """The jet at checked (y, te), on float64 or at ``digits``."""
    if digits is None:
        flow, F = _at(model, omega, None, checked)
        return _jet(flow, F, tuple(float(v) for v in y), float(te), order, False)
    with mpmath.mp.workdps(digits):
        flow, F = _at(model, omega, digits, checked)
        return _jet(flow, F, tuple(mpmath.mpf(v) for v in y), mpmath.mpf(te), order, True)


def _check_grazing(vals, mp):
    g_th = abs(vals["g_theta"])
    scale = g_th * (1 + float(max(map(abs, vals["theta1"].tolist()))))
    if g_th <= 1e3 * (mpmath.mp.eps if mp else 2.2e-16) * max(scale, 1):
        raise SingularCaseError("grazing", "dg/d(dtheta) = 0 at the point: the impact is "
                                "grazing and the implicit function theorem of eq. (30) fails")


def _jet(flow, F, y, te, order, mp):
    vals = evaluate(flow, F, y, te, order)
    _check_grazing(vals, mp)
    kw = dict(omega=F.omega, y=y, order=order, jacobian=vals["J"], theta1=vals["theta1"],
              g_theta=vals["g_theta"], digits=flow.bk.digits)
    if order >= 2:
        J, d2 = vals["J"], vals["d2"]
        dy = fixed_point_motion(J, vals["dwP"], mp)
        kw.update(d2=d2, dP_domega=vals["dwP"], dJ_domega=vals["dwJ"], dy_domega=dy,
                  dA=vals["dwJ"] + d2 @ dy)
    if order >= 3:
        kw.update(d3=vals["d3"])
    return Jet(**kw)


@dataclass(frozen=True)
class ParameterDerivative:
    """d/dp of the map and of its Jacobian at y (fixed y), and along the fixed point."""

    name: str
    dP: np.ndarray            # explicit dP/dp at fixed y
    dJ: np.ndarray            # explicit dJ/dp at fixed y
    dy: np.ndarray = None     # dy*/dp of the fixed point (when y is one)
    dJ_branch: np.ndarray = None   # dJ/dp along the fixed point: dJ + d2 . dy


def parameter_derivatives(model, omega, y, te, name, *, digits=None, fixed_point=True):
    """Exact first derivatives of P and DP with respect to the named parameter ``name``
    (a name or a :class:`symvi.model.parameters.Parameter`).

    ``omega`` uses the generated omega-slot; any other name the generic slot fed
    by :func:`symvi.codegen.layout.tangent_data` (Frechet derivative of e^{At}).
    With ``fixed_point`` (y a fixed point, te its period) the motion of the fixed
    point and the derivative of the Jacobian along it are added.
    """
    y, te = _checked(model, y, te)
    par = model.parameter(name)
    name = par.name
    tangent = None if par.is_forcing_frequency else par.tangent(model)
    with mpmath.mp.workdps(digits) if digits else contextlib.nullcontext():
        flow, F = _at(model, omega, digits)
        mp = digits is not None
        num = mpmath.mpf if mp else float
        vals = evaluate(flow, F, tuple(num(v) for v in y), num(te), 2, tangent)
        dP, dJ = ((vals["dwP"], vals["dwJ"]) if par.is_forcing_frequency
                  else (vals["dpP"], vals["dpJ"]))
        if not fixed_point:
            return ParameterDerivative(name, dP, dJ)
        dy = fixed_point_motion(vals["J"], dP, mp)
        return ParameterDerivative(name, dP, dJ, dy, dJ + vals["d2"] @ dy)


def fixed_point_motion(J, dP, mp):
    """dy*/dp = (I - J)^{-1} dP/dp; refuses a multiplier at 1 (fold), warns near one."""
    n = J.shape[0]
    if mp:
        x = mpmath.lu_solve(mpmath.matrix((np.eye(n, dtype=object) - J).tolist()),
                            mpmath.matrix(list(dP)))
        out = np.empty(n, dtype=object)
        out[:] = [x[i] for i in range(n)]
        return out
    x, had = fixed_solve64(np.ascontiguousarray(J, dtype=float),
                           np.ascontiguousarray(dP, dtype=float))
    if not had > 1e-6:
        lam = np.linalg.eigvals(J)
        if np.abs(lam).max() > 1e8:
            raise SingularCaseError("near-singular-map", f"the Jacobian has a multiplier of "
                                    f"modulus {np.abs(lam).max():.3g}: the orbit is close to "
                                    "grazing and the fixed point's motion cannot be resolved")
        gap = np.abs(1 - lam).min()
        if not gap >= 1e-10:
            raise SingularCaseError("multiplier-one", "a multiplier equals 1: the fixed point "
                                    "does not move smoothly with the parameter (fold)")
        if gap < 1e-6:
            warnings.warn(f"a multiplier is within {gap:.1e} of 1 (near a fold): derivatives "
                          f"along the branch lose about {-np.log10(gap):.0f} digits",
                          NearSingularWarning, stacklevel=4)
        if had == 0:                  # an exactly zero pivot: LAPACK says what it can
            return np.linalg.solve(np.eye(n) - J, dP)
    return x
