"""The numerical flow of a model with nonlinear forces (issue 28,
:mod:`symvi.flow.nonlinear`, its Taylor method by default): the nonlinearity off against
the exact linear flow, one flight against mpmath's Taylor integrator at 30 digits and
against SciPy's DOP853, the forces' program against SymPy, the Bernstein bound that finds
every contact of DOP853's dense output, and every rigid constraint (between masses, a
two-sided clearance) against the exact flow and solve_ivp with events."""
import math

import mpmath
import numpy as np
import pytest
import sympy

from symvi.errors import ParameterError
from symvi.flow import compiled as cf
from symvi.flow import nonlinear as nl
from symvi.flow.linear import LinearFlow
from symvi.model import Model, Stop

ONE = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
TWO = dict(mass=[1.0, 2.0], stiffness=[[2.0, -1.0], [-1.0, 1.5]],
           damping=[[0.05, 0.0], [0.0, 0.05]], forcing=[1.0, 0.3],
           stops=[Stop(mass=1, gap=0.5, restitution=0.8),
                  Stop(mass=2, gap=-0.4, side="lower", restitution=0.7)])


def _rel(a, b):
    return float(np.max(np.abs(np.asarray(a) - b) / np.maximum(1.0, np.abs(b))))


@pytest.mark.parametrize("kw, forces, omega, y0", [
    (ONE, ["beta*x1**3"], 1.3, (-0.3, 0.1)),
    (TWO, ["beta*x1**3", "beta*x2*v2**2 + beta*sin(x1)"], 1.1, (-0.3, 0.1, 0.0, 0.2)),
])
def test_nonlinearity_off_equals_the_exact_linear_flow(kw, forces, omega, y0):
    """beta = 0: 100 impacts (times, section points, stops hit) as the exact flow's, to
    1e-12 relative (issue 28, "Nonlinearity off")."""
    m = Model(**kw, nonlinear=forces, parameters={"beta": 0.0})
    code, sec, t, vimp, hits, _ = nl.NonlinearFlow(m).run(omega, y0, 100)
    c = cf.constants(Model(**kw), omega)
    code0, sec0, t0, vimp0, _, hits0 = cf.run(c, y0, 100, 0, hits=True)
    assert code == code0 == cf.COMPLETED and len(sec) == 100
    assert (hits == hits0).all()
    if len(kw.get("stops", ())) > 1:
        assert 0 < hits.sum() < 100                     # both stops are hit
    assert _rel(sec, sec0) < 1e-12
    assert _rel(t, t0) < 1e-12 and _rel(vimp, vimp0) < 1e-12
    # and the force is used: beta = 0.5 moves the impacts
    code, sec5, *_ = nl.NonlinearFlow(m.with_(beta=0.5)).run(omega, y0, 100)
    assert _rel(sec5, sec0) > 1e-3


def _mp_duffing(omega, tau, z0, beta=0.5):
    mpmath.mp.dps = 30
    b, c = mpmath.mpf(beta), mpmath.mpf("0.1")
    return mpmath.odefun(lambda t, y: [y[1], mpmath.sin(omega * t + tau) - c * y[1] - y[0]
                                       - b * y[0] ** 3], 0, [mpmath.mpf(v) for v in z0])


def test_one_flight_against_mpmath_at_30_digits():
    """The Duffing oscillator's flight of 2.5 time units against mpmath.odefun (a Taylor
    method) at 30 digits: 1e-13 relative."""
    m = Model(**ONE, nonlinear=["beta*x1**3"], parameters={"beta": 0.5})
    omega, tau, z0, T = 1.3, 0.1, (0.5, -0.3), 2.5
    z = nl.NonlinearFlow(m).state(omega, z0, tau, T)
    with mpmath.workdps(30):
        ref = np.array([float(v) for v in _mp_duffing(omega, tau, z0)(T)])
    assert _rel(z, ref) < 1e-13


def test_first_impact_against_solve_ivp_dop853():
    """The first contact's time and state against solve_ivp (DOP853, rtol 1e-13) with an
    event: 1e-11."""
    from scipy.integrate import solve_ivp
    m = Model(**ONE, nonlinear=["beta*x1**3 + 0.2*sin(v1)"], parameters={"beta": 0.5})
    omega, tau, z0 = 1.3, 0.1, (0.5, -0.3)
    status, te, con, ze = nl.NonlinearFlow(m).first_impact(omega, z0, tau, just_hit=0)

    def rhs(t, y):
        return [y[1], math.sin(omega * t + tau) - 0.1 * y[1] - y[0] - 0.5 * y[0] ** 3
                - 0.2 * math.sin(y[1])]
    ev = lambda t, y: y[0] - 0.5                                  # noqa: E731
    ev.terminal, ev.direction = True, 1
    s = solve_ivp(rhs, (0, 100), z0, method="DOP853", rtol=1e-13, atol=1e-13, events=ev)
    assert status == "impact" and con == 0
    assert abs(te - s.t_events[0][0]) < 1e-11 * te
    assert _rel(ze, s.y_events[0][0]) < 1e-11


def test_the_program_evaluates_the_forces_as_sympy_does():
    """The postfix program of a composite force against SymPy's own evaluation, and x**3
    at x = 0 is 0 (no NaN)."""
    text = ["beta*x1**3 - x2**-2*exp(-v1) + sqrt(1 + v2**2)*atan(x1) + x1**2.5",
            "tanh(v1)*cosh(x2)/sinh(1 + x1**2) + log(2 + cos(x1))*tan(v2/3) + pi*v1**3"]
    m = Model(**{**TWO, "stops": TWO["stops"][:1]}, nonlinear=text, parameters={"beta": 0.3})
    f = nl.NonlinearFlow(m)
    syms = sympy.symbols("x1 x2 v1 v2 beta", real=True)
    for z in ((0.3, 0.7, -0.2, 0.4), (1.1, -0.4, 0.5, -1.3)):
        vals = dict(zip(syms, (*z, 0.3)))
        ref = [float(e.subs(vals)) for e in
               Model(**{**TWO, "stops": TWO["stops"][:1]}, nonlinear=text,
                     parameters={"beta": 0.3}).nonlinear]
        out = f.rhs(1.0, 0.0, 0.0, z)                 # sin(0) = 0: no forcing
        x, v = np.array(z[:2]), np.array(z[2:])
        acc = np.linalg.solve(m.mass, -m.damping @ v - m.stiffness @ x - np.array(ref))
        assert np.allclose(out[2:], acc, rtol=1e-14, atol=1e-14)
    cubic = nl.NonlinearFlow(Model(**ONE, nonlinear=["x1**3"]))
    assert cubic.rhs(1.0, 0.0, 0.0, (0.0, 0.0))[1] == 0.0


def _bernstein(coeffs):
    p = np.zeros(8)
    p[:len(coeffs)] = coeffs
    b = np.empty(8)
    nl._bernstein(p, b)
    return b


def test_the_bernstein_hull_finds_a_short_excursion():
    """A guard that peeks above 0 over a theta-interval of width 2e-4 between two samples
    of a fine grid is found; one whose maximum is -1e-9 is not."""
    stack, lohi = np.empty((96, 8)), np.empty((96, 2))
    # g = 1e-8 - (theta - a)^2: positive on (a - 1e-4, a + 1e-4)
    a = 0.30037
    g = [1e-8 - a * a, 2 * a, -1.0]
    assert not any(np.polyval(g[::-1], th) > 0 for th in np.linspace(0, 1, 1001))
    th = nl._first_root(_bernstein(g), stack, lohi)
    assert abs(th - (a - 1e-4)) < 1e-9
    assert nl._first_root(_bernstein([-1e-9 - a * a, 2 * a, -1.0]), stack, lohi) == -1.0
    # the leftmost of two roots
    g2 = np.polynomial.polynomial.polyfromroots([0.2, 0.25, 0.7, 0.9]) * -1
    th2 = nl._first_root(_bernstein(g2), stack, lohi)
    assert np.polyval(g2[::-1], 0.1) < 0 and abs(th2 - 0.2) < 1e-9


def test_what_it_does_not_take_yet():
    with pytest.raises(ParameterError, match="^stop = .*rigid stops \\(this run loop.s"):
        nl.NonlinearFlow(Model(**{**ONE, "stop": Stop(mass=1, gap=0.5, stiffness=50.0)},
                               nonlinear=["x1**3"]))
    two = {**TWO, "stops": [Stop(between=(1, 2), gap=0.3, restitution=0.8)]}
    with pytest.raises(ParameterError, match="^method = 'dop853'.*a stop between masses"):
        nl.NonlinearFlow(Model(**two, nonlinear=["x1**3", "0"]), method="dop853")
    with pytest.raises(ParameterError, match="^method = 'rk4'"):
        nl.NonlinearFlow(Model(**ONE, nonlinear=["x1**3"]), method="rk4")


def test_the_exact_linear_flow_refuses_a_nonlinear_model():
    m = Model(**ONE, nonlinear=["beta*x1**3"], parameters={"beta": 0.5})
    for make in (lambda: LinearFlow.of(m), lambda: LinearFlow.free(m),
                 lambda: cf.constants(m, 1.3)):
        with pytest.raises(ParameterError) as exc:
            make()
        assert str(exc.value) == ("model = 'nonlinear' is invalid; valid range: a linear "
                                  "model: with nonlinear forces this analysis is a later "
                                  "step of issue 28 (simulate, orbit, continue, curve, hopf, sweep and plane run them)")


# --- every rigid constraint (issue 28, with issue 25's constraints) ------------------------
MASSES = dict(mass=[1.0, 2.0], stiffness=[[2.0, -1.0], [-1.0, 1.5]],
              damping=[[0.05, 0.0], [0.0, 0.05]], forcing=[1.0, 0.3])
BETWEEN = Stop(between=(1, 2), gap=0.3, restitution=0.8)
CLEARANCE = [BETWEEN, Stop(between=(1, 2), gap=-0.3, side="lower", restitution=0.7)]
CUBIC = ["beta*x1**3", "beta*(x2 - x1)**3"]


@pytest.mark.parametrize("stops", [[BETWEEN], CLEARANCE,
                                   [BETWEEN, Stop(mass=1, gap=0.6, restitution=0.9)]])
def test_constraints_between_masses_with_the_nonlinearity_off(stops):
    """An impact between the masses (guard x2 - x1 - g), a two-sided clearance as two
    constraints, and one with a stop on a mass: beta = 0 gives symvi.simulate's exact
    linear run of the same model without forces (section points in the flow's frame,
    times, impact speeds, constraints hit) to 1e-12 over 100 impacts."""
    import symvi
    y0 = (-0.3, 0.1, 0.0, 0.2)
    lin = symvi.simulate(Model(**MASSES, stops=stops), 1.1, y0=y0, n_impacts=100)
    m = Model(**MASSES, stops=stops, nonlinear=CUBIC, parameters={"beta": 0.0})
    sim = symvi.simulate(m, 1.1, y0=y0, n_impacts=100)
    assert sim.stop == lin.stop == "completed" and sim.n == lin.n == 100
    assert np.array_equal(sim.hits, lin.hits) and len(set(sim.hits)) == len(stops)
    assert _rel(sim.section, lin.section) < 1e-12
    assert _rel(sim.t, lin.t) < 1e-12 and _rel(sim.impact_velocity, lin.impact_velocity) < 1e-12
    # the table's mass column and the mass-order section indices are for stops on masses
    flow = nl.NonlinearFlow(m)
    assert np.isnan(flow.cons[0, 0]) and flow.sidx is None
    assert nl.NonlinearFlow(Model(**ONE)).sidx.tolist() == [[1]]


def _ivp_run(model, omega, z, tau, n, beta):
    """n impacts by solve_ivp (DOP853, rtol 1e-13) with a terminal event on every guard and
    the constraint's reset: (flight time, constraint, approach speed) of each."""
    from scipy.integrate import solve_ivp
    M, K, C, P = model.mass, model.stiffness, model.damping, model.forcing
    Minv = np.linalg.inv(M)
    cons = model.constraints

    def rhs(t, y, tau):
        x, v = y[:2], y[2:]
        f = beta * np.array([x[0] ** 3, (x[1] - x[0]) ** 3])
        return np.concatenate([v, Minv @ (P * math.sin(omega * t + tau) - C @ v - K @ x - f)])
    events = []
    for c in cons:
        ev = (lambda c: lambda t, y, tau: c.guard(y[:2]))(c)
        ev.terminal, ev.direction = True, 1
        events.append(ev)
    out = []
    for _ in range(n):
        s = solve_ivp(rhs, (0, 200), z, method="DOP853", rtol=1e-13, atol=1e-13,
                      events=events, args=(tau,))
        k = min((i for i in range(len(cons)) if len(s.t_events[i])),
                key=lambda i: s.t_events[i][0])
        te, ze = s.t_events[k][0], s.y_events[k][0]
        out.append((te, k, cons[k].approach(ze[2:])))
        z = np.concatenate([ze[:2], cons[k].reset_matrix(Minv) @ ze[2:]])
        tau = (tau + omega * te) % (2 * math.pi)
    return np.array(out)


def test_an_impact_between_masses_with_cubic_forces_against_solve_ivp():
    """Two masses, cubic springs to the ground and between them, a two-sided clearance
    between the masses with the two-body impact law (v+ = R v-, R = (I - Q) - r Q): 30
    impacts as solve_ivp's with events, flight times and impact speeds to 1e-9."""
    m = Model(**MASSES, stops=CLEARANCE, nonlinear=CUBIC, parameters={"beta": 0.5})
    flow = nl.NonlinearFlow(m)
    y0 = (-0.3, 0.1, 0.0, 0.2)
    code, sec, t, vimp, hits, _ = flow.run(1.1, y0, 30)
    ref = _ivp_run(m, 1.1, flow.start(y0), y0[-1], 30, 0.5)
    assert code == cf.COMPLETED and set(hits) == {0, 1}
    assert np.array_equal(hits, ref[:, 1].astype(int))
    assert np.abs(np.diff(np.concatenate([[0.0], t])) - ref[:, 0]).max() < 1e-9
    assert np.abs(vimp - ref[:, 2]).max() < 1e-9
    # the cubic forces matter
    lin = nl.NonlinearFlow(m.with_(beta=0.0)).run(1.1, y0, 30)
    assert np.abs(lin[2][:5] - t[:5]).max() > 1e-3
