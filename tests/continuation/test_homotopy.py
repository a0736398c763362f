"""Period-1 orbits of a model with nonlinear forces found from its linear part's closed
form by continuation in the forces' scale (:mod:`symvi.continuation.homotopy`, issue 28).

Checks that could fail: the nonlinearity off gives the closed form's orbit; the number of
orbits found at one omega matches the folds that continuation in omega locates (three
between them, one outside); each stable orbit found is the attractor a simulation from
next to it settles on (two coexisting attractors), and the saddle between them is left by
a run started next to it."""
import math

import numpy as np
import pytest

import symvi
from symvi.continuation.homotopy import period1_orbits
from symvi.model import Model, Stop
from symvi.orbits.period1 import admissible_orbits
from symvi.orbits.periodic import detect_period

KW = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
          stop=Stop(mass=1, gap=0.0, restitution=0.8))
#: its branch in omega has folds at 2.50033192 and 2.89981144 (test_nonlinear_branch.py)
DUFFING = Model(**KW, nonlinear=["beta*x1**3"], parameters={"beta": 0.2})


def test_nonlinearity_off_finds_the_closed_form_orbit():
    lin = Model(**KW)
    off = Model(**KW, nonlinear=["beta*x1**3"], parameters={"beta": 0.0})
    ref = admissible_orbits(lin, 2.6)
    got = period1_orbits(off, 2.6)
    assert len(ref) == 1 and len(got.orbits) == 1
    assert np.max(np.abs(np.subtract(got.orbits[0].y, ref[0].y))) < 1e-12
    assert got.origins[0] == "linear branch +"
    assert any("linear branch -: not followed" in n for n in got.notes)


@pytest.fixture(scope="module")
def at_2_6():
    return period1_orbits(DUFFING, 2.6)


def test_the_attractor_is_added_once(at_2_6):
    """nonlinear_period1: the homotopy's orbits and the attractor of a run, which is one
    of them at omega = 2.6 (so nothing is added twice)."""
    from symvi.continuation.start import nonlinear_period1
    both = nonlinear_period1(DUFFING, 2.6)
    assert len(both.orbits) == len(at_2_6.orbits) == 3
    assert "attractor" not in both.origins


@pytest.mark.parametrize("omega, count", [(2.45, 1), (2.75, 3), (2.95, 1)])
def test_the_count_matches_the_folds_in_omega(omega, count):
    found = period1_orbits(DUFFING, omega)
    assert len(found.orbits) == count
    assert all(o.residual < 1e-10 for o in found.orbits)


def test_between_the_folds_two_stable_orbits_and_a_saddle(at_2_6):
    orbits = at_2_6.orbits
    assert len(orbits) == 3
    stable = [o for o in orbits if o.stable]
    saddle = [o for o in orbits if not o.stable]
    assert len(stable) == 2 and len(saddle) == 1
    lam = saddle[0].multipliers
    assert max(abs(complex(z)) for z in lam) > 1 and all(abs(complex(z).imag) < 1e-12
                                                           for z in lam)
    # the two attractors are distinct (one impact slower than the other)
    assert abs(stable[0].y[0] - stable[1].y[0]) > 0.5


def test_each_stable_orbit_is_an_attractor_of_a_simulation(at_2_6):
    for o in at_2_6.orbits:
        if not o.stable:
            continue
        y0 = (o.y[0] + 1e-3, o.y[1] - 1e-3)
        sim = symvi.simulate(DUFFING, 2.6, y0=y0, n_impacts=20, transient=400)
        assert detect_period(sim) == (1, 1)
        last = sim.section[-1]
        dtau = (last[1] - o.y[1] + math.pi) % (2 * math.pi) - math.pi
        assert abs(last[0] - o.y[0]) < 1e-8 and abs(dtau) < 1e-8


def test_a_run_next_to_the_saddle_leaves_it(at_2_6):
    o = next(o for o in at_2_6.orbits if not o.stable)
    sim = symvi.simulate(DUFFING, 2.6, y0=(o.y[0] + 1e-4, o.y[1]), n_impacts=20,
                         transient=300)
    last = sim.section[-1]
    assert abs(last[0] - o.y[0]) > 0.1
