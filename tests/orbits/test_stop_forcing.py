"""Models whose stop mass gets no steady-state forcing (issue 23, defect 4).

No forcing at all, forcing only on masses not coupled to the stop's mass, or an
anti-resonance of the stop's mass (the paper's model with mu_m = mu_k = 1/3, f2 = 0
at omega = 2: k2 - omega^2 m2 = 0): the phase columns of the period-1 conditions
vanish.  This divided by zero in the compiled kernel in every command.  Now: no
period-1 orbit, with the reason; SingularCaseError where the answer cannot be
decided; a warning near (not at) the anti-resonance; simulation from a given start
runs (free decay onto the stop is a legitimate run).
"""
import math
import warnings

import numpy as np
import pytest

from symvi.errors import NearSingularWarning, SingularCaseError
from symvi.model import Model, Stop
from symvi.orbits import period1 as p1
from symvi.simulations.simulation import STOP_NAMES, simulate, start_point

from ..fuzz._cli import assert_bad_input, cli

THIRD = 0.3333333333333333
ANTI = Model.luo_xie(THIRD, THIRD, 0, 1.5, 0.8)        # anti-resonance of mass 1 at omega = 2
UNCOUPLED = Model(mass=[1.0, 1.0], stiffness=[[1.0, 0.0], [0.0, 2.0]], forcing=[0.0, 1.0],
                  stop=Stop(mass=1, gap=0.5, restitution=0.8))
ZERO = Model(mass=[1.0, 1.5], stiffness=[[2.0, -1.0], [-1.0, 2.0]], forcing=[0.0, 0.0],
             stop=Stop(mass=1, gap=0.5, restitution=0.8))
ZERO_DAMPED = ZERO.with_(**{"damping[1,1]": 0.1, "damping[2,2]": 0.1})
CASES = {"anti-resonance": (ANTI, "anti-resonance"),
         "uncoupled": (UNCOUPLED, "not coupled to mass 1"),
         "zero": (ZERO, "no forcing"), "zero-damped": (ZERO_DAMPED, "no forcing")}

ANTI_FILE = """[model]
mass = [1.0, 1.0]
stiffness = [[1.0, 0.0], [0.0, 2.0]]
forcing = [0.0, 1.0]

[stop]
mass = 1
gap = 0.5
restitution = 0.8
"""


@pytest.mark.parametrize("name", sorted(CASES))
def test_no_steady_forcing_on_the_stop_mass_means_no_orbit_with_the_reason(name, monkeypatch):
    model, words = CASES[name]
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # and no numpy warning on the way
        assert p1.period1_orbits(model, 2.0) == []
        why = p1.no_orbit_reason(model, 2.0)
        assert words in why and "no period-1 one-impact orbit" in why
        assert p1.existence_ratio(model, 2.0) == math.inf
        assert p1.period1_orbits(model, 2.0, digits=30) == []
        monkeypatch.setattr(p1, "COMPILED", False)      # the numpy reference agrees
        assert p1.period1_orbits(model, 2.0) == []


def test_near_the_anti_resonance_orbits_are_computed_and_the_loss_is_said():
    # |X_1| ~ 1e-9 of the largest: resolved, not zero; a gap that small is reached
    small_gap = ANTI.with_(gap=1e-14)
    with pytest.warns(NearSingularWarning, match="anti-resonance"):
        orbits = p1.period1_orbits(small_gap, 2.0 + 1e-9)
    assert len(orbits) == 2 and all(np.isfinite(o.y).all() for o in orbits)
    # at the paper's gap the existence ratio is huge: no orbit, said with rho
    assert p1.period1_orbits(ANTI, 2.0 + 1e-9) == []
    assert "|rho|" in p1.no_orbit_reason(ANTI, 2.0 + 1e-9)


def test_undecidable_cases_are_singular_not_a_guess():
    # gap 0 at the exact anti-resonance: the only solution grazes the stop
    with pytest.raises(SingularCaseError, match="degenerate-forcing.*grazing"):
        p1.period1_orbits(ANTI.with_(gap=0.0), 2.0)
    # r = 1, no damping: I - E Phi is singular; a solution at every phase, or none
    elastic = UNCOUPLED.with_(restitution=1.0)
    with pytest.raises(SingularCaseError, match="no period-1 orbit is isolated"):
        p1.period1_orbits(elastic, 0.7)
    assert p1.period1_orbits(elastic, 2.0) == []           # kernel = v_1 only
    assert "kernel does not reach the gap" in p1.no_orbit_reason(elastic, 2.0)


def test_a_forcing_whose_squares_underflow_leaves_no_orbit_by_the_reach_bound(monkeypatch):
    tiny = ZERO.with_(**{"forcing[1]": 1e-300})
    assert p1.period1_orbits(tiny, 2.0) == []
    assert "too small to reach the stop" in p1.no_orbit_reason(tiny, 2.0)
    monkeypatch.setattr(p1, "COMPILED", False)
    assert p1.period1_orbits(tiny, 2.0) == []


@pytest.mark.parametrize("model", [ZERO, ZERO_DAMPED, UNCOUPLED, ANTI])
def test_simulation_from_a_given_start_runs(model):
    y0 = (-0.1,) + (0.1,) * (model.dim - 1)
    sim = simulate(model, 2.0, y0=y0, n_impacts=200)
    assert sim.stop in STOP_NAMES and np.isfinite(sim.section).all()
    with pytest.raises(SingularCaseError, match="pass y0 explicitly.*no period-1"):
        start_point(model, 2.0)


def test_free_decay_onto_the_stop_is_a_run_not_a_crash():
    pushed = ZERO_DAMPED.with_(gap=-0.5)          # the stop holds the mass: chatter
    sim = simulate(pushed, 2.0, y0=(-0.1, 0.1, 0.1, 0.1), n_impacts=2000)
    assert sim.stop in ("chatter", "sticking", "grazing")


def test_commands_on_such_models(tmp_path):
    f = tmp_path / "uncoupled.toml"
    f.write_text(ANTI_FILE)
    z = tmp_path / "zero.toml"
    z.write_text(ANTI_FILE.replace("forcing = [0.0, 1.0]", "forcing = [0, 0]"))
    preset = ["--mu-m", THIRD, "--mu-k", THIRD, "--f2", "0", "--b", "1.5", "--r", "0.8"]
    for system in (preset, ["--model", f], ["--model", z]):
        rc, out, err = cli("orbit", *system, "--omega", "2")
        assert rc == 0 and "no period-1 one-impact orbit" in out, err
        rc, out, err = cli("simulate", *system, "--omega", "2", "--impacts", "50",
                           "--out", tmp_path / "s.npz", "--y0", "-0.1", "0.2", "0.3", "0.4")
        assert rc == 0 and (tmp_path / "s.npz").exists(), err
        assert_bad_input(cli("simulate", *system, "--omega", "2", "--out", tmp_path / "t.npz"),
                         "pass y0 explicitly", "no period-1 one-impact orbit")
        assert_bad_input(cli("sweep", *system, "--range", "omega=1.9:2.1:3", "--impacts", "5",
                             "--transient", "5",
                             "--out", tmp_path / "w.npz", "--workers", "0"), "no-orbit")
        assert_bad_input(cli("continue", *system, "--range", "omega=1.9:2.1"), "--range")
    rc, out, err = cli("hopf", "--model", z, "--range", "omega=1.9:2.1")
    assert rc == 0 and "internal error" not in err, err
