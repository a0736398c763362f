"""The paper's 2-DOF modal closed form of the period-1 orbits, eqs. (10)–(18): the
independent oracle of :mod:`symvi.orbits.period1` (which serves ``Params`` too).

It solves the paper's own modal reduction (psi, omega_1, omega_2, no damping) and takes
the multipliers from the paper's generated jets (``generated/order1.py``), so the
state-space chain of every model is checked against a derivation that shares none
of its code.  Nothing in the production path imports it.

Derivation (ours; the printed eqs. (11)–(16) are audited separately in
:mod:`symvi.paper.audit`).  With xi_j = a_j cos w_j t + b_j sin w_j t + A_j sin(omega t + tau)
and T = 2 pi / omega, c_j = cos w_j T, s_j = sin w_j T:

* x(T) = x(0) (both components, psi invertible) gives xi_j(T) = xi_j(0), i.e.
  a_j = kappa_j b_j with kappa_j = s_j / (1 - c_j) = cot(pi w_j / omega)   eq. (15)
* then xi_j'(T) = xi_j'(0) - 2 w_j b_j, and x2'(T) = x2'(0) gives
  psi21 w1 b1 + psi22 w2 b2 = 0, so b = u (psi22 w2, -psi21 w1)           eq. (14)
* the impact law x1'(0) = -r x1'(T) gives
  (1 - r) w1 w2 D u = (1 + r) omega d cos tau,  d = -(psi11 A1 + psi12 A2)   eq. (13)
* x1(0) = b gives  K u - d sin tau = b,  K = psi11 psi22 w2 kappa1 - psi12 psi21 w1 kappa2.

Eliminating u:  K gamma cos tau - alpha d sin tau = alpha b  with
alpha = (1 - r) w1 w2 D, gamma = (1 + r) omega d, i.e. rho cos(tau - phi) = alpha b:
two branches tau = phi +- arccos(alpha b / rho) when |alpha b| <= rho (eq. 16).
This form stays regular at r = 1 and b = 0.
"""
import warnings
import mpmath

from ..numerics.backend import FLOAT64, backend
from ..errors import NearSingularWarning, ParameterError, SingularCaseError
from .modal_flow import first_impact, forcing_amplitudes, motion_from
from ..maps.section import Section
from .orbit import Orbit
from ..numerics.tolerances import ISOLATION_REFUSE, ISOLATION_WARN
from .params import check_omega, modal as _modal

#: |sin(pi w_j / omega)| below which 1 - cos(2 pi w_j / omega) -> 0 is refused / warned
#: about: the general isolation bounds on |1 - e^{i w_j T}| = 2 |sin(pi w_j / omega)|
KAPPA_REFUSE = ISOLATION_REFUSE / 2
KAPPA_WARN = ISOLATION_WARN / 2


def _branches(params, omega, m, lib):
    """Solve conditions (10) in backend ``lib``: a list of raw branch tuples, or raise."""
    pi = lib.pi
    w1, w2 = m.omegas
    p = m.psi
    r, b = lib.num(params.r), lib.num(params.b)
    kappa = []
    for j, wj in enumerate((w1, w2), start=1):
        sn = lib.sin(pi * wj / omega)
        if lib.fabs(sn) < KAPPA_REFUSE:
            raise SingularCaseError(
                "one-minus-cos",
                f"1 - cos(2 pi omega_{j} / omega) = {float(2 * sn * sn):.3e} at omega = "
                f"{float(omega):.12g}: omega_{j} / omega is an integer, eq. (15) divides by zero "
                "and the period-1 orbit is not isolated. Move omega away from omega_"
                f"{j} / n.")
        if lib is FLOAT64 and abs(sn) < KAPPA_WARN:
            warnings.warn(f"1 - cos(2 pi omega_{j}/omega) = {2 * sn * sn:.2e} is small: "
                          "eq. (15) is ill-conditioned", NearSingularWarning, stacklevel=3)
        kappa.append(lib.cos(pi * wj / omega) / sn)
    A = forcing_amplitudes(m, omega)
    d = -(p[0][0] * A[0] + p[0][1] * A[1])
    alpha = (1 - r) * w1 * w2 * m.D
    gamma = (1 + r) * omega * d
    K = p[0][0] * p[1][1] * w2 * kappa[0] - p[0][1] * p[1][0] * w1 * kappa[1]
    Ac, Bs = K * gamma, -alpha * d
    rho = lib.sqrt(Ac * Ac + Bs * Bs)
    scale = (lib.fabs(K) + lib.fabs(alpha)) * (lib.fabs(gamma) + lib.fabs(d)) + lib.eps
    if rho <= 1e3 * lib.eps * scale:
        raise SingularCaseError("degenerate-forcing",
                                "d = -(psi11 A1 + psi12 A2) = 0: the forcing does not move mass 1 "
                                "and conditions (10) do not fix the orbit")
    phi = lib.atan2(Bs, Ac)
    ratio = alpha * b / rho
    if lib.fabs(ratio) > 1:
        return [], float(ratio)
    ac = lib.acos(ratio)
    out = []
    for branch, tau in (("+", phi + ac), ("-", phi - ac)):
        tau = tau % (2 * pi)
        ct, st = lib.cos(tau), lib.sin(tau)
        u = (alpha * gamma * ct + K * (b + d * st)) / (alpha * alpha + K * K)
        bj = (p[1][1] * w2 * u, -p[1][0] * w1 * u)
        aj = (kappa[0] * bj[0], kappa[1] * bj[1])
        v1p = sum(p[0][j] * (m.omegas[j] * bj[j] + A[j] * omega * ct) for j in range(2))
        vimp = sum(p[0][j] * (-m.omegas[j] * bj[j] + A[j] * omega * ct) for j in range(2))
        x20 = sum(p[1][j] * (aj[j] + A[j] * st) for j in range(2))
        x20d = sum(p[1][j] * (m.omegas[j] * bj[j] + A[j] * omega * ct) for j in range(2))
        out.append((branch, tau, aj, bj, v1p, vimp, x20, x20d))
    return out, float(ratio)


def _admissibility(params, omega, m, lib, tau, v1p, vimp, x20, x20d):
    """(admissible, reason) of :func:`symvi.orbits.admissibility.check_flight`, on the
    paper's modal flow: x1 < b on (0, 2 pi / omega)."""
    from ..orbits.admissibility import END_TOL, check_flight
    b = lib.num(params.b)
    mot = motion_from(m, omega, (b, x20), (v1p, x20d), tau, lib)
    return check_flight(lambda t_max: first_impact(mot, b, lib, t_max=t_max), 2 * lib.pi / omega,
                        v1p, vimp, mass=1, tol=END_TOL if lib is FLOAT64 else lib.eps ** 0.5,
                        require_return=True)


def period1_orbits(params, omega, *, digits=None, multipliers=True):
    """Every period-1 one-impact orbit at omega (both branches), conditions (10).

    Returns a list of :class:`Orbit` (empty when the discriminant of eq. (16) is
    negative: no orbit exists).  Inadmissible orbits are returned with
    ``admissible=False`` and a reason, never silently analysed.  ``digits``
    selects mpmath at that precision.  ``multipliers=False`` skips the Jacobian.
    """
    omega_f = check_omega(params, omega)
    if digits is not None:
        if not isinstance(digits, int) or digits < 16 or digits > 10000:
            raise ParameterError("digits", digits, "an integer from 16 to 10000")
        with mpmath.mp.workdps(digits):
            # keep an mpf omega at full precision (a 50-digit v_c must not be rounded)
            bk = backend(digits)
            w = bk.num(omega) if isinstance(omega, (mpmath.mpf, str)) else bk.num(omega_f)
            return _orbits(params, w, bk, multipliers, digits)
    return _orbits(params, omega_f, FLOAT64, multipliers, None)


def _orbits(params, omega, lib, want_multipliers, digits):
    m = _modal(params, lib)
    raw, _ = _branches(params, omega, m, lib)
    orbits = []
    for branch, tau, aj, bj, v1p, vimp, x20, x20d in raw:
        ok, why = _admissibility(params, omega, m, lib, tau, v1p, vimp, x20, x20d)
        model = params.as_model()
        orb = Orbit(model=model, omega=omega, branch=branch, y=(v1p, x20, x20d, tau),
                    names=Section.of(model).names, impact_velocity=vimp,
                    admissible=ok, reason=why, digits=digits, params=params)
        if want_multipliers:
            from ._eval import multipliers_of
            lam = multipliers_of(params, orb)
            orb = _replace(orb, multipliers=lam,
                           stable=bool(ok and max(abs(complex(l)) for l in lam) < 1))
        orbits.append(orb)
    return orbits


def admissible_orbits(params, omega, *, digits=None, multipliers=True):
    """The admissible period-1 orbits at omega, branch "+" first (empty when none).

    Raises SingularCaseError where conditions (10) are singular.
    """
    orbits = period1_orbits(params, omega, digits=digits, multipliers=multipliers)
    return sorted((o for o in orbits if o.admissible), key=lambda o: o.branch != "+")


def _replace(obj, **kw):
    import dataclasses
    return dataclasses.replace(obj, **kw)


def existence_ratio(params, omega):
    """alpha b / rho: the period-1 orbit exists iff |ratio| <= 1 (eq. 16, corrected)."""
    omega = check_omega(params, omega, warn=False)
    return _branches(params, omega, _modal(params), FLOAT64)[1]
