"""Branches of orbits with a sticking phase (issue 27, item 4:
:mod:`symvi.continuation.sticking`), each point checked against a long run of
``symvi.simulate`` at its parameter value, and the end where the held phase vanishes."""
import json
import math

import numpy as np
import pytest

from symvi import simulate
from symvi.continuation import continue_orbits, continue_sticking
from symvi.errors import SymviError
from symvi.model import Model, Stop
from symvi.orbits import StickingOrbit, StickingSignature

GAP = 0.2
#: x'' + 0.1 x' + x = sin(omega t + tau), a stop at x = GAP, r = 0.5
ONE = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
            stop=Stop(mass=1, gap=GAP, restitution=0.5))
TWO = Model(mass=[[1.0, 0], [0, 1.3]], stiffness=[[2.0, -1.0], [-1.0, 2.5]],
            damping=[[0.1, 0], [0, 0.1]], forcing=[0.8, 1.1],
            stop=Stop(mass=1, gap=0.1, restitution=0.5))


@pytest.fixture(scope="module")
def up():
    """The branch from omega = 0.5 upwards, to where its held phase vanishes."""
    run = simulate(ONE, 0.5, y0=(-0.5, 0.0), n_impacts=2000)
    return continue_sticking(ONE, "omega", 0.5, 0.7, guess=run)


def _settled(model, omega, y0, n=1500):
    run = simulate(model, omega, y0=y0, n_impacts=n)
    st = run.sticks[np.isfinite(run.sticks[:, 1])]
    assert run.stop == "completed" and len(st) > 20
    return run, st


def test_branch_points_against_simulations(up):
    """At three points of the branch a fresh run at that omega settles on the point's
    orbit: its time from a release to the accumulation point and its held phase agree to
    1e-8; every release lies at the closed-form phase pi - asin(GAP)."""
    assert len(up) > 10 and all(isinstance(pt.orbit, StickingOrbit) for pt in up.points)
    taus = np.array([pt.orbit.tau_release for pt in up.points])
    assert np.abs(taus - (math.pi - math.asin(GAP))).max() < 1e-7
    assert all(abs(pt.multipliers[0]) < 1e-5 for pt in up.points)
    vals = up.values
    for target in (0.52, 0.55, 0.56):
        pt = up.points[int(np.argmin(np.abs(vals - target)))]
        _, st = _settled(ONE, pt.value, (-0.5, 0.0))
        o = pt.orbit
        assert st[-1, 0] - st[-2, 1] == pytest.approx(o.t_stick, abs=1e-8)
        assert st[-1, 1] - st[-1, 0] == pytest.approx(o.hold, abs=1e-8)
        assert o.t_stick + o.hold == pytest.approx(2 * math.pi / pt.value, abs=1e-9)


def test_branch_ends_where_the_held_phase_vanishes(up):
    """The branch ends, with its reason, where the held phase's length reaches 0 (the
    chatter's accumulation point reaches the release, at omega ~ 0.56424); past that
    omega (0.565, 0.575) a run holds the mass once at its start, then never again: its
    attractor chatters without sticking."""
    assert "held phase vanishes near omega = 0.5642" in up.end
    holds = [pt.orbit.hold for pt in up.points]
    assert holds[-1] < 1e-2 * holds[0] and holds[-1] > 0.0
    assert up.values[-1] == pytest.approx(0.56424, abs=1e-4)
    for w in (0.565, 0.575):
        run = simulate(ONE, w, y0=(-0.5, 0.0), n_impacts=3000)
        assert run.stop == "completed" and len(run.sticks) == 1
        assert run.sticks[0, 1] < run.t[100]
    run = simulate(ONE, 0.56, y0=(-0.5, 0.0), n_impacts=3000)     # before it: every period
    assert len(run.sticks) > 50


def test_two_masses_from_continue_orbits():
    """continue_orbits started from a run that sticks gives its sticking branches (both
    ways in omega); a point of each against a run at its omega."""
    run = simulate(TWO, 0.7, y0=(-0.5, 0.0, 0.0, 0.0), n_impacts=800)
    brs = continue_orbits(TWO, "omega", 0.6, 0.8, simulation=run)
    assert len(brs) == 2 and [br.values[0] for br in brs] == [0.7, 0.7]
    assert [br.end for br in brs] == ["reached omega = 0.6", "reached omega = 0.8"]
    for br in brs:
        assert all(pt.admissible for pt in br.points) and br.n == 1
        d = json.loads(json.dumps(br.as_dict()))          # the branches' one JSON shape
        assert d["signature"] == "1-0+stick" and len(d["points"]) == len(br)
        pt = br.points[len(br) // 2]
        _, st = _settled(TWO, pt.value, (-0.5, 0.0, 0.0, 0.0))
        assert st[-1, 1] - st[-1, 0] == pytest.approx(pt.orbit.hold, abs=1e-8)
        assert st[-1, 0] - st[-2, 1] == pytest.approx(pt.orbit.t_stick, abs=1e-8)


def test_continued_in_the_gap():
    """Another parameter: in the gap the release phase follows pi - asin(k gap / P)."""
    run = simulate(ONE, 0.5, y0=(-0.5, 0.0), n_impacts=2000)
    br = continue_sticking(ONE, "gap", GAP, 0.3, guess=run, max_points=30)
    assert br.param == "gap" and br.end == "reached gap = 0.3"
    for pt in br.points:
        assert pt.orbit.tau_release == pytest.approx(math.pi - math.asin(pt.value), abs=1e-7)


def test_bad_branch_input_in_one_line():
    """An elastic stop, omega both continued and fixed, equal ends: one line each."""
    elastic = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
                    stop=Stop(mass=1, gap=0.2, stiffness=50.0, damping=0.1))
    for call in (lambda: continue_sticking(elastic, "omega", 0.5, 0.6, guess=[2.9]),
                 lambda: continue_sticking(ONE, "omega", 0.5, 0.6, guess=[2.9], omega=0.5),
                 lambda: continue_sticking(ONE, "omega", 0.5, 0.5, guess=[2.9]),
                 lambda: continue_sticking(ONE, "omega", 0.5, 0.6, guess=[2.9],
                                           signature=StickingSignature(stop=3))):
        with pytest.raises(SymviError) as exc:
            call()
        assert "\n" not in str(exc.value)
