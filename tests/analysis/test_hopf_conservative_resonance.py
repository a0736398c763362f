"""hopf_points across a natural frequency (the scan is cut there) and on conservative
models (r = 1, no damping: no Neimark–Sacker point, det DP = 1); (H3) needs a resolved speed."""
import dataclasses
import json
import warnings

import numpy as np
import pytest

from symvi import Params, period1_orbits
from symvi.analysis.hopf import CONSERVATIVE, RESONANCE_GAP, hopf_points
from symvi.errors import NearSingularWarning, SingularCaseError
from symvi.model import Model, Stop

OMEGA_1 = 0.8804857344718374          # example 1's lower natural frequency
EX1_WC = 0.73687692209059288146931    # chain B, 50 digits (test_hopf_points.REF)
BASE = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5"]
ONE = Model(mass=[1.0], stiffness=[[1.0]], forcing=[1.0],
            stop=Stop(mass=1, gap=0.2, restitution=1.0))
THREE = Model(mass=[1.0, 1.5, 0.8],
              stiffness=[[1.0, -1.0, 0.0], [-1.0, 1.7, -0.7], [0.0, -0.7, 2.7]],
              forcing=[1.0, 0.5, 0.0], stop=Stop(mass=2, gap=0.5, restitution=1.0))


def _scan(p, a, b):
    with warnings.catch_warnings():
        # the expected near-resonance warnings stay inside the scan
        warnings.simplefilter("error", NearSingularWarning)
        return hopf_points(p, a, b)


# --------------------------------------------------------------------------- item A
@pytest.mark.parametrize("p", [Params(2, 5, 0, 1.5, 0.8), Model.luo_xie(2, 5, 0, 1.5, 0.8)],
                         ids=["Params", "Model"])
def test_interval_through_a_natural_frequency_is_cut(p):
    """[0.7, 1.3] contains omega_1 = 0.88049 of example 1: the scan gives the NS points of
    the two scans on either side (paper's v_c = 0.7368 unchanged) and a forcing-resonance event."""
    res = _scan(p, 0.7, 1.3)
    sides = (_scan(p, 0.7, OMEGA_1 * (1 - RESONANCE_GAP)).points
             + _scan(p, OMEGA_1 * (1 + RESONANCE_GAP), 1.3).points)
    assert len(res.points) == len(sides) == 3
    assert [q.branch for q in res.points] == [q.branch for q in sides]
    for q, s in zip(res.points, sides):
        assert abs(q.omega_c - s.omega_c) < 1e-10
    assert res.points[0].omega_c < OMEGA_1 < res.points[-1].omega_c
    assert abs(res.points[0].omega_c - EX1_WC) < 1e-12 and res.points[0].h3
    (ev,) = [e for e in res.events if e.kind == "forcing-resonance"]
    assert ev.omega == pytest.approx(OMEGA_1, rel=1e-14) and ev.branch == ""
    assert "cut" in ev.detail and "infinite" in ev.detail and "omega_1" in ev.detail
    assert not res.conservative and res.as_dict()["statement"] is None


@pytest.mark.parametrize("p", [Params(2, 5, 0, 1.5, 0.8), Model.luo_xie(2, 5, 0, 1.5, 0.8)],
                         ids=["Params", "Model"])
def test_end_at_a_natural_frequency_refused(p):
    with pytest.raises(SingularCaseError, match="omega_1"):
        hopf_points(p, OMEGA_1, 1.0)


def test_cli_interval_through_a_natural_frequency(capsys):
    from symvi.cli import main
    args = ["hopf", *BASE, "--r", "0.8", "--range", "omega=0.7:1.0"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "forcing-resonance: natural frequency omega_1" in out and "Traceback" not in out
    assert main([*args, "--json"]) == 0
    obj = json.loads(capsys.readouterr().out)
    assert "forcing-resonance" in [e["kind"] for e in obj["events"]]
    assert abs(obj["points"][0]["omega_c"] - EX1_WC) < 1e-12


# --------------------------------------------------------------------------- item B
def test_conservative_paper_preset():
    """Example 1 with r = 1: no NS point, the statement, and the flips that remain are
    true: det(J + I) changes sign across each; det DP = r^2 = 1 (identity)."""
    res = _scan(Params(2, 5, 0, 1.5, 1.0), 0.9, 1.3)
    assert res.conservative and len(res.points) == 0
    (ev,) = [e for e in res.events if e.kind == "conservative"]
    assert ev.span == (0.9, 1.3) and ev.detail == CONSERVATIVE
    assert "(H3) cannot occur" in CONSERVATIVE and "det DP = 1" in CONSERVATIVE
    d = res.as_dict()
    assert d["conservative"] is True and d["statement"] == CONSERVATIVE and d["points"] == []
    json.dumps(d, allow_nan=False)
    flips = [e for e in res.events if e.kind == "multiplier-1"]
    assert len(flips) == 4
    for e in flips:
        sign = []
        for w in (e.omega - 1e-7, e.omega + 1e-7):
            o = {x.branch: x for x in period1_orbits(res.params, w)}[e.branch]
            lam = np.array(o.multipliers, dtype=complex)
            assert abs(np.prod(lam) - 1) < 1e-10
            sign.append(np.prod(lam + 1).real > 0)
        assert sign[0] != sign[1]


@pytest.mark.parametrize("model,a,b", [(ONE, 0.3, 0.8), (THREE, 1.9, 2.5)], ids=["N=1", "N=3"])
def test_conservative_models(model, a, b):
    assert model.conservative
    res = _scan(model, a, b)
    assert res.conservative and len(res.points) == 0
    assert [e.detail for e in res.events if e.kind == "conservative"] == [CONSERVATIVE]
    assert res.samples < 1000


def test_damped_model_with_r_1_is_not_conservative():
    m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.01]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.2, restitution=1.0))
    res = _scan(m, 0.3, 0.8)
    assert not res.conservative and not any(e.kind == "conservative" for e in res.events)


@pytest.mark.parametrize("p", [Params(2, 5, 0, 1.5, 0.999), Model.luo_xie(2, 5, 0, 1.5, 0.999)],
                         ids=["Params", "Model"])
def test_slightly_dissipative_keeps_its_ns_points(p):
    """r = 0.999: the pair leaves the circle at 0.73630 and comes back at 0.81802."""
    res = _scan(p, 0.7, 0.85)
    assert not res.conservative
    assert [round(q.omega_c, 5) for q in res.points] == [0.7363, 0.81802]
    a, b = res.points
    assert a.crossing_resolved and b.crossing_resolved and a.detail == b.detail == ""
    assert a.h3 and not b.h3


def test_nearly_conservative_pairs_swapping_are_not_crossings():
    """r = 0.999, [0.9, 1.3]: near 1.0321 two complex pairs collide off the circle (two
    multipliers stay outside from 0.95 to 1.1256, a dense scan shows); a sign change of
    |lambda|^2 - 1 made by the tracked multiplier jumping between the pairs is no NS point."""
    with warnings.catch_warnings():
        # the normal form at 1.1668 (impact velocity near 0) warns of a near collision
        warnings.simplefilter("ignore", NearSingularWarning)
        res = hopf_points(Params(2, 5, 0, 1.5, 0.999), 0.9, 1.3)
    assert not any(1.0 < q.omega_c < 1.1 for q in res.points)
    (q,) = [q for q in res.points if abs(q.omega_c - 1.1256) < 1e-3]
    assert abs(abs(q.multiplier) - 1) < 1e-12 and q.h1 and not q.h3
    assert all(abs(abs(q.multiplier) - 1) < 1e-8 for q in res.points)


def test_h3_needs_a_resolved_crossing_speed():
    """A zero-speed touch (d|lambda1|/domega ~ -4e-11, as met on a conservative map) and
    two estimates of opposite sign do not give (H3)."""
    pt = _scan(Params(2, 5, 0, 1.5, 0.8), 0.70, 0.76).points[0]
    assert pt.h3 and pt.crossing_resolved and pt.detail == ""
    for dmod, branch, word in ((4e-11, 9e-9, "omega_c <="), (2.3, -1.1, "another sign")):
        q = dataclasses.replace(pt, dmod_domega=dmod, dmod_domega_branch=branch)
        assert not q.h3 and not q.crossing_resolved
        assert "(H3) not decided" in q.detail and word in q.detail
        d = q.as_dict()
        assert d["h3"] is False and d["crossing_resolved"] is False and d["detail"] == q.detail


def test_cli_conservative_preset(capsys):
    from symvi.cli import main
    args = ["hopf", "--mu-m", "2", "--mu-k", "2", "--f2", "0", "--b", "0.3", "--r", "1",
            "--range", "omega=0.5:3"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "conservative model: " + CONSERVATIVE in out
    assert "Hopf point" not in out and "forcing-resonance" in out
    assert main([*args, "--json"]) == 0
    obj = json.loads(capsys.readouterr().out)
    assert obj["conservative"] is True and obj["statement"] == CONSERVATIVE
    assert obj["points"] == []


@pytest.mark.slow
def test_conservative_model_events_match_the_paper_chain():
    old = _scan(Params(2, 5, 0, 1.5, 1.0), 0.9, 1.3)
    new = _scan(Model.luo_xie(2, 5, 0, 1.5, 1.0), 0.9, 1.3)
    # events at equal omega (to rounding) may come in either order: compare them sorted
    def key(events):
        return sorted((e.kind, e.branch, round(e.omega, 7)) for e in events)
    assert key(new.events) == key(old.events)
