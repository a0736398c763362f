"""n-p orbits by multiple shooting: against the closed form, the map, the generated jets,
finite differences and simulation."""
import math

import numpy as np
import pytest

import symvi
from symvi.codegen.jets import jacobian_at
from symvi.errors import ParameterError
from symvi.maps.impact import poincare_map
from symvi.orbits import admissible_orbits
from symvi.orbits.periodic import (ConvergenceError, Problem, detect_period, from_simulation,
                                   periodic_orbit)
from tests.zoo import N_MASS_SET, ONE_DAMPED_GAP0



@pytest.mark.parametrize("name", sorted(N_MASS_SET))
def test_period1_equals_closed_form(name):
    model = N_MASS_SET[name]
    w = 1.3
    orbits = admissible_orbits(model, w)
    assert orbits, "the test needs an admissible orbit"
    for o in orbits:
        guess = np.array(o.y) + 1e-3 * np.cos(np.arange(len(o.y)))
        po = periodic_orbit(model, n=1, p=1, guess=guess, omega=w)
        assert np.max(np.abs(np.array(po.y) - np.array(o.y))) < 1e-10
        assert po.times[0] == pytest.approx(2 * math.pi / w, rel=1e-12)
        assert po.admissible and po.residual < 1e-10
        # multipliers of the eliminated shooting Jacobian = eigenvalues of the generated DP
        ev = np.sort_complex(np.linalg.eigvals(jacobian_at(model, w, o.y, 2 * math.pi / w)))
        assert np.max(np.abs(np.sort_complex(np.array(po.multipliers)) - ev)) < 1e-9
        # det DP = r^2 exp(-tr(M^-1 C) 2 pi / omega)
        tr = np.trace(np.linalg.solve(np.asarray(model.mass), np.asarray(model.damping)))
        det = np.prod(np.array(po.multipliers)).real
        assert det == pytest.approx(model.stop.restitution ** 2 * math.exp(-tr * 2 * math.pi / w),
                                    rel=1e-9)


def _doubled():
    sim = symvi.simulate(ONE_DAMPED_GAP0, 2.69, n_impacts=200, transient=3000)
    return sim, from_simulation(sim)


def test_2_2_orbit_from_simulation_is_a_fixed_point_of_P2():
    sim, po = _doubled()
    assert (po.n, po.p) == (2, 2)
    assert po.admissible and po.stable
    # the orbit matches the simulated section, and P^2(y*) = y*
    assert np.max(np.abs(np.array(po.points) - sim.section[-2:])) < 1e-8
    y = po.points[0]
    for _ in range(2):
        s = poincare_map(ONE_DAMPED_GAP0, 2.69, y)
        y = s.y
    assert np.max(np.abs(np.array(y[:-1]) - np.array(po.points[0][:-1]))) < 1e-10
    assert abs((y[-1] - po.points[0][-1] + math.pi) % (2 * math.pi) - math.pi) < 1e-10
    assert sum(po.times) == pytest.approx(2 * 2 * math.pi / 2.69, rel=1e-12)


def test_monodromy_against_generated_jets_and_finite_differences():
    _, po = _doubled()
    A, d2, d3 = po.jet(3)
    mono = np.sort_complex(np.array(po.multipliers))
    assert np.max(np.abs(np.sort_complex(np.linalg.eigvals(A)) - mono)) < 1e-9

    def P2(y):
        for _ in range(2):
            s = poincare_map(ONE_DAMPED_GAP0, 2.69, y)
            y = np.array(s.y[:-1] + (s.tau_unwrapped,))
        return y
    y0 = np.array(po.points[0])
    h = 1e-6
    fd = np.column_stack([(P2(y0 + h * e) - P2(y0 - h * e)) / (2 * h) for e in np.eye(len(y0))])
    assert np.max(np.abs(fd - A)) < 1e-6 * (1 + np.max(np.abs(A)))
    # the composed second derivative against differences of P^2's finite-difference Jacobian
    def J(y):
        return np.column_stack([(P2(y + h * e) - P2(y - h * e)) / (2 * h)
                                for e in np.eye(len(y))])
    k = 1e-4
    fd2 = np.stack([(J(y0 + k * e) - J(y0 - k * e)) / (2 * k) for e in np.eye(len(y0))], axis=2)
    assert np.max(np.abs(fd2 - d2)) < 1e-3 * (1 + np.max(np.abs(d2)))


def test_detect_period_and_refusals():
    sim, po = _doubled()
    assert detect_period(sim) == (2, 2)
    with pytest.raises(ParameterError, match="omega"):
        periodic_orbit(ONE_DAMPED_GAP0, n=1, p=1, guess=po.points[0])
    with pytest.raises(ParameterError, match="^p = 0"):
        periodic_orbit(ONE_DAMPED_GAP0, n=1, p=0, guess=po.points[0], omega=2.69)
    with pytest.raises(ParameterError, match="guess"):
        periodic_orbit(ONE_DAMPED_GAP0, n=1, p=1, guess=[1.0, 2.0, 3.0], omega=2.69)


def test_no_convergence_raises_with_the_residual():
    # a 1-1 orbit sought at the 2-2 attractor's point, where the 1-1 orbit is far off and
    # unstable: Newton either finds the true 1-1 orbit or says it did not converge
    _, po = _doubled()
    try:
        o = periodic_orbit(ONE_DAMPED_GAP0, n=3, p=1, guess=po.points[0], omega=2.69, )
    except ConvergenceError as exc:
        assert math.isfinite(exc.residual) or exc.residual == math.inf
        assert "residual" in str(exc) or "impact" in str(exc)
    else:
        # whatever it returns must be a 3-1 orbit: one impact in three periods
        assert o.residual < 1e-9 and o.times[0] == pytest.approx(3 * 2 * math.pi / 2.69)


def test_parameter_derivative_is_exact():
    """dG/dlam of the shooting system against central differences, for omega and names."""
    model = N_MASS_SET["three"]
    o = admissible_orbits(model, 1.3)[0]
    po = periodic_orbit(model, n=1, p=1, guess=o.y, omega=1.3)
    for name, lam in (("omega", 1.3), ("gap", 0.5), ("damping[1,2]", -0.005),
                      ("forcing[2]", 0.5), ("restitution", 0.8), ("mass[3]", 0.8)):
        pr = Problem(model, 1, 1, omega=None if name == "omega" else 1.3, param=name)
        _, _, Gl = pr.evaluate(po.u, lam, jac=False, dparam=True)
        h = 1e-6 * max(1.0, abs(lam))
        fd = (pr.evaluate(po.u, lam + h, jac=False)[0]
              - pr.evaluate(po.u, lam - h, jac=False)[0]) / (2 * h)
        assert np.max(np.abs(Gl - fd)) < 1e-7 * (1 + np.max(np.abs(Gl))), name


@pytest.mark.parametrize("omega, y0, expect", [(0.7, (-0.614, 5.15), (1, 2)),
                                               (0.65, (-2.55, 3.20), (1, 3))])
def test_multi_impact_orbits_from_simulation(omega, y0, expect):
    from tests.zoo import ONE_LIGHT_GAP0
    sim = symvi.simulate(ONE_LIGHT_GAP0, omega, y0=y0, n_impacts=300, transient=3000)
    po = from_simulation(sim)
    assert (po.n, po.p) == expect
    assert po.admissible and po.stable and po.residual < 1e-10
    assert np.max(np.abs(np.array(po.points) - sim.section[-po.p:])) < 1e-8
    y = po.points[0]
    for _ in range(po.p):
        y = poincare_map(ONE_LIGHT_GAP0, omega, y).y
    assert np.max(np.abs(np.array(y[:-1]) - np.array(po.points[0][:-1]))) < 1e-10
    assert sum(po.times) == pytest.approx(po.n * 2 * math.pi / omega, rel=1e-12)
