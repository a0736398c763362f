"""Two-parameter curves of a model with nonlinear forces in a stop's gap or restitution
(issue 28): the curve system's dg/dp from the series jets with the gap or r as a variable
(:func:`symvi.flow.nljet.map_jet`), and the front ends that ask for them.

Checks that could fail: each checked point of a flip curve in (omega, gap) and of a fold
curve in (omega, restitution) of the impact Duffing oscillator is the flip (fold) that
one-parameter continuation in omega at that gap (r) locates, to 1e-8, with the same
normal-form coefficient; with the nonlinearity off the curve is the exact linear flow's;
``symvi curve --params omega,gap`` works on the nonlinear model, and a parameter the model
does not have is refused in one line naming ``--params`` before anything is computed."""
import json

import numpy as np
import pytest

import symvi
from symvi.continuation.branch import continue_branch
from symvi.curves import curve_params
from symvi.curves.curve import continue_curve
from symvi.errors import ParameterError
from symvi.model import Model, Stop, dumps
from symvi.orbits.periodic import periodic_orbit
from tests.fuzz._cli import assert_bad_input, cli

IMPACT = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.0, restitution=0.8))
DUFFING = Model(**IMPACT, nonlinear=["beta*x1**3"], parameters={"beta": 0.2})
#: the period-1 orbit at omega = 2.2 (the gallery's start: docs/gallery/duffing.md)
START = (-1.9266902123252434, 2.0285280896008815)


@pytest.fixture(scope="module")
def branch():
    """The Duffing branch in omega over [2.2, 3.0]: folds near 2.8998 and 2.5003, the
    flip near 2.7474 (as the gallery's branch shows them)."""
    o = periodic_orbit(DUFFING, n=1, p=1, guess=START, omega=2.2)
    br = continue_branch(DUFFING, "omega", 2.2, 3.0, orbit=o)
    assert sorted(s.kind for s in br.special) == ["flip", "fold", "fold"]
    return br


def _located(model, kind, omega, guess, name):
    """The ``kind`` point nearest ``omega`` that continuation in omega locates at
    ``model``: (value, coefficient ``name``).  A flip from the orbit corrected at omega -
    0.01 (from ``guess``) over omega +- 0.01; a fold on the branch from the orbit at
    omega = 2.2 over [2.2, 3.0] (near a fold the orbits have a square root in omega: a
    guess from the fold does not lead Newton to them reliably)."""
    if kind == "flip":
        o = periodic_orbit(model, n=1, p=1, guess=guess, omega=omega - 0.01)
        br = continue_branch(model, "omega", omega - 0.01, omega + 0.01, orbit=o)
    else:
        o = periodic_orbit(model, n=1, p=1, guess=START, omega=2.2)
        br = continue_branch(model, "omega", 2.2, 3.0, orbit=o)
    found = [s for s in br.special if s.kind == kind and abs(s.value - omega) < 0.01]
    assert len(found) == 1, [(s.kind, s.value) for s in br.special]
    return found[0].value, found[0].coefficients[name]


def _check_points(cv, kind, coefficient):
    """Both ends and the middle of the curve: each is located by continuation in omega
    at its own value of the other parameter."""
    other = cv.names[1]
    par = DUFFING.parameter(other)
    for pt in (cv.points[0], cv.points[len(cv.points) // 2], cv.points[-1]):
        assert pt.admissible
        m = par.apply(DUFFING, pt.params[other])
        w, c = _located(m, kind, pt.params["omega"], pt.orbit.y, coefficient)
        assert abs(w - pt.params["omega"]) < 1e-8, (pt.params, w)
        assert abs(c - pt.coefficient) < 1e-6 * abs(c), (c, pt.coefficient)


@pytest.mark.slow
def test_a_flip_curve_in_omega_and_gap(branch):
    """From the flip at gap = 0 the curve runs to both gap bounds (the flip moves down in
    omega as the gap opens); every checked point is a flip of the branch at its gap."""
    sp = next(s for s in branch.special if s.kind == "flip")
    cv = continue_curve(DUFFING, "flip", ("omega", "gap"), sp,
                        bounds={"omega": (2.0, 3.5), "gap": (-0.05, 0.05)}, max_points=200)
    assert sorted(pt.params["gap"] for pt in (cv.points[0], cv.points[-1])) == [-0.05, 0.05]
    ends = {pt.params["gap"]: pt.params["omega"] for pt in (cv.points[0], cv.points[-1])}
    assert ends[0.05] < sp.value < ends[-0.05]
    _check_points(cv, "flip", "c")


@pytest.mark.slow
def test_a_fold_curve_in_omega_and_restitution(branch):
    """From the lower fold (omega near 2.50) at r = 0.8, to r = 0.7 and 0.82: every
    checked point is a fold of the branch at its restitution (over r in [0.7, 0.82] the
    branch from omega = 2.2 folds back twice before omega = 3)."""
    sp = min((s for s in branch.special if s.kind == "fold"), key=lambda s: s.value)
    cv = continue_curve(DUFFING, "fold", ("omega", "restitution"), sp,
                        bounds={"omega": (2.0, 3.5), "restitution": (0.7, 0.82)},
                        max_points=200)
    assert sorted(pt.params["restitution"] for pt in (cv.points[0], cv.points[-1])) == \
        [0.7, 0.82]
    _check_points(cv, "fold", "a")


@pytest.mark.slow
def test_nonlinearity_off_the_curve_is_the_linear_flows():
    """beta = 0: the flip curve in (omega, gap) on the series jets ends at the gap bounds
    where the exact linear flow's (its generated jets, an independent path) does, to
    1e-9 in omega, with the same coefficient c."""
    from symvi.orbits.period1 import admissible_orbits
    lin = Model(**IMPACT)
    off = Model(**IMPACT, nonlinear=["beta*x1**3"], parameters={"beta": 0.0})
    curves = []
    for m in (lin, off):
        o = periodic_orbit(m, n=1, p=1, guess=admissible_orbits(lin, 2.6)[0].y, omega=2.6)
        sp = next(s for s in continue_branch(m, "omega", 2.6, 2.8, orbit=o).special
                  if s.kind == "flip")
        cv = continue_curve(m, "flip", ("omega", "gap"), sp,
                            bounds={"omega": (2.0, 3.5), "gap": (-0.03, 0.03)},
                            max_points=200)
        curves.append({pt.params["gap"]: pt for pt in (cv.points[0], cv.points[-1])})
    a, b = curves
    assert sorted(a) == sorted(b) == [-0.03, 0.03]
    for g in a:
        assert abs(a[g].params["omega"] - b[g].params["omega"]) < 1e-9
        assert abs(a[g].coefficient - b[g].coefficient) < 1e-7 * abs(a[g].coefficient)


# --------------------------------------------------------------------------- front ends
@pytest.mark.slow
def test_symvi_curve_in_omega_and_gap_on_a_nonlinear_model(tmp_path):
    """``symvi curve --params omega,gap`` on the Duffing model (refused by name before
    issue 28's gap step): it starts at the flip of the branch, reaches both gap bounds,
    each end has a multiplier -1, and continuation in omega at one end's gap locates
    its flip there."""
    f = tmp_path / "duffing.toml"
    f.write_text(dumps(DUFFING))
    rc, out, err = cli("curve", "--model", f, "--kind", "flip", "--range", "omega=2.6:2.9",
                       "--params", "omega,gap", "--bounds", "gap=-0.02:0.02",
                       "--max-points", "100", "--json")
    assert rc == 0, err
    obj = json.loads(out)
    assert abs(obj["start"]["omega"] - 2.7473542619) < 1e-9
    ends = [obj["points"][0], obj["points"][-1]]
    assert sorted(e["params"]["gap"] for e in ends) == [-0.02, 0.02]
    for e in ends:
        mu = [complex(*z) for z in e["multipliers"]]
        assert min(abs(z + 1) for z in mu) < 1e-8
    e = ends[0]["params"]
    m = DUFFING.with_(gap=e["gap"])
    sim = symvi.simulate(m, e["omega"] - 0.01, n_impacts=50, transient=3000)
    o = periodic_orbit(m, n=1, p=1, guess=sim, omega=e["omega"] - 0.01)
    br = continue_branch(m, "omega", e["omega"] - 0.01, e["omega"] + 0.01, orbit=o)
    flips = [s.value for s in br.special if s.kind == "flip"]
    assert len(flips) == 1 and abs(flips[0] - e["omega"]) < 1e-8


#: nonlinear forces on an elastic stop (its gap, stiffness and damping are series variables:
#: tests/flow/test_nonlinear_elastic_params.py); it has no restitution
ELASTIC = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                stop=Stop(mass=1, gap=0.0, stiffness=50.0, damping=0.1),
                nonlinear=["beta*x1**3"], parameters={"beta": 0.2})


def _no_computing(monkeypatch):
    """Any start search or curve fails the test: a refusal must come before them."""
    import symvi.curves
    import symvi.curves.start

    def fail(*a, **k):
        raise AssertionError("computed before refusing")

    monkeypatch.setattr(symvi.curves, "curve_from_interval", fail)
    monkeypatch.setattr(symvi.curves.start, "start_points", fail)


def test_a_parameter_the_model_does_not_have_is_refused_first(tmp_path, monkeypatch):
    """``--params omega,restitution`` on a model whose stop is elastic: one line naming
    --params and the stop's numbers, exit 2, before any start is searched."""
    f = tmp_path / "elastic.toml"
    f.write_text(dumps(ELASTIC))
    _no_computing(monkeypatch)
    line = assert_bad_input(cli("curve", "--model", f, "--kind", "flip", "--range",
                                "omega=2.6:2.9", "--params", "omega,restitution"),
                            "--params", "restitution", "stop[1].stiffness")
    assert "param =" not in line


def test_the_library_checks_the_pair_before_computing(monkeypatch):
    """curve_from_interval refuses the pair before its start search (naming ``names``);
    a force parameter beside a gap is a pair (it asked for the force parameter's tangent
    and was refused naming ``parameter``); an elastic stop's stiffness and damping are
    two parameters (their tangents differ in dk and dc only)."""
    from symvi.curves.start import curve_from_interval
    _no_computing(monkeypatch)
    with pytest.raises(ParameterError, match="^names = 'restitution'"):
        curve_from_interval(ELASTIC, 2.6, 2.9, ("omega", "restitution"), kind="flip")
    assert curve_params(DUFFING, "beta,gap") == ("beta", "gap")
    assert curve_params(DUFFING, "omega,restitution") == ("omega", "restitution")
    assert curve_params(ELASTIC, "omega,stop[1].stiffness") == ("omega", "stop[1].stiffness")
    assert curve_params(ELASTIC, "stop[1].stiffness,stop[1].damping") == \
        ("stop[1].stiffness", "stop[1].damping")
    with pytest.raises(ParameterError, match="^--params"):
        curve_params(DUFFING, "gap,stop[1].gap")
    with pytest.raises(ParameterError, match="^--params"):
        curve_params(ELASTIC, "stop[1].damping,stop[1].damping")
