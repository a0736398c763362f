"""Two-parameter curves of models with nonlinear forces (issue 28): a flip curve and an NS
curve in (omega, beta), followed on the series jets of :mod:`symvi.flow.nljet`, land at
beta = 0 on the exact linear flow's flip and NS points (located on its generated jets, an
independent path), with their coefficients."""
import symvi
from symvi.continuation.branch import continue_branch
from symvi.curves.curve import continue_curve
from symvi.model import Model, Stop
from symvi.orbits.period1 import admissible_orbits
from symvi.orbits.periodic import periodic_orbit

IMPACT = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.0, restitution=0.8))
LX = dict(mass=[1.0, 2.0], stiffness=[[1.0, -1.0], [-1.0, 6.0]], damping=[[0, 0], [0, 0]],
          forcing=[1.0, 0.0], stop=Stop(mass=1, gap=1.5, restitution=0.8))


def _special(model, kind, omega, lo, hi, guess):
    o = periodic_orbit(model, n=1, p=1, guess=guess, omega=omega)
    br = continue_branch(model, "omega", lo, hi, orbit=o)
    found = [s for s in br.special if s.kind == kind]
    assert len(found) == 1
    return found[0]


def _at_beta_zero(curve):
    ends = [pt for pt in (curve.points[0], curve.points[-1]) if pt.params["beta"] == 0.0]
    assert len(ends) == 1
    return ends[0]


def test_a_flip_curve_lands_on_the_linear_flip():
    lin = Model(**IMPACT)
    ref = _special(lin, "flip", 2.6, 2.6, 2.8, admissible_orbits(lin, 2.6)[0].y)
    nl = Model(**IMPACT, nonlinear=["beta*x1**3"], parameters={"beta": 0.2})
    sim = symvi.simulate(nl, 2.6, n_impacts=50, transient=3000)
    sp = _special(nl, "flip", 2.6, 2.6, 2.8, sim)
    cv = continue_curve(nl, "flip", ("omega", "beta"), sp,
                        bounds={"omega": (2.0, 3.5), "beta": (0.0, 0.3)}, max_points=200)
    end = _at_beta_zero(cv)
    assert abs(end.params["omega"] - ref.value) < 1e-9
    assert abs(end.coefficient - ref.coefficients["c"]) < 1e-7 * abs(ref.coefficients["c"])


def test_an_ns_curve_lands_on_the_linear_ns_point():
    lin = Model(**LX)
    ref = symvi.hopf_points(lin, 0.70, 0.76).points[0]
    nl = Model(**LX, nonlinear=["beta*x1**3", "0"], parameters={"beta": 0.01})
    sp = _special(nl, "ns", 0.73, 0.73, 0.76, admissible_orbits(lin, 0.73)[0].y)
    cv = continue_curve(nl, "ns", ("omega", "beta"), sp,
                        bounds={"omega": (0.6, 0.9), "beta": (0.0, 0.012)}, max_points=200)
    end = _at_beta_zero(cv)
    assert abs(end.params["omega"] - ref.omega_c) < 1e-9
    assert abs(end.l1 - ref.l1) < 1e-8


def test_symvi_curve_on_a_nonlinear_model(tmp_path):
    """``symvi curve --model`` with nonlinear forces (its start: the flip that the branch
    from the homotopy's orbits locates in the range); at each end of the flip curve in
    (omega, beta) continuation in omega alone locates the flip at the curve's omega."""
    import json

    from symvi.model import dumps
    from tests.fuzz._cli import cli
    duffing = Model(**IMPACT, nonlinear=["beta*x1**3"], parameters={"beta": 0.2})
    f = tmp_path / "duffing.toml"
    f.write_text(dumps(duffing))
    rc, out, err = cli("curve", "--model", f, "--kind", "flip", "--range", "omega=2.6:2.9",
                       "--params", "omega,beta", "--bounds", "beta=0.15:0.25",
                       "--max-points", "60", "--json")
    assert rc == 0, err
    obj = json.loads(out)
    assert abs(obj["start"]["omega"] - 2.7473542619) < 1e-9
    ends = [obj["points"][0]["params"], obj["points"][-1]["params"]]
    assert sorted(e["beta"] for e in ends) == [0.15, 0.25]
    for e in ends:
        m = duffing.with_(beta=e["beta"])
        sim = symvi.simulate(m, e["omega"] - 0.01, n_impacts=50, transient=3000)
        sp = _special(m, "flip", e["omega"] - 0.01, e["omega"] - 0.01, e["omega"] + 0.01, sim)
        assert abs(sp.value - e["omega"]) < 1e-8
