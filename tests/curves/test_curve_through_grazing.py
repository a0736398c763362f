"""NS curves that run into an impact at zero velocity (issue 27, item 2): they end at the
located grazing-NS point, or with through=True go on, on the regular test
q(z) = w det(M - z I) of symvi.curves.regular, to the next admissible piece."""
import json

import numpy as np
import pytest

import symvi
from symvi.cli import main
from symvi.curves.curve import continue_curve
from symvi.curves.regular import regular_char
from symvi.curves.start import start_points
from symvi.model import Model
from symvi.orbits import admissible_orbits
from symvi.orbits.periodic import Problem, periodic_orbit

EX1 = symvi.Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
EX1_FLAGS = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]


@pytest.fixture(scope="module")
def ns_start():
    """Example 1's NS point at omega = 0.7369 (b = 1.5): its NS curve in (omega, b) grazes
    at both ends."""
    sp = start_points(Model.of(EX1), 0.7, 0.75, "ns")[0][0]
    assert abs(sp.value - 0.736876922090593) < 1e-9
    return sp


def test_regular_char_is_w_times_the_characteristic_polynomial():
    """q(z) = w det(M - z I) at an orbit far from grazing, for real and complex z, M the
    shooting monodromy and w = dg/dT of the flight (matrix determinant lemma)."""
    model = Model.of(EX1)
    y = admissible_orbits(model, 0.8, multipliers=False)[0].y
    o = periodic_orbit(model, n=1, p=1, guess=tuple(y), omega=0.8)
    pr = Problem(model, 1, 1, param="omega")
    u = np.asarray(o.u, dtype=float)
    _, Gu, _ = pr.evaluate(u, 0.8)
    M = pr.monodromy(u, Gu)[1]
    w = Gu[pr.d, pr.d]
    zs = [1.0, -1.0, 0.3 + 0.8j, np.exp(2.1j), 2.5]
    q = regular_char(pr, u, 0.8, 0, zs)
    for z, qz in zip(zs, q):
        ref = w * np.linalg.det(M - z * np.eye(pr.d))
        assert abs(qz - ref) <= 1e-10 * (1 + abs(ref)), (z, qz, ref)


@pytest.mark.slow
def test_ns_curve_ends_at_the_grazing_ns_point(ns_start):
    """Upwards in b the NS curve's impact slows to zero: the curve ends at the grazing-NS
    point, solved on the regular test; the standard curve's points (bordered test,
    impact speed 0.02 ... 0.08), extrapolated to zero speed, land on it."""
    c = continue_curve(EX1, "ns", ("omega", "b"), ns_start.orbit,
                       bounds={"omega": (0.5, 1.0), "b": (1.5, 3.0)}, both=False,
                       max_points=4000)
    assert "grazing-NS" in c.ends[-1]
    g = c.special[-1]
    assert g.kind == "grazing-NS" and g.coefficients["impact"] == 1
    assert abs(g.orbit.impact_velocities[0]) < 1e-9
    # the pair on the unit circle at the grazing orbit: q(e^{i theta}) = 0 there
    assert 0 < g.coefficients["theta"] < np.pi
    std = [p for p in c.points if not getattr(p, "_bridged", False)]
    v = np.array([min(p.orbit.impact_velocities) for p in std])
    sel = (v > 0.02) & (v < 0.08)
    assert sel.sum() > 20
    for name in ("omega", "b"):
        y = np.array([p.params[name] for p in std])
        assert abs(np.polyval(np.polyfit(v[sel], y[sel], 4), 0) - g.params[name]) < 1e-6
    # the points before it followed on the regular test carry theta, not l1
    bridged = [p for p in c.points if getattr(p, "_bridged", False)]
    assert bridged and all(p.l1 is None and p.theta is not None for p in bridged)
    assert any("regular test" in n for n in c.notes)


@pytest.mark.slow
def test_through_resumes_on_the_next_admissible_piece(capsys):
    """With --through the curve crosses grazing twice (impact 1's speed through zero and
    back) and resumes at omega ~ 0.5986, b ~ 1.9647 on a second admissible piece, where
    l1 is computed again and the pair lies on the unit circle, down to the flight's
    touch near b = 0.936."""
    code = main(["curve", *EX1_FLAGS, "--range", "omega=0.7:0.75", "--params", "omega,b",
                 "--bounds", "b=0.5:3", "--through", "--max-points", "6000", "--json"])
    assert code in (0, None)
    d = json.loads(capsys.readouterr().out)
    gns = [s for s in d["special"] if s["kind"] == "grazing-NS"]
    assert len(gns) == 2
    assert all("zero velocity" in s["detail"] for s in gns)
    assert abs(gns[1]["params"]["omega"] - 0.5986) < 1e-3
    assert abs(gns[1]["params"]["b"] - 1.9647) < 1e-3
    pts = d["points"]
    b = np.array([p["params"]["b"] for p in pts])
    w = np.array([p["params"]["omega"] for p in pts])
    # the second piece: points with omega < 0.598 and b < 1.96, admissible, l1 computed
    second = [p for p, bb, ww in zip(pts, b, w) if ww < 0.598 and bb < 1.95 and p["admissible"]]
    assert len(second) > 50
    # handed back to the standard test once the multipliers are below 25
    far = [p for p in second if max(abs(complex(*z)) for z in p["multipliers"]) < 25]
    assert len(far) > 0.8 * len(second)
    assert all(p["l1"] is not None for p in far)
    for p in second[::25]:
        mu = [complex(*z) for z in p["multipliers"]]
        assert min(abs(abs(z) - 1) for z in mu if abs(z.imag) > 1e-6) < 1e-8
    # between the crossings the orbit penetrates the stop: not admissible
    between = [p for p in pts if p["params"]["b"] > 1.97 and p["params"]["omega"] < 0.669]
    assert between and not any(p["admissible"] for p in between)
    touch = [s for s in d["special"] if s["kind"] == "grazing" and s["params"]["b"] < 1.5]
    assert touch and abs(touch[0]["params"]["b"] - 0.936) < 2e-3
