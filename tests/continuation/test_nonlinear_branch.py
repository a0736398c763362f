"""Orbits, branches and special points of a model with nonlinear forces (issue 28): the
shooting system on the series flights of :mod:`symvi.flow.nljet`.

Checks that could fail: the nonlinearity off gives the exact linear flow's orbits; the
determinant identity det DP = r^2 exp(-c T) holds at every point of a Duffing impact
oscillator's branch (its cubic spring does not change the divergence); the flip located in
omega is the flip located in beta; and the flip's cubic coefficient predicts the size of
the period-2 orbit a simulation settles on past it."""
import math

import numpy as np
import pytest

import symvi
from symvi.continuation import continue_orbits
from symvi.continuation.branch import continue_branch
from symvi.model import Model, Stop
from symvi.orbits.period1 import admissible_orbits
from symvi.orbits.periodic import detect_period, periodic_orbit

ONE = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
TWO = dict(mass=[1.0, 2.0], stiffness=[[2.0, -1.0], [-1.0, 1.5]],
           damping=[[0.05, 0.0], [0.0, 0.05]], forcing=[1.0, 0.3],
           stop=Stop(mass=2, gap=0.3, restitution=0.7))
#: a Duffing impact oscillator: x'' + 0.05 x' + x + 0.2 x^3 = sin(omega t), stop at x = 0
DUFFING = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                stop=Stop(mass=1, gap=0.0, restitution=0.8), nonlinear=["beta*x1**3"],
                parameters={"beta": 0.2})


@pytest.mark.parametrize("kw, forces, omega", [
    (ONE, ["beta*x1**3"], 1.3),
    (TWO, ["beta*x1**3", "beta*x2*v2**2 + beta*sin(x1)"], 1.1),
])
def test_nonlinearity_off_orbits_are_the_linear_ones(kw, forces, omega):
    lin = Model(**kw)
    nl = Model(**kw, nonlinear=forces, parameters={"beta": 0.0})
    ref = periodic_orbit(lin, n=1, p=1, guess=admissible_orbits(lin, omega)[0].y, omega=omega)
    got = periodic_orbit(nl, n=1, p=1, guess=ref.y, omega=omega)
    assert np.max(np.abs(np.subtract(got.y, ref.y))) < 1e-12
    assert abs(got.times[0] - ref.times[0]) < 1e-12
    assert np.max(np.abs(np.subtract(got.multipliers, ref.multipliers))) < 1e-11
    for a, b in zip(got.jet(3), ref.jet(3)):
        assert np.max(np.abs(a - b)) < 1e-11 * max(1.0, np.max(np.abs(b)))
    assert got.admissible


@pytest.fixture(scope="module")
def branch():
    sim = symvi.simulate(DUFFING, 2.6, n_impacts=50, transient=3000)
    o = periodic_orbit(DUFFING, n=1, p=1, guess=sim, omega=2.6)
    return continue_branch(DUFFING, "omega", 2.6, 2.8, orbit=o)


def test_determinant_identity_along_the_branch(branch):
    """det DP = r^2 exp(-tr(M^-1 C) T) at every point: the cubic spring is conservative."""
    assert len(branch.points) > 20
    for pt in branch.points:
        det = np.prod(pt.multipliers).real
        want = 0.8 ** 2 * math.exp(-0.05 * pt.orbit.times[0])
        assert abs(det - want) < 1e-10 * want


def test_the_flip_in_omega_is_the_flip_in_beta(branch):
    flips = [s for s in branch.special if s.kind == "flip"]
    assert len(flips) == 1
    w = flips[0].value
    assert abs(flips[0].coefficients["multiplier"] + 1) < 1e-9
    # at that omega, the branch in beta through 0.2 flips at beta = 0.2
    at = flips[0].orbit
    br = continue_branch(DUFFING, "beta", 0.2, 0.15, orbit=at, omega=w)
    br2 = continue_branch(DUFFING, "beta", 0.2, 0.25, orbit=at, omega=w)
    got = [s.value for b in (br, br2) for s in b.special if s.kind == "flip"]
    assert got and min(abs(v - 0.2) for v in got) < 1e-8


def test_the_flip_coefficient_predicts_the_doubled_orbit(branch):
    """Past a supercritical flip (c > 0 in eta -> -(1 + mu) eta + c eta^3, ||q|| = 1,
    <p, q> = 1) the map settles on a 2-cycle y* +- eta q with eta^2 = mu / c, mu = -1 - the
    period-1 orbit's multiplier: its two points lie 2 sqrt(mu / c) apart.  Before the flip
    the run settles on the period-1 orbit."""
    sp = [s for s in branch.special if s.kind == "flip"][0]
    c = sp.coefficients["c"]
    assert c > 0 and "supercritical" in sp.detail
    lam = np.array(sp.orbit.multipliers)
    unstable = 1.0 if any(abs(z) > 1 for z in branch.points[-1].multipliers) else -1.0
    before = symvi.simulate(DUFFING, sp.value - unstable * 0.004, n_impacts=16,
                            transient=4000)
    assert detect_period(before) == (1, 1)
    w = sp.value + unstable * 0.001
    run = symvi.simulate(DUFFING, w, n_impacts=16, transient=12000)
    assert detect_period(run) == (2, 2)
    a, b = run.section[-1], run.section[-2]
    d = a - b
    d[-1] = (d[-1] + math.pi) % (2 * math.pi) - math.pi
    o = periodic_orbit(DUFFING, n=1, p=1, guess=a, omega=w)
    mu = -1.0 - min(o.multipliers, key=lambda z: z.real).real
    pred = 2 * math.sqrt(mu / c)
    assert abs(np.linalg.norm(d) / pred - 1) < 0.03
    assert abs(lam.real.min() + 1) < 1e-9


def test_continue_orbits_starts_a_nonlinear_model_from_the_homotopy():
    """continue_orbits: no closed form to start from, so the orbits the homotopy from the
    linear part reaches (symvi.continuation.homotopy); the branch names its folds and its
    flip."""
    res = continue_orbits(DUFFING, "omega", 2.2, 3.2)
    kinds = sorted(s.kind for b in res for s in b.special)
    assert kinds.count("fold") == 2 and kinds.count("flip") >= 1
    assert "forces' scale" in res[0].notes[0]


LX = dict(mass=[1.0, 2.0], stiffness=[[1.0, -1.0], [-1.0, 6.0]], damping=[[0, 0], [0, 0]],
          forcing=[1.0, 0.0], stop=Stop(mass=1, gap=1.5, restitution=0.8))


def test_nonlinearity_off_ns_point_is_the_papers():
    """The Luo-Xie model (mu_m = 2, mu_k = 5, b = 1.5, r = 0.8) with a cubic spring at
    beta = 0: the series branch locates the NS point and its l1 as the certified scan of
    the exact flow does (symvi.hopf_points, generated jets), to 1e-10; beta = 0.05 moves
    it (omega_c up, |l1| down), still supercritical."""
    ref = symvi.hopf_points(Model(**LX), 0.70, 0.76).points[0]
    got = {}
    for beta in (0.0, 0.05):
        nl = Model(**LX, nonlinear=["beta*x1**3", "0"], parameters={"beta": beta})
        o = periodic_orbit(nl, n=1, p=1, guess=admissible_orbits(Model(**LX), 0.73)[0].y,
                           omega=0.73)
        br = continue_branch(nl, "omega", 0.73, 0.76, orbit=o)
        ns = [s for s in br.special if s.kind == "ns"]
        assert len(ns) == 1
        got[beta] = ns[0]
    assert abs(got[0.0].value - ref.omega_c) < 1e-10
    assert abs(got[0.0].coefficients["l1"] - ref.l1) < 1e-10
    assert got[0.05].value > ref.omega_c + 1e-4
    assert ref.l1 < got[0.05].coefficients["l1"] < 0


def test_the_ns_coefficient_predicts_the_simulated_circle():
    """beta = 0.05, past the supercritical NS point: the map settles on an invariant circle
    whose half-widths are 2 rho |q_k| to leading order, rho^2 = -(d|mu|/d omega) d omega /
    l1 (||q||_2 = 1, <p, q> = 1, l1 = Re(e^{-i theta} c1)).  The relative error is O(d
    omega): within 8 % at d omega = 1e-3 and about twice that at 2e-3 (the prediction is
    the limit)."""
    nl = Model(**LX, nonlinear=["beta*x1**3", "0"], parameters={"beta": 0.05})
    o = periodic_orbit(nl, n=1, p=1, guess=admissible_orbits(Model(**LX), 0.73)[0].y,
                       omega=0.73)
    br = continue_branch(nl, "omega", 0.73, 0.76, orbit=o)
    ns = [s for s in br.special if s.kind == "ns"][0]
    c = ns.coefficients
    assert c["l1"] < 0 and c["dmod_dparam"] > 0
    A = ns.orbit.jet(2)[0]
    ev, V = np.linalg.eig(A)
    k = int(np.argmin(np.abs(ev - np.exp(1j * c["theta"]))))
    q = V[:, k] / np.linalg.norm(V[:, k])
    errors = []
    for dw in (1e-3, 2e-3):
        w = ns.value + dw
        pred = 2 * math.sqrt(-c["dmod_dparam"] * dw / c["l1"]) * np.abs(q)
        fixed = periodic_orbit(nl, n=1, p=1, guess=ns.orbit, omega=w)
        run = symvi.simulate(nl, w, y0=np.array(fixed.y) + 1e-3 * q.real, n_impacts=1500,
                             transient=8000)
        assert run.stop == "completed"
        sec = np.array(run.section)
        sec[:, -1] = (sec[:, -1] - fixed.y[-1] + math.pi) % (2 * math.pi) - math.pi
        half = (sec.max(axis=0) - sec.min(axis=0)) / 2
        errors.append(abs(np.linalg.norm(half) / np.linalg.norm(pred) - 1))
    assert errors[0] < 0.08
    assert 1.3 < errors[1] / errors[0] < 3.0


def test_nonlinearity_off_orbit_of_a_stop_between_masses():
    """An impact between two masses (the flow's frame q = T x): with beta = 0 the series
    orbit is the exact flow's 1-2 orbit to 1e-12, its multipliers too, and the eigenvalues
    of its composed jet's Jacobian are those multipliers."""
    from symvi.simulations.simulation import default_start
    kw = dict(mass=[1.0, 0.5], stiffness=[[2.0, -1.0], [-1.0, 1.0]],
              damping=[[0.05, 0.0], [0.0, 0.05]], forcing=[1.0, 0.0],
              stops=[Stop(between=(1, 2), gap=0.3, restitution=0.7)])
    lin = Model(**kw)
    nl = Model(**kw, nonlinear=["beta*(x1-x2)**3", "-beta*(x1-x2)**3"],
               parameters={"beta": 0.0})
    w = 1.2
    sim = symvi.simulate(lin, w, y0=default_start(lin, w), n_impacts=40, transient=2000)
    assert detect_period(sim) == (1, 2)
    ref = periodic_orbit(lin, n=1, p=2, guess=sim, omega=w)
    got = periodic_orbit(nl, n=1, p=2, guess=sim, omega=w)
    assert got.admissible and ref.admissible
    assert np.max(np.abs(np.subtract(got.y, ref.y))) < 1e-12
    assert np.max(np.abs(np.subtract(got.multipliers, ref.multipliers))) < 1e-12
    mu = sorted(np.linalg.eigvals(got.jet(3)[0]), key=lambda z: (-abs(z), -z.imag))
    assert np.max(np.abs(np.subtract(mu, got.multipliers))) < 1e-11


@pytest.mark.parametrize("name", ["gap", "restitution"])
def test_a_jet_along_a_gap_or_a_restitution_agrees_with_the_shooting_system(name):
    """A branch continues in them through the shooting system's dG/dp (the flights' ends
    moved with each flight's Phi, :meth:`Problem._dstop`); the series take them as a
    variable too (what a two-parameter curve in them needs, tests/flow/test_nljet_gap.py):
    the map's dP/dp at the 1-1 orbit equals dG/dp with the flight time eliminated,
    dP/dp = G_p - G_T g_p / g_T (eq. (30))."""
    from symvi.flow.nljet import FlowView, map_jet
    from symvi.orbits.periodic import Problem
    sim = symvi.simulate(DUFFING, 2.6, n_impacts=20, transient=500)
    o = periodic_orbit(DUFFING, n=1, p=1, guess=sim, omega=2.6)
    got = map_jet(FlowView(DUFFING), 2.6, o.y, o.times[0], 2, param=DUFFING.parameter(name))
    pr = Problem(DUFFING, 1, 1, omega=2.6, param=name)
    u = np.append(o.y, o.times)
    _, Gu, Gp = pr.evaluate(u, DUFFING.value(name), dparam=True)
    d = len(o.y)
    want = Gp[:d] - Gu[:d, d] * Gp[d] / Gu[d, d]
    assert np.max(np.abs(got["dpP"] - want)) < 1e-10 * max(1.0, np.max(np.abs(want)))
    assert np.max(np.abs(want)) > 0.1
