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
