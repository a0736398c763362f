"""Periodic orbits with a sticking phase, solved on the release section (issue 27, item 4:
:mod:`symvi.orbits.sticking`), against the contact force's closed form and long runs of
``symvi.simulate`` through chatter and sticking (:mod:`symvi.flow.sticking`)."""
import math

import numpy as np
import pytest

from symvi import simulate
from symvi.errors import ParameterError, SymviError
from symvi.model import Model, Stop
from symvi.orbits import StickingSignature, sticking_orbit

ZETA, A, GAP, R, W = 0.05, 1.0, 0.2, 0.5, 0.5
#: x'' + 2 zeta x' + x = A sin(omega t + tau), a stop at x = GAP: it chatters and sticks
#: once every forcing period
ONE = Model(mass=[1.0], stiffness=[[1.0]], damping=[[2 * ZETA]], forcing=[A],
            stop=Stop(mass=1, gap=GAP, restitution=R))
#: two masses, mass 1 held on its stop while mass 2 moves: one sticking phase a period
TWO = Model(mass=[[1.0, 0], [0, 1.3]], stiffness=[[2.0, -1.0], [-1.0, 2.5]],
            damping=[[0.1, 0], [0, 0.1]], forcing=[0.8, 1.1],
            stop=Stop(mass=1, gap=0.1, restitution=0.5))
W2 = 0.7


@pytest.fixture(scope="module")
def one_run():
    return simulate(ONE, W, y0=(-0.5, 0.0), n_impacts=2000)


@pytest.fixture(scope="module")
def two_run():
    return simulate(TWO, W2, y0=(-0.5, 0.0, 0.0, 0.0), n_impacts=1000)


def _done(sim):
    return sim.sticks[np.isfinite(sim.sticks[:, 1])]


def test_one_mass_release_phase_is_the_closed_form(one_run):
    """Held at x = GAP the contact force is A sin(phase) - k GAP: every release lies at
    the phase pi - asin(k GAP / A), whatever came before.  R is constant: its one
    multiplier is 0 (superstable), to the central differences' accuracy."""
    o = sticking_orbit(ONE, guess=one_run)
    assert o.admissible and o.reason == ""
    assert str(o.signature) == "1-0+stick" and o.names == ("tau",)
    assert o.tau_release == pytest.approx(math.pi - math.asin(GAP / A), abs=1e-12)
    assert len(o.multipliers) == 1 and abs(o.multipliers[0]) < 1e-6 and o.stable
    assert o.t_stick + o.hold == pytest.approx(2 * math.pi / W, abs=1e-9)
    # the release is a root of the force, falling
    ph = o.xi[-1]
    assert A * math.sin(ph) - GAP == pytest.approx(0.0, abs=1e-12) and math.cos(ph) < 0


def test_one_mass_times_against_a_long_run(one_run):
    """The accumulation (sticking) time and the held phase against the run's every
    period once it has stuck once (superstable: it forgets its state at once)."""
    o = sticking_orbit(ONE, guess=one_run)
    st = _done(one_run)
    assert len(st) > 50
    t_stick = st[1:, 0] - st[:-1, 1]
    hold = st[1:, 1] - st[1:, 0]
    assert np.abs(t_stick - o.t_stick).max() < 1e-9
    assert np.abs(hold - o.hold).max() < 1e-9
    # every release after the first at the orbit's phase
    ph = (one_run.y0[-1] + W * st[:, 1] - o.tau_release + math.pi) % (2 * math.pi) - math.pi
    assert np.abs(ph).max() < 1e-9
    # the first impact after a release: time and approach speed
    after = np.flatnonzero(one_run.t > st[-2, 1])[0]
    assert one_run.t[after] - st[-2, 1] == pytest.approx(o.t_impacts[0], abs=1e-9)
    assert one_run.impact_velocity[after] == pytest.approx(o.speeds[0], abs=1e-9)


def test_two_masses_against_a_long_run(two_run):
    """Mass 1 held while mass 2 moves: the release phase, the held phase, the time of the
    accumulation and the first impact after a release agree with the settled run."""
    o = sticking_orbit(TWO, guess=two_run)
    assert o.admissible and str(o.signature) == "1-0+stick"
    assert o.names == ("x2", "v2", "tau") and len(o.multipliers) == 3
    st = _done(two_run)
    ph = (two_run.y0[-1] + W2 * st[-1, 1] - o.tau_release + math.pi) % (2 * math.pi) - math.pi
    assert abs(ph) < 1e-9
    assert st[-1, 0] - st[-2, 1] == pytest.approx(o.t_stick, abs=1e-9)
    assert st[-1, 1] - st[-1, 0] == pytest.approx(o.hold, abs=1e-9)
    after = np.flatnonzero(two_run.t > st[-2, 1])[0]
    assert two_run.t[after] - st[-2, 1] == pytest.approx(o.t_impacts[0], abs=1e-9)
    assert two_run.impact_velocity[after] == pytest.approx(o.speeds[0], abs=1e-9)
    # the run's state right after that impact: mass 2's position and speed
    assert two_run.section[after][1] == pytest.approx(
        two_run.section[np.flatnonzero(two_run.t > st[-3, 1])[0]][1], abs=1e-9)


def test_two_mass_multipliers_against_the_runs_convergence(two_run):
    """The leading reduced multiplier (real, about -0.268) is the ratio of successive
    deviations of the run's release phases from the orbit's; one multiplier is 0 (R's
    image lies on the release manifold, where the contact force is 0)."""
    o = sticking_orbit(TWO, guess=two_run)
    lead = o.multipliers[0]
    assert abs(lead.imag) < 1e-12 and -0.3 < lead.real < -0.2
    assert min(abs(m) for m in o.multipliers) < 1e-6 and o.stable
    st = _done(two_run)
    dev = (two_run.y0[-1] + W2 * st[:, 1] - o.tau_release + math.pi) % (2 * math.pi) - math.pi
    # deviations small enough to be linear, large enough for the run's ~1e-12 rounding;
    # the second multiplier (-0.15) fades from the ratio as (0.15 / 0.27)^k
    mid = (np.abs(dev) < 1e-6) & (np.abs(dev) > 1e-9)
    idx = np.flatnonzero(mid[:-1] & mid[1:])
    assert len(idx) >= 4
    ratios = dev[idx + 1] / dev[idx]
    assert np.abs(ratios - lead.real).max() < 3e-4


def test_an_ordinary_impact_before_the_chatter():
    """A two-mass orbit whose flight from the release has one impact before its chatter:
    signature 1-1+stick, the same release as the run's."""
    m = Model(mass=[[1.0, 0], [0, 1.3]], stiffness=[[2.0, -1.0], [-1.0, 2.5]],
              damping=[[0.1, 0], [0, 0.1]], forcing=[1.0, 0.5],
              stop=Stop(mass=1, gap=0.1, restitution=0.5))
    run = simulate(m, 0.4, y0=(-0.5, 0.0, 0.0, 0.0), n_impacts=1000)
    o = sticking_orbit(m, guess=run)
    assert str(o.signature) == "1-1+stick" and o.admissible
    # the ordinary impact's speed is above the next one's (its chatter starts after it)
    assert o.speeds[0] < o.speeds[1] and o.speeds[2] < o.speeds[1]
    st = _done(run)
    assert st[-1, 1] - st[-1, 0] == pytest.approx(o.hold, abs=1e-9)


def test_a_signature_is_printed_and_checked():
    assert str(StickingSignature(stop=1, impacts=2, periods=3)) == "3-2+stick@2"
    for bad in ({"periods": 0}, {"impacts": -1}, {"stop": 1.5}):
        with pytest.raises(ParameterError) as exc:
            StickingSignature(**bad)
        assert "\n" not in str(exc.value)


def test_bad_input_in_one_line(one_run):
    """A wrong signature (another count of impacts) is an inadmissible orbit with the
    reason; a stop the model lacks, an elastic stop, a run that never sticks and a
    guess of the wrong size are refused in one line."""
    o = sticking_orbit(ONE, guess=one_run, signature=StickingSignature(impacts=2))
    assert not o.admissible and "signature's 2" in o.reason
    elastic = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
                    stop=Stop(mass=1, gap=0.2, stiffness=50.0, damping=0.1))
    free = simulate(ONE, W, y0=(-0.5, 0.0), n_impacts=3)       # not yet held twice
    assert len(free.sticks) < 2
    for call in (lambda: sticking_orbit(ONE, guess=[2.9], omega=W,
                                           signature=StickingSignature(stop=1)),
                 lambda: sticking_orbit(elastic, guess=[2.9], omega=W),
                 lambda: sticking_orbit(ONE, guess=free),
                 lambda: sticking_orbit(ONE, guess=[1.0, 2.0], omega=W)):
        with pytest.raises(SymviError) as exc:
            call()
        assert "\n" not in str(exc.value)
