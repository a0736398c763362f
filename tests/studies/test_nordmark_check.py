"""Nordmark's map against simulation just past grazing (issue 27, item 3): the square-root
law of the first new impact, the scenario of the leading multiplier, the attractor's
impacts under the 1-D bound, the impacting period-1 orbit's velocity."""
import functools
import math

import numpy as np
import pytest

from symvi.errors import ParameterError
from symvi.model import Model, Stop
from symvi.studies.nordmark_check import check, check_branch

from ..zoo import PAPER_EX1

#: an overdamped 1-DOF (c = 3, lambda = -0.382, -2.618): real multipliers e^{lambda 2 pi/omega}
OVER = Model(mass=[1.0], stiffness=[[1.0]], damping=[[3.0]], forcing=[1.0],
             stop=Stop(mass=1, gap=0.1, restitution=0.8))
DEPTHS = (1e-3, 1e-4, 1e-5, 1e-6)


@functools.lru_cache(maxsize=None)
def run(omega):
    X = 1 / abs(1 - omega ** 2 + 3j * omega)
    return check_branch(OVER, "gap", 0.3 * X, 2 * X, omega=omega, depths=DEPTHS)


@pytest.mark.parametrize("omega", [0.8, 2.0, 4.0])
def test_first_new_impact_follows_the_sqrt_law(omega):
    """v1 / (c_first sqrt(mu)) -> 1 with an error O(sqrt(delta)) (the flight's apex moves
    past the stop by delta = |delta'| mu; the measured v1 is the simulation's own)."""
    r = run(omega)
    for row in r.rows:
        assert abs(row["v1_ratio"] - 1) < 0.3 * math.sqrt(row["delta"]), row
        assert row["delta"] == pytest.approx(abs(r.map.delta_rate) * row["mu"], rel=1e-2)


def test_period_adding_below_a_quarter():
    """lambda1 = e^{-0.382 * 2 pi / 0.8} = 0.050 < 1/4: a period-adding cascade, each
    attractor a periodic orbit with one new impact per period, its period growing as mu
    decreases."""
    r = run(0.8)
    assert r.map.scenario.startswith("period-adding cascade: stable")
    periods = []
    for row in r.rows:
        assert row["stop"] == "completed" and row["attractor"].startswith("period-"), row
        k = int(row["attractor"].split("-")[1])
        assert row["periods_per_new_impact"] == pytest.approx(k, rel=1e-6)
        periods.append(k)
    assert periods == sorted(periods) and periods[-1] > periods[0]


def test_period1_orbit_velocity():
    """Where the run settles on the impacting period-1 orbit (omega 0.8, delta = 1e-3), its
    new impact's velocity is sqrt(2 |a|) s, s^2 - c s - delta = 0 (Nordmark's map's fixed
    point), not the first impact's c_first sqrt(mu)."""
    row = run(0.8).rows[0]
    assert row["attractor"] == "period-1"
    assert row["v_new_max"] == pytest.approx(row["v_period1_predicted"], rel=0.02)
    assert abs(row["v_new_max"] / row["v1_predicted"] - 1) > 0.2


def test_attractor_impacts_under_the_bound_and_chaos_above_two_thirds_window():
    """lambda1 = 0.30 and 0.55 (in (1/4, 2/3)): periodic windows of growing period with
    chaos between them (omega 4: chaos at the smallest depths); every new impact on the
    attractor is slower than c_attractor sqrt(mu) = sqrt(2 |a| (1 - lambda1) delta), and a
    chaotic attractor reaches that bound."""
    for omega in (2.0, 4.0):
        r = run(omega)
        assert "with chaotic windows" in r.map.scenario
        for row in r.rows:
            assert row["v_new_ratio"] <= 1 + 1e-3, row
    kinds = [row["attractor"] for row in run(4.0).rows]
    assert "chaos" in kinds and kinds[0].startswith("period-")
    for row in run(4.0).rows:
        if row["attractor"] == "chaos":
            assert row["v_new_ratio"] > 0.98


def test_paper_example_unstable_grazing_orbit():
    """Example 1's first grazing (omega 0.5956): the first new impact still follows the
    square-root law, while the scenario says no local attractor (|lambda1| = 1.22)."""
    r = check_branch(PAPER_EX1, "omega", 0.5, 1.0, depths=(1e-4, 1e-5, 1e-6), n_impacts=50,
                     transient=0)
    assert "unstable" in r.map.scenario and r.map.c_attractor is None
    ratios = [row["v1_ratio"] for row in r.rows]
    assert all(abs(q - 1) < 2 * math.sqrt(row["delta"]) for q, row in zip(ratios, r.rows))
    assert abs(ratios[-1] - 1) < abs(ratios[0] - 1)
    d = r.as_dict()
    assert len(d["rows"]) == 3 and d["map"]["kind"] == "flight"


def test_refuses_a_nonpositive_mu():
    with pytest.raises(ParameterError, match="mus"):
        check(run(2.0).map, [0.0])
    assert np.isfinite(run(2.0).map.delta_rate)


def test_immediate_chaos_above_two_thirds():
    """lambda1 = e^{-0.382 * 2 pi / 8} = 0.74 > 2/3: every depth gives a chaotic attractor
    at once, whose fastest new impact reaches the 1-D bound sqrt(2 |a| (1 - lambda1) delta)
    (and never exceeds it), with more forcing periods between new impacts as mu shrinks."""
    r = run(8.0)
    assert r.map.scenario.startswith("immediate chaos")
    assert 2 / 3 < r.map.multipliers[0].real < 1
    for row in r.rows:
        assert row["attractor"] == "chaos", row
        assert 0.99 < row["v_new_ratio"] <= 1 + 1e-3, row
    gaps = [row["periods_per_new_impact"] for row in r.rows]
    assert gaps == sorted(gaps)
