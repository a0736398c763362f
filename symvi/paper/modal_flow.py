"""The paper's 2-DOF modal flow between impacts and its first-impact finder, eqs. (7)–(8), (19)–(20).

Between impacts the motion is a sum of three sinusoids (two modes, one forcing
term), so it is evaluated in closed form; no ODE integrator is used.

The first-impact finder steps along h(t) = x1(t) - b < 0 with a step that is
provably safe: with M2 >= |h''| (a bound from the known amplitudes),
h(t + s) <= h + h' s + M2 s^2 / 2, so no crossing can occur before the first
positive root of that quadratic.  The iterates increase monotonically towards
the first crossing and converge to it quadratically when the crossing is
transversal; a crossing with h' ~ 0 is reported as grazing, never stepped over.
"""
from dataclasses import dataclass

from ..numerics.backend import FLOAT64
from ..numerics.tolerances import CONTACT_TIME_ULPS, CONTACT_ULPS, GRAZING_SPEED_FACTOR

#: statuses returned by first_impact
IMPACT, GRAZING, NO_IMPACT = "impact", "grazing", "no-impact"


@dataclass(frozen=True)
class Motion:
    """Free flight from an impact at t = 0: xi_j(t) = a_j cos w_j t + b_j sin w_j t
    + A_j sin(omega t + tau), eqs. (7)–(8) and (28)–(29)."""

    modal: object
    omega: object
    tau: object
    a: tuple
    b: tuple
    A: tuple

    def state(self, t, lib=FLOAT64):
        """(x1, x2, x1dot, x2dot) at time t, eqs. (7)–(8)."""
        m, w = self.modal, self.omega
        ph = w * t + self.tau
        sph, cph = lib.sin(ph), lib.cos(ph)
        xi, xid = [], []
        for j, wj in enumerate(m.omegas):
            c, s = lib.cos(wj * t), lib.sin(wj * t)
            xi.append(self.a[j] * c + self.b[j] * s + self.A[j] * sph)
            xid.append(wj * (-self.a[j] * s + self.b[j] * c) + self.A[j] * w * cph)
        p = m.psi
        return (p[0][0] * xi[0] + p[0][1] * xi[1], p[1][0] * xi[0] + p[1][1] * xi[1],
                p[0][0] * xid[0] + p[0][1] * xid[1], p[1][0] * xid[0] + p[1][1] * xid[1])


def forcing_amplitudes(modal, omega):
    """A_j = psi_j^T P / (omega_j^2 - omega^2), eq. (7)."""
    return tuple(modal.F[j] / (wj * wj - omega * omega) for j, wj in enumerate(modal.omegas))


def motion_from(modal, omega, x, xdot, tau, lib=FLOAT64):
    """Integration constants for initial physical state (x, xdot) and phase tau, eqs. (21)–(24).

    xi(0) = psi^{-1} x(0) = adj(psi) x(0) / D.
    """
    A = forcing_amplitudes(modal, omega)
    p, D = modal.psi, modal.D
    xi0 = ((p[1][1] * x[0] - p[0][1] * x[1]) / D, (-p[1][0] * x[0] + p[0][0] * x[1]) / D)
    xd0 = ((p[1][1] * xdot[0] - p[0][1] * xdot[1]) / D, (-p[1][0] * xdot[0] + p[0][0] * xdot[1]) / D)
    st, ct = lib.sin(tau), lib.cos(tau)
    a = tuple(xi0[j] - A[j] * st for j in range(2))
    b = tuple((xd0[j] - A[j] * omega * ct) / modal.omegas[j] for j in range(2))
    return Motion(modal, omega, tau, a, b, A)


@dataclass(frozen=True)
class FirstImpact:
    """Result of :func:`first_impact`: the time and state at the first x1 = b crossing."""

    status: str          # IMPACT, GRAZING or NO_IMPACT
    t: object            # time of the crossing (or where the search stopped)
    state: tuple         # (x1, x2, x1dot, x2dot) at t
    steps: int


def _bounds(motion, lib):
    """Amplitude scale L of h and bound M2 >= |h''| for the x1 component."""
    m = motion.modal
    L = M2 = 0
    for j, wj in enumerate(m.omegas):
        amp = lib.fabs(m.psi[0][j]) * lib.sqrt(motion.a[j] ** 2 + motion.b[j] ** 2)
        L += amp
        M2 += amp * wj * wj
    q = lib.fabs(m.psi[0][0] * motion.A[0] + m.psi[0][1] * motion.A[1])
    return L + q, M2 + q * motion.omega ** 2


def first_impact(motion, b, lib=FLOAT64, t_max=None, max_steps=100000):
    """First t > 0 with x1(t) = b, for a motion that leaves x1 = b with x1dot < 0.

    Grazing: the crossing is reported as GRAZING when x1dot at contact is below
    ``sqrt(2 M2 eps_h) * 8``, where eps_h is the resolution of h; the time of
    such a crossing is not resolvable from a tangency.
    """
    if t_max is None:
        t_max = 2000 * lib.pi / motion.omega   # 1000 forcing periods
    L, M2 = _bounds(motion, lib)
    L = L + lib.fabs(b)
    eps_h = CONTACT_ULPS * lib.eps * L
    v_graze = GRAZING_SPEED_FACTOR * lib.sqrt(2 * M2 * eps_h)
    x1, x2, v1, v2 = motion.state(0, lib)
    h, hd = x1 - b, v1
    if not hd < 0:
        return FirstImpact(GRAZING, 0 * t_max, (x1, x2, v1, v2), 0)
    t = -hd / M2                      # vertex of the bound: h(t) <= -hd^2 / (2 M2) < 0
    for n in range(1, max_steps + 1):
        st = motion.state(t, lib)
        h, hd = st[0] - b, st[2]
        if h >= -eps_h:
            if hd <= v_graze:
                return FirstImpact(GRAZING, t, st, n)
            for _ in range(3):        # Newton polish of a transversal root
                dt = -h / hd
                t += dt
                st = motion.state(t, lib)
                h, hd = st[0] - b, st[2]
                if lib.fabs(dt) <= CONTACT_TIME_ULPS * lib.eps * t:
                    break
            return FirstImpact(IMPACT, t, st, n)
        if t > t_max:
            return FirstImpact(NO_IMPACT, t, st, n)
        # safe step: first positive root of h + hd s + M2 s^2/2 = 0 (stable form)
        t += -2 * h / (hd + lib.sqrt(hd * hd - 2 * M2 * h))
    return FirstImpact(NO_IMPACT, t, motion.state(t, lib), max_steps)
