"""Neimark-Sacker points and branches in an elastic stop's numbers on models with elastic
stops and nonlinear forces (issue 28).

The model: the 2-mass impact damper of ``examples/contacts/impact_damper.toml`` with its two
stops between the masses made elastic (k_s = 200, c_s = 1) and a cubic spring on the
primary mass (beta = 0.1).

Checks that could fail: ``symvi hopf`` (the uncertified scan of the continued attractors)
finds a supercritical NS point of the symmetric 1-4 orbit, its pair on the unit circle;
continuation in stop 1's gap at omega_c - 0.005 meets an NS point, and continuation in
omega at that gap locates it again at omega_c - 0.005 to 1e-8 with the same l1 (1e-6);
a branch in the elastic stiffness downwards stays admissible (the admissibility walked
the phases of the problem's own model, not the model at the continued value, and cut
such branches at once)."""
import json

import pytest

from symvi.continuation import attractor_orbit
from symvi.continuation.branch import continue_branch
from symvi.model import Model, Stop, dumps
from symvi.orbits.periodic import periodic_orbit
from tests.flow.test_nonlinear_elastic import DUFFING
from tests.fuzz._cli import cli

DAMPER = Model(mass=[1.0, 0.1], stiffness=[[1.0, 0.0], [0.0, 0.0]],
               damping=[[0.05, 0.0], [0.0, 0.0]], forcing=[0.1, 0.0],
               stops=[Stop(between=(1, 2), gap=1.0, stiffness=200.0, damping=1.0),
                      Stop(between=(1, 2), gap=-1.0, side="lower", stiffness=200.0,
                           damping=1.0)],
               nonlinear=["beta*x1**3", "0"], parameters={"beta": 0.1})


@pytest.mark.slow
def test_hopf_and_an_ns_point_in_an_elastic_gap(tmp_path):
    f = tmp_path / "damper.toml"
    f.write_text(dumps(DAMPER))
    rc, out, err = cli("hopf", "--model", f, "--range", "omega=1.0:1.15", "--json")
    assert rc == 0, err
    pts = [p for p in json.loads(out)["points"] if p["kind"] == "ns"]
    assert len(pts) == 1 and abs(pts[0]["value"] - 1.0799235) < 1e-6, pts
    ns = pts[0]
    assert ns["coefficients"]["l1"] < 0 and ns["admissible"]
    mods = sorted(abs(complex(*z)) for z in ns["multipliers"])
    assert abs(mods[-1] - 1) < 1e-8 and abs(mods[-2] - 1) < 1e-8
    # the branch in omega from the scan's start meets it too
    start = json.loads(out)["starts"][0]["omega"]
    br = continue_branch(DAMPER, "omega", start, 1.1, orbit=attractor_orbit(DAMPER, start))
    sp = [s for s in br.special if s.kind == "ns"]
    assert len(sp) == 1 and abs(sp[0].value - ns["value"]) < 1e-10
    # continuation in stop 1's gap at omega_c - 0.005, from the orbit there
    w = ns["value"] - 0.005
    o = periodic_orbit(DAMPER, n=1, p=4, guess=sp[0].orbit, omega=w)
    br = continue_branch(DAMPER, "stop[1].gap", 1.0, 1.2, orbit=o, omega=w)
    found = [s for s in br.special if s.kind == "ns"]
    assert len(found) == 1 and 1.0 < found[0].value < 1.2, br.special
    g, l1 = found[0].value, found[0].coefficients["l1"]
    # at that gap, continuation in omega meets the NS at omega = w
    m = DAMPER.parameter("stop[1].gap").apply(DAMPER, g)
    o = periodic_orbit(m, n=1, p=4, guess=found[0].orbit, omega=w - 0.01)
    br = continue_branch(m, "omega", w - 0.01, w + 0.01, orbit=o)
    again = [s for s in br.special if s.kind == "ns"]
    assert len(again) == 1 and abs(again[0].value - w) < 1e-8, (again, w)
    assert abs(again[0].coefficients["l1"] - l1) < 1e-6 * abs(l1)


@pytest.mark.slow
@pytest.mark.parametrize("linear", [False, True])
def test_a_branch_down_in_the_elastic_stiffness_stays_admissible(linear):
    """The 1-2 orbit of the elastic Duffing oscillator (beta = 0.5, and its linear part) at
    omega = 1.3 continued in k_s from 50 down to 10: every point admissible, the branch
    reaches 10 (it ended at k_s = 49.6, "the orbit would penetrate the stop", on both)."""
    m = DUFFING.linear_part if linear else DUFFING
    br = continue_branch(m, "stop[1].stiffness", 50.0, 10.0, orbit=attractor_orbit(m, 1.3),
                         omega=1.3)
    assert br.end.startswith("reached"), br.end
    assert all(pt.orbit.admissible for pt in br.points)
