"""Continuation: consistency with hopf_points, a fold, grazing in closed form, flips and the
period-doubled branch, resonance and conservative cases."""
import math
import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

import symvi
from symvi.continuation import continue_branch, switch_at_flip
from symvi.errors import NearSingularWarning, ParameterError
from symvi.maps.impact import poincare_map
from symvi.model import Model
from symvi.orbits import admissible_orbits, existence_ratio, period1_orbits
from tests.zoo import ONE_DAMPED_GAP0, ONE_GRAZING, ONE_UNDAMPED, PAPER_EX1


@pytest.fixture(scope="module")
def paper_branch():
    return continue_branch(PAPER_EX1, "omega", 1.3, 0.9, through=True)


@pytest.fixture(scope="module")
def paper_hopf():
    return symvi.hopf_points(PAPER_EX1, 0.9, 1.3)


def _kinds(br, kind):
    return [s for s in br.special if s.kind == kind]


def test_ns_and_flips_agree_with_hopf_points(paper_branch, paper_hopf):
    ns = _kinds(paper_branch, "ns")
    assert len(ns) == len(paper_hopf.points) == 1
    assert abs(ns[0].value - paper_hopf.points[0].omega_c) < 1e-10
    assert ns[0].coefficients["l1"] == pytest.approx(paper_hopf.points[0].normal_form.l1,
                                                     rel=1e-8)
    flips = sorted(s.value for s in _kinds(paper_branch, "flip"))
    ev = sorted(e.omega for e in paper_hopf.events
                if e.kind == "multiplier-1" and e.branch == "+")
    assert len(flips) == len(ev) == 2
    assert np.max(np.abs(np.array(flips) - ev)) < 1e-10
    for s in _kinds(paper_branch, "flip"):
        assert min(abs(z + 1) for z in s.orbit.multipliers) < 1e-8
    # hopf_points locates through the same locator: its flips carry the same coefficient
    ev_c = {round(e.omega, 8): e.coefficients["c"] for e in paper_hopf.events
            if e.kind == "multiplier-1" and e.branch == "+"}
    for s in _kinds(paper_branch, "flip"):
        assert s.coefficients["c"] == pytest.approx(ev_c[round(s.value, 8)], rel=1e-6)


def test_interior_grazing_agrees_with_hopf_points(paper_branch, paper_hopf):
    g = [s for s in _kinds(paper_branch, "grazing") if "flight" in s.coefficients]
    ev = [e.omega for e in paper_hopf.events if e.branch == "+" and "grazing" in e.detail]
    assert len(g) == 1 and len(ev) == 1
    assert abs(g[0].value - ev[0]) < 1e-9
    # at the grazing point the flight's interior maximum touches the stop: x1(t_m) = b
    assert "touches the stop" in g[0].detail


def test_ends_at_the_admissibility_boundary_by_default():
    br = continue_branch(PAPER_EX1, "omega", 1.3, 0.9)
    assert "admissible" in br.end
    assert br.points[-2].admissible and not br.points[-1].admissible
    assert _kinds(br, "grazing")


def test_fold_turns_onto_the_other_closed_form_branch():
    # eq. (16): the two period-1 branches exist while |ratio| <= 1 and meet at the fold
    w_fold = brentq(lambda w: abs(existence_ratio(PAPER_EX1, w)) - 1, 1.5, 1.6, xtol=1e-15)
    br = continue_branch(PAPER_EX1, "omega", 1.45, 1.7, through=True)
    folds = _kinds(br, "fold")
    assert folds and abs(folds[0].value - w_fold) < 1e-10
    assert "turns" in folds[0].detail and folds[0].coefficients["a"] != 0
    # beyond the fold the branch comes back along the other closed-form orbit
    after = [pt for pt in br.points[folds[0].index + 2:] if pt.value < w_fold - 1e-3]
    assert after
    for pt in after[:5]:
        ys = [o.y for o in period1_orbits(PAPER_EX1, pt.value)]
        assert min(np.max(np.abs(np.array(pt.y) - np.array(y))) for y in ys) < 1e-8


def test_grazing_in_the_forcing_amplitude_closed_form():
    # the impacting orbit grazes where the free steady state just reaches the gap:
    # F / |k - m omega^2 + i c omega| = b  ->  F = b * 0.1 at omega = 1
    br = continue_branch(ONE_GRAZING, "forcing[1]", 0.3, 0.05, omega=1.0, through=True)
    g = _kinds(br, "grazing")
    assert g, br.end
    assert abs(g[0].value - 0.1) < 1e-10
    assert "zero velocity" in g[0].detail
    assert abs(g[0].coefficients["impact_velocity"]) < 1e-8


def test_flip_and_period_doubled_branch_of_a_damped_oscillator():
    br = continue_branch(ONE_DAMPED_GAP0, "omega", 2.0, 3.0)
    flips = _kinds(br, "flip")
    assert len(flips) == 1
    f = flips[0]
    assert f.coefficients["c"] > 0 and "supercritical" in f.detail
    doubled = switch_at_flip(br, f)
    assert (doubled.n, doubled.p) == (2, 2)
    assert len(doubled) > 10
    for pt in doubled.points[1:6]:
        assert pt.orbit.residual < 1e-9
        y = pt.orbit.points[0]
        for _ in range(2):
            y = poincare_map(ONE_DAMPED_GAP0, pt.value, y).y
        assert np.max(np.abs(np.array(y[:-1]) - np.array(pt.orbit.points[0][:-1]))) < 1e-9
        # supercritical: the doubled orbit is born stable, where the period-1 orbit is not
        assert pt.stable == (pt.value > f.value)
        assert pt.value > f.value
    # the cascade goes on: the doubled branch has its own flip
    assert _kinds(doubled, "flip")


def test_branch_point_where_an_orbit_traversed_twice_meets_its_doubled_branch():
    """The 1-1 orbit solved as a 2-2 orbit has the multipliers mu^2: at the 1-1 flip one
    passes +1 without a fold, and the period-doubled branch crosses there (a pitchfork).
    The branch point is located, at the flip of the 1-1 branch, and no fold is claimed."""
    one = continue_branch(ONE_DAMPED_GAP0, "omega", 2.0, 3.0)
    flip = _kinds(one, "flip")[0].value
    two = continue_branch(ONE_DAMPED_GAP0, "omega", 2.0, 3.0, n=2, p=2, guess=one.points[0].orbit.y)
    bps = _kinds(two, "branch-point")
    assert len(bps) == 1 and not _kinds(two, "fold") and not _kinds(two, "unlocated")
    assert abs(bps[0].value - flip) < 1e-10
    assert abs(bps[0].coefficients["multiplier"] - 1) < 1e-9
    assert bps[0].orbit.residual < 1e-12
    # on the primary branch the same crossing is the flip, not a branch point
    assert not _kinds(one, "branch-point")


def test_continuation_in_b_and_r_agrees_with_hopf_points(paper_hopf):
    wc = paper_hopf.points[0].omega_c
    for name, val, a, b in (("b", 1.5, 1.45, 1.55), ("r", 0.8, 0.78, 0.82)):
        for start, stop in ((a, b), (b, a)):
            br = continue_branch(PAPER_EX1, name, start, stop, omega=wc, through=True)
            ns = _kinds(br, "ns")
            assert ns, (name, br.end)
            assert min(abs(s.value - val) for s in ns) < 1e-9, name


def test_forcing_resonance_cuts_the_branch_cleanly():
    one = ONE_UNDAMPED                 # undamped, natural frequency 1
    o = admissible_orbits(one, 1.3)
    assert o
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        br = continue_branch(one, "omega", 1.3, 0.7, through=True)
    assert "resonance" in br.end or "not isolated" in br.end
    assert min(abs(pt.value - 1.0) for pt in br.points) < 1e-2
    assert all(pt.value > 1.0 for pt in br.points)


def test_conservative_model_is_said_and_seeks_no_ns():
    cons = Model.luo_xie(2, 5, 0, 1.5, 1.0)
    br = continue_branch(cons, "omega", 1.3, 1.0, through=True)
    assert any("conservative" in n for n in br.notes)
    assert not _kinds(br, "ns")
    # the multipliers move along the unit circle: the strong resonances met are located
    for kind, m in (("R3", 3), ("R4", 4)):
        pts = _kinds(br, kind)
        assert pts, kind
        for s in pts:
            assert min(abs(z ** m - 1) for z in s.orbit.multipliers) < 1e-9
    # a -1 reached by two multipliers colliding is not called a plain flip
    for s in _kinds(br, "flip"):
        assert s.coefficients["separation"] > 1e-4 or "degenerate" in s.detail
        assert s.as_dict()["coefficients"]["gap"] == s.coefficients["separation"]
    for pt in br.points[:20]:
        assert abs(np.prod(np.array(pt.multipliers)).real - 1) < 1e-9


def test_bad_input_names_the_parameter():
    with pytest.raises(ParameterError, match="param"):
        continue_branch(PAPER_EX1, "nonsense", 1.0, 1.2)
    with pytest.raises(ParameterError, match="omega"):
        continue_branch(PAPER_EX1, "b", 1.0, 1.2)
    with pytest.raises(ParameterError, match="stop"):
        continue_branch(PAPER_EX1, "omega", 1.2, 1.2)
    with pytest.raises(ParameterError, match="start"):
        continue_branch(PAPER_EX1, "omega", float("nan"), 1.2)
