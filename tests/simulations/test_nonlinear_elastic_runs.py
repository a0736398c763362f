"""Runs of models with elastic stops and nonlinear forces (issue 28 with issue 25's contact
phases): simulate's records against the exact linear walk with the nonlinearity off (1e-12)
and against solve_ivp on the piecewise ODE, sweeps with the classifier, the attractor's
orbit and its multipliers, the command line, and the one-line refusals."""
import json
import math

import numpy as np
import pytest

from symvi import Model
from symvi.errors import ParameterError
from symvi.flow import contact as ct
from symvi.model import Signature, Stop, dumps
from symvi.simulations.simulation import _simulate_contacts, simulate, sweep
from tests.flow.test_nonlinear_elastic import _ONE, _TWO, CHAIN, DUFFING, reference
from tests.fuzz._cli import assert_bad_input, cli

LIN_ONE, OFF_ONE = Model(**_ONE), Model(**_ONE, nonlinear=["0*x1**3"])
LIN_TWO = Model(**_TWO, stops=CHAIN.stops)
OFF_TWO = Model(**_TWO, nonlinear=["0*beta*x1**3", "0"], parameters={"beta": 0.3},
                stops=CHAIN.stops)
#: starts on the first stop's section: entering the elastic stop (v1+ > 0; v2 < 0 for the
#: lower stop on mass 2 of the chain, whose layout is (v2, x1, v1, tau))
Y_ONE, Y_TWO = (0.8, 0.2), (-0.4, 0.1, 0.0, 0.3)


def _close(a, b, rel=1e-12):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape
    assert np.array_equal(np.isnan(a), np.isnan(b))
    ok = ~np.isnan(a)
    scale = np.max(np.abs(a[ok])) if ok.any() else 1.0
    assert np.all(np.abs(a[ok] - b[ok]) <= rel * np.maximum(np.abs(a[ok]), 1e-3 * scale))


@pytest.mark.parametrize("lin,off,y0", [(LIN_ONE, OFF_ONE, Y_ONE), (LIN_TWO, OFF_TWO, Y_TWO)])
def test_nonlinearity_off_equals_the_exact_walk(lin, off, y0):
    """With the nonlinear coefficient 0 every record of simulate (section points, times,
    approach speeds, hits, exit times and speeds, every event) equals the exact linear
    walk's (_simulate_contacts of the model without nonlinear forces) to 1e-12 relative."""
    a = _simulate_contacts(lin, 1.2, y0, 30, 5)
    b = simulate(off, 1.2, y0=y0, n_impacts=30, transient=5)
    assert a.stop == b.stop == "completed" and a.n == b.n == 30
    np.testing.assert_array_equal(a.hits, b.hits)
    for name in ("section", "t", "impact_velocity", "exit_t", "exit_velocity"):
        _close(getattr(a, name), getattr(b, name))
    _close(a.events.section, b.events.section)
    _close(a.events.t, b.events.t)
    np.testing.assert_array_equal(a.events.hits, b.events.hits)
    assert a.events.active == b.events.active


def test_duffing_records_match_solve_ivp():
    """simulate's records of the impact Duffing oscillator with an elastic stop: each entry
    (time, approach speed, the section point keeping the velocity) and its exit (time and
    speed) against DOP853 (rtol 1e-13) on the piecewise ODE, to 1e-9."""
    sim = simulate(DUFFING, 1.3, y0=Y_ONE, n_impacts=6)
    assert sim.stop == "completed" and sim.n == 6
    ref = reference(DUFFING, 1.3, np.array([0.5, Y_ONE[0]]), Y_ONE[1], 14, active=(0,))
    exits = [r for r in ref if r[0] == ct.EXIT]
    entries = [r for r in ref if r[0] == ct.ENTRY]
    for j in range(6):
        # records are the entries after the start's (ref: the start's exit, then pairs)
        _, _, te, zb = entries[j]
        assert abs(sim.t[j] - te) < 1e-9 and abs(sim.impact_velocity[j] - zb[1]) < 1e-9
        assert abs(sim.section[j, 0] - zb[1]) < 1e-9
        assert abs(sim.exit_t[j] - exits[j + 1][2]) < 1e-9
        assert abs(sim.exit_velocity[j] - exits[j + 1][3][1]) < 1e-9
        assert sim.exit_velocity[j] < 0


def test_two_masses_with_a_cubic_spring_and_both_stop_kinds():
    """The 2-DOF chain (a cubic spring, an elastic lower stop, a rigid upper one): the
    records meet both stops, rigid impacts have no exit, contacts one each; the transient
    drops records and keeps the rest."""
    full = simulate(CHAIN, 1.2, y0=Y_TWO, n_impacts=30)
    part = simulate(CHAIN, 1.2, y0=Y_TWO, n_impacts=20, transient=10)
    assert full.stop == "completed" and set(np.unique(full.hits)) == {0, 1}
    assert np.all(np.isnan(full.exit_t) == (full.hits == 1))
    assert np.all(full.exit_t[full.hits == 0] > full.t[full.hits == 0])
    np.testing.assert_array_equal(part.section, full.section[10:])
    np.testing.assert_array_equal(part.exit_t, full.exit_t[10:])


def test_sweep_and_classifier_with_the_nonlinearity_off_and_on():
    """The classified sweep (the classifier's Lyapunov exponents from each event's DP, the
    contact phases' series) equals the linear model's with the nonlinearity off; with
    beta = 0.5 every omega runs and is labelled."""
    omegas = [1.2, 1.3]
    a = sweep(LIN_ONE, omegas, n_impacts=40, transient=100, classify=True)
    b = sweep(OFF_ONE, omegas, n_impacts=40, transient=100, classify=True)
    assert list(a.labels()) == list(b.labels())
    np.testing.assert_allclose(b.classes.lyapunov, a.classes.lyapunov, rtol=1e-9)
    c = sweep(DUFFING, omegas, n_impacts=40, transient=100, classify=True)
    assert c.stops == ("completed", "completed") and all(c.labels())
    assert np.all(np.isfinite(c.classes.lyapunov))


def test_the_attractor_orbit_and_its_multipliers():
    """The attractor's orbit (shooting through the phases' series flights): with the
    nonlinearity off the exact walk's orbit and multipliers; with beta = 0.5 a fixed point
    of the run (its last records) whose multipliers give the Lyapunov exponents' sum."""
    from symvi.continuation import attractor_orbit
    from symvi.simulations.diagnostics import lyapunov
    lin, off = attractor_orbit(LIN_ONE, 1.3), attractor_orbit(OFF_ONE, 1.3)
    assert (lin.n, lin.p) == (off.n, off.p)
    np.testing.assert_allclose(off.points, lin.points, rtol=0, atol=1e-10)
    np.testing.assert_allclose(sorted(off.multipliers, key=lambda z: (z.real, z.imag)),
                               sorted(lin.multipliers, key=lambda z: (z.real, z.imag)),
                               atol=1e-9)
    o = attractor_orbit(DUFFING, 1.3)
    assert o.stable and o.admissible and o.itinerary.names(DUFFING) == \
        ["stop1:entry", "stop1:exit"]
    sim = simulate(DUFFING, 1.3, y0=o.points[0][:-1] + (o.points[0][-1],), n_impacts=40,
                   transient=200)
    np.testing.assert_allclose(sim.section[-1], o.points[0], rtol=0, atol=1e-8)
    got = lyapunov(sim).exponents
    want = sum(math.log(abs(z)) for z in o.multipliers) / o.p
    assert abs(sum(got) - want) < 1e-6


@pytest.mark.slow
def test_continue_with_the_nonlinearity_off_finds_the_linear_special_points(tmp_path):
    """symvi continue on elastic + nonlinear: the branch of 1-2 orbits and its flips (jets
    by the phases' series) are the linear model's with the nonlinearity off."""
    outs = []
    for m in (LIN_ONE, OFF_ONE):
        f = tmp_path / "m.toml"
        f.write_text(dumps(m))
        rc, out, err = cli("continue", "--model", f, "--range", "omega=1.3:0.9", "--orbit",
                           "1-2", "--max-points", "400", "--json")
        assert rc == 0, err
        outs.append(json.loads(out))
    pts = [[(s["kind"], s["value"], s["coefficients"]["c"]) for s in o["special"]]
           for o in outs]
    assert [k for k, *_ in pts[0]] == [k for k, *_ in pts[1]] == ["flip", "flip"]
    np.testing.assert_allclose([p[1:] for p in pts[1]], [p[1:] for p in pts[0]], rtol=1e-8)


def test_the_command_line_runs_it(tmp_path):
    f = tmp_path / "duffing.toml"
    f.write_text(dumps(DUFFING))
    rc, out, err = cli("simulate", "--model", f, "--omega", "1.3", "--y0", "0.8", "0.2",
                       "--impacts", "10", "--out", tmp_path / "run.npz")
    assert rc == 0, err
    assert (tmp_path / "run.npz").exists()
    rc, out, err = cli("orbit", "--model", f, "--omega", "1.3")
    assert rc == 0, err
    assert "stop1:entry, stop1:exit" in out


@pytest.mark.parametrize("name", ["restitution", "stop[2].gap"])
def test_a_parameter_the_model_does_not_have_is_refused_in_one_line(tmp_path, name):
    """The phases' series take every parameter of the model (an elastic stop's stiffness
    and an entry of K included: tests/flow/test_nonlinear_elastic_params.py); a name the
    model does not have (a restitution of its elastic stop, a second stop) is refused in
    one line naming it, exit 2."""
    f = tmp_path / "duffing.toml"
    f.write_text(dumps(DUFFING))
    assert_bad_input(cli("continue", "--model", f, "--range", f"{name}=0.5:0.6",
                         "--set", "omega=1.3", "--orbit", "1-2"), name)


def test_refusals_in_one_line():
    """No start: refused, as for the linear walk; the rigid run loop of NonlinearFlow names
    the stop (its elastic phases run in the walk)."""
    from symvi.flow.nonlinear import NonlinearFlow
    with pytest.raises(ParameterError, match=r"^y0 = None .*elastic stop") as e:
        simulate(DUFFING, 1.3, n_impacts=5)
    assert "\n" not in str(e.value)
    with pytest.raises(ParameterError, match=r"^stop = .*symvi.flow.nlcontact") as e:
        NonlinearFlow(DUFFING)
    assert "\n" not in str(e.value)
    from symvi.orbits.periodic import Problem
    with pytest.raises(ParameterError, match=r"^parameter = 'restitution'.*elastic"):
        Problem(DUFFING, 1, 2, omega=1.3, param="restitution",
                signature=Signature((0, 0), contact=(0,)))


def test_a_force_not_finite_along_the_motion_ends_the_walk_as_non_finite():
    """sqrt(x1) with the elastic stop at 0: the phase's series stop being finite at once
    (a division by the zero leading coefficient); the walk ends "non-finite", not as no
    impact or a sticking."""
    model = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                  stop=Stop(mass=1, gap=0.0, stiffness=50.0, damping=0.5),
                  nonlinear=["beta*sqrt(x1)"], parameters={"beta": 1.0})
    run = simulate(model, 1.3, y0=(0.8, 0.2), n_impacts=5)
    assert run.stop == "non-finite"
