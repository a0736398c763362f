"""Nordmark's map at a grazing orbit of a model with nonlinear forces (issue 28): its
smooth part on the series flights (FlowView), its square-root part from the model.

Checks that could fail: with the forces off the map is the exact linear flow's; with a
cubic spring the square-root coefficient E0 is the limit of the exact discontinuity map
of the numerical flow at depths 1e-4 .. 1e-8 (the test of tests/orbits/test_nordmark.py
on FlowView's flights)."""
import math

import numpy as np
from scipy.optimize import brentq

from symvi.continuation.branch import continue_branch
from symvi.continuation.homotopy import period1_orbits
from symvi.flow.compiled import table
from symvi.model import Model, Stop
from symvi.orbits.nordmark import discontinuity_map
from symvi.orbits.periodic import free_flow

KW = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
          stop=Stop(mass=1, gap=0.0, restitution=0.8))


def _grazing(model):
    o = period1_orbits(model, 2.6).orbits[0] if model.nonlinear else None
    br = continue_branch(model, "gap", 0.0, 0.3, omega=2.6, orbit=o)
    (g,) = [s for s in br.special if s.kind == "grazing"]
    return discontinuity_map(g.orbit, g, param="gap")


def test_forces_off_give_the_exact_flows_map():
    a = _grazing(Model(**KW))
    b = _grazing(Model(**KW, nonlinear=["beta*x1**3"], parameters={"beta": 0.0}))
    assert abs(a.value - b.value) < 1e-9
    for name in ("N", "E0", "E", "m"):
        x, y = np.asarray(getattr(a, name)), np.asarray(getattr(b, name))
        assert np.max(np.abs(x - y)) < 1e-6 * max(1.0, np.max(np.abs(x))), name
    assert a.scenario == b.scenario


def _back(flow, F, z, phi, s):
    """The state w at phase phi - omega s whose forward flight of time s ends at z (the
    series flights run forward only): Newton on flight(w, s) = z with its Phi."""
    w = np.array(z, dtype=float)
    for _ in range(30):
        zt, Phi = flow.flight(F, w, phi - F.omega * s, s)[:2]
        dw = np.linalg.solve(Phi, z - zt)
        w += dw
        if np.max(np.abs(dw)) < 1e-15 * (1 + np.max(np.abs(w))):
            break
    return w


def _exact_pdm(nm, delta, s0=0.4):
    """The discontinuity map on Pi at depth delta on the numerical flow: xi* + delta e_h,
    back by s0 (Newton on forward flights), the first root of h by brentq, the reset,
    then the point on Pi (g . v = 0) whose forward flight reaches the reset state (Newton
    in (x, t) with Phi and z')."""
    flow = free_flow(nm.model)
    F = flow.forcing(nm.omega)
    n = flow.n
    row = table(flow)[0]
    R = row[3 + n:].reshape(n, n)
    z = np.array(nm.state, dtype=float)
    z[0] += delta
    phi = nm.phase
    zm = _back(flow, F, z, phi, s0)
    mo = flow.motion(F, zm, phi - nm.omega * s0)
    ti = brentq(lambda t: mo.h(t)[0], 0.0, s0, xtol=1e-15, rtol=1e-15)
    zi = mo.state(ti)
    zp = np.concatenate([zi[:n], R @ zi[n:]])
    phi_i = phi - nm.omega * (s0 - ti)
    # w = (x, v = 0) at phase phi_i - omega t, flown for t > 0, lands on zp (one mass)
    x, t = zi[0], abs(zp[n]) / abs(nm.acceleration)
    for _ in range(30):
        zt, Phi, _, f = flow.flight(F, np.array([x, 0.0]), phi_i - nm.omega * t, t)
        res = zt - zp
        # d/dt at fixed end phase: the start's phase moves back as t grows
        dphase = flow.flight(F, np.array([x, 0.0]), phi_i - nm.omega * t, t)[2]
        Jm = np.column_stack([Phi[:, 0], f - nm.omega * dphase])
        step = np.linalg.solve(Jm, -res)
        x, t = x + step[0], t + step[1]
        if np.max(np.abs(step)) < 1e-15:
            break
    return np.array([x - row[2], phi_i - nm.omega * t])


def test_sqrt_coefficient_against_the_numerical_flows_impact():
    nm = _grazing(Model(**KW, nonlinear=["beta*x1**3"], parameters={"beta": 0.2}))
    deltas = np.array([1e-4, 1e-5, 1e-6, 1e-7, 1e-8])
    rows = []
    for d in deltas:
        x0 = nm.point.copy()
        x0[0] += d
        rows.append((_exact_pdm(nm, d) - x0) / math.sqrt(d))
    A = np.column_stack([np.ones_like(deltas), np.sqrt(deltas), deltas])
    coef = np.linalg.lstsq(A, np.array(rows), rcond=None)[0][0]
    scale = np.max(np.abs(nm.E0))
    assert np.max(np.abs(coef - nm.E0)) < 1e-5 * scale, (coef, nm.E0)
    assert nm.acceleration < 0
