"""symvi.simulation with a Model: the paper's preset against the Params path,
stop codes on constructed cases, start points and bad input."""
import math

import numpy as np
import pytest

from symvi import ParameterError, Params
from symvi.model import Model, Stop
from symvi.simulations.simulation import DEFAULT_PERTURBATION, fixed_point, simulate, sweep
from tests.zoo import ONE_DAMPED_GAP02, PAPER_EX1, THREE_STOP2_GAP12
from tests.flow.gap_reference import Gap, random_states, tangent_states

EX1 = Params(2, 5, 0, 1.5, 0.8)


def test_luo_xie_preset_matches_params_path():
    """Model.luo_xie and Params run the same map: 1000 impacts on the invariant
    circle of example 1 (paper, Sec. 4, omega = 0.7372) agree to 1e-9."""
    y0 = (-1.46, 0.30, 0.04, 1.51)
    a = simulate(EX1, 0.7372, y0=y0, n_impacts=1000)
    b = simulate(PAPER_EX1, 0.7372, y0=y0, n_impacts=1000)
    assert a.stop == b.stop == "completed" and b.section.shape == (1000, 4)
    d = np.abs(a.section - b.section)
    d[:, 3] = np.minimum(d[:, 3], 2 * math.pi - d[:, 3])
    assert d.max() < 1e-9
    assert np.abs(a.t - b.t).max() < 1e-9 * a.t[-1]
    assert np.abs(a.impact_velocity - b.impact_velocity).max() < 1e-9


def test_default_start_is_period1_orbit_plus_perturbation():
    """Without y0 a Model starts at its admissible period-1 orbit + 1e-4 in each of
    the 2N components; a stable period-1 orbit attracts the run back."""
    s = simulate(THREE_STOP2_GAP12, 0.8, n_impacts=200, transient=3000)
    assert len(s.fixed_point) == 6 and s.section.shape == (200, 6)
    assert s.y0 == pytest.approx(np.add(s.fixed_point, 1e-4), abs=1e-15)
    assert s.stop == "completed"
    assert np.abs(s.section - s.fixed_point).max() < 1e-8
    assert np.diff(s.t) == pytest.approx(2 * math.pi / 0.8, rel=1e-8)
    assert fixed_point(PAPER_EX1, 0.7372) == pytest.approx(fixed_point(EX1, 0.7372), abs=1e-12)


def test_sweep_of_a_model():
    """sweep runs a Model over omega in parallel, rows as simulate gives them."""
    oms = [0.4, 0.8, 1.3]
    starts = random_states(THREE_STOP2_GAP12, 3, np.random.default_rng(1))
    sw = sweep(THREE_STOP2_GAP12, oms, n_impacts=50, transient=100, starts=starts)
    assert sw.section.shape == (3, 50, 6) and sw.starts.shape == (3, 6)
    for i, w in enumerate(oms):
        s = simulate(THREE_STOP2_GAP12, w, y0=starts[i], n_impacts=50, transient=100)
        assert sw.stops[i] == s.stop and sw.counts[i] == s.n
        assert np.array_equal(sw.section[i, :s.n], s.section)
    sw = sweep(PAPER_EX1, [0.735, 0.74], n_impacts=20, transient=10)
    assert sw.section.shape == (2, 20, 4) and sw.stops == ("completed", "completed")


def test_stop_no_impact():
    """Heavy damping, gap far above the steady-state amplitude: the mass never
    returns to the stop (within 1000 forcing periods)."""
    m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.2]], forcing=[1.0],
              stop=Stop(mass=1, gap=5.0, restitution=0.8))
    s = simulate(m, 0.5, y0=(-0.1, 0.0), n_impacts=10)
    assert s.stop == "no-impact" and s.n == 0


def test_stop_grazing():
    """A start whose flight touches the stop tangentially (h = 0, h' = 0 at t*,
    x_k'' < 0) ends the run as grazing, with nothing stored past the contact."""
    rng = np.random.default_rng(4)
    ys, ts = tangent_states(THREE_STOP2_GAP12, 0.4, random_states(THREE_STOP2_GAP12, 40, rng), rng, deltas=(0.0,))
    g = Gap(THREE_STOP2_GAP12, 0.4, ys)
    # the tangency is the first approach to the stop, with x_k'' < 0 there
    i = np.flatnonzero((g.first_crossing(30.0, 0.002) > ts - 0.05) & (g.at(ts, 2) < 0))[0]
    s = simulate(THREE_STOP2_GAP12, 0.4, y0=ys[i], n_impacts=10)
    assert s.stop == "grazing" and s.n == 0


def test_sticking_goes_through():
    """Leaving the stop at 1e-8 while the forcing pushes the mass into it
    (x'' = sin(tau) - b > 0): the contact at ~zero speed sticks, and the mass is released
    where sin(omega t + tau) = b (the contact force sin - b changes sign, falling)."""
    s = simulate(ONE_DAMPED_GAP02, 0.8, y0=(-1e-8, math.pi / 2), n_impacts=10)
    assert s.stop == "completed" and s.n == 10
    t_stick, t_release, k = s.sticks[0]
    assert t_stick < 1e-6 and k == 0
    phase = 0.8 * t_release + math.pi / 2
    assert math.sin(phase) == pytest.approx(0.2, abs=1e-12) and math.cos(phase) < 0


def test_chatter_goes_through():
    """Slow forcing pressing the mass on the stop, r = 0.7: flights shrink geometrically
    (an accumulation of impacts); the run goes on through the accumulation point."""
    m = Model(mass=[1.0], stiffness=[[1.0]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.2, restitution=0.7))
    s = simulate(m, 0.1, y0=(-0.02, math.pi / 2), n_impacts=100)
    assert s.stop == "completed" and s.n == 100
    first = s.t < s.sticks[0, 0]
    assert first.sum() >= 16
    te = np.diff(s.t[first])
    assert (te[1:] < te[:-1]).all()


@pytest.mark.parametrize("y0, why", [((-1.0, 0.1, 0.2, 0.3, 0.4), "6 finite numbers"),
                                     ((-1.0, 0.1, float("nan"), 0.3, 0.4, 1.0), "finite"),
                                     ((0.5, 0.1, 0.2, 0.3, 0.4, 1.0), r"v2\+ < 0"),
                                     ("abc", "finite")], ids=["length", "nan", "sign", "text"])
def test_bad_start_names_y0(y0, why):
    with pytest.raises(ParameterError, match=why) as e:
        simulate(THREE_STOP2_GAP12, 0.4, y0=y0, n_impacts=10)
    assert e.value.name == "y0"


def test_bad_input_names_the_argument():
    for kw, name in (({"omega": float("nan")}, "omega"), ({"n_impacts": 0}, "n_impacts"),
                     ({"perturbation": (1e-4,) * 4}, "perturbation"),
                     ({"transient": -1}, "transient")):
        args = {"omega": 0.4, **kw}
        with pytest.raises(ParameterError) as e:
            simulate(THREE_STOP2_GAP12, args.pop("omega"), **args)
        assert e.value.name == name
    with pytest.raises(ParameterError) as e:
        sweep(THREE_STOP2_GAP12, [0.4, 0.8], starts=[(-1.0, 0, 0, 0, 0, 0.0)], n_impacts=5, transient=0)
    assert e.value.name == "starts"
    assert DEFAULT_PERTURBATION == (1e-4,) * 4        # the Params default, untouched
