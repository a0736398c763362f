"""Nordmark's map at a grazing orbit (issue 27, item 3, test "Nordmark's map"):
the square-root coefficient against the exact impact just past grazing, a damped
1-DOF oscillator in closed form, the paper's two-mass model, refusals."""
import dataclasses
import functools
import math

import numpy as np
import pytest
from scipy.optimize import brentq

import symvi
from symvi.continuation import continue_orbits
from symvi.errors import ParameterError, SingularCaseError
from symvi.flow.compiled import table
from symvi.flow.linear import LinearFlow
from symvi.model import Model, Stop
from symvi.orbits.nordmark import _grazing_of, check_acceleration, discontinuity_map
from symvi.orbits.periodic import Problem, newton

from ..zoo import ONE_GRAZING, PAPER_EX1


@functools.lru_cache(maxsize=None)
def _grazing(model, param, lo, hi, **fixed):
    for br in continue_orbits(model, param, lo, hi, **fixed):
        for s in br.special:
            if s.kind == "grazing":
                return s
    raise AssertionError("no grazing point")


def ex1():
    return _grazing(PAPER_EX1, "omega", 0.5, 1.0)


def one():
    return _grazing(ONE_GRAZING, "gap", 1.0, 5.0, omega=1.0)


def _exact_pdm(nm, delta, s0=0.4):
    """The discontinuity map on Pi at depth delta, computed on its own: the point xi* +
    delta e_h, the flow back by s0 (below the stop), the first root of h by brentq on the
    exact flow, the reset v+ = R v-, and the post-impact flight carried back to
    g . v = 0 by brentq.  (One stop on the flow's first coordinate, upper side.)"""
    flow = LinearFlow.of(nm.model)
    F = flow.forcing(nm.omega)
    n = flow.n
    row = table(flow)[0]
    R = row[3 + n:].reshape(n, n)
    z = np.array(nm.state, dtype=float)
    z[0] += delta
    phi = nm.phase
    zm = flow.flight(F, z, phi, -s0)[0]
    mo = flow.motion(F, zm, phi - nm.omega * s0)
    assert mo.h(0.0)[0] < 0
    ti = brentq(lambda t: mo.h(t)[0], 0.0, s0, xtol=1e-15, rtol=1e-15)
    zi = mo.state(ti)
    zp = np.concatenate([zi[:n], R @ zi[n:]])
    phi_i = phi - nm.omega * (s0 - ti)
    back = 3 * zi[n] / abs(nm.acceleration) + 1e-3
    tb = brentq(lambda t: flow.flight(F, zp, phi_i, t)[0][n], -back, 0.0, xtol=1e-15,
                rtol=1e-15)
    zb = flow.flight(F, zp, phi_i, tb)[0]
    xi = np.concatenate(([zb[0] - row[2]], zb[1:n], zb[n + 1:], [phi_i + nm.omega * tb]))
    return xi, zi[n]


@pytest.mark.parametrize("case", [ex1, one])
def test_sqrt_coefficient_against_the_exact_impact(case):
    """(PDM(xi* + delta e_h) - (xi* + delta e_h)) / sqrt(delta) -> E0 at depths 1e-4 ...
    1e-8: the intercept of a fit in (1, sqrt(delta), delta) is E0 (the ratio's error is
    O(sqrt(delta))), and
    the first impact's approach speed is sqrt(2 |a| delta) (1 + O(sqrt(delta)))."""
    g = case()
    nm = discontinuity_map(g.orbit, g, param="gap" if case is one else "omega")
    deltas = np.array([1e-4, 1e-5, 1e-6, 1e-7, 1e-8])
    rows, speeds = [], []
    for d in deltas:
        xi, v = _exact_pdm(nm, d)
        x0 = nm.point.copy()
        x0[0] += d
        rows.append((xi - x0) / math.sqrt(d))
        speeds.append(v / math.sqrt(2 * abs(nm.acceleration) * d))
    rows = np.array(rows)
    A = np.column_stack([np.ones_like(deltas), np.sqrt(deltas), deltas])
    coef = np.linalg.lstsq(A, rows, rcond=None)[0][0]
    scale = np.max(np.abs(nm.E0))
    assert np.max(np.abs(coef - nm.E0)) < 1e-5 * scale, (coef, nm.E0)
    # the raw ratio at the smallest depth is E0 to O(sqrt(1e-8))
    assert np.max(np.abs(rows[-1] - nm.E0)) < 1e-3 * scale
    err = np.abs(np.array(speeds) - 1)         # relative error O(sqrt(delta))
    assert err[-1] < 1e-3 and np.all(err / np.sqrt(deltas) < 10)


def test_one_dof_in_closed_form():
    """x'' + 0.1 x' + x = 0.3 sin(t + tau), stop at the gap b with r = 0.8: the
    non-impacting orbit x = X sin(...) grazes at b = |X| = 3 (the 1-1 branch's impact
    velocity -> 0, an "impact" grazing).  At its apex h'' = -omega^2 b, so
    E0 = (0, -(1 + r) omega sqrt(2 / |a|)) = (0, -(1 + r) sqrt(2 / b)); the smooth part N is
    the homogeneous flow over one period, multipliers e^{lambda_j 2 pi / omega},
    lambda_j = -0.05 +- i sqrt(1 - 0.0025); the depth moves as delta = |X| - b, delta' = -1."""
    g = one()
    assert g.coefficients.get("impact") == 1
    nm = discontinuity_map(g.orbit, g, param="gap")
    b = 0.3 / abs(1 - 1 + 0.1j)
    assert g.value == pytest.approx(b, rel=1e-10)
    assert nm.kind == "impact" and nm.names == ("h", "phase")
    assert nm.acceleration == pytest.approx(-b, rel=1e-9)
    assert nm.E0[0] == pytest.approx(0.0, abs=1e-12)
    assert nm.E0[1] == pytest.approx(-1.8 * math.sqrt(2 / b), rel=1e-9)
    lam = complex(-0.05, math.sqrt(1 - 0.0025))
    mu = np.exp(lam * 2 * math.pi)
    got = sorted(nm.multipliers, key=lambda z: z.imag)
    want = sorted([mu, mu.conjugate()], key=lambda z: z.imag)
    assert got == [pytest.approx(w, rel=1e-9) for w in want]
    assert nm.delta_rate == pytest.approx(-1.0, rel=1e-6)
    assert nm.past_direction == -1.0          # a smaller gap: the orbit reaches past it
    assert np.allclose(nm.E, nm.N @ nm.E0)
    assert "complex" in nm.scenario           # outside the 1-D reduction, said so


def test_overdamped_one_dof_leading_multiplier_and_scenario():
    """An overdamped 1-DOF (c = 3: lambda = (-3 +- sqrt 5) / 2) forced at omega = 2: the
    multipliers are e^{lambda_j 2 pi / omega}, real; lambda1 = 0.301 lies in (1/4, 2/3)."""
    m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[3.0]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.1, restitution=0.8))
    X = 1 / abs(1 - 4 + 6j)
    g = _grazing(m, "gap", 0.3 * X, 2 * X, omega=2.0)
    nm = discontinuity_map(g.orbit, g, param="gap")
    lam = [(-3 + math.sqrt(5)) / 2, (-3 - math.sqrt(5)) / 2]
    expect = sorted(math.exp(v * math.pi) for v in lam)[::-1]
    assert [z.real for z in nm.multipliers] == pytest.approx(expect, rel=1e-9)
    assert nm.gamma < 0
    assert "with chaotic windows" in nm.scenario


def test_paper_two_masses():
    """Example 1 (mu_m 2, mu_k 5, b 1.5, r 0.8): the 1-1 branch's first grazing is a touch
    inside the flight at omega = 0.5956.  N's eigenvalues are the orbit's multipliers (the
    touch adds no impact at grazing); N equals the central differences of the smooth return
    map; delta' equals the rate of the orbit's largest h over its flight, solved on its own
    at omega* +- 1e-5 by the shooting system."""
    g = ex1()
    nm = discontinuity_map(g.orbit, g)
    assert nm.kind == "flight" and nm.names == ("h", "x2", "v2", "phase")
    assert nm.acceleration < 0
    for a, b in zip(nm.multipliers, g.orbit.multipliers):
        assert a == pytest.approx(b, abs=1e-9)
    G = _grazing_of(nm)
    eps, d = 1e-6, len(nm.point)
    J = np.column_stack([(G.smooth_return(nm.point + eps * e) -
                          G.smooth_return(nm.point - eps * e)) / (2 * eps)
                         for e in np.eye(d)])
    assert np.max(np.abs(J - nm.N)) < 1e-6 * np.max(np.abs(nm.N))
    assert np.max(np.abs(G.smooth_return(nm.point) - nm.point)) < 1e-12
    pr = Problem(PAPER_EX1, 1, 1, param="omega")

    def hmax(lam):
        u = newton(pr, np.array(g.orbit.u), lam)
        fl, (_, flow, F) = pr.flights(u, lam)
        mo = flow.motion(F, fl[0][0], fl[0][1])
        ts = g.coefficients["t"] + np.linspace(-0.05, 0.05, 2001)
        return max(mo.h(t)[0] for t in ts)

    rate = (hmax(g.value + 1e-5) - hmax(g.value - 1e-5)) / 2e-5
    assert nm.delta_rate == pytest.approx(rate, rel=1e-3)
    assert nm.past_direction == math.copysign(1.0, rate)
    assert "unstable" in nm.scenario          # |lambda1| = 1.22: no local attractor
    d = nm.as_dict()
    assert d["kind"] == "flight" and len(d["N"]) == 4 and d["normalisation"]


def test_refusals():
    """Not a grazing place, an orbit away from grazing, an elastic stop, a degenerate or
    sticking contact: one-line errors."""
    g = ex1()
    with pytest.raises(ParameterError, match="where"):
        discontinuity_map(g.orbit, {"fold": 1})
    with pytest.raises(ParameterError, match="grazing"):
        discontinuity_map(g.orbit, {"flight": 1, "t": 0.5 * g.coefficients["t"]})
    with pytest.raises(ParameterError, match="flight 1"):
        discontinuity_map(g.orbit, {"flight": 1, "t": -1.0})
    br = continue_orbits(PAPER_EX1, "omega", 0.70, 0.76)[0]
    pt = br.points[len(br.points) // 2]
    with pytest.raises(ParameterError, match="grazing"):
        discontinuity_map(pt.orbit, {"impact": 1})
    elastic = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                    stop=Stop(mass=1, gap=0.5, stiffness=50.0, damping=0.3))
    with pytest.raises(ParameterError, match="elastic"):
        discontinuity_map(dataclasses.replace(g.orbit, model=elastic), g)
    with pytest.raises(SingularCaseError, match="degenerate-grazing"):
        check_acceleration(1e-12, 1.0)
    with pytest.raises(SingularCaseError, match="not-grazing"):
        check_acceleration(0.5, 1.0)
    check_acceleration(-0.5, 1.0)             # a regular grazing passes


def test_exported():
    assert symvi.discontinuity_map is discontinuity_map
