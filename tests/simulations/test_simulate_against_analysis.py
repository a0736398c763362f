"""Simulation of any model against the analysis: the normal form's invariant circle
next to a Neimark–Sacker point of the damped 3-mass chain, and the Lyapunov spectrum
against the volume identity."""
import math
import warnings

import numpy as np
import pytest

from symvi import hopf_points
from symvi.errors import NearSingularWarning
from symvi.simulations.diagnostics import classify, lyapunov
from symvi.simulations.simulation import simulate

from tests.zoo import THREE_STOP2_GAP05


@pytest.fixture(scope="module")
def ns_point():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        return hopf_points(THREE_STOP2_GAP05, 0.99, 1.02).points[0]


def _half_widths(sim):
    d = np.array(sim.section) - np.array(sim.fixed_point)
    d[:, -1] = (d[:, -1] + math.pi) % (2 * math.pi) - math.pi
    return (d.max(axis=0) - d.min(axis=0)) / 2


def test_simulated_circle_matches_the_normal_form(ns_point):
    """l1 < 0, d|lambda|/dv > 0: a stable circle for omega > omega_c, of half-widths
    2 rho |q_i| sqrt(mu).  The relative error is O(mu): it must shrink with mu."""
    c = ns_point.circle
    assert c.stable and c.side > 0
    errs = []
    for mu in (4e-4, 1e-4):
        sim = simulate(THREE_STOP2_GAP05, ns_point.omega_c + mu, n_impacts=20000, transient=300000)
        assert sim.stop == "completed"
        ratio = _half_widths(sim) / np.array(c.half_widths(mu))
        errs.append(np.abs(ratio - 1).max())
    assert errs[1] < 0.03 and errs[0] < 0.1
    assert errs[1] < errs[0] / 2


def test_circle_classified_with_the_critical_rotation_number(ns_point):
    sim = simulate(THREE_STOP2_GAP05, ns_point.omega_c + 3e-3, n_impacts=4000, transient=100000)
    cl = classify(sim)
    assert cl.kind == "invariant circle"
    assert cl.rotation == pytest.approx(ns_point.theta_over_2pi, abs=5e-3)


def test_lyapunov_sum_is_the_volume_contraction():
    """Sum of the exponents = mean log |det DP| = 2 log r - tr(M^-1 C) <t_e> (+ O(1/n))."""
    sim = simulate(THREE_STOP2_GAP05, 1.003, n_impacts=4000, transient=50000)
    ly = lyapunov(sim)
    trMC = float(np.trace(np.linalg.solve(THREE_STOP2_GAP05.mass, THREE_STOP2_GAP05.damping)))
    expected = 2 * math.log(THREE_STOP2_GAP05.stop.restitution) - trMC * ly.mean_flight_time
    assert ly.exponents.sum() == pytest.approx(expected, abs=2e-3)
    assert abs(ly.largest) < 1e-3          # on an invariant circle


def test_circle_check_study_on_a_model(ns_point):
    """symvi.circle_check (bracketed measurement) on the 3-mass chain: O(mu) error."""
    from symvi.studies import circle_check as cc
    r = cc.check(THREE_STOP2_GAP05, ns_point, [4e-4, 2e-4, 1e-4])
    assert all(r.converged) and r.names[0] == "v2+"
    assert np.abs(r.rel_error[-1]).max() < 0.02
    assert 0.7 < r.error_slope < 1.3
    assert r.printed_scale is None           # eq. (60) is the paper's


def test_compiled_simulation_against_the_mpmath_reference():
    """Twenty impacts of the compiled run equal the 40-digit run of the exact map."""
    from symvi.simulations.simulation import simulate_mp
    y0 = [-0.75, 0.02, -1.7, 0.85, 4.1, 3.4]
    fast = simulate(THREE_STOP2_GAP05, 0.95, y0=y0, n_impacts=20, transient=0)
    ref = simulate_mp(THREE_STOP2_GAP05, 0.95, y0, 20)
    assert ref.stop == fast.stop == "completed"
    d = np.array(fast.section) - np.array(ref.section)
    d[:, -1] = (d[:, -1] + math.pi) % (2 * math.pi) - math.pi
    assert np.abs(d).max() < 1e-10
    assert np.abs(np.array(fast.t) - np.array(ref.t)).max() < 1e-9
