"""``symvi.continuation.continue_orbits`` from Python (issue 24, item 7): the starting
orbits, de-duplication and flip switching that ``symvi continue`` runs, and errors that
name the keyword arguments (or the spellings a front end passes in ``names``)."""
from itertools import combinations

import numpy as np
import pytest

import symvi
from symvi.continuation import Branch, continue_branch, continue_orbits, same_branch
from symvi.continuation.start import NAMES
from symvi.errors import ParameterError
from symvi.model import Model
from symvi.orbits.period1 import admissible_orbits

from tests.zoo import ONE_DAMPED_GAP0, PAPER_EX1



@pytest.fixture(scope="module")
def sim269():
    """ONE_DAMPED simulated at omega = 2.69: it settles on a 2-2 orbit (past the flip
    near 2.656)."""
    return symvi.simulate(ONE_DAMPED_GAP0, 2.69, n_impacts=200, transient=3000)


def test_period1_start_is_continue_branch_from_each_admissible_orbit():
    """The default start: every admissible period-1 orbit at ``start``, each continued
    by continue_branch; the paper's example 1 has its NS point at omega = 1.12405893784
    (the value tests/cli/test_cli_continue.py pins for ``symvi continue``)."""
    brs = continue_orbits(PAPER_EX1, "omega", 1.3, 1.1)
    assert brs and all(isinstance(b, Branch) for b in brs)
    guesses = [o.y for o in admissible_orbits(PAPER_EX1, 1.3, multipliers=False)]
    ref = continue_branch(PAPER_EX1, "omega", 1.3, 1.1, guess=guesses[0])
    assert np.array_equal(brs[0].values, ref.values)
    assert [s.kind for s in brs[0].special] == [s.kind for s in ref.special]
    ns = [s for b in brs for s in b.special if s.kind == "ns"]
    assert abs(ns[0].value - 1.12405893783818) < 1e-9
    assert not any(same_branch(a, b) for a, b in combinations(brs, 2))


def test_switch_adds_the_period_doubled_branch():
    brs = continue_orbits(ONE_DAMPED_GAP0, "omega", 2.0, 3.0, switch=True)
    orbits = [(b.n, b.p) for b in brs]
    assert orbits[0] == (1, 1) and (2, 2) in orbits
    flip = [s for s in brs[0].special if s.kind == "flip"][0]
    doubled = brs[orbits.index((2, 2))]
    # the doubled branch is born at the flip
    assert min(abs(v - flip.value) for v in doubled.values) < 1e-3


def test_start_omega_goes_both_ways():
    brs = continue_orbits(PAPER_EX1, "omega", 1.1, 1.3, start_omega=1.2, max_points=60)
    lo = min(b.values.min() for b in brs)
    hi = max(b.values.max() for b in brs)
    assert lo < 1.2 < hi
    assert all(b.points[0].value == 1.2 for b in brs)


def test_other_parameter_with_omega_fixed():
    brs = continue_orbits(ONE_DAMPED_GAP0, "restitution", 0.8, 0.6, omega=2.5)
    assert brs[0].param == "restitution"
    assert brs[0].points[0].value == 0.8 and brs[0].values.min() >= 0.6 - 1e-12


def test_from_a_simulation_or_its_npz(sim269, tmp_path):
    """A Simulation starts the branch on the orbit it settled on (n-p found), at its
    omega, both ways; the .npz of ``symvi simulate --out`` gives the same branches."""
    brs = continue_orbits(ONE_DAMPED_GAP0, "omega", 2.66, 2.72, simulation=sim269)
    assert all((b.n, b.p) == (2, 2) for b in brs) and len(brs) == 2
    start = [pt for pt in brs[0].points if pt.value == 2.69][0]
    assert min(np.max(np.abs(np.asarray(start.y) - s)) for s in sim269.section[-2:]) < 1e-8
    npz = tmp_path / "s.npz"
    np.savez(npz, section=sim269.section, t=sim269.t, omega=sim269.omega)
    again = continue_orbits(ONE_DAMPED_GAP0, "omega", 2.66, 2.72, simulation=npz)
    assert [b.values.tolist() for b in again] == [b.values.tolist() for b in brs]
    # another parameter: the simulation's omega is the fixed one
    gap = continue_orbits(ONE_DAMPED_GAP0, "gap", 0.0, 0.05, simulation=sim269, max_points=20)
    assert gap[0].problem.omega == sim269.omega and (gap[0].n, gap[0].p) == (2, 2)


def test_n_p_orbit_from_a_run_of_the_map(sim269):
    """orbit=(2, 2) without a simulation: the 2-2 orbit a run of the map from the
    period-1 orbit settles on at ``start`` (what symvi.simulate finds there)."""
    brs = continue_orbits(ONE_DAMPED_GAP0, "omega", 2.69, 2.72, orbit=(2, 2), max_points=40)
    assert (brs[0].n, brs[0].p) == (2, 2) and brs[0].points[0].value == 2.69
    y = np.asarray(brs[0].points[0].y)
    assert min(np.max(np.abs(y - s)) for s in sim269.section[-2:]) < 1e-8
    same = continue_orbits(ONE_DAMPED_GAP0, "omega", 2.69, 2.72, orbit="2-2", max_points=40)
    assert same[0].values.tolist() == brs[0].values.tolist()


# --------------------------------------------------------------------------- errors
def _error(*args, **kw):
    with pytest.raises(ParameterError) as e:
        continue_orbits(*args, **kw)
    return e.value


@pytest.mark.parametrize("args, kw, name, words", [
    ((PAPER_EX1, "zeta", 1.0, 2.0), {"omega": 1.0}, "param", "gap"),
    ((PAPER_EX1, "omega", 1.2, 1.2), {}, "stop", "a value != start = 1.2"),
    ((PAPER_EX1, "omega", 0.0, 1.2), {}, "start", "forcing frequency"),
    ((PAPER_EX1, "r", 0.8, 1.5), {"omega": 1.2}, "stop", "0 < r <= 1"),
    ((PAPER_EX1, "b", 1.4, 1.6), {}, "omega", "give omega=VALUE when param is not omega"),
    ((PAPER_EX1, "b", 1.4, 1.6), {"omega": 1.2, "b": 1.5}, "fixed",
     "a parameter other than param"),
    ((PAPER_EX1, "omega", 1.3, 1.1), {"zeta": 1.0}, "fixed", "gap"),
    ((PAPER_EX1, "omega", 1.3, 1.1), {"omega": 1.2}, "fixed", "other than param"),
    ((PAPER_EX1, "omega", 1.3, 1.1), {"orbit": "x-1"}, "orbit", "n-p"),
    ((PAPER_EX1, "omega", 1.3, 1.1), {"orbit": (0, 1)}, "orbit", "n-p"),
    ((PAPER_EX1, "omega", 1.3, 1.1), {"max_points": 1}, "max_points", "from 2"),
    ((PAPER_EX1, "omega", 1.3, 1.1), {"max_points": 2.5}, "max_points", "integer"),
    ((PAPER_EX1, "omega", 1.3, 1.1), {"start_omega": 1.4}, "start_omega", "[1.1, 1.3]"),
    ((PAPER_EX1, "b", 1.4, 1.6), {"omega": 1.2, "start_omega": 1.5}, "start_omega",
     "only with param omega (fix omega with omega=W otherwise)"),
    ((PAPER_EX1, "omega", 1.3, 1.1), {"simulation": "/nonexistent/s.npz"}, "simulation",
     ".npz"),
    ((PAPER_EX1, "omega", 1.3, 1.1), {"simulation": 3}, "simulation", "Simulation"),
    ((PAPER_EX1, "omega", 1.3, 1.1), {"names": {"begin": "x"}}, "names", "start"),
    (("model", "omega", 1.3, 1.1), {}, "model", "symvi.Model"),
])
def test_errors_name_the_keyword_arguments(args, kw, name, words):
    e = _error(*args, **kw)
    assert e.name == name and words in str(e), str(e)


def test_errors_about_the_start(sim269):
    # the simulated orbit is 2-2, not 3-1
    e = _error(ONE_DAMPED_GAP0, "omega", 2.66, 2.72, orbit=(3, 1), simulation=sim269)
    assert e.name == "orbit" and "the simulated orbit's 2-2" in str(e)
    e = _error(ONE_DAMPED_GAP0, "omega", 2.0, 2.2, simulation=sim269)
    assert e.name == "simulation" and "(it has 2.69)" in str(e)
    # the run of the map at omega = 1.3 does not settle on a 3-1 orbit
    e = _error(PAPER_EX1, "omega", 1.3, 1.1, orbit=(3, 1))
    assert e.name == "orbit" and "(give simulation)" in str(e)
    # no period-1 orbit at the stop mass's anti-resonance (tests/cli: the same for --from)
    e = _error(Model.luo_xie(1 / 3, 1 / 3, 0, 1.5, 0.8), "omega", 2.0, 2.1)
    assert e.name == "start" and "anti-resonance" in str(e)


def test_names_spell_the_arguments_as_a_front_end_does():
    """The command line passes its flags; each message then names the flag."""
    flags = {"start": "--from", "stop": "--to", "param": "--param", "omega": "--set omega"}
    e = _error(PAPER_EX1, "omega", 1.2, 1.2, names=flags)
    assert str(e) == ("--to = 1.2 is invalid; valid range: a value != --from = 1.2 (the "
                      "branch lies between them)")
    e = _error(PAPER_EX1, "b", 1.4, 1.6, names=flags)
    assert str(e) == ("--set omega = None is invalid; valid range: a fixed forcing "
                      "frequency: give --set omega=VALUE when --param is not omega")
    assert set(NAMES) >= set(flags)


def test_continue_branch_takes_the_signature_of_a_guess_that_has_none():
    """``signature`` was accepted and ignored: a guess passed without it was solved as an
    orbit on stop 1 only."""
    from pathlib import Path

    import symvi
    from symvi.continuation import attractor_orbit, continue_branch
    from symvi.errors import SymviError
    m = symvi.load_model(Path(__file__).resolve().parents[2] / "examples" / "contacts"
                         / "oscillator_two_stops.toml")
    o = attractor_orbit(m, 2.0)
    assert o.signature == (1, 0)
    br = continue_branch(m, "omega", 2.0, 2.1, guess=o, n=o.n, p=o.p, signature=o.signature,
                         max_points=20)
    assert br.points[0].orbit.signature == (1, 0) and len(br.points) > 5
    with pytest.raises(SymviError):       # the same guess read as two impacts on stop 1
        continue_branch(m, "omega", 2.0, 2.1, guess=o, n=o.n, p=o.p, max_points=20)


def test_a_special_points_index_is_the_first_branch_point_past_it():
    """SpecialPoint.index: the point lies between the branch's points index - 1 and index
    (as the docstring says; it said "after which it lies")."""
    import symvi
    from symvi.continuation import continue_branch
    m = symvi.Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    br = continue_branch(m, "omega", 1.3, 1.1)
    for sp in br.special:
        a, b = br.points[sp.index - 1].value, br.points[sp.index].value
        assert min(a, b) <= sp.value <= max(a, b), (sp.kind, sp.index, a, sp.value, b)


def test_no_period1_orbit_to_settle_from_names_what_continuation_takes():
    """The hint named simulate's y0, which continue_orbits does not take."""
    import symvi
    from symvi.continuation import continue_orbits
    from symvi.errors import SingularCaseError
    m = symvi.Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.0]], forcing=[1.0],
                    stops=[symvi.Stop(mass=1, gap=0.1, restitution=0.8)])
    with pytest.raises(SingularCaseError, match="simulation=, or --from-section") as e:
        continue_orbits(m, "omega", 3.5, 4.5, orbit="2-1")
    assert "y0" not in str(e.value)
