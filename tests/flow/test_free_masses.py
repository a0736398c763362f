"""Free masses (issue 25): a positive semi-definite stiffness, a mass on no spring.

The flow is e^{At} = Re(W e^{Lambda t} W^-1) + t NIL (a Jordan block at lambda = 0 for a
mode that neither K nor C holds: :meth:`LinearFlow._free_modal`).  Held to DOP853
(rtol = atol = 1e-12), to the determinant identity det Phi(t) = exp(tr(A) t), to the
structure of NIL (NIL^2 = A NIL = NIL A = 0), to mpmath, and a run with impacts to solve_ivp
with one event per guard.
"""
import math

import mpmath
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from symvi import simulate
from symvi.errors import SingularCaseError
from symvi.flow import compiled as cf
from symvi.flow.linear import LinearFlow
from symvi.model import Model, Stop
from tests.flow.test_compiled_constraints import state
from tests.zoo import N_MASS_SET, PAPER_EX1, THREE_STOP2_GAP12, TWO_OVERDAMPED

WALLS = [Stop(mass=1, gap=0.3, restitution=0.8),
         Stop(mass=1, gap=-0.3, side="lower", restitution=0.7)]
#: (a) one free undamped mass, forced, between two walls
FREE_ONE = Model(mass=[2.0], stiffness=[[0.0]], forcing=[1.0], stops=WALLS)
#: (b) two masses on one spring and no ground spring (K = [[k, -k], [-k, k]]): a rigid
#: mode of the pair; undamped, and with C proportional to K (the rigid mode undamped)
PAIR = Model(mass=[1.0, 1.5], stiffness=[[2.0, -2.0], [-2.0, 2.0]], forcing=[1.0, 0.2],
             stops=[Stop(mass=1, gap=0.5, restitution=0.8),
                    Stop(mass=2, gap=-0.5, side="lower", restitution=0.9)])
PAIR_CPROP = Model(mass=[1.0, 1.5], stiffness=[[2.0, -2.0], [-2.0, 2.0]],
                   damping=[[0.1, -0.1], [-0.1, 0.1]], forcing=[1.0, 0.2],
                   stops=[Stop(mass=1, gap=0.5, restitution=0.8),
                          Stop(mass=2, gap=-0.5, side="lower", restitution=0.9)])
#: (c) a free mass damped to the ground: a simple lambda = 0 (no Jordan block)
DAMPED_FREE = Model(mass=[1.0, 0.5], stiffness=[[1.0, 0.0], [0.0, 0.0]],
                    damping=[[0.05, 0.0], [0.0, 0.2]], forcing=[1.0, 0.6],
                    stops=[Stop(mass=2, gap=0.3, restitution=0.8),
                           Stop(mass=2, gap=-0.3, side="lower", restitution=0.8)])
#: an impact damper with the stops of today (rigid, on masses): a forced primary mass on a
#: spring and a damper with its own stop, and a light free mass between two walls
DAMPER = Model(mass=[1.0, 0.2], stiffness=[[1.0, 0.0], [0.0, 0.0]],
               damping=[[0.05, 0.0], [0.0, 0.0]], forcing=[1.0, 0.3],
               stops=[Stop(mass=2, gap=0.4, restitution=0.8),
                      Stop(mass=2, gap=-0.4, side="lower", restitution=0.8),
                      Stop(mass=1, gap=0.8, restitution=0.8)])
#: a rigid mode (mass 3), a null direction of K that C damps (the pair 1-2) and a damped
#: elastic mode (mass 4) at once
MIXED = Model(mass=[1.0, 1.5, 0.7, 1.0],
              stiffness=[[1.0, -1.0, 0, 0], [-1.0, 1.0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1.0]],
              damping=[[0.1, 0, 0, 0.02], [0, 0, 0, 0], [0, 0, 0, 0], [0.02, 0, 0, 0.03]],
              forcing=[1.0, 0, 0.5, 0], stop=Stop(mass=2, gap=0.5, restitution=0.8))

MODELS = {"free-one": FREE_ONE, "pair": PAIR, "pair-cprop": PAIR_CPROP,
          "damped-free": DAMPED_FREE, "damper": DAMPER, "mixed": MIXED}
#: which have a Jordan block (a mode on no spring and no damper)
JORDAN = {"free-one", "pair", "pair-cprop", "damper", "mixed"}
OMEGA = {"free-one": 1.3, "pair": 1.1, "pair-cprop": 1.1, "damped-free": 1.2, "damper": 0.9,
         "mixed": 0.8}
TOL = dict(method="DOP853", rtol=1e-12, atol=1e-12)


def _ivp_phi(A, t):
    """e^{At} column by column by DOP853."""
    return np.column_stack([solve_ivp(lambda s, z: A @ z, (0, t), e, **TOL).y[:, -1]
                            for e in np.eye(len(A))])


@pytest.mark.parametrize("name", sorted(MODELS))
def test_phi_against_solve_ivp(name):
    """Phi(t) = e^{At} (the flow's order) against DOP853, over a long flight too (the drift
    t NIL grows linearly): (a) one free mass, (b) a rigid pair, undamped and with C
    proportional, (c) a free mass damped to the ground (simple lambda = 0)."""
    flow = LinearFlow.of(MODELS[name])
    assert flow.free == (name in JORDAN)
    A = np.asarray(flow.A, dtype=float)
    for t in (0.7, 9.0):
        ref = _ivp_phi(A, t)
        np.testing.assert_allclose(flow.phi(t), ref, atol=1e-9 * (1 + t), rtol=0)
    if name in JORDAN:                              # the drift is there and is needed
        assert np.abs(flow.NIL).max() > 0.1
        modal = np.real((flow.W * np.exp(flow.lam * 9.0)) @ flow.Winv)
        assert np.abs(modal - ref).max() > 1.0


@pytest.mark.parametrize("name", sorted(MODELS))
def test_phis_nil_structure_and_determinant(name):
    """Phi(t) A^k from :meth:`phis` equals phi(t) A^k (k = 1, 2: the Jordan block gives
    NIL, then 0); NIL^2 = A NIL = NIL A = 0 (NIL = A P0 on the rigid modes, positions only);
    det Phi(t) = exp(tr(A) t) (Liouville)."""
    flow = LinearFlow.of(MODELS[name])
    A, NIL, n = np.asarray(flow.A, dtype=float), flow.NIL, flow.n
    for t in (0.3, 4.1, 25.0):
        P0, P1, P2 = flow.phis(t, 2)
        scale = np.abs(P0).max()
        np.testing.assert_allclose(P0, flow.phi(t), atol=0, rtol=0)
        np.testing.assert_allclose(P1, P0 @ A, atol=1e-13 * scale * np.abs(A).max())
        np.testing.assert_allclose(P2, P0 @ A @ A, atol=1e-13 * scale * np.abs(A).max() ** 2)
        assert np.linalg.det(P0) == pytest.approx(math.exp(np.trace(A) * t), rel=1e-12)
    for prod in (NIL @ NIL, A @ NIL, NIL @ A):
        assert np.abs(prod).max() < 1e-14
    assert not NIL[:, :n].any() and not NIL[n:].any()     # (x, v) -> (G v, 0)


@pytest.mark.parametrize("name", ["free-one", "pair", "damped-free", "mixed"])
def test_mpmath_flow_agrees(name):
    """The mpmath flow (30 digits) builds the same exact form (no eig on a defective A)."""
    model = MODELS[name]
    f64, fmp = LinearFlow.of(model), LinearFlow.of(model, digits=30)
    assert fmp.free == f64.free
    with mpmath.workdps(30):
        P = np.array(fmp.phi(mpmath.mpf("6.5")), dtype=float)
    np.testing.assert_allclose(P, _ivp_phi(np.asarray(f64.A, dtype=float), 6.5), atol=1e-9)
    np.testing.assert_allclose(f64.phi(6.5), P, atol=1e-13 * np.abs(P).max())


def test_models_without_free_modes_keep_their_modal_form():
    """No free mode: NIL is zero and the flow is the modal sum, as before (the zoo)."""
    for model in list(N_MASS_SET.values()) + [THREE_STOP2_GAP12, TWO_OVERDAMPED]:
        flow = LinearFlow.of(model)
        assert not flow.free and not np.any(flow.NIL)
        assert len(cf.constants(model, 1.3)) == cf.size(model.n, len(model.constraints))
        assert cf.constants(model, 1.3)[cf._FREE] == 0.0
        assert len(flow.modal64) == 4


@pytest.mark.parametrize("name", sorted(MODELS))
def test_flight_with_forcing_against_solve_ivp(name):
    """A whole forced flight: z(t), dz/dtau and dz/dt of :meth:`flight`, the Python
    :class:`Motion`, and the compiled state at the finder's stop, against DOP853."""
    model, omega = MODELS[name], OMEGA[name]
    flow = LinearFlow.of(model)
    n = flow.n
    F = flow.forcing(omega)
    p = list(flow.perm)
    Minv = np.linalg.inv(np.asarray(flow.M, dtype=float))
    K, C, P = (np.asarray(a, dtype=float) for a in (flow.K, flow.C, flow.P))
    rng = np.random.default_rng(3)
    z0, tau, t = rng.uniform(-1, 1, 2 * n), 0.7, 8.3

    def rhs(s, z, tau=tau):
        return np.concatenate([z[n:], Minv @ (P * math.sin(omega * s + tau) - K @ z[:n]
                                              - C @ z[n:])])
    ref = solve_ivp(rhs, (0, t), z0, **TOL).y[:, -1]
    z, Phi, dtau, dt = flow.flight(F, z0, tau, t)
    np.testing.assert_allclose(z, ref, atol=1e-10)
    np.testing.assert_allclose(flow.motion(F, z0, tau).state(t), ref, atol=1e-10)
    np.testing.assert_allclose(dt, rhs(t, ref), atol=1e-9)
    h = 1e-6
    zt = [solve_ivp(lambda s, y, a=a: rhs(s, y, a), (0, t), z0, **TOL).y[:, -1]
          for a in (tau + h, tau - h)]
    np.testing.assert_allclose(dtau, (zt[0] - zt[1]) / (2 * h), atol=1e-5)
    # the compiled flight: from a section point of the first stop, to its finder's stop
    c = cf.constants(model, omega)
    y = np.zeros(2 * n)
    y[0], y[-1] = -0.4, tau
    st, te, zc, _, _, _ = cf.first_impact_from(c, y, t_max=5.0)
    zs = state(model, c, y, 0)                          # mass order
    ref = solve_ivp(lambda s, zz: _rhs_mass(model, omega, tau, s, zz), (0, te), zs,
                    **TOL).y[:, -1]
    np.testing.assert_allclose(zc, np.concatenate([ref[:n][p], ref[n:][p]]), atol=1e-10)


def _rhs_mass(model, omega, tau, t, z):
    n = model.n
    Minv = np.linalg.inv(np.asarray(model.mass, dtype=float))
    K, C, P = (np.asarray(a, dtype=float) for a in (model.stiffness, model.damping,
                                                     model.forcing))
    return np.concatenate([z[n:], Minv @ (P * math.sin(omega * t + tau) - K @ z[:n]
                                          - C @ z[n:])])


def _reference(model, omega, z0, tau, n_impacts):
    """Impacts (time, constraint, state just after, mass order) by DOP853 with one event
    per guard (max step 0.02: two crossings within one step are not missed), the rigid
    reset at each."""
    n = model.n
    Minv = np.linalg.inv(np.asarray(model.mass, dtype=float))
    cons = model.constraints
    events = []
    for con in cons:
        def ev(t, z, con=con):
            return con.guard(z[:n])
        ev.terminal, ev.direction = True, 1.0
        events.append(ev)
    t0, z, out, last = 0.0, np.array(z0, dtype=float), [], None
    while len(out) < n_impacts:
        sol = solve_ivp(lambda s, zz: _rhs_mass(model, omega, tau, s, zz), (t0, t0 + 200),
                        z, events=events, max_step=0.02, first_step=1e-6, method="DOP853",
                        rtol=1e-13, atol=1e-13)
        hit = [(sol.t_events[g][0], g) for g in range(len(cons)) if len(sol.t_events[g])
               and not (g == last and sol.t_events[g][0] - t0 < 1e-9)]
        assert hit, "no impact within 200 time units"
        te, g = min(hit)
        ze = sol.y_events[g][0]
        R = cons[g].reset_matrix(Minv)
        z = np.concatenate([ze[:n], R @ ze[n:]])
        out.append((te, g, z.copy()))
        t0, last = te, g
    return out


@pytest.mark.parametrize("name", ["free-one", "pair-cprop", "damped-free", "damper"])
def test_run_with_impacts_against_solve_ivp(name):
    """simulate (the compiled run loop) from a point of the first stop's section: the
    impact times, the stop hit and the states after each impact agree with DOP853 + events
    over 15 impacts; the impact damper's free mass bounces between its walls while the
    primary mass hits its own stop."""
    model, omega = MODELS[name], OMEGA[name]
    n = model.n
    y0 = np.zeros(2 * n)
    y0[0], y0[-1] = -0.3, 0.4
    sim = simulate(model, omega, y0=y0, n_impacts=15)
    assert sim.stop == "completed" and len(sim.section) == 15
    c = cf.constants(model, omega)
    ref = _reference(model, omega, state(model, c, y0, 0), y0[-1], 15)
    for i, (te, g, z) in enumerate(ref):
        assert sim.hits[i] == g
        assert abs(sim.t[i] - te) < 1e-8 * (1 + te)
        np.testing.assert_allclose(state(model, c, sim.section[i], g), z, atol=1e-8)
    if name == "damper":
        assert set(sim.hits) == {0, 1, 2}


def test_python_finder_and_map_match_the_compiled_ones():
    """One stop: the Python map (Motion and its finder, with the drift) and the compiled
    step agree, and both tangent maps match (central differences of the compiled map)."""
    from symvi.maps import impact
    model = Model(mass=[1.0, 1.5], stiffness=[[2.0, -2.0], [-2.0, 2.0]], forcing=[1.0, 0.2],
                  stop=Stop(mass=1, gap=0.5, restitution=0.8))
    omega = 1.1
    c = cf.constants(model, omega)
    y = np.array([-0.2, 0.3, 0.1, 0.4])
    st, te, yc, _, _, _, _ = cf.step(c, y)
    assert cf.STATUS_NAMES[st] == "impact"
    flow = LinearFlow.of(model)
    F = flow.forcing(omega)
    n = flow.n
    z0 = np.array([0.5, y[1], y[0], y[2]])
    fi = flow.motion(F, z0, y[3]).first_impact()
    assert fi.status == "impact" and fi.t == pytest.approx(te, rel=1e-12, abs=1e-12)
    zc = cf.first_impact_from(c, y)[2]
    np.testing.assert_allclose(fi.state, zc, atol=1e-12)
    r = impact.step(flow, F, y)                      # the Python map P
    assert r.status == "impact" and r.t == pytest.approx(te, rel=1e-12)
    np.testing.assert_allclose(np.asarray(r.y, dtype=float), yc, atol=1e-11)
    J = cf.jacobian_tangent(c, y)
    h = 1e-7
    for j in range(2 * n):
        e = np.eye(2 * n)[j] * h
        fd = (cf.step(c, y + e)[2] - cf.step(c, y - e)[2]) / (2 * h)
        np.testing.assert_allclose(J[:, j], fd, atol=1e-6)


def test_a_free_mass_leaving_its_only_stop_never_returns():
    """Nothing forces the free mass (M2 = 0, h linear): both finders say no impact, at
    t_max, without dividing by M2 = 0."""
    model = Model(mass=[1.0, 0.3], stiffness=[[1.0, 0.0], [0.0, 0.0]], forcing=[1.0, 0.0],
                  stop=Stop(mass=2, gap=0.2, restitution=0.8))
    flow = LinearFlow.of(model)
    F = flow.forcing(1.3)
    z0 = np.array([0.2, 0.1, -0.5, 0.3])              # the free mass (first) leaving
    fi = flow.motion(F, z0, 0.0).first_impact(t_max=50.0)
    assert fi.status == "no-impact" and fi.state[0] == pytest.approx(0.2 - 0.5 * 50.0)
    c = cf.constants(model, 1.3, t_max=50.0)
    st, t, z, _, _, _ = cf.first_impact_from(c, np.array([-0.5, 0.1, 0.3, 0.0]))
    assert cf.STATUS_NAMES[st] == "no-impact" and t > 50.0
    assert z[0] == pytest.approx(0.2 - 0.5 * t)


def test_phi_into_includes_the_drift():
    """The kernel helper for code that forms Phi itself (the shooting kernel) adds t NIL."""
    for model in (PAIR, MIXED, PAPER_EX1):
        flow = LinearFlow.of(model)
        lam, W, Winv, A, NIL = flow.modal_nil64
        out = np.empty((2 * flow.n, 2 * flow.n))
        for t in (0.4, 7.0):
            cf.phi_into(lam, W, Winv, NIL, t, out)
            np.testing.assert_allclose(out, flow.phi(t), atol=1e-13 * np.abs(out).max())


def test_modal64_refuses_a_free_model():
    """Code that forms Phi from (lambda, W, W^-1) alone would drop the drift: refused."""
    with pytest.raises(SingularCaseError, match="free"):
        LinearFlow.of(PAIR).modal64
    assert len(LinearFlow.of(DAMPED_FREE).modal64) == 4     # simple lambda = 0: modal


def test_the_rigid_mode_is_never_a_forcing_resonance():
    """omega_j = 0 for the rigid mode: no resonance at any omega > 0; the elastic mode's
    still is, and the steady response stays finite (K - omega^2 M + i omega C invertible)."""
    flow = LinearFlow.of(PAIR)
    assert flow.omegas[0] == 0.0
    for w in (1e-3, 0.05, 1.0, 3.0):
        assert flow.check_omega(w) == w
        F = flow.forcing(w)
        assert np.all(np.isfinite(F.U)) and np.all(np.isfinite(F.V))
    with pytest.raises(SingularCaseError, match="resonance"):
        flow.check_omega(float(flow.omegas[1]))
    d, _ = flow.one_minus_exp(1.1)                  # the rigid mode: 1 - e^{0} = 0
    assert d == 0.0


@pytest.mark.parametrize("name", ["free-one", "pair", "damper", "mixed"])
def test_the_finder_never_steps_over_a_contact(name):
    """From 150 random points of the first stop's section, the compiled finder's first
    contact (any guard) is the first sign change of the guards on a fine grid, sampled from
    Phi(t) (never from the finder's sums): none stepped over, none invented."""
    model, omega = MODELS[name], OMEGA[name]
    flow = LinearFlow.of(model)
    n = flow.n
    F = flow.forcing(omega)
    c = cf.constants(model, omega)
    rows = flow.constraint_rows()
    G = np.array([r[3:3 + n] for r in rows])
    level = np.array([r[2] for r in rows])
    rng = np.random.default_rng(7)
    k = 150
    ys = np.column_stack([rng.uniform(-1.5, -0.05, k), rng.uniform(-0.2, 0.2, (k, n - 1)),
                          rng.uniform(-1, 1, (k, n - 1)), rng.uniform(0, 2 * np.pi, k)])
    if n == 1:
        ys = ys[:, [0, -1]]
    Z0 = np.array([state(model, c, y, 0) for y in ys])       # mass order
    p = list(flow.perm)
    Z0 = np.hstack([Z0[:, :n][:, p], Z0[:, n:][:, p]])          # flow order
    zp0 = np.array([F.zp(y[-1], flow.bk) for y in ys])
    T, dt = 12.0, 2e-3
    grid = np.arange(1, int(T / dt) + 1) * dt
    first = np.full(k, np.inf)
    for t in grid:
        live = first == np.inf
        if not live.any():
            break
        zt = (Z0[live] - zp0[live]) @ flow.phi(t).T + np.array(
            [F.zp(omega * t + y[-1], flow.bk) for y in ys[live]])
        hit = ((zt[:, :n] @ G.T - level) >= 0).any(axis=1)
        idx = np.flatnonzero(live)[hit]
        first[idx] = t
    checked = 0
    for i in range(k):
        st, te, _, _, _, _ = cf.first_impact_from(c, ys[i], t_max=T)
        if first[i] < np.inf:
            assert te <= first[i] + 1e-12, "a contact stepped over"
            assert te > first[i] - dt - 1e-9 or cf.STATUS_NAMES[st] == "grazing"
            checked += 1
        else:
            assert te >= T - dt or cf.STATUS_NAMES[st] == "grazing"
    assert checked > 50


@pytest.mark.parametrize("name, omega", [("free-one", 1.3), ("damper", 2.0)])
def test_a_periodic_orbit_of_the_simulation_is_one_of_solve_ivp(name, omega):
    """The attractor of a long run (3000 impacts dropped) is periodic, with impacts on both
    walls; from one of its points, DOP853 with events returns to that point (section state
    and phase mod 2 pi) after the same impacts and the same time: the orbit of the exact
    flow is an orbit of the differential equation."""
    model = MODELS[name]
    n = model.n
    y0 = np.zeros(2 * n)
    y0[0], y0[-1] = -0.3, 0.4
    sim = simulate(model, omega, y0=y0, n_impacts=40, transient=3000)
    assert sim.stop == "completed"
    sec = sim.section
    p = next(q for q in range(1, 21) if np.abs(sec[q:q + 10] - sec[:10]).max() < 1e-10)
    assert {0, 1} <= set(sim.hits[:p])
    c = cf.constants(model, omega)
    # the orbit from sec[0] (on the section of the constraint it hit) for p impacts
    y, g0 = sec[0], sim.hits[0]
    ref = _reference(model, omega, state(model, c, y, g0), y[-1], p)
    te, g, z = ref[-1]
    assert [r[1] for r in ref] == list(sim.hits[1:p + 1])
    assert te == pytest.approx(sim.t[p] - sim.t[0], rel=1e-9)
    np.testing.assert_allclose(z, state(model, c, y, g0), atol=1e-8)
    d = (omega * te) % (2 * np.pi)                 # a whole number of forcing periods
    assert min(d, 2 * np.pi - d) < 1e-8


def test_the_mpmath_map_agrees_with_the_float_one():
    """The Python map on the mpmath flow (30 digits: Motion with the drift, its finder) and
    on float64 land on the same impact (what simulate_mp iterates)."""
    from symvi.maps import impact
    model = Model(mass=[1.0, 1.5], stiffness=[[2.0, -2.0], [-2.0, 2.0]], forcing=[1.0, 0.2],
                  stop=Stop(mass=1, gap=0.5, restitution=0.8))
    y = [-0.2, 0.3, 0.1, 0.4]
    f64 = LinearFlow.of(model)
    r64 = impact.step(f64, f64.forcing(1.1), np.array(y))
    with mpmath.workdps(30):
        fmp = LinearFlow.of(model, digits=30)
        rmp = impact.step(fmp, fmp.forcing(mpmath.mpf("1.1")), fmp.bk.arr(y))
    assert rmp.status == r64.status == "impact"
    assert float(rmp.t) == pytest.approx(r64.t, rel=1e-12)
    np.testing.assert_allclose(np.array(rmp.y, dtype=float), r64.y, atol=1e-11)


def test_the_compiled_tangent_over_several_stops_is_the_derivative_of_the_map():
    """DP of the compiled map (the drift's t G u in the variation) against central
    differences, on the impact damper's walls and on the rigid pair's two stops."""
    for model, omega, y in ((DAMPER, 0.9, [-0.3, 0.1, 0.2, 0.4]),
                            (PAIR, 1.1, [-0.3, 0.2, 0.1, 0.4])):
        c = cf.constants(model, omega)
        y = np.array(y)
        J = cf.jacobian_tangent(c, y)
        h = 1e-7
        for j in range(len(y)):
            e = np.eye(len(y))[j] * h
            a, b = cf.step(c, y + e), cf.step(c, y - e)
            assert a[-1] == b[-1] == cf.step(c, y)[-1]          # the same stop hit
            np.testing.assert_allclose(J[:, j], (a[2] - b[2]) / (2 * h), atol=1e-6)


def test_modal_form_is_the_flow_of_any_matrices():
    """:func:`symvi.flow.linear.modal_form` (the one construction, for the flow and for
    any (M, K, C), e.g. a contact phase's K_S) gives e^{At} with and without free modes."""
    from scipy.linalg import expm

    from symvi.flow.linear import modal_form
    from symvi.numerics.backend import FLOAT64
    M = np.diag([1.0, 1.5, 0.7])
    for K, C, jordan in (([[2, -2, 0], [-2, 2, 0], [0, 0, 0]], np.zeros((3, 3)), True),
                         ([[2, -2, 0], [-2, 2, 0], [0, 0, 0]], np.diag([0, 0, 0.3]), True),
                         ([[3, -1, 0], [-1, 2, -1], [0, -1, 1]], 0.02 * np.eye(3), False)):
        K, C = np.array(K, dtype=float), np.asarray(C, dtype=float)
        Mi = np.linalg.inv(M)
        A = np.block([[np.zeros((3, 3)), np.eye(3)], [-Mi @ K, -Mi @ C]])
        om, lam, W, Winv, NIL = modal_form(FLOAT64, M, K, C, A, bool(C.any()))
        for t in (0.5, 6.0):
            P = np.real((W * np.exp(lam * t)) @ Winv) + (0 if NIL is None else t * NIL)
            np.testing.assert_allclose(P, expm(A * t), atol=1e-12 * (1 + t))
        assert (NIL is not None) == jordan
