"""Runs through complete chatter and sticking (issue 27, item 4): simulate, sweep, the
plane's classifier and ``symvi simulate --classify`` go on through the accumulation
point, the held phase and the release, and find the sticking attractor."""
import json
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from symvi import simulate
from symvi.flow import compiled as cf
from symvi.model import Model, Stop
from symvi.simulations import classifier as cl
from symvi.simulations.simulation import sweep
from tests.fuzz._cli import cli

ZETA, A, W, R = 0.05, 1.0, 0.5, 0.5
#: x'' + 2 zeta x' + x = A sin(omega t), a stop at x = 0: pressed on it for half of each
#: forcing period, a chatter and a sticking phase every period
ONE = Model(mass=[1.0], stiffness=[[1.0]], damping=[[2 * ZETA]], forcing=[A],
            stop=Stop(mass=1, gap=0.0, restitution=R))
TOML = """[model]
mass = [1.0]
stiffness = [[1.0]]
damping = [[0.1]]
forcing = [1.0]

[[stop]]
mass = 1
gap = 0.0
restitution = 0.5
"""


def _reference_period(t0):
    """One period of the sticking orbit, event by event, independently of symvi: DOP853
    (rtol 1e-12) for each flight from the release at t0 (x = v = 0), the impacts stepped
    (v+ = -r v-) while the approach speed is above 1e-6, then the chatter's geometric tail
    2 r u / (a (1 - r)).  Returns (first impact time, its speed, impacts stepped,
    accumulation time)."""
    def f(t, u):
        return [u[1], A * math.sin(W * t) - 2 * ZETA * u[1] - u[0]]

    def hit(t, u):
        return u[0]
    hit.terminal, hit.direction = True, 1
    t, v, n, first = t0, 0.0, 0, None
    while True:
        sol = solve_ivp(f, (t, t + 4 * math.pi / W), [0.0, -R * v], method="DOP853",
                        rtol=1e-12, atol=1e-14, events=hit)
        t, v = float(sol.t_events[0][0]), float(sol.y_events[0][0][1])
        n += 1
        if first is None:
            first = (t, v)
        if v < 1e-6:
            a = A * math.sin(W * t) + 2 * ZETA * R * v       # x'' just after the impact
            return first[0], first[1], n, t + 2 * R * v / (a * (1 - R))


def test_thousands_of_chatters_reach_the_sticking_orbit():
    """3000 forcing periods, each with a chatter, a sticking phase and a release (about
    60000 stored impacts): the run completes, every held phase ends at the contact
    force's root (A sin(omega t) = 0, falling: phase pi) and starts after the chatter's
    accumulation; the settled period matches the independent event-by-event reference."""
    s = simulate(ONE, W, y0=(-0.5, 0.0), n_impacts=60000, transient=0)
    assert s.stop == "completed" and s.n == 60000
    T = 2 * math.pi / W
    st = s.sticks[np.isfinite(s.sticks[:, 1])]
    assert len(st) > 2500
    # the times are sums of up to 60000 flight times: their rounding drifts by ~sqrt(n)
    # ulps (~2e-9 at t ~ 4e4), what the tolerances on absolute times below allow for
    ph_release = (W * st[:, 1]) % (2 * math.pi)
    assert np.allclose(ph_release, math.pi, atol=1e-8)
    assert (st[:, 1] > st[:, 0]).all() and (st[:, 2] == 0).all()
    # one sticking phase a period, once settled
    assert np.allclose(np.diff(st[-50:, 0]), T, atol=1e-9)
    # the last full period against the reference
    t_rel = st[-2, 1]
    after = np.flatnonzero(s.t > t_rel)
    t1, v1, n_ref, t_acc = _reference_period(t_rel)
    assert s.t[after[0]] - t_rel == pytest.approx(t1 - t_rel, abs=1e-8)
    assert s.impact_velocity[after[0]] == pytest.approx(v1, abs=1e-11)
    assert st[-1, 0] == pytest.approx(t_acc, abs=2e-8)
    n_run = np.count_nonzero((s.t > t_rel) & (s.t < st[-1, 0]))
    assert abs(n_run - n_ref) <= 4          # both step to a small speed (1e-7 vs 1e-6)


def test_the_sticking_attractor_is_period_1_in_the_classifier():
    """The plane's classifier (the shared compiled loop, then through the sticking phases
    in Python) names the attractor period-1 with sticking; without the models it keeps
    the old label."""
    C = np.array([cf.constants(ONE, W)])
    Y0 = np.array([[-0.5, 0.0]])
    res = cl.classify_runs(C, Y0, 200, 1000, models=ONE)
    assert list(res.labels()) == ["period-1"] and res.sticking[0]
    assert res.impacts[0] >= 10 and cf.STOP_NAMES[res.stop[0]] == "completed"
    old = cl.classify_runs(C, Y0, 200, 1000)
    assert list(old.labels()) == ["sticking"] and old.sticking is None


def test_sweep_goes_through_and_classifies():
    """sweep continues the runs that stick and classifies them as period-1."""
    res = sweep(ONE, [0.45, 0.5], n_impacts=200, transient=500,
                starts=[(-0.5, 0.0)] * 2, classify=True)
    assert res.stops == ("completed", "completed")
    assert list(res.classes.labels()) == ["period-1", "period-1"]
    assert res.classes.sticking.all()


def test_simulate_classify_names_the_sticking_orbit(tmp_path):
    """symvi simulate --classify --json: attractor period-1, "sticking": true, every
    sticking phase listed."""
    f = tmp_path / "one.toml"
    f.write_text(TOML)
    rc, text, err = cli("simulate", "--model", str(f), "--omega", "0.5", "--y0", "-0.5", "0",
                        "--impacts", "400", "--transient", "400", "--out",
                        str(tmp_path / "one.npz"), "--classify", "--json")
    assert rc == 0, err
    got = json.loads(text)
    assert got["attractor"] == "period-1" and got["sticking"] is True
    assert got["stop"] == "completed" and len(got["sticks"]) >= 10
    assert all(a < b and k == 1 for a, b, k in got["sticks"])


def test_what_cannot_go_on_says_why():
    """r = 1 has no accumulation point: the run stops as sticking, and says why in one
    line; a held mass whose neighbour is free (no spring left) likewise."""
    m = Model(mass=[1.0], stiffness=[[1.0]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.2, restitution=1.0))
    s = simulate(m, 0.8, y0=(-1e-8, math.pi / 2), n_impacts=10)
    assert s.stop == "sticking" and "restitution" in s.stop_reason
    assert "\n" not in s.stop_reason
    free = Model(mass=[[1.0, 0], [0, 1.0]], stiffness=[[1.0, 0.0], [0.0, 0.0]],
                 damping=[[0.1, 0], [0, 0.1]], forcing=[1.0, 0.0],
                 stop=Stop(mass=1, gap=0.1, restitution=0.5))
    s = simulate(free, 0.8, y0=(-1e-8, 0.0, 0.0, math.pi / 2), n_impacts=10)
    assert s.stop == "sticking" and "free" in s.stop_reason and "\n" not in s.stop_reason
    assert len(s.sticks) == 0
