"""The printed orbit formulas, eqs. (11)–(16) and (21)–(24), evaluated as printed.

Each function evaluates one printed formula literally, so the report can set it
beside symvi's own derivation (:mod:`symvi.orbit`, :mod:`symvi.flow`).

Discrepancies found (shown by ``tests/paper/test_audit_orbit.py``):

* eq. (11) prints the second numerator term as psi12 psi21 (1 - c1) w1; the
  derivation from conditions (10) gives psi12 psi21 s2 (1 - c1) w1 (a factor
  s2 = sin(2 pi w2 / omega) is missing).  Corrected:
  \\tan\\bar\\tau_0 = \\frac{(\\psi_{22}\\psi_{11}s_1(1-c_2)\\omega_2-\\psi_{12}\\psi_{21}s_2(1-c_1)\\omega_1)(1+R)\\omega}{D\\omega_1\\omega_2(1-c_1)(1-c_2)(1-R)}
* eq. (12) prints tan(tau0bar) in the numerator where b tan(tau0bar) is needed
  (the printed form is not even dimensionally consistent in b).  Corrected:
  \\cos\\tau_0 = \\frac{b\\tan\\bar\\tau_0 \\pm \\sqrt{(\\tan^2\\bar\\tau_0+1)d^2-b^2}}{(\\tan^2\\bar\\tau_0+1)d}
  and, since it comes from squaring, each root must also satisfy
  d (tan(tau0bar) cos tau0 - sin tau0) = b, which fixes the sign of sin tau0.
* eq. (16) inherits (12): the corrected existence condition is
  |b| <= |d| sqrt(1 + tan^2 tau0bar) (our |alpha b / rho| <= 1).
* eqs. (13)–(15) and (21)–(24) agree with the derivation.
"""
import math

from .modal_flow import forcing_amplitudes
from .params import modal


def _common(params, omega):
    m = modal(params)
    (p11, p12), (p21, p22) = m.psi
    w1, w2 = m.omegas
    c = [math.cos(2 * math.pi * w / omega) for w in (w1, w2)]
    s = [math.sin(2 * math.pi * w / omega) for w in (w1, w2)]
    A = forcing_amplitudes(m, omega)
    d = -(p11 * A[0] + p12 * A[1])
    return m, p11, p12, p21, p22, w1, w2, c, s, d


def tan_tau0bar_printed(params, omega):
    """tan(tau0bar) by eq. (11) as printed."""
    m, p11, p12, p21, p22, w1, w2, c, s, d = _common(params, omega)
    R = params.r
    num = (p22 * p11 * s[0] * (1 - c[1]) * w2 - p12 * p21 * (1 - c[0]) * w1) * (1 + R) * omega
    return num / (m.D * w1 * w2 * (1 - c[0]) * (1 - c[1]) * (1 - R))


def tan_tau0bar_corrected(params, omega):
    """tan(tau0bar), eq. (11) corrected: the factor s2 restored."""
    m, p11, p12, p21, p22, w1, w2, c, s, d = _common(params, omega)
    R = params.r
    num = (p22 * p11 * s[0] * (1 - c[1]) * w2 - p12 * p21 * s[1] * (1 - c[0]) * w1) * (1 + R) * omega
    return num / (m.D * w1 * w2 * (1 - c[0]) * (1 - c[1]) * (1 - R))


def cos_tau0_printed(params, omega, sign, tan_bar=None):
    """cos(tau0) by eq. (12) as printed (with printed (11) unless ``tan_bar`` given);
    None where the square root of (16) is imaginary."""
    d = _common(params, omega)[-1]
    t = tan_tau0bar_printed(params, omega) if tan_bar is None else tan_bar
    disc = (t * t + 1) * d * d - params.b ** 2
    if disc < 0:
        return None
    return (t + sign * math.sqrt(disc)) / ((t * t + 1) * d)


def cos_tau0_corrected(params, omega, sign):
    """cos(tau0), eq. (12) corrected (b tan(tau0bar) in the numerator)."""
    d = _common(params, omega)[-1]
    t = tan_tau0bar_corrected(params, omega)
    disc = (t * t + 1) * d * d - params.b ** 2
    if disc < 0:
        return None
    return (params.b * t + sign * math.sqrt(disc)) / ((t * t + 1) * d)


def b1_printed(params, omega, tau0):
    """b_1 by eq. (13) as printed, at a given tau0."""
    m, p11, p12, p21, p22, w1, w2, c, s, d = _common(params, omega)
    R = params.r
    return d * p22 * omega * (1 + R) * math.cos(tau0) / (m.D * w1 * (1 - R))


def b2_printed(params, omega, b1):
    """b_2 by eq. (14) as printed."""
    m, p11, p12, p21, p22, w1, w2, c, s, d = _common(params, omega)
    return -p21 * w1 * b1 / (p22 * w2)


def a_printed(params, omega, b1, b2):
    """a_i by eq. (15) as printed."""
    c, s = _common(params, omega)[7:9]
    return (b1 * s[0] / (1 - c[0]), b2 * s[1] / (1 - c[1]))


def exists_printed(params, omega, sign):
    """Condition (16) as printed."""
    v = cos_tau0_printed(params, omega, sign)
    return v is not None and abs(v) <= 1


def modal_constants_printed(params, omega, y, tau0, dX):
    """a~_1, a~_2, b~_1, b~_2 by eqs. (21)–(24) as printed, at orbit y and perturbation dX."""
    m, p11, p12, p21, p22, w1, w2, c, s, d = _common(params, omega)
    A = forcing_amplitudes(m, omega)
    v1, x20, x20d = y[:3]
    dv, dx2, dx2d, dtau = dX
    D, b = m.D, params.b
    ph = tau0 + dtau
    a1 = (p22 * b - p12 * x20 - p12 * dx2 - D * A[0] * math.sin(ph)) / D
    a2 = (-p21 * b + p11 * x20 + p11 * dx2 - D * A[1] * math.sin(ph)) / D
    b1 = (p22 * v1 + p22 * dv - p12 * x20d - p12 * dx2d - D * A[0] * omega * math.cos(ph)) / (D * w1)
    b2 = (-p21 * v1 - p21 * dv + p11 * x20d + p11 * dx2d - D * A[1] * omega * math.cos(ph)) / (D * w2)
    return a1, a2, b1, b2
