"""Period-1 orbits, conditions (10), and the numeric map P."""
import math
import warnings

import numpy as np
import pytest

from symvi import NearSingularWarning, ParameterError, Params, SingularCaseError, modal
from symvi import period1_orbits, poincare_map
from symvi.paper.modal_map import fd_jacobian

from ..conftest import EX1, EX2, OWN


def _admissible(params, omega):
    return [o for o in period1_orbits(params, omega) if o.admissible]


def test_fixed_point_of_P_over_omega_grid(example):
    """P(y*) = y* to 1e-12 at the paper's examples over a grid of omega."""
    params, grid = example
    for omega in np.linspace(grid[0], grid[-1], 9):
        orbs = _admissible(params, omega)
        assert len(orbs) == 1          # only the "+" branch is physical here
        o = orbs[0]
        s = poincare_map(params, omega, o.y)
        assert s.status == "impact"
        d = np.array(s.y) - np.array(o.y)
        d[3] = (d[3] + math.pi) % (2 * math.pi) - math.pi
        assert np.max(np.abs(d)) < 1e-12
        assert abs(s.t - 2 * math.pi / omega) < 1e-12


@pytest.mark.parametrize("params,omega", [(EX1, 0.7369), (EX2, 0.4917), (OWN, 1.2)])
def test_jacobian_matches_finite_differences(params, omega):
    """DP at y* (generated code) against central differences of P: float64 with
    h = 1e-6 where the orbit is far from grazing, and always 30-digit mpmath
    differences with h = 1e-10 (the OWN "-" branch has impact velocity 0.04)."""
    from symvi.paper.jets import jet
    for o in _admissible(params, omega):
        J = jet(params, omega, 1, orbit=o).jacobian
        Jmp = np.array(fd_jacobian(params, omega, o.y, h=1e-10, digits=30).tolist(), dtype=float)
        assert np.max(np.abs(J - Jmp)) < 1e-10 * max(1, np.abs(J).max())
        if o.impact_velocity > 0.5:
            Jfd = fd_jacobian(params, omega, o.y, h=1e-6)
            assert np.max(np.abs(J - Jfd)) < 1e-7 * max(1, np.abs(J).max())


def test_multiplier_product_is_r_squared():
    """Undamped flight: the product of the four multipliers is r^2 at every orbit."""
    rng = np.random.default_rng(3)
    n = 0
    for _ in range(60):
        p = Params(rng.uniform(0.2, 5), rng.uniform(0.2, 8), rng.uniform(-0.5, 1),
                   rng.uniform(-1, 2), rng.uniform(0.05, 1))
        omega = rng.uniform(0.2, 3)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", NearSingularWarning)
                orbs = period1_orbits(p, omega)
        except SingularCaseError:
            continue
        for o in orbs:
            prod = np.prod(np.array(o.multipliers, dtype=complex))
            assert abs(prod - p.r ** 2) < 1e-9 * max(1, max(abs(np.array(o.multipliers))) ** 4)
            n += 1
    assert n > 30


def test_orbit_satisfies_conditions_10_and_velocity_law():
    """x1(0) = x1(T) = b, the impact law and continuity of mass 2, eq. (10)."""
    from symvi.paper.modal_flow import motion_from
    for params, omega in [(EX1, 0.73), (OWN, 1.2), (Params(2, 5, 0, 0.0, 0.8), 0.73)]:
        m = modal(params)
        for o in period1_orbits(params, omega, multipliers=False):
            mot = motion_from(m, omega, (params.b, o.x20), (o.v1_plus, o.x20_dot), o.tau0)
            T = 2 * math.pi / omega
            x1, x2, v1, v2 = mot.state(T)
            assert abs(x1 - params.b) < 1e-12
            assert abs(x2 - o.x20) < 1e-12 and abs(v2 - o.x20_dot) < 1e-12
            assert abs(o.v1_plus + params.r * v1) < 1e-12
            assert abs(v1 - o.impact_velocity) < 1e-12


def test_physical_branch_and_reasons():
    """Only the branch with x1dot+ < 0 and x1 < b inside the period is admissible."""
    orbs = period1_orbits(EX1, 0.7369)
    assert {o.branch for o in orbs} == {"+", "-"}
    for o in orbs:
        if o.admissible:
            assert o.v1_plus < 0 and o.reason == ""
        else:
            assert o.reason
    bad = [o for o in orbs if not o.admissible][0]
    assert "impact velocity" in bad.reason


def test_penetrating_orbit_is_inadmissible():
    """An orbit with x1(t) > b inside (0, 2 pi/omega) is reported, not analysed."""
    found = False
    for omega in np.linspace(0.3, 0.7, 41):
        for o in period1_orbits(EX1, omega, multipliers=False):
            if not o.admissible and "reaches b" in o.reason:
                found = True
                assert not o.stable
    assert found


def test_b_zero_and_r_one_are_regular():
    """b = 0 (eq. 11) and r = 1 are solved exactly, P(y*) = y* still."""
    for p, omega in [(Params(2, 5, 0, 0.0, 0.8), 0.73), (Params(2, 5, 0, 1.5, 1.0), 0.73)]:
        orbs = period1_orbits(p, omega)
        assert orbs
        for o in orbs:
            if o.admissible:
                s = poincare_map(p, omega, o.y)
                assert np.allclose(s.y[:3], o.y[:3], atol=1e-11)


def test_no_orbit_when_discriminant_negative():
    """Gap beyond reach: conditions (10) have no solution (eq. 16), empty list."""
    assert period1_orbits(Params(2, 5, 0, 50.0, 0.8), 0.7369) == []


def test_one_minus_cos_singularity_refused_and_warned():
    """omega = omega_j / n makes 1 - cos(2 pi omega_j/omega) = 0: refused; near it: warned."""
    w2 = modal(EX1).omega2
    with pytest.raises(SingularCaseError, match="one-minus-cos"):
        period1_orbits(EX1, w2 / 2)
    with pytest.warns(NearSingularWarning):
        period1_orbits(EX1, w2 / 2 * (1 + 1e-6))


def test_forcing_resonance_refused_and_warned():
    w1 = modal(EX1).omega1
    with pytest.raises(SingularCaseError, match="forcing-resonance"):
        period1_orbits(EX1, w1)
    with pytest.warns(NearSingularWarning):
        period1_orbits(EX1, w1 * (1 + 1e-6))


@pytest.mark.parametrize("kw,name", [
    (dict(mu_m=0), "mu_m"), (dict(mu_m=-1), "mu_m"), (dict(mu_k=0), "mu_k"),
    (dict(r=0), "r"), (dict(r=1.01), "r"), (dict(b=float("nan")), "b"),
    (dict(f2=float("inf")), "f2"), (dict(mu_m="x"), "mu_m")])
def test_bad_params_name_the_parameter(kw, name):
    base = dict(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    base.update(kw)
    with pytest.raises(ParameterError) as e:
        Params(**base)
    assert name in str(e.value) and "valid range" in str(e.value)


@pytest.mark.parametrize("omega", [0.0, -1.0, float("nan"), float("inf")])
def test_bad_omega(omega):
    with pytest.raises(ParameterError, match="omega"):
        period1_orbits(EX1, omega)


def test_mpmath_orbit_agrees_with_float():
    f = _admissible(EX1, 0.7369)[0]
    m = [o for o in period1_orbits(EX1, 0.7369, digits=40) if o.admissible][0]
    assert np.allclose([float(v) for v in m.y], f.y, rtol=0, atol=1e-13)
    lam_f = np.array(f.multipliers)
    lam_m = np.array([complex(z) for z in m.multipliers])
    assert np.max(np.abs(lam_f - lam_m)) < 1e-12
