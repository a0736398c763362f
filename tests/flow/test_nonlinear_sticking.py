"""Complete chatter and sticking with nonlinear forces (issue 28): the accumulation point
with a, b, kappa from the nonlinear field, the held motion and its release
(:mod:`symvi.flow.nlsticking`), and runs through them against the linear module's."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import symvi
from symvi.flow import nlsticking as ns
from symvi.flow.nonlinear import NonlinearFlow
from symvi.flow.sticking import accumulation_time
from symvi.model import Model, Stop

ZETA, P, B, R, W, TAU = 0.1, 1.0, 0.2, 0.5, 0.7, 1.2
BETA, EPS = 0.5, 0.8
#: an impact Duffing oscillator x'' + 2 zeta x' + x + beta x^3 + eps x^2 x' = P sin, a stop
#: at x = B the forcing pushes into at TAU; eps x^2 x' makes kappa depend on the forces
DUFFING = Model(mass=[1.0], stiffness=[[1.0]], damping=[[2 * ZETA]], forcing=[P],
                stop=Stop(mass=1, gap=B, restitution=R),
                nonlinear=["beta*x1**3 + eps*x1**2*v1"],
                parameters={"beta": BETA, "eps": EPS})


def _brute_chatter(flow, w0, u_end=1e-9):
    """Brute force: every impact after a rebound at speed w0 on the stop, each an exact
    Taylor flight, down to approach speeds below u_end; the tail after it (O(u_end^2))."""
    z, tau, T = np.array([B, -w0]), TAU, 0.0
    for i in range(10_000):
        st, te, g, ze = flow.first_impact(W, z, tau, just_hit=0)
        assert st == "impact" and g == 0
        T, tau, u = T + te, tau + W * te, ze[1]
        z = np.array([B, -R * u])
        if u < u_end:
            a = flow.rhs(W, tau, 0.0, z)[1]
            return T + 2 * R * u / (a * (1 - R)), i
    raise AssertionError("no accumulation")


def _brute_stick(flow, omega, sim, t_stick):
    """The accumulation point at t_stick by brute force: the exact impacts from the last
    stored one before it (one constraint), down to approach speeds below 1e-9, and the
    tail after them (O(1e-18))."""
    n, R_ = flow.n, flow.R[0]
    gh = flow.cons[0, 2] * flow.normals[0]
    r = -float(gh @ R_ @ flow.Minv @ gh) / float(gh @ flow.Minv @ gh)
    i = np.flatnonzero(sim.t < t_stick)[-1]
    z, tau, T = flow.start(sim.section[i]), sim.section[i][-1], sim.t[i]
    for _ in range(10_000):
        st, te, g, ze = flow.first_impact(omega, z, tau, just_hit=0)
        assert st == "impact" and g == 0
        T, tau, u = T + te, tau + omega * te, float(gh @ ze[n:])
        z = np.concatenate([ze[:n], R_ @ ze[n:]])
        if u < 1e-9:
            a = float(gh @ flow.rhs(omega, tau, 0.0, z)[n:])
            return T + 2 * r * u / (a * (1 - r))
    raise AssertionError("no accumulation")


def test_chatter_coefficients_of_the_duffing_oscillator():
    """a = x'', b = x''' and kappa = 2 zeta + d f/d v just after an impact, against their
    closed forms for the Duffing forces."""
    flow = NonlinearFlow(DUFFING)
    for w0 in (1e-2, 0.3):
        x, v = B, -w0
        a, b, kappa = ns.chatter_coefficients(flow, W, np.array([x, v]), TAU, 0)
        a_ = P * math.sin(TAU) - 2 * ZETA * v - x - BETA * x ** 3 - EPS * x * x * v
        b_ = (P * W * math.cos(TAU) - (2 * ZETA + EPS * x * x) * a_
              - (1 + 3 * BETA * x * x + 2 * EPS * x * v) * v)
        assert a == pytest.approx(a_, abs=1e-13) and b == pytest.approx(b_, abs=1e-12)
        assert kappa == pytest.approx(2 * ZETA + EPS * x * x, abs=1e-9)


@pytest.mark.parametrize("w0", [1e-2, 5e-3, 2.5e-3])
def test_accumulation_time_against_brute_force_impacts(w0):
    """The chatter map's formula with a, b, kappa from the nonlinear field against
    brute-force stepping of ~25 exact impacts down to 1e-9: the leading term is off by
    O(w0^2), the full formula by O(w0^3) with the same constant (~27) at each w0.  The
    run (its impacts to the grazing speed, then the formula) puts the accumulation point
    on the brute-force one to rounding."""
    flow = NonlinearFlow(DUFFING)
    T, n_exact = _brute_chatter(flow, w0)
    a, b, kappa = ns.chatter_coefficients(flow, W, np.array([B, -w0]), TAU, 0)
    t1 = accumulation_time(w0, a, R)
    t2 = accumulation_time(w0, a, R, b, kappa)
    assert 1.0 < abs(T - t1) / w0 ** 2 < 10                  # a genuine O(w0^2) error
    assert 20 < abs(T - t2) / w0 ** 3 < 35                   # the next order removes it
    assert n_exact > 20
    sim = symvi.simulate(DUFFING, W, y0=(-w0, TAU), n_impacts=20)
    assert sim.stop == "completed" and len(sim.sticks)
    assert abs(sim.sticks[0, 0] - T) < 1e-12


def test_accumulation_formula_is_third_order():
    """The remainder of the full formula scales as w0^3 (ratio 8 per halving)."""
    flow = NonlinearFlow(DUFFING)

    def err(w0):
        a, b, kappa = ns.chatter_coefficients(flow, W, np.array([B, -w0]), TAU, 0)
        return _brute_chatter(flow, w0)[0] - accumulation_time(w0, a, R, b, kappa)
    assert 7.0 < err(1e-2) / err(5e-3) < 9.0


def test_one_mass_release_at_the_root_of_mu():
    """Held on x = B, the Duffing mass is released where mu(t) = P sin(omega t + tau) - B
    - beta B^3 falls through 0 (v = 0: the eps term is 0): the closed form against a root
    of mu bracketed on a grid, mu > 0 before it."""
    flow = NonlinearFlow(DUFFING)
    H = ns.Held(flow, W, 0)

    def mu(t, tau):
        return P * math.sin(W * t + tau) - B - BETA * B ** 3

    for tau in (0.4, 1.2, 2.0):
        kind, t, z = H.run(np.array([B, 0.0]), tau, 1e3)
        assert kind == -1 and z[0] == B and z[1] == 0.0
        ts = np.linspace(0.0, t + 1.0, 4001)
        j = np.flatnonzero(np.array([mu(s, tau) for s in ts]) <= 0)[0]
        t_ref = brentq(mu, ts[j - 1], ts[j], args=(tau,), xtol=1e-15)
        assert t == pytest.approx(t_ref, abs=1e-12)
        assert (np.array([mu(s, tau) for s in ts[ts < t - 1e-9]]) > 0).all()


def test_the_run_resumes_after_the_release():
    """After each release the run's next impact comes later than the release with an
    approach speed well above grazing, and mu is 0 at every release (the closed form)."""
    sim = symvi.simulate(DUFFING, 0.5, y0=(-0.3, 1.2), n_impacts=200)
    assert sim.stop == "completed" and len(sim.sticks) > 3
    for t_s, t_r, g in sim.sticks:
        assert t_r > t_s and g == 0
        assert abs(P * math.sin(0.5 * t_r + 1.2) - B - BETA * B ** 3) < 1e-12
        after = sim.t[sim.t > t_r]
        if len(after):
            assert sim.impact_velocity[np.searchsorted(sim.t, t_r)] > 1e-4


ONE = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.2]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.2, restitution=0.5))
LOWER = dict(ONE, stop=Stop(mass=1, gap=-0.2, side="lower", restitution=0.5))
TWO = dict(mass=[[1.0, 0], [0, 1.3]], stiffness=[[2.0, -1.0], [-1.0, 2.5]],
           damping=[[0.03, 0], [0, 0.02]], forcing=[0.8, 1.1],
           stop=Stop(mass=1, gap=0.1, restitution=0.6))
#: a stop between the masses (s = x2 - x1 <= 0): held, they move as one
BETWEEN = dict(TWO, forcing=[-0.5, 1.1], stop=Stop(between=(1, 2), gap=0.0, restitution=0.5))


@pytest.mark.parametrize("kw, omega, y0, forces", [
    (ONE, 0.5, (-0.3, 1.2), ["0*x1**3"]),
    (LOWER, 0.5, (0.3, 1.2), ["0*x1**3"]),
    (TWO, 0.3, (-0.1, 0.3, -0.2, 1.0), ["0*x1**3", "0*x2**3"]),
    (BETWEEN, 0.5, (-0.1, 0.1, 0.0, 1.0), ["0*x1**3", "0*x2**3"]),
])
def test_nonlinearity_off_runs_as_the_linear_run(kw, omega, y0, forces):
    """With the forces 0 the run through chatter and sticking gives the linear
    run_through's records: releases and impacts (speeds above 1e-4: the two loops call
    grazing at slightly different speeds, so the last chatter impact of a sequence may
    be stored by one only) to 1e-10.  The accumulation points agree to 1e-8 only: the
    linear module sums the sequence from its grazing contact by the leading term, error
    O(u^2) ~ 1e-9; the full formula here is on the brute-force point to 1e-12."""
    lin = symvi.simulate(Model(**kw), omega, y0=y0, n_impacts=300)
    sim = symvi.simulate(Model(**kw, nonlinear=forces), omega, y0=y0, n_impacts=300)
    assert sim.stop == lin.stop and sim.stop_reason == lin.stop_reason
    end = min(lin.t[-1], sim.t[-1]) - 1.0
    sl, sn = lin.sticks[lin.sticks[:, 1] < end], sim.sticks[sim.sticks[:, 1] < end]
    assert len(sl) == len(sn) > 5
    assert np.abs(sl[:, 1:] - sn[:, 1:]).max() < 1e-10
    assert np.abs(sl[:, 0] - sn[:, 0]).max() < 1e-8
    flow = NonlinearFlow(Model(**kw, nonlinear=forces))
    brute = _brute_stick(flow, omega, sim, sn[0, 0])
    assert abs(sn[0, 0] - brute) < 1e-12
    fl = (lin.impact_velocity > 1e-4) & (lin.t < end)
    fn = (sim.impact_velocity > 1e-4) & (sim.t < end)
    assert fl.sum() == fn.sum() > 100
    assert np.abs(lin.t[fl] - sim.t[fn]).max() < 1e-10
    assert np.abs(lin.section[fl] - sim.section[fn]).max() < 1e-10
    assert np.abs(lin.impact_velocity[fl] - sim.impact_velocity[fn]).max() < 1e-10
    assert np.array_equal(lin.hits[fl], sim.hits[fn])


#: TWO with cubic springs to the ground and between the masses
CUBIC = ["beta*x1**3 - gamma*(x2 - x1)**3", "beta*x2**3 + gamma*(x2 - x1)**3"]
G2 = 0.7


def test_two_mass_held_phase_against_solve_ivp():
    """Mass 1 held on its stop (x1 = 0.1, v1 = 0) while mass 2 moves by the reduced system
    with the cubic forces: the release (mu = row 1's free acceleration through 0) and
    mass 2's state there against DOP853 of the reduced system and a root of its mu."""
    m = Model(**TWO, nonlinear=CUBIC, parameters={"beta": 0.5, "gamma": G2})
    flow = NonlinearFlow(m)
    Pv = np.array(TWO["forcing"])
    x1, tau0, x2, v2 = 0.1, 1.0, 0.3, -0.2

    def f(x2):
        return 0.5 * x1 ** 3 - G2 * (x2 - x1) ** 3, 0.5 * x2 ** 3 + G2 * (x2 - x1) ** 3

    def rhs(t, u):
        s = math.sin(W * t + tau0)
        return [u[1], (Pv[1] * s - 0.02 * u[1] + x1 - 2.5 * u[0] - f(u[0])[1]) / 1.3]

    def mu(t, u):
        return Pv[0] * math.sin(W * t + tau0) - 2.0 * x1 + u[0] - f(u[0])[0]

    kind, t, z = ns.Held(flow, W, 0).run(np.array([x1, x2, 0.0, v2]), tau0, 1e3)
    assert kind == -1 and t > 0.5
    sol = solve_ivp(rhs, (0, 1.5 * t), [x2, v2], method="DOP853", rtol=1e-13, atol=1e-13,
                    dense_output=True)
    ts = np.linspace(0, 1.5 * t, 3001)
    mus = np.array([mu(s, sol.sol(s)) for s in ts])
    j = np.flatnonzero(mus <= 0)[0]
    assert (mus[:j] > 0).all()
    t_ref = brentq(lambda s: mu(s, sol.sol(s)), ts[j - 1], ts[j], xtol=1e-14)
    assert t == pytest.approx(t_ref, abs=1e-9)
    u = sol.sol(t)
    assert z[1] == pytest.approx(u[0], abs=1e-9) and z[3] == pytest.approx(u[1], abs=1e-9)
    assert z[0] == x1 and z[2] == 0.0


def test_two_mass_run_through_sticking_with_cubic_forces():
    """A run of the two-mass chain with cubic forces goes on through its stickings: each
    release has mu = 0 (row 1's free acceleration at the stored state, the forcing's phase
    from the start's), and the run stores all its impacts."""
    m = Model(**TWO, nonlinear=CUBIC, parameters={"beta": 0.5, "gamma": G2})
    sim = symvi.simulate(m, 0.3, y0=(-0.1, 0.3, -0.2, 1.0), n_impacts=200)
    assert sim.stop == "completed" and sim.n == 200 and len(sim.sticks) > 2
    assert (sim.sticks[:, 1] > sim.sticks[:, 0]).all()
    assert (np.diff(sim.t) > 0).all()


def test_another_stop_met_while_held_stops_the_run():
    """Two stops on the chain's masses: while mass 1 is held, mass 2 reaches its stop (a
    guard watched on the held motion's series); the run stops as the linear one does,
    with the same reason, at the same time."""
    stops = [Stop(mass=1, gap=0.1, restitution=0.6), Stop(mass=2, gap=0.45, restitution=0.6)]
    kw = {k: v for k, v in TWO.items() if k != "stop"}
    y0 = (-0.1, 0.1, -0.2, 1.0)
    lin = symvi.simulate(Model(**kw, stops=stops), 0.3, y0=y0, n_impacts=300)
    sim = symvi.simulate(Model(**kw, stops=stops, nonlinear=["0*x1**3", "0*x2**3"]), 0.3,
                         y0=y0, n_impacts=300)
    assert sim.stop == lin.stop == "sticking"
    assert sim.stop_reason == lin.stop_reason == "stop 2 met while stop 1 holds its mass"
    assert len(sim.sticks) == len(lin.sticks) == 1
    assert abs(sim.sticks[-1, 1] - lin.sticks[-1, 1]) < 1e-10
