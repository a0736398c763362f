"""Two-parameter curves of a model with an elastic stop and nonlinear forces (issue 28): the
impact Duffing oscillator with an elastic stop (k_s = 50, c_s = 0.5, gap 0.5, beta = 0.5).

Checks that could fail: each checked point of its flip curve in (omega, beta) and in
(omega, stop[1].stiffness) is the flip that one-parameter continuation in omega at that
beta (k_s) locates, to 1e-7 in omega, with the same coefficient c (1e-5); both curves run
to the bounds of their second parameter (the curve in beta used to crawl in steps of
2e-7 to max_points: dG/dbeta flew the contact flight in the free field); the generalised
flip (c = 0) on the curve in k_s is where the branch's flip has c = 0; ``symvi curve
--params omega,stop[1].stiffness`` runs."""
import json

import numpy as np
import pytest

from symvi.continuation import attractor_orbit
from symvi.continuation.branch import continue_branch
from symvi.curves.curve import continue_curve
from symvi.model import dumps
from symvi.orbits.periodic import periodic_orbit
from tests.flow.test_nonlinear_elastic import DUFFING
from tests.fuzz._cli import cli


@pytest.fixture(scope="module")
def flip():
    """The flip of the 1-2 orbit (entry, exit) near omega = 1.2071 on the branch from the
    attractor at omega = 1.3 (the other flip, near 1.2375, is the far side of the curve
    in beta: over beta it is an arc that turns back near beta = 0.69)."""
    br = continue_branch(DUFFING, "omega", 1.3, 1.15, orbit=attractor_orbit(DUFFING, 1.3))
    flips = sorted(s.value for s in br.special if s.kind == "flip")
    assert len(flips) == 2 and abs(flips[0] - 1.2071) < 1e-3, br.special
    return next(s for s in br.special if s.value == flips[0])


def _located(model, omega, guess):
    """The flip nearest ``omega`` that continuation in omega over omega +- 0.01 locates at
    ``model``, from the orbit corrected at omega - 0.01 (from ``guess``): (omega, c)."""
    o = periodic_orbit(model, n=1, p=2, guess=guess, omega=omega - 0.01)
    br = continue_branch(model, "omega", omega - 0.01, omega + 0.01, orbit=o)
    found = [s for s in br.special if s.kind == "flip" and abs(s.value - omega) < 0.01]
    assert len(found) == 1, [(s.kind, s.value) for s in br.special]
    return found[0].value, found[0].coefficients["c"]


def _check(cv):
    other = cv.names[1]
    par = DUFFING.parameter(other)
    for pt in (cv.points[0], cv.points[len(cv.points) // 2], cv.points[-1]):
        assert pt.admissible
        w, c = _located(par.apply(DUFFING, pt.params[other]), pt.params["omega"], pt.orbit)
        assert abs(w - pt.params["omega"]) < 1e-7, (pt.params, w)
        assert abs(c - pt.coefficient) < 1e-5 * max(abs(c), 1e-3), (c, pt.coefficient)


@pytest.mark.slow
def test_a_flip_curve_in_omega_and_beta(flip):
    """From the flip at beta = 0.5 the curve reaches both bounds, beta = 0.4 and 0.6, in
    a few hundred points (it crawled to max_points before dG/dbeta flew each flight in
    its own phase); every checked point is a flip of the branch at its beta."""
    cv = continue_curve(DUFFING, "flip", ("omega", "beta"), flip,
                        bounds={"omega": (0.9, 1.6), "beta": (0.4, 0.6)}, max_points=400)
    assert sorted(pt.params["beta"] for pt in (cv.points[0], cv.points[-1])) == [0.4, 0.6]
    assert len(cv.points) < 400
    _check(cv)


@pytest.mark.slow
def test_a_flip_curve_in_omega_and_the_elastic_stiffness(flip):
    """The curve in (omega, k_s) from k_s = 50 to the bounds 45 and 65, with a generalised
    flip (c = 0) near k_s = 58.47: every checked point is a flip of the branch at its
    stiffness, and at the generalised flip's the branch's flip has |c| < 1e-5 (against c
    = 0.022 at k_s = 50)."""
    name = "stop[1].stiffness"
    cv = continue_curve(DUFFING, "flip", ("omega", name), flip,
                        bounds={"omega": (0.9, 1.6), name: (45.0, 65.0)}, max_points=2000)
    assert sorted(pt.params[name] for pt in (cv.points[0], cv.points[-1])) == [45.0, 65.0]
    _check(cv)
    gpd = [s for s in cv.special if s.kind == "GPD"]
    assert len(gpd) == 1 and abs(gpd[0].params[name] - 58.47) < 0.01, cv.special
    m = DUFFING.parameter(name).apply(DUFFING, gpd[0].params[name])
    near = min(cv.points, key=lambda pt: abs(pt.params[name] - gpd[0].params[name]))
    w, c = _located(m, gpd[0].params["omega"], near.orbit)
    assert abs(w - gpd[0].params["omega"]) < 1e-7 and abs(c) < 1e-5
    assert abs(flip.coefficients["c"]) > 1e-2


@pytest.mark.slow
def test_symvi_curve_in_omega_and_the_elastic_stiffness(tmp_path):
    """``symvi curve --params omega,stop[1].stiffness`` on the elastic Duffing model (refused
    by name before): it starts at the flip of the 1-2 branch and runs; every point has a
    multiplier -1."""
    f = tmp_path / "duffing.toml"
    f.write_text(dumps(DUFFING))
    rc, out, err = cli("curve", "--model", f, "--kind", "flip", "--range", "omega=0.9:1.3",
                       "--params", "omega,stop[1].stiffness", "--bounds",
                       "stop[1].stiffness=49:51", "--max-points", "100", "--json")
    assert rc == 0, err
    obj = json.loads(out)
    assert abs(obj["start"]["omega"] - 1.2070865783) < 1e-8
    ks = [pt["params"]["stop[1].stiffness"] for pt in obj["points"]]
    assert sorted((ks[0], ks[-1])) == [49.0, 51.0]
    for pt in obj["points"]:
        mu = [complex(*z) for z in pt["multipliers"]]
        assert min(abs(z + 1) for z in mu) < 1e-8
