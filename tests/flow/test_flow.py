"""The closed-form flow, eqs. (7)-(8), and the first-impact finder."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from symvi import Params, modal
from symvi.paper.modal_flow import GRAZING, IMPACT, NO_IMPACT, first_impact, motion_from

from ..conftest import EX1, OWN


def _rhs(params, omega, tau):
    M = np.diag([1.0, params.mu_m])
    K = np.array([[1.0, -1.0], [-1.0, 1.0 + params.mu_k]])
    P = np.array([1 - params.f2, params.f2])
    Minv = np.linalg.inv(M)

    def f(t, s):
        x, v = s[:2], s[2:]
        return np.concatenate([v, Minv @ (P * math.sin(omega * t + tau) - K @ x)])
    return f


@pytest.mark.parametrize("params,omega", [(EX1, 0.7369), (OWN, 1.3)])
def test_closed_form_flow_matches_solve_ivp(params, omega):
    """eqs. (7)-(8) against DOP853 at rtol 1e-12 over five forcing periods."""
    m = modal(params)
    x0, v0, tau = (0.3, -0.2), (-1.1, 0.4), 0.9
    mot = motion_from(m, omega, x0, v0, tau)
    T = 5 * 2 * math.pi / omega
    ts = np.linspace(0, T, 41)
    sol = solve_ivp(_rhs(params, omega, tau), (0, T), [*x0, *v0], method="DOP853",
                    rtol=1e-12, atol=1e-13, t_eval=ts)
    ours = np.array([mot.state(t) for t in ts])        # (x1, x2, x1dot, x2dot)
    ref = sol.y.T
    assert np.max(np.abs(ours - ref)) < 1e-9


def test_modal_is_mass_normalised():
    """psi^T M psi = I and psi^T K psi = diag(omega_j^2), eqs. (5)-(6)."""
    for p in (EX1, OWN, Params(0.01, 100, 0.5, 1, 1)):
        m = modal(p)
        psi = np.array(m.psi)
        M = np.diag([1, p.mu_m])
        K = np.array([[1, -1], [-1, 1 + p.mu_k]])
        assert np.allclose(psi.T @ M @ psi, np.eye(2), atol=1e-13)
        assert np.allclose(psi.T @ K @ psi, np.diag([m.omega1 ** 2, m.omega2 ** 2]), atol=1e-12)
        assert m.omega1 < m.omega2


def _x1_dense(mot, ts):
    """Vectorised x1(t) of a Motion: brute force for the finder test."""
    m = mot.modal
    x = (m.psi[0][0] * mot.A[0] + m.psi[0][1] * mot.A[1]) * np.sin(mot.omega * ts + mot.tau)
    for j, wj in enumerate(m.omegas):
        x = x + m.psi[0][j] * (mot.a[j] * np.cos(wj * ts) + mot.b[j] * np.sin(wj * ts))
    return x


def _refine_max(mot, tm):
    """Newton on x1dot for a local maximum of x1 near tm."""
    for _ in range(30):
        acc = (mot.state(tm + 1e-6)[2] - mot.state(tm - 1e-6)[2]) / 2e-6
        tm -= mot.state(tm)[2] / acc
    return tm


def _restart_at_level(mot, m, ts, h, k, level):
    """Restart the flight where x1 last falls through ``level`` before sample k;
    returns (new motion, its start time) or None."""
    before = np.where((h[:k - 1] > level) & (h[1:k] <= level))[0]
    if len(before) == 0:
        return None
    t0 = ts[before[-1]]
    for _ in range(50):      # Newton on the down-crossing
        s = mot.state(t0)
        t0 -= (s[0] - level) / s[2]
    s = mot.state(t0)
    if not s[2] < 0:
        return None
    return motion_from(m, mot.omega, (s[0], s[1]), (s[2], s[3]), mot.tau + mot.omega * t0), t0


def _random_motions(rng, n):
    """Random flights leaving x1 = b downward, plus near-grazing ones built by
    restarting a flight where x1 sits delta above a later local maximum."""
    out = []
    p = Params(2, 5, 0.2, 1.0, 0.8)
    m = modal(p)
    while len(out) < n:
        omega = rng.uniform(0.3, 2.5)
        if min(abs(omega - w) for w in m.omegas) < 1e-2:
            continue
        x = rng.normal(0, 1, 2)
        v = np.array([-abs(rng.normal(0, 1)) - 1e-3, rng.normal(0, 1)])
        tau = rng.uniform(0, 2 * math.pi)
        mot = motion_from(m, omega, tuple(x), tuple(v), tau)
        b = x[0]
        if len(out) % 2 == 0:
            out.append((mot, b, None))
            continue
        # near-grazing: find a local max of x1, restart earlier at x1 = max + delta
        ts = np.linspace(0, 40, 40001)
        h = _x1_dense(mot, ts)
        imax = np.where((h[1:-1] > h[:-2]) & (h[1:-1] >= h[2:]))[0] + 1
        if len(imax) < 2:
            continue
        k = imax[rng.integers(1, len(imax))]
        tm = _refine_max(mot, ts[k])
        hmax = mot.state(tm)[0]
        delta = float(rng.choice([-1e-3, -1e-6, -1e-9, 1e-12, 1e-9, 1e-6, 1e-3]))
        # b = level; delta > 0: the max lies delta below the stop
        got = _restart_at_level(mot, m, ts, h, k, hmax + delta)
        if got is None:
            continue
        mot2, t0 = got
        s = mot2.state(0)
        out.append((mot2, s[0], (tm - t0, delta)))
    return out


@pytest.mark.slow
def test_first_impact_never_missed_against_dense_sampling():
    """10^4 random flights, half near-grazing: the finder's crossing is real (h = 0,
    h' > 0) and no dense sample before it reaches the stop."""
    rng = np.random.default_rng(7)
    cases = _random_motions(rng, 10000)
    n_graze = n_near = 0
    for mot, b, near in cases:
        hit = first_impact(mot, b)
        tf = float(hit.t) if hit.status != NO_IMPACT else 200.0
        ts = np.arange(0, tf, 2e-3)[1:]
        h = _x1_dense(mot, ts) - b
        # nothing in (0, t_f) reaches the stop (beyond the finder's resolution)
        assert np.all(h[ts < tf - 1e-9] < 1e-10), (near, tf)
        if hit.status == IMPACT:
            assert abs(hit.state[0] - b) < 1e-11
            assert hit.state[2] > 0
        elif hit.status == GRAZING:
            n_graze += 1
        if near is not None:
            n_near += 1
            tm, delta = near
            if delta < -1e-9:        # a genuine excursion past the stop: must be caught
                assert hit.status == IMPACT and tf < tm + 1e-6
    assert n_near >= 4000


def test_grazing_contact_is_reported_not_stepped_over():
    """A flight whose maximum touches x1 = b exactly is GRAZING, not a miss."""
    p = Params(2, 5, 0.0, 1.0, 0.8)
    m = modal(p)
    # pure forcing response + one mode: x1 has a smooth max; start where x1 = max
    omega = 0.5
    mot = motion_from(m, omega, (0.2, 0.1), (-0.3, 0.2), 0.4)
    ts = np.linspace(0, 60, 600001)
    h = _x1_dense(mot, ts)
    for k in np.where((h[1:-1] > h[:-2]) & (h[1:-1] >= h[2:]))[0] + 1:
        tm = _refine_max(mot, ts[k])
        got = _restart_at_level(mot, m, ts, h, k, mot.state(tm)[0])
        if got is not None:
            break
    mot2, t0 = got
    s = mot2.state(0)
    hit = first_impact(mot2, s[0])
    assert hit.status == GRAZING
    assert abs(hit.t - (tm - t0)) < 1e-3
