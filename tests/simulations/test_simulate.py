"""symvi.simulation: runs of the Poincaré map, stop reasons, float64 against mpmath."""
import math

import numpy as np
import pytest

from symvi import Model, ParameterError, SingularCaseError
from symvi.flow import compiled as cf
from symvi.paper.modal_map import poincare_map
from symvi.simulations.diagnostics import jacobian, lyapunov
from symvi.simulations.simulation import (DEFAULT_PERTURBATION, fixed_point, simulate,
                                          simulate_mp, sweep)

from ..conftest import EX1, EX2, OWN


def test_default_start_and_shapes():
    """Default start is y* + DEFAULT_PERTURBATION; section (n, 4), tau in [0, 2 pi), t increasing."""
    s = simulate(EX1, 0.7372, n_impacts=300, transient=10)
    ys = fixed_point(EX1, 0.7372)
    assert s.y0 == pytest.approx(np.add(ys, DEFAULT_PERTURBATION), abs=1e-15)
    assert s.fixed_point == pytest.approx(ys)
    assert s.section.shape == (300, 4) and s.t.shape == (300,)
    assert s.stop == "completed"
    assert ((s.section[:, 3] >= 0) & (s.section[:, 3] < 2 * math.pi)).all()
    assert (np.diff(s.t) > 0).all() and s.t[0] > 0
    assert (s.section[:, 0] < 0).all() and (s.impact_velocity > 0).all()
    with pytest.raises(ValueError):
        s.section[0, 0] = 1.0         # results are read-only


def test_matches_reference_map():
    """50 steps agree with the reference poincare_map (pure Python, float64) to 1e-10."""
    s = simulate(EX1, 0.7400, n_impacts=50)
    y = s.y0
    for k in range(50):
        y = poincare_map(EX1, 0.7400, y).y
        d = np.subtract(y, s.section[k])
        d[3] = (d[3] + math.pi) % (2 * math.pi) - math.pi
        assert np.abs(d).max() < 1e-10


def test_transient_dropped_and_times_continue():
    a = simulate(EX1, 0.7400, n_impacts=40)
    b = simulate(EX1, 0.7400, n_impacts=20, transient=20)
    assert np.array_equal(a.section[20:], b.section)
    assert np.allclose(a.t[20:], b.t, rtol=1e-14)


def test_float_tracks_mpmath_on_circle():
    """On an invariant circle (largest exponent 0) float64 stays within 1e-11 of a
    40-digit mpmath run for 120 impacts."""
    s = simulate(EX1, 0.7400, n_impacts=10, transient=3000)
    y0 = tuple(s.section[-1])
    f = simulate(EX1, 0.7400, y0=y0, n_impacts=120)
    m = simulate_mp(EX1, 0.7400, y0, 120, digits=40)
    assert m.stop == "completed" and m.n == 120
    assert np.abs(f.section - m.section).max() < 1e-11
    assert np.abs(f.t - m.t).max() < 1e-11 * f.t[-1]


@pytest.mark.slow
def test_float_tracks_mpmath_for_lyapunov_time():
    """Chaos (paper, Sec. 4: example 2 at 0.4944): float64 and 40-digit mpmath part
    after k impacts with k consistent with lambda_1: exp(lambda_1 k) * 2e-16 ~ 1e-7
    predicts k within a factor 2."""
    om = 0.4944
    s = simulate(EX2, om, n_impacts=3000, transient=5000)
    lam = lyapunov(s).largest
    assert lam > 0.02
    y0 = tuple(s.section[-1])
    k_pred = math.log(1e-7 / 2.2e-16) / lam
    n = int(2 * k_pred)
    f = simulate(EX2, om, y0=y0, n_impacts=n)
    m = simulate_mp(EX2, om, y0, n, digits=40)
    d = np.abs(f.section - m.section)
    d[:, 3] = np.minimum(d[:, 3], 2 * math.pi - d[:, 3])
    err = d.max(axis=1)
    k_div = int(np.argmax(err > 1e-7)) if (err > 1e-7).any() else n
    assert 0.5 * k_pred <= k_div <= 2 * k_pred, (k_div, k_pred)
    # before that, the error is the rounding of each step carried along this stretch of the
    # attractor (its own growth, not the average lambda_1: stretches differ by ~1e3 in it):
    # err_k <= eps_step * sum_j ||DP(y_k-1) ... DP(y_j)||, eps_step = 1e-14 (the float
    # map's one-step error is ~1e-15, at most 3.3e-15 against 40 digits)
    K = int(0.3 * k_pred)
    pts = [y0] + [tuple(v) for v in m.section[:K - 1]]
    carried, bound = [], []
    for y in pts:
        J = jacobian(EX2, om, y)
        carried = [J @ A for A in carried] + [np.eye(4)]
        bound.append(1e-14 * sum(np.linalg.norm(A, 2) for A in carried))
    assert (err[:K] <= np.array(bound)).all(), max(zip(err[:K] / np.array(bound), range(K)))


def test_validation():
    with pytest.raises(ParameterError):
        simulate(EX1, -0.7, n_impacts=10)
    with pytest.raises(ParameterError):
        simulate(EX1, 0.74, y0=(0.1, 0.0, 0.0, 1.0), n_impacts=10)    # x1dot+ >= 0
    with pytest.raises(ParameterError):
        simulate(EX1, 0.74, y0=(-1.0, float("nan"), 0.0, 1.0), n_impacts=10)
    with pytest.raises(ParameterError):
        simulate(EX1, 0.74, n_impacts=0)
    with pytest.raises(ParameterError):
        simulate(EX1, 0.74, n_impacts=10, transient=-1)


def test_no_orbit_needs_y0():
    """Where no period-1 orbit exists, the default start is refused with a clear error."""
    with pytest.raises(SingularCaseError, match="no-orbit"):
        simulate(EX1, 3.0, n_impacts=10)


def test_stop_no_impact():
    """A flight longer than t_max ends the run as no-impact, not a hang."""
    c = cf.constants(Model.of(EX1), 0.7372, t_max=1.0)
    code, sec, t, _, _ = cf.run(c, (-1.46, 0.30, 0.04, 1.51), 100)
    assert cf.STOP_NAMES[code] == "no-impact" and len(sec) == 0


def _slow_return_state(params):
    """Leave the stop slowly while the force pushes mass 1 into it: low-speed returns."""
    m_tau = np.linspace(0, 2 * math.pi, 64, endpoint=False)
    for tau in m_tau:
        y = (-1e-3, params.b, 0.0, tau)
        # x1'' at x1 = x2 = b, eq. (3): the spring between the masses is relaxed
        if (1 - params.f2) * math.sin(tau) > 0.05:      # x1'' > 0: pressed into the stop
            return y
    raise AssertionError("no such phase")


@pytest.mark.parametrize("r", [0.3, 0.8])
def test_chatter_and_sticking_go_through(r):
    """Low-speed returns against the force give an accumulation of impacts: the run goes
    on through the chatter's accumulation point, a sticking phase and the release
    (issue 27), and stores every requested impact."""
    p = type(OWN)(OWN.mu_m, OWN.mu_k, OWN.f2, OWN.b, r)
    y = _slow_return_state(p)
    s = simulate(p, 1.3, y0=y, n_impacts=3000)
    assert s.stop == "completed" and s.n == 3000 and s.stop_reason == ""
    assert len(s.sticks) >= 1
    t_stick, t_release, k = s.sticks[0]
    assert 0 < t_stick < t_release and k == 0
    # the chatter's impacts before the accumulation point, none stored inside the phase
    before = s.t[s.t <= t_stick]
    assert len(before) >= 2 and s.impact_velocity[len(before) - 1] < 1e-3
    assert not ((s.t > t_stick) & (s.t < t_release)).any()


def test_stop_grazing():
    """A start whose first approach touches the stop tangentially stops as grazing."""
    from .test_finder import _states
    rng = np.random.default_rng(3)
    ys = _states(EX1, 0.7372, 60, rng)
    c = cf.constants(Model.of(EX1), 0.7372)
    grazing = [y for y in ys[:20] if cf.step(c, y)[0] == cf.GRAZING]
    assert grazing
    s = simulate(EX1, 0.7372, y0=grazing[0], n_impacts=10)
    assert s.stop == "grazing" and s.n == 0


def test_sweep_matches_single_runs():
    """The parallel batch gives the same points as one run per omega."""
    oms = [0.7300, 0.7400, 0.7440]
    sw = sweep(EX1, oms, n_impacts=50, transient=100, chunk=2)
    for i, om in enumerate(oms):
        s = simulate(EX1, om, n_impacts=50, transient=100)
        assert sw.stops[i] == s.stop
        assert np.array_equal(sw.section[i, : sw.counts[i]], s.section)
