"""Period-1 orbits of any model: fixed points of the exact map, the determinant
identity, and the paper's model through Model against the paper's own chain."""
import math
import warnings

import mpmath
import numpy as np
import pytest

from symvi import Params
from symvi.paper.modal_orbit import period1_orbits as paper_orbits  # the modal oracle
from symvi.errors import NearSingularWarning, SingularCaseError
from symvi.maps.impact import poincare_map
from symvi.model import Model
from symvi.orbits import period1_orbits

from tests.zoo import N_MASS_SET

OMEGAS = np.linspace(0.3, 3.0, 28)


def _admissible(model):
    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        for w in OMEGAS:
            try:
                out += [o for o in period1_orbits(model, float(w)) if o.admissible]
            except SingularCaseError:
                pass
    return out


@pytest.mark.parametrize("name", list(N_MASS_SET))
def test_fixed_point_and_determinant_identity(name):
    """P(y*) = y* at every admissible orbit, and det DP = r^2 exp(-tr(M^-1 C) 2 pi / omega)."""
    model = N_MASS_SET[name]
    orbits = _admissible(model)
    assert len(orbits) >= 3, name
    trMC = float(np.trace(np.linalg.solve(model.mass, model.damping)))
    r = model.stop.restitution
    for o in orbits:
        s = poincare_map(model, o.omega, o.y)
        assert s.status == "impact"
        T = 2 * math.pi / o.omega
        assert abs(s.t - T) < 1e-9 * T
        d = np.array(s.y) - np.array(o.y)
        d[-1] = (d[-1] + math.pi) % (2 * math.pi) - math.pi
        assert np.abs(d).max() < 1e-9 * (1 + np.abs(o.y).max())
        det = np.prod(np.array(o.multipliers)).real
        assert det == pytest.approx(r * r * math.exp(-trMC * T), rel=1e-9)
        assert o.y[0] < 0 and o.impact_velocity > 0


@pytest.mark.parametrize("params,omega", [(Params(2, 5, 0, 1.5, 0.8), 0.7369),
                                          (Params(4, 2, 0, 1.8, 0.8), 0.4906),
                                          (Params(1.5, 3.0, 0.3, 0.9, 0.7), 1.3),
                                          (Params(2, 5, 0, 1.5, 1.0), 0.7369),
                                          (Params(2, 5, 0, -0.4, 0.8), 0.7369)])
def test_paper_model_through_Model_gives_todays_numbers(params, omega):
    """Model.luo_xie (and so Params, its preset) gives the orbits of the paper's own modal
    closed form (the oracle, symvi.paper.modal_orbit) to 1e-12, branch names too."""
    old = {o.branch: o for o in paper_orbits(params, omega)}
    new = {o.branch: o for o in period1_orbits(Model.luo_xie(**params.as_dict()), omega)}
    assert set(old) == set(new)
    for br, o in old.items():
        n = new[br]
        assert np.allclose([float(v) for v in n.y], [float(v) for v in o.y], rtol=0, atol=1e-12)
        assert abs(n.impact_velocity - o.impact_velocity) < 1e-12
        assert n.admissible == o.admissible
        for z in o.multipliers:
            assert min(abs(z - x) for x in n.multipliers) < 1e-12


def test_branch_names_at_r_one_follow_the_paper_on_a_grid():
    """At r = 1 (no damping) b no longer moves the line of fixed points and the orientation
    is the limit r -> 1-: the names match the paper chain at every omega, float and mpmath."""
    params = Params(2, 5, 0, 1.5, 1.0)
    model = Model.luo_xie(**params.as_dict())
    for omega in np.linspace(0.9, 1.3, 41)[1:]:
        old = {o.branch: o.tau0 for o in paper_orbits(params, omega)}
        new = {o.branch: o.y[-1] for o in period1_orbits(model, omega)}
        assert set(old) == set(new) and len(old) == 2
        for br in old:
            assert abs(math.remainder(new[br] - old[br], 2 * math.pi)) < 1e-9, (omega, br)
    old = {o.branch: o.tau0 for o in paper_orbits(params, 1.25, digits=30)}
    new = {o.branch: o.y[-1] for o in period1_orbits(model, 1.25, digits=30)}
    with mpmath.mp.workdps(30):
        for br in old:
            d = (new[br] - old[br]) / (2 * mpmath.pi)
            assert abs(d - mpmath.nint(d)) < mpmath.mpf(10) ** -25


def test_mpmath_orbit_agrees_and_is_a_fixed_point_to_40_digits():
    model = N_MASS_SET["three"]
    o = [x for x in period1_orbits(model, 0.95, digits=45) if x.admissible][0]
    s = poincare_map(model, o.omega, o.y, digits=45)
    with mpmath.mp.workdps(45):
        err = max(abs(a - b) for a, b in zip(s.y, o.y))
    assert err < mpmath.mpf(10) ** -38
    f = [x for x in period1_orbits(model, 0.95) if x.admissible][0]
    assert np.allclose([float(v) for v in o.y], f.y, atol=1e-12)


def test_singular_frequency_is_refused_with_its_cause():
    """omega = omega_2 / 2 (undamped): 1 - cos(2 pi omega_2 / omega) = 0, not isolated."""
    from symvi.flow.linear import LinearFlow
    model = N_MASS_SET["paper"]
    w2 = float(LinearFlow.of(model).omegas[1])
    with pytest.raises(SingularCaseError, match="one-minus-cos"):
        period1_orbits(model, w2 / 2)


def test_forcing_resonance_is_refused():
    from symvi.flow.linear import LinearFlow
    model = N_MASS_SET["paper"]
    w1 = float(LinearFlow.of(model).omegas[0])
    with pytest.raises(SingularCaseError, match="forcing-resonance"):
        period1_orbits(model, w1)


def test_top_level_functions_take_a_model():
    """symvi.period1_orbits, symvi.poincare_map, symvi.jet, symvi.hopf_points and
    symvi.simulate accept a Model as well as the paper's Params."""
    import symvi
    model = N_MASS_SET["three"]
    o = [x for x in symvi.period1_orbits(model, 0.95) if x.admissible][0]
    assert o.names[0] == "v2+"
    s = symvi.poincare_map(model, 0.95, o.y)
    assert abs(s.t - 2 * math.pi / 0.95) < 1e-9
    j = symvi.jet(model, 0.95, 2)
    assert np.allclose(j.jacobian, jet_at_orbit(model, o))


def jet_at_orbit(model, o):
    from symvi.codegen.jets import jet_at
    return jet_at(model, o.omega, o.y, 2 * math.pi / o.omega, 1).jacobian
