"""The compiled finder, map, tangent and run loop over several constraints (issue 25):
against solve_ivp with one event per guard, the determinant identity along the constraints
hit, and never a contact stepped over.

"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from symvi.flow import compiled as cf
from symvi.flow.linear import LinearFlow
from symvi.model import Model, Stop


def _one_dof(gap_up, gap_lo, r_up, r_lo, damping, forcing):
    """One mass between an upper stop x <= gap_up and a lower one x >= gap_lo."""
    return Model(mass=[[1.0]], stiffness=[[1.0]], damping=[[damping]], forcing=[forcing],
                 stops=[Stop(mass=1, gap=gap_up, restitution=r_up),
                        Stop(mass=1, gap=gap_lo, side="lower", restitution=r_lo)])


def _two_mass(gap1, gap2, r1, r2):
    """Two masses in a chain; an upper stop on mass 1, a lower stop on mass 2."""
    return Model(mass=[[1.0, 0], [0, 1.3]], stiffness=[[2.0, -1.0], [-1.0, 2.5]],
                 damping=[[0.03, 0], [0, 0.02]], forcing=[0.8, 1.1],
                 stops=[Stop(mass=1, gap=gap1, restitution=r1),
                        Stop(mass=2, gap=gap2, side="lower", restitution=r2)])


def state(model, c, y, k):
    """The full state (mass order) of section point y of constraint k (compiled layout)."""
    n = model.n
    flow = LinearFlow.of(model)
    _, _, _, oc, cb = cf._offsets(n)
    p = int(c[oc + k * cb + cf._P])
    z = np.empty(2 * n)
    for i in range(n):
        if i == p:
            z[i], z[n + i] = c[oc + k * cb + cf._GAP], y[0]
        else:
            s = cf._slot(i, p)
            z[i], z[n + i] = y[s], y[n - 1 + s]
    perm = list(flow.perm)
    out = np.empty(2 * n)
    out[perm] = z[:n]
    out[[n + j for j in perm]] = z[n:]
    return out


def first_contact(model, omega, tau, z0, t0, t1, leaving=None, tol=1e-13, first_step=1e-6):
    """(time, constraint, state at contact) of the first contact after t0 (before t1) by
    DOP853 with one terminal event per guard, from z0 (mass order) under the forcing
    P sin(omega t + tau); a contact with ``leaving`` within 1e-9 of t0 is the one just
    left.  None without one."""
    n = model.n
    Minv = np.linalg.inv(np.asarray(model.mass, dtype=float))
    K, C, P = (np.asarray(a, dtype=float) for a in (model.stiffness, model.damping,
                                                     model.forcing))
    cons = model.constraints

    def rhs(t, z):
        x, v = z[:n], z[n:]
        return np.concatenate([v, Minv @ (P * math.sin(omega * t + tau) - K @ x - C @ v)])

    events = []
    for con in cons:
        def ev(t, z, con=con):
            return con.guard(z[:n])
        ev.terminal, ev.direction = True, 1.0
        events.append(ev)
    sol = solve_ivp(rhs, (t0, t1), z0, method="DOP853", rtol=tol, atol=tol,
                    events=events, first_step=first_step)
    hit = [(sol.t_events[g][0], g) for g in range(len(cons))
           if len(sol.t_events[g]) and not (g == leaving and sol.t_events[g][0] - t0 < 1e-9)]
    if not hit:
        return None
    te, g = min(hit)
    return te, g, sol.y_events[g][-1] if sol.t_events[g][-1] == te else sol.y_events[g][0]


def _reference(model, omega, z0, tau, n_impacts):
    """Impacts (time, constraint, state just after, mass order) by DOP853 with one event
    per guard, the rigid reset applied at each."""
    n = model.n
    Minv = np.linalg.inv(np.asarray(model.mass, dtype=float))
    t0, z, out = 0.0, np.array(z0, dtype=float), []
    last = None
    while len(out) < n_impacts:
        hit = first_contact(model, omega, tau, z, t0, t0 + 200.0, last)
        assert hit, "no impact within 200 time units"
        te, g, ze = hit
        R = model.constraints[g].reset_matrix(Minv)
        z = np.concatenate([ze[:n], R @ ze[n:]])
        out.append((te, g, z.copy()))
        t0, last = te, g
    return out


CASES = {
    "1dof-two-sided": (lambda: _one_dof(0.5, -0.4, 0.8, 0.7, 0.05, 1.3), 1.1),
    "2mass-two-stops": (lambda: _two_mass(0.6, -0.5, 0.85, 0.75), 1.2),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_run_matches_solve_ivp_over_every_constraint(case):
    """Impact times, the constraint hit and the states after each impact agree with
    DOP853 + events (tolerances 1e-13) over 25 impacts that visit both constraints."""
    make, omega = CASES[case]
    model = make()
    c = cf.constants(model, omega)
    assert int(c[cf._NC]) == 2
    n = model.n
    y0 = np.zeros(2 * n)
    y0[0], y0[-1] = -0.3, 0.4                       # leaving the first stop at phase 0.4
    code, sec, times, vimp, _, hits = cf.run(c, y0, 25, hits=True)
    assert code == cf.COMPLETED
    assert set(hits) == {0, 1}, "the run should visit both constraints"
    ref = _reference(model, omega, state(model, c, y0, 0), y0[-1], 25)
    for i, (te, g, z) in enumerate(ref):
        assert hits[i] == g
        assert abs(times[i] - te) < 1e-8 * (1 + te)
        np.testing.assert_allclose(state(model, c, sec[i], g)[:2 * n], z, atol=1e-8)
        assert vimp[i] > 0                          # a rigid impact arrives moving in


@pytest.mark.parametrize("case", sorted(CASES))
def test_determinant_identity_along_the_constraints_hit(case):
    """det DP = -r_g (v_p(0+) / v_q(t_e-)) exp(-tr(M^-1 C) t_e) for each flight from the
    section x_p = gap of constraint k to that of the constraint g hit (coordinate q):
    the flow's volume change, the flux ratio through the two sections, and det R = -r_g
    of the reset.  Along a periodic orbit the ratios telescope to prod r_i^2 (the brief's
    identity).  The tangent map is also held to central differences."""
    make, omega = CASES[case]
    model = make()
    c = cf.constants(model, omega)
    n = model.n
    y = np.zeros(2 * n)
    y[0], y[-1] = -0.3, 0.4
    k = 0
    tr = np.trace(np.linalg.solve(np.asarray(model.mass, float), np.asarray(model.damping,
                                                                            float)))
    seen = set()
    for _ in range(12):
        st, te, y1, vm, acc, steps, g = cf.step(c, y, k)
        assert st == cf.IMPACT
        J = cf.jacobian_tangent(c, y, k)
        con = model.constraints[g]
        v_out = con.sign * vm                       # v_q(t_e-): guard . v- = sign v_q
        want = -con.restitution * y[0] / v_out * math.exp(-tr * te)
        assert np.linalg.det(J) == pytest.approx(want, rel=1e-8)
        # the tangent map is DP: central differences along each direction
        h = 1e-6
        for j in range(2 * n):
            e = np.zeros(2 * n)
            e[j] = h
            yp, ym = cf.step(c, y + e, k), cf.step(c, y - e, k)
            if yp[6] != g or ym[6] != g:
                continue
            d = (yp[2] - ym[2]) / (2 * h)
            d[-1] = (math.remainder(yp[2][-1] - ym[2][-1], 2 * math.pi)) / (2 * h)
            np.testing.assert_allclose(d, J[:, j], rtol=1e-5, atol=1e-5)
        seen.add(g)
        y, k = y1, g
    assert seen == {0, 1}


def test_one_constraint_table_is_the_stop():
    """A one-stop model's table is the flow's constraint (p = 0, the gap, the level)."""
    m = Model(mass=[[1.0]], stiffness=[[1.0]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.25, restitution=0.9))
    c = cf.constants(m, 1.7)
    _, _, _, oc, cb = cf._offsets(1)
    assert int(c[cf._NC]) == 1 and len(c) == cf.size(1, 1)
    assert (c[oc + cf._P], c[oc + cf._GAP], c[oc + cf._LEVEL]) == (0.0, 0.25, 0.25)
    assert c[oc + cf._CB] == 1.0 and c[oc + cf._CB + 1] == -0.9


def test_no_contact_is_stepped_over_between_close_stops():
    """A narrow clearance (0.02) and fast motion: every flight ends on a contact that
    the reference finds too, none skipped: the positions between impacts never leave
    the clearance (sampled densely by the exact flow)."""
    model = _one_dof(0.01, -0.01, 0.9, 0.9, 0.02, 3.0)
    omega = 1.3
    c = cf.constants(model, omega)
    y0 = np.array([-0.5, 0.1])
    code, sec, times, _, _, hits = cf.run(c, y0, 400, hits=True)
    # a converging chatter is followed to its grazing impact (the loop's sticking stop)
    assert code in (cf.COMPLETED, cf.STOP_CHATTER, cf.STOP_STICKING)
    flow = LinearFlow.of(model)
    F = flow.forcing(omega)
    k = 0
    y = y0
    for i in range(len(hits)):
        z0 = state(model, c, y, k)
        tau = y[-1]
        mo = flow.motion(F, z0, tau)
        t_prev = times[i - 1] if i else 0.0
        for s in np.linspace(0, times[i] - t_prev, 50)[1:-1]:
            x = mo.state(s)[0]
            assert -0.01 - 1e-12 <= x <= 0.01 + 1e-12
        y, k = sec[i], hits[i]
