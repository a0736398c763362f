"""``simulate`` of a model with nonlinear forces (issue 28, first step): the impact Duffing
oscillator against solve_ivp with events over 50 impacts, the Simulation it returns, the
stop reasons, its start, and the one-line refusals of every analysis that rests on the
exact linear flow."""
import math

import numpy as np
import pytest

import symvi
from symvi.errors import ParameterError
from symvi.model import Model, Stop, dumps
from symvi.simulations.simulation import Simulation
from tests.fuzz._cli import cli

LIN = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
DUFFING = Model(**LIN, nonlinear=["beta*x1**3"], parameters={"beta": 0.5})
OMEGA, Y0 = 1.3, (-0.3, 0.1)


def _reference(n, omega=OMEGA, y0=Y0, beta=0.5, gap=0.5, r=0.8):
    """The same run by solve_ivp (DOP853, rtol 1e-13) with a terminal event per flight."""
    from scipy.integrate import solve_ivp

    def rhs(t, y, tau):
        return [y[1], math.sin(omega * t + tau) - 0.1 * y[1] - y[0] - beta * y[0] ** 3]
    ev = lambda t, y, tau: y[0] - gap                              # noqa: E731
    ev.terminal, ev.direction = True, 1
    z, tau, out = np.array([gap, y0[0]]), y0[1], []
    for _ in range(n):
        s = solve_ivp(rhs, (0, 1000), z, method="DOP853", rtol=1e-13, atol=1e-13,
                      events=ev, args=(tau,))
        te, ze = s.t_events[0][0], s.y_events[0][0]
        tau = (tau + omega * te) % (2 * math.pi)
        z = np.array([gap, -r * ze[1]])
        out.append((z[1], tau, te, ze[1]))
    return np.array(out)


def test_the_impact_duffing_oscillator_against_solve_ivp():
    """50 impacts: section points (v+, tau), flight times and impact speeds to 1e-9."""
    sim = symvi.simulate(DUFFING, OMEGA, y0=Y0, n_impacts=50)
    ref = _reference(50)
    assert isinstance(sim, Simulation) and sim.stop == "completed" and sim.n == 50
    assert np.abs(sim.section - ref[:, :2]).max() < 1e-9
    assert np.abs(np.diff(np.concatenate([[0.0], sim.t])) - ref[:, 2]).max() < 1e-9
    assert np.abs(sim.impact_velocity - ref[:, 3]).max() < 1e-9
    assert sim.fixed_point is None and (np.asarray(sim.hits) == 0).all()
    assert not sim.section.flags.writeable
    # the cubic spring matters: the linear model's run is elsewhere
    lin = symvi.simulate(Model(**LIN), OMEGA, y0=Y0, n_impacts=50)
    assert np.abs(lin.section - sim.section).max() > 1e-2


def test_transient_and_the_model_file(tmp_path):
    """A transient drops images as the compiled run does; the CLI runs the model file."""
    full = symvi.simulate(DUFFING, OMEGA, y0=Y0, n_impacts=30)
    tail = symvi.simulate(DUFFING, OMEGA, y0=Y0, n_impacts=10, transient=20)
    assert np.array_equal(tail.section, full.section[20:]) and tail.transient == 20
    assert np.array_equal(tail.t, full.t[20:])
    f = tmp_path / "duffing.toml"
    f.write_text(dumps(DUFFING))
    rc, out, err = cli("simulate", "--model", f, "--omega", OMEGA, "--y0", *Y0,
                       "--impacts", 30, "--out", tmp_path / "o.npz", "--json")
    assert rc == 0, err
    assert np.array_equal(np.load(tmp_path / "o.npz")["section"], full.section)


STUCK = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[0.05],
             stop=Stop(mass=1, gap=-0.2, restitution=0.5))


def test_a_run_held_for_good_stops_there():
    """The equilibrium lies past the gap: the impacts accumulate and the stop holds the
    mass for good (mu > 0 at every phase).  beta = 0: the run goes through the chatter to
    the sticking phase as the exact linear run does, and stops with the same reason."""
    m = Model(**STUCK, nonlinear=["beta*x1**3"], parameters={"beta": 0.0})
    sim = symvi.simulate(m, 1.0, y0=(-0.3, 0.0), n_impacts=200)
    lin = symvi.simulate(Model(**STUCK), 1.0, y0=(-0.3, 0.0), n_impacts=200)
    assert sim.stop == lin.stop == "sticking" and sim.stop_reason == lin.stop_reason
    assert "held on stop 1 for longer than" in sim.stop_reason
    assert 0 < sim.n < 200 and sim.sticks.shape == (1, 3) and np.isnan(sim.sticks[0, 1])
    assert abs(sim.sticks[0, 0] - lin.sticks[0, 0]) < 1e-9


def test_a_run_that_never_returns_stops_as_no_impact():
    """No forcing: the motion dies before it reaches the stop again, as the linear run."""
    kw = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.3]], forcing=[0.0],
              stop=Stop(mass=1, gap=0.5, restitution=0.5))
    m = Model(**kw, nonlinear=["beta*x1**3"], parameters={"beta": 0.0})
    sim = symvi.simulate(m, 1.0, y0=(-0.1, 0.0), n_impacts=200)
    lin = symvi.simulate(Model(**kw), 1.0, y0=(-0.1, 0.0), n_impacts=200)
    assert sim.stop == lin.stop == "no-impact" and sim.n == lin.n == 0


def test_the_start_defaults_and_is_checked():
    # no closed-form orbit to start near: the default start off the stop, as with several
    from symvi.simulations.simulation import default_start
    a, b = symvi.simulate(DUFFING, OMEGA, n_impacts=5), symvi.simulate(
        DUFFING, OMEGA, y0=default_start(DUFFING, OMEGA), n_impacts=5)
    assert a.n == 5 and np.array_equal(a.section, b.section)
    with pytest.raises(ParameterError, match="^y0 .*must leave the stop"):
        symvi.simulate(DUFFING, OMEGA, y0=(0.3, 0.1))
    with pytest.raises(ParameterError, match="^omega"):
        symvi.simulate(DUFFING, float("nan"), y0=Y0)
    with pytest.raises(ParameterError, match="^n_impacts"):
        symvi.simulate(DUFFING, OMEGA, y0=Y0, n_impacts=0)


@pytest.mark.parametrize("argv, out", [
    (("orbit", "--omega", "1.3"), None),
    (("hopf", "--range", "omega=1.2:1.4"), None),
    (("sweep", "--range", "omega=1.0:1.5:3", "--out", "sw.npz"), "sw.npz"),
    (("plane", "--x", "omega=1:1.5:2", "--y", "beta=0.4:0.6:2", "--impacts", "50",
      "--transient", "10", "--out", "p.zarr", "--workers", "0"), "p.zarr"),
])
def test_the_command_line_runs_a_nonlinear_model(tmp_path, argv, out):
    """Issue 28: orbit, hopf, sweep and plane take a model with nonlinear forces (the
    homotopy from the linear part, the branch scan, runs of the numerical flow); their
    JSON says what is not certified.  (curve: tests/curves/test_nonlinear_curves.py.)"""
    import json
    f = tmp_path / "duffing.toml"
    f.write_text(dumps(DUFFING))
    rc, stdout, err = cli(*argv, "--model", f, "--json", cwd=tmp_path)
    assert rc == 0, err
    obj = json.loads(stdout)
    if argv[0] == "orbit":
        assert obj["orbits"] and "not complete" in obj["found"]
    if argv[0] == "hopf":
        assert obj["complete"] is False and "forces' scale" in obj["uncertified_reasons"][0]
    if out:
        assert (tmp_path / out).exists()


REFUSED = "model = 'nonlinear' is invalid; valid range: a linear model: with nonlinear " \
          "forces this analysis is a later step of issue 28 (simulate, orbit, continue, " \
          "curve, hopf, sweep and plane run them)"


def test_the_python_analyses_refuse_a_nonlinear_model():
    from symvi.orbits import admissible_orbits
    for call in (lambda: admissible_orbits(DUFFING, OMEGA),
                 lambda: symvi.jet(DUFFING, OMEGA)):
        with pytest.raises(ParameterError) as exc:
            call()
        assert str(exc.value) == REFUSED


def test_lyapunov_exponents_and_the_classifier_of_a_nonlinear_run():
    """The exponents of a run settled on a period-1 orbit tend to log |mu| of its multipliers
    (DP of each flight from its series), and the classifier names the orbit."""
    from symvi.orbits.periodic import periodic_orbit
    from symvi.simulations.diagnostics import classify, lyapunov
    sim = symvi.simulate(DUFFING, OMEGA, y0=Y0, n_impacts=200, transient=2000)
    orbit = periodic_orbit(DUFFING, n=1, p=1, guess=sim, omega=OMEGA)
    want = sorted((math.log(abs(z)) for z in orbit.multipliers), reverse=True)
    got = lyapunov(sim).exponents
    # the sum is log |det DP| at every step; each exponent converges like 1/n (QR)
    assert abs(sum(got) - sum(want)) < 1e-9
    assert np.allclose(got, want, atol=5e-3)
    c = classify(sim)
    assert c.kind == "period-1" and c.period == 1


def test_poincare_map_of_a_nonlinear_model_is_one_impact_of_a_run():
    """symvi.poincare_map on the numerical flow: P(y0) is the first stored impact of a run
    from y0, and the period-1 orbit Newton found maps to itself; digits are refused."""
    st = symvi.poincare_map(DUFFING, OMEGA, Y0)
    run = symvi.simulate(DUFFING, OMEGA, y0=Y0, n_impacts=1)
    assert st.status == "impact" and st.impact_velocity > 0
    assert np.max(np.abs(np.subtract(st.y, run.section[0]))) < 1e-12
    assert abs(st.t - run.t[0]) < 1e-12
    from symvi.continuation.homotopy import period1_orbits
    o = period1_orbits(DUFFING, OMEGA).orbits[0]
    back = symvi.poincare_map(DUFFING, OMEGA, o.y)
    assert np.max(np.abs(np.subtract(back.y, o.y))) < 1e-11 and back.t == pytest.approx(
        2 * math.pi / OMEGA, rel=1e-12)
    with pytest.raises(ParameterError, match="^digits"):
        symvi.poincare_map(DUFFING, OMEGA, Y0, digits=30)
