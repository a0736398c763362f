"""Simulation evidence next to codimension-two points (issue 13), paper example 1 in
(omega, r): bistability next to a Chenciner point, the period-3 / period-4 saddle orbits
of the R3 / R4 normal forms found in the full map."""
import json

import numpy as np
import pytest

import symvi
from symvi.curves import curve_from_interval
from symvi.curves.evidence import chenciner_coexistence, resonance_dynamics, wedge
from symvi.errors import ParameterError
from tests.zoo import PAPER_EX1


@pytest.fixture(scope="module")
def curve():
    c, _ = curve_from_interval(PAPER_EX1, 0.70, 0.76, ("omega", "r"),
                               bounds={"omega": (0.5, 1.0), "r": (0.05, 1.0)})
    return c


def _point(curve, kind, k=0):
    return [s for s in curve.special if s.kind == kind][k]


def test_wedge():
    """Two circles exactly inside 0 < -dmu < l1^2/(4|l2|); they solve the radial equation."""
    l1, l2 = 1e-4, -1e-3
    edge = l1 ** 2 / (4 * -l2)
    assert wedge(l1, l2, -1.01 * edge) is None and wedge(l1, l2, 1e-9) is None
    assert wedge(-l1, l2, -0.5 * edge) is None
    rm, rp, _ = wedge(l1, l2, -0.5 * edge)
    for r in (rm, rp):
        assert abs(-0.5 * edge + l1 * r ** 2 + l2 * r ** 4) < 1e-15
    assert 0 < rm < rp


@pytest.mark.slow
def test_chenciner_bistability(curve):
    """Next to the CH point (0.7852, 0.2762) (l2 = -8.03e-4), on the l1 > 0 side and the
    stable side: from x* the run decays at log|lambda|, from outside it settles on a circle
    of the predicted size: two attractors at the same parameters."""
    ch = _point(curve, "CH", 1)
    assert abs(ch.params["omega"] - 0.785201353) < 1e-6
    res, arr = chenciner_coexistence(PAPER_EX1, curve, ch)
    json.dumps(res)
    assert res["coexist"], res["verdict"]
    assert res["l1"] > 0 > res["l2"] and res["wedge"]["dmu_min"] < res["dmu"] < 0
    fx, cc = res["run_fixed"], res["run_circle"]
    assert fx["w_last_block"] < 0.7 * fx["w_first_block"]
    assert abs(fx["rate"] / fx["predicted_rate"] - 1) < 0.05
    assert cc["w_min"] > 2 * res["wedge"]["rho_inner"] and cc["classification"]["kind"] == \
        "invariant circle"
    assert np.max(np.abs(cc["rel_error"])) < 0.05
    # two different attractors: the circle's points stay far from x*
    d = np.abs(arr["circle"][:, :3] - arr["fixed_point"][:3]).max(axis=1)
    assert d.min() > 100 * np.abs(arr["fixed_last"][:, :3] - arr["fixed_point"][:3]).max()


def test_r3_saddle_cycle(curve):
    """Next to R3 the normal form predicts one period-3 saddle orbit of |w| = |lambda/lambda0
    - 1| / |b1| (+ cubic terms): Newton in the full map finds it with the same |w|, phase and
    saddle type; it bounds the basin of x*."""
    res, _ = resonance_dynamics(PAPER_EX1, curve, _point(curve, "R3"))
    json.dumps(res)
    (o,) = res["orbits"]
    assert o["found"] and o["type"] == o["predicted"]["type"] == "saddle"
    assert abs(o["rel_error_abs_w"]) < 0.01
    assert res["runs"]["0.5"]["back_to_fixed_point"] and res["runs"]["1.5"]["left"]


@pytest.mark.slow
def test_r4_saddle_cycle(curve):
    """Next to R4 (|A| = 0.63 < 1): one period-4 saddle orbit, found in the full map with
    |w| to 1e-3 and its critical multipliers to 1e-6."""
    res, _ = resonance_dynamics(PAPER_EX1, curve, _point(curve, "R4"))
    (o,) = res["orbits"]
    assert o["found"] and o["type"] == o["predicted"]["type"] == "saddle"
    assert abs(o["rel_error_abs_w"]) < 1e-2
    pred = sorted(complex(*z).real for z in o["predicted"]["multipliers"])
    got = sorted(complex(*z).real for z in o["multipliers"])
    assert np.allclose(pred, got, atol=1e-6)
    assert res["runs"]["0.5"]["back_to_fixed_point"] and res["runs"]["1.5"]["left"]


def test_wrong_kind(curve):
    with pytest.raises(ParameterError):
        chenciner_coexistence(PAPER_EX1, curve, _point(curve, "R3"))
    with pytest.raises(ParameterError):
        resonance_dynamics(PAPER_EX1, curve, _point(curve, "CH"))


def test_figure(curve, tmp_path):
    from symvi.reporting import figures
    res, arr = resonance_dynamics(PAPER_EX1, curve, _point(curve, "R3"))
    path = figures.save(figures.codim2_evidence(res, arr), tmp_path / "r3.png")
    assert (tmp_path / "r3.png").stat().st_size > 0 and path.endswith("r3.png")
