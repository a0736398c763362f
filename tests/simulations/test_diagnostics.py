"""symvi.diagnostics: Lyapunov exponents, rotation number, classification."""
import math

import numpy as np
import pytest

from symvi.paper.orbit import period1_orbits
from symvi.paper.modal_map import fd_jacobian
from symvi.simulations import diagnostics as dg
from symvi.simulations.simulation import Simulation, simulate

from ..conftest import EX1, EX2


def _multipliers(params, omega):
    """Multipliers of the admissible orbit (generated order-1 jet)."""
    orb = [o for o in period1_orbits(params, omega) if o.admissible][0]
    return np.array(orb.multipliers, dtype=complex), orb


def test_jacobian_matches_finite_difference():
    """The Jacobian used by the diagnostics agrees with the reference fd of poincare.py."""
    s = simulate(EX1, 0.7519, n_impacts=5, transient=2000)
    for k in range(3):
        J = dg.jacobian(EX1, 0.7519, s.section[k], s.t[k + 1] - s.t[k])
        F = fd_jacobian(EX1, 0.7519, s.section[k], h=1e-6)
        assert np.abs(J - F).max() < 1e-6 * max(1.0, np.abs(F).max())


@pytest.mark.parametrize("params, omega", [(EX1, 0.7300), (EX2, 0.4800)])
def test_lyapunov_of_period1_equals_log_multipliers(params, omega):
    """At a stable period-1 orbit the QR exponents equal log|lambda_i| (sorted)."""
    lam, orb = _multipliers(params, omega)
    T = 2 * math.pi / omega
    n = 3000
    sec = np.tile(np.array(orb.y, dtype=float), (n, 1))
    sim = Simulation(params, omega, orb.y, sec, T * np.arange(1, n + 1), np.ones(n),
                     "completed", 0, orb.y)
    ly = dg.lyapunov(sim)
    expect = np.sort(np.log(np.abs(lam)))[::-1]
    assert np.abs(ly.exponents - expect).max() < 2e-3
    # and a run started off the orbit converges onto it
    s = simulate(params, omega, n_impacts=50, transient=4000)
    assert dg.classify(s).kind == "period-1"


def test_exponent_sum_identity():
    """det DP = r^2 v_k / v_{k+1} (impact speeds), so the exponents sum to
    2 log r + log(v_0 / v_n) / n along any run: here a chaotic one."""
    s = simulate(EX2, 0.4944, n_impacts=1500, transient=3000)
    ly = dg.lyapunov(s)
    v = s.impact_velocity
    expect = 2 * math.log(EX2.r) + math.log(v[0] / v[-1]) / ly.n
    assert ly.exponents.sum() == pytest.approx(expect, abs=1e-6)
    assert ly.largest > 0.02


def test_rotation_number_near_hopf():
    """Just past the Hopf point (paper: v_c = 0.7368) the rotation number on the
    small circle is arg(lambda_1) / 2 pi of the orbit's critical multipliers."""
    om = 0.7369
    lam, orb = _multipliers(EX1, om)
    expect = abs(np.angle(lam[0])) / (2 * math.pi)
    s = simulate(EX1, om, n_impacts=3000, transient=60000)
    rho = dg.rotation_number(s.section, center=orb.y)
    assert rho == pytest.approx(expect, abs=2e-3)


def test_rotation_number_synthetic():
    """Points y_k = c + R(k rho) on an ellipse give back rho (and 1 - rho -> rho)."""
    k = np.arange(2000)
    for rho in (0.1234, 0.4321, 1 - 0.2):
        th = 2 * math.pi * rho * k
        sec = np.column_stack([np.cos(th), 0.3 * np.sin(th), 0.1 * np.cos(th) + 2,
                               0.05 * np.sin(th) + 1.0])
        assert dg.rotation_number(sec) == pytest.approx(min(rho, 1 - rho), abs=1e-5)


def test_branch_count_synthetic():
    """One closed curve -> 1 sheet; a curve winding twice (doubled torus) -> 2."""
    rng = np.random.default_rng(0)
    phi = rng.uniform(0, 4 * math.pi, 4000)
    r1 = 1 + 0.2 * np.cos(3 * phi)
    one = np.column_stack([r1 * np.cos(phi), r1 * np.sin(phi), 0.1 * np.cos(phi), 1 + 0 * phi])
    r2 = 1 + 0.05 * np.cos(phi / 2)        # returns after two turns: a doubled curve
    two = np.column_stack([r2 * np.cos(phi), r2 * np.sin(phi), 0.1 * np.cos(phi), 1 + 0 * phi])
    assert dg.branch_count(one) == 1
    assert dg.branch_count(two) == 2


def test_period_of_synthetic():
    base = np.array([[-1.0, 0.1, 0.2, 0.3], [-1.2, 0.0, 0.1, 6.2], [-0.9, 0.3, 0.0, 3.0]])
    sec = np.tile(base, (20, 1))
    assert dg.period_of(sec) == 3
    sec[::3, 3] = 6.283185307179586 - 1e-12  # tau near the cut: still period 3
    sec[1::3, 3] = 1e-13
    assert dg.period_of(sec) == 3
    assert dg.period_of(sec + np.random.default_rng(1).normal(0, 1e-3, sec.shape)) is None


@pytest.mark.parametrize("params, omega, kind", [
    (EX1, 0.7400, "invariant circle"),      # paper: circles just past 0.7368
    (EX1, 0.7460, "doubled torus"),         # paper: torus doubling past 0.7438
    (EX1, 0.7519, "chaos"),                 # paper: chaos at 0.7519 (weak: lambda_1 ~ 0.01)
    # a phase-locked orbit on the circle (ours): 117 impacts in 114 forcing periods
    # (period-k counts forcing periods, as the plane's labels; before issue 24 item 5
    # simulate --classify printed period-117, the impacts, now impacts_per_orbit)
    (EX2, 0.4935, "period-114"),
    (EX2, 0.4944, "chaos"),                 # paper: chaos at 0.4944
])
def test_classify_paper_cases(params, omega, kind):
    s = simulate(params, omega, n_impacts=3000, transient=60000)
    c = dg.classify(s, lyap_points=3000)
    assert c.kind == kind
    if kind.startswith("period-"):
        assert (c.period, c.impacts) == (114, 117)
        # the orbit closes after 117 impacts and not before, over 114 forcing periods
        sec, t = np.asarray(s.section), np.asarray(s.t)
        assert dg.period_of(sec, max_period=400) == 117
        assert round(0.4935 * (t[-1] - t[-1 - 117]) / (2 * math.pi)) == 114


def test_compiled_qr_logs_match_the_paper_generated_jacobian():
    """The compiled QR loop (DP of one flight by eq. (30), any model) gives the logs of a
    Python QR loop over the paper's own generated Jacobian (generated/order1.py, the
    modal oracle), point by point along a chaotic run."""
    from symvi.paper._eval import _evaluate, _inputs
    from symvi.paper.params import modal
    s = simulate(EX2, 0.4944, n_impacts=400, transient=3000)
    sec, te = np.asarray(s.section), np.diff(s.t)
    logs = dg._qr_logs_model(EX2, 0.4944, sec[:-1], te)
    Q, ref = np.eye(4), []
    for k in range(len(te)):
        J = _evaluate(1, _inputs(modal(EX2), 0.4944, EX2.r, EX2.b, tuple(sec[k]), te[k]),
                      False)["J"]
        Q, R = np.linalg.qr(J @ Q)
        d = np.diag(R)
        ref.append(np.log(np.abs(d)))
        Q = Q * np.where(d < 0, -1.0, 1.0)
    assert np.abs(logs - np.array(ref)).max() < 1e-10
