"""Complete chatter and sticking on a rigid stop (issue 27, item 4): the chatter map's
accumulation point, the held motion and its release (:mod:`symvi.flow.sticking`)."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from symvi.flow import compiled as cf
from symvi.flow import sticking as sk
from symvi.flow.linear import LinearFlow
from symvi.model import Model, Stop

ZETA, P, B, R, W = 0.1, 1.0, 0.2, 0.5, 0.7
#: x'' + 2 zeta x' + x = P sin(omega t + tau), an upper stop at x = B
ONE = Model(mass=[1.0], stiffness=[[1.0]], damping=[[2 * ZETA]], forcing=[P],
            stop=Stop(mass=1, gap=B, restitution=R))
TAU = 1.2          # P sin(TAU) - B > 0: the force pushes the mass into the stop


def _chatter_time(w0):
    """Brute force: every impact after a rebound at speed w0 stepped by the exact flow
    until the finder calls one grazing (speed ~1e-7), then the O(u^2) tail."""
    c = cf.constants(ONE, W)
    y, T = np.array([-w0, TAU]), 0.0
    for i in range(10_000):
        st, te, y2, _, _, _, _ = cf.step(c, y)
        if st != cf.IMPACT:
            ta, z, g = sk.accumulate(c, y, 0)
            return T + ta, i, z
        T, y = T + te, y2
    raise AssertionError("no accumulation")


@pytest.mark.parametrize("w0", [1e-2, 5e-3, 2.5e-3])
def test_accumulation_time_against_the_chatter_map(w0):
    """The chatter map's closed form (1-DOF, a = h'', b = h''', kappa = 2 zeta known in
    closed form after the impact) against brute-force exact impact stepping: the leading
    term 2 w0 / (a (1 - r)) is off by O(w0^2), the next order by O(w0^3) (its constant,
    ~26 here, is the same at each w0: the third order of the expansion)."""
    a = P * math.sin(TAU) - 2 * ZETA * (-w0) - B            # x'' just after the impact
    b = P * W * math.cos(TAU) - 2 * ZETA * a - (-w0)        # x''' there
    T, n_exact, z = _chatter_time(w0)
    t1 = sk.accumulation_time(w0, a, R)
    t2 = sk.accumulation_time(w0, a, R, b, 2 * ZETA)
    assert 0.1 < abs(T - t1) / w0 ** 2 < 20                  # a genuine O(w0^2) error
    assert 20 < abs(T - t2) / w0 ** 3 < 30                   # the next order removes it
    assert n_exact < 30                                       # O(1) exact impacts
    assert z[0] == B and z[1] == 0.0                          # held: on the stop, at rest


def test_accumulation_constant_is_third_order():
    """The remainder of the next-order formula scales as w0^3 (ratio 8 per halving)."""
    def err(w0):
        a = P * math.sin(TAU) + 2 * ZETA * w0 - B
        b = P * W * math.cos(TAU) - 2 * ZETA * a + w0
        return _chatter_time(w0)[0] - sk.accumulation_time(w0, a, R, b, 2 * ZETA)
    assert 7.0 < err(1e-2) / err(5e-3) < 9.0


def test_bad_accumulation_refused_in_one_line():
    """r = 1 has no accumulation point; a must push into the stop."""
    for args in ((1e-3, 0.5, 1.0), (1e-3, -0.5, 0.5)):
        with pytest.raises(ValueError) as exc:
            sk.accumulation_time(*args)
        assert "\n" not in str(exc.value) and "0 <= r < 1" in str(exc.value)


def test_release_of_one_mass_at_the_contact_force_root():
    """Held on the stop x = B, the mass is released where the contact force
    P sin(omega t + tau) - k B changes sign (falling): the closed form."""
    c = cf.constants(ONE, W)
    S = sk.Stuck(c, LinearFlow.of(ONE), 0)
    z = np.array([B, 0.0])
    for tau in (0.4, 1.2, 2.0):
        kind, t, zr = S.run(z, tau, 1e3)
        ph = W * t + tau
        assert kind == -1
        assert P * math.sin(ph) - B == pytest.approx(0.0, abs=1e-13)
        assert math.cos(ph) < 0                               # falling through zero
        # the first such root: the force stays positive before it
        ts = np.linspace(0, t, 400)[:-1]
        assert (P * np.sin(W * ts + tau) - B > 0).all()


TWO = Model(mass=[[1.0, 0], [0, 1.3]], stiffness=[[2.0, -1.0], [-1.0, 2.5]],
            damping=[[0.03, 0], [0, 0.02]], forcing=[0.8, 1.1],
            stop=Stop(mass=1, gap=0.1, restitution=0.6))


def _two_mass_reference(tau0, x2, v2, t_end):
    """The held motion of TWO by DOP853 (mass 1 at x1 = 0.1, v1 = 0) and the contact
    force lambda = (M x'' + C x' + K x - P sin)_1 along it, independently of the modal
    form: returns (t, x2, v2, lambda)."""
    M, K, C = (np.asarray(a, float) for a in (TWO.mass, TWO.stiffness, TWO.damping))
    Pv = np.asarray(TWO.forcing, float)
    x1 = 0.1

    def f(t, u):
        s = math.sin(W * t + tau0)
        a2 = (Pv[1] * s - C[1, 1] * u[1] - K[1, 0] * x1 - K[1, 1] * u[0]) / M[1, 1]
        return [u[1], a2]

    sol = solve_ivp(f, (0, t_end), [x2, v2], method="DOP853", rtol=1e-12, atol=1e-13,
                    dense_output=True)
    ts = np.linspace(0, t_end, 2001)
    u = sol.sol(ts)
    s = np.sin(W * ts + tau0)
    # row 1 with x1'' = 0: the force the stop exerts (positive: pushing the mass out)
    lam = Pv[0] * s - C[0, 1] * u[1] - K[0, 0] * x1 - K[0, 1] * u[0]
    return ts, u[0], u[1], lam, sol


def test_two_mass_held_phase_against_dop853():
    """Mass 1 held on its stop while mass 2 keeps moving: the release (contact force
    through zero) and mass 2's state there agree with DOP853 of the reduced system; the
    force is positive throughout the held phase."""
    c = cf.constants(TWO, W)
    S = sk.Stuck(c, LinearFlow.of(TWO), 0)
    tau0, x2, v2 = 1.0, 0.3, -0.2
    z = np.array([0.1, x2, 0.0, v2])          # flow order (the stop's mass first)
    kind, t, zr = S.run(z, tau0, 1e3)
    assert kind == -1 and t > 0
    ts, X2, V2, lam, sol = _two_mass_reference(tau0, x2, v2, t * 1.2)
    # the first sign change of the reference force
    j = np.flatnonzero(lam <= 0)[0]
    assert ts[j - 1] < t <= ts[j] + 1e-9
    assert (lam[ts < t - 1e-6] > 0).all()
    u = sol.sol(t)
    assert zr[1] == pytest.approx(u[0], abs=1e-9) and zr[3] == pytest.approx(u[1], abs=1e-9)
    assert zr[0] == 0.1 and zr[2] == 0.0
    # the contact force at the release (M x'' + C x' + K x - P sin, row 1): zero
    s = math.sin(W * t + tau0)
    lam_r = 0.8 * s - (-1.0) * u[0] - 2.0 * 0.1
    assert abs(lam_r) < 1e-9


def test_two_mass_accumulation_against_the_chatter_map():
    """A chatter of mass 1 in the two-mass chain: the accumulation time against the chatter
    map's leading term (error O(w0^2)), and the state: every velocity jump is along
    q = M^-1 e_1, which moves v1 only (M diagonal), so x2 and v2 are the free flight's at
    the accumulation point to O(w0^2)."""
    c = cf.constants(TWO, W)
    M, K, C = (np.asarray(a, float) for a in (TWO.mass, TWO.stiffness, TWO.damping))
    for w0 in (2e-3, 1e-3):
        tau = 1.0
        y = np.array([-w0, 0.3, -0.2, tau])       # v1+, x2, v2, tau: pressed into the stop
        x, v = np.array([0.1, 0.3]), np.array([-w0, -0.2])
        a = (np.linalg.solve(M, np.asarray(TWO.forcing) * math.sin(tau) - C @ v - K @ x))[0]
        assert a > 0
        T, yy = 0.0, y.copy()
        for _ in range(1000):                     # the exact impacts, to the grazing one
            st, te, y2, _, _, _, _ = cf.step(c, yy)
            if st != cf.IMPACT:
                break
            T, yy = T + te, y2
        ta, z, g = sk.accumulate(c, yy, 0)
        t_acc = T + ta
        assert g == 0 and z[0] == 0.1 and z[2] == 0.0
        assert abs(t_acc - sk.accumulation_time(w0, a, 0.6)) < 20 * w0 ** 2
        free = cf.state_from(c, y, t_acc, 0)      # no impact at all: mass 2 unaffected
        assert abs(free[1] - z[1]) < 20 * w0 ** 2 and abs(free[3] - z[3]) < 20 * w0 ** 2


def test_release_start_is_a_flight():
    """From the release point (h = h' = h'' = 0, h''' < 0) the finder no longer reports
    grazing at t = 0: the flight leaves the stop and returns with an impact."""
    c = cf.constants(ONE, W)
    S = sk.Stuck(c, LinearFlow.of(ONE), 0)
    kind, t, zr = S.run(np.array([B, 0.0]), TAU, 1e3)
    y = np.array([0.0, (TAU + W * t) % (2 * math.pi)])
    st, te, z, acc, steps, g = cf.first_impact_from(c, y)
    assert st == cf.IMPACT and te > 1.0
    # the flight stays off the stop until then
    for s in np.linspace(0, te, 200)[1:-1]:
        assert cf.state_from(c, y, s)[0] < B


def test_a_free_reduced_system_is_refused_in_one_line():
    """Held on its stop, a mass whose only spring is to the held one leaves a free reduced
    system if that spring is zero: out of reach, said in one line."""
    m = Model(mass=[[1.0, 0], [0, 1.0]], stiffness=[[1.0, 0.0], [0.0, 0.0]],
              damping=[[0.1, 0], [0, 0.1]], forcing=[1.0, 0.0],
              stop=Stop(mass=1, gap=0.1, restitution=0.5))
    c = cf.constants(m, W)
    with pytest.raises(ValueError) as exc:
        sk.Stuck(c, LinearFlow.of(m), 0)
    assert "\n" not in str(exc.value) and "free" in str(exc.value)


BETWEEN = Model(mass=[[1.0, 0], [0, 1.3]], stiffness=[[2.0, -1.0], [-1.0, 2.5]],
                damping=[[0.03, 0], [0, 0.02]], forcing=[-0.5, 1.1],
                stop=Stop(between=(1, 2), gap=0.0, restitution=0.5))


def test_held_between_two_masses_against_the_joined_pair():
    """A stop between masses (s = x2 - x1 <= 0, the flow's frame): held, the two masses
    move as one, (m1 + m2) x'' + 1.C.1 x' + 1.K.1 x = (P1 + P2) sin; the contact force on
    mass 2, lambda = P2 sin - (C v)_2 - (K x)_2 - m2 x'', is positive until the release,
    found where it changes sign (DOP853 of the joined pair, independently of the frame)."""
    from scipy.optimize import brentq
    M, K, C = (np.asarray(a, float) for a in (BETWEEN.mass, BETWEEN.stiffness,
                                              BETWEEN.damping))
    Pv = np.asarray(BETWEEN.forcing, float)
    m, k, cs, p = M.sum(), K.sum(), C.sum(), Pv.sum()
    flow = LinearFlow.of(BETWEEN)
    c = cf.constants(BETWEEN, W)
    S = sk.Stuck(c, flow, 0)
    tau0, x0, v0 = 2.0, 0.1, 0.05

    def f(t, u):
        return [u[1], (p * math.sin(W * t + tau0) - cs * u[1] - k * u[0]) / m]

    def lam(t, u):
        a = f(t, u)[1]
        return (Pv[1] * math.sin(W * t + tau0) - (C[1, 0] + C[1, 1]) * u[1]
                - (K[1, 0] + K[1, 1]) * u[0] - M[1, 1] * a)

    assert lam(0.0, [x0, v0]) > 0
    kind, t, zr = S.run(flow.to_flow(np.array([x0, x0, v0, v0])), tau0, 1e3)
    assert kind == -1
    sol = solve_ivp(f, (0, 2 * t), [x0, v0], method="DOP853", rtol=1e-12, atol=1e-13,
                    dense_output=True)
    ts = np.linspace(0, 2 * t, 4001)
    lams = np.array([lam(s, sol.sol(s)) for s in ts])
    j = np.flatnonzero(lams <= 0)[0]
    t_ref = brentq(lambda s: lam(s, sol.sol(s)), ts[j - 1], ts[j], xtol=1e-14)
    assert t == pytest.approx(t_ref, abs=1e-9)
    zm = flow.to_mass(zr)
    u = sol.sol(t)
    assert zm[0] == pytest.approx(u[0], abs=1e-9) and zm[1] == pytest.approx(u[0], abs=1e-9)
    assert zm[2] == pytest.approx(u[1], abs=1e-9) and zm[3] == pytest.approx(u[1], abs=1e-9)
