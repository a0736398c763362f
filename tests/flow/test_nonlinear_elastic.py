"""Elastic stops with nonlinear forces (issue 28 on issue 25's contact law): the walk of
symvi.flow.contact with each phase on the Taylor flow (symvi.flow.nlcontact), against
solve_ivp on the piecewise ODE (an impact Duffing oscillator with an elastic stop, a 2-DOF
chain with a cubic spring), the exact linear walk with the nonlinearity off, and the
phase's field and saltation matrix."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from symvi import Model, Stop
from symvi.flow import contact as ct
from symvi.flow import nlcontact

#: the impact Duffing oscillator with an elastic stop (k_s = 50, c_s = 0.5, gap 0.5)
_ONE = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
            stop=Stop(mass=1, gap=0.5, stiffness=50.0, damping=0.5))
DUFFING = Model(**_ONE, nonlinear=["beta*x1**3"], parameters={"beta": 0.5})
#: two masses, a cubic spring on mass 1, an elastic lower stop on mass 2 and a rigid stop
_TWO = dict(mass=[[1.0, 0.0], [0.0, 1.5]], stiffness=[[2.0, -1.0], [-1.0, 1.0]],
            damping=[[0.03, 0.0], [0.0, 0.02]], forcing=[1.0, 0.3])
CHAIN = Model(**_TWO, nonlinear=["beta*x1**3", "0"], parameters={"beta": 0.3},
              stops=[Stop(mass=2, gap=-0.3, side="lower", stiffness=40.0, damping=0.5),
                     Stop(mass=1, gap=0.6, restitution=0.8)])


def _forces(model):
    """f(x, v) of the model's texts, in plain Python (independent of the postfix program)."""
    names = model._nl.names
    vals = {p: model._nl.value(p) for p in names}
    texts = model._nl.texts
    n = model.n

    def f(y):
        env = dict(vals, **{f"x{i + 1}": y[i] for i in range(n)},
                   **{f"v{i + 1}": y[n + i] for i in range(n)})
        return np.array([eval(t, {}, env) for t in texts], dtype=float)
    return f


def reference(model, omega, z0, tau, n_events, active=()):
    """The events (kind, constraint, t, state before) of the piecewise ODE
    M x'' + C_S x' + K_S x + f(x, v) = P sin(omega t + tau) + f_S by DOP853 (rtol = atol =
    1e-13) with one terminal event per guard (h_i outside a contact, -h_i inside)."""
    n = model.n
    K0, C0 = (np.array(a, dtype=float) for a in (model.stiffness, model.damping))
    P, Minv = np.array(model.forcing, dtype=float), np.linalg.inv(np.array(model.mass))
    force = _forces(model)
    cons = model.constraints
    S, t, z, out = set(active), 0.0, np.array(z0, dtype=float), []
    while len(out) < n_events:
        K, C, fS = K0.copy(), C0.copy(), np.zeros(n)
        for i in S:
            c = np.array(cons[i].normal)
            K += cons[i].stiffness * np.outer(c, c)
            C += (cons[i].damping or 0.0) * np.outer(c, c)
            fS += cons[i].stiffness * cons[i].gap * c

        def rhs(s, y, K=K, C=C, fS=fS):
            return np.concatenate([y[n:], Minv @ (P * math.sin(omega * s + tau) + fS
                                                  - C @ y[n:] - K @ y[:n] - force(y))])
        evs = []
        for i, con in enumerate(cons):
            sg = -con.sign if i in S else con.sign

            def ev(s, y, sg=sg, con=con):
                return sg * (np.array(con.normal) @ y[:n] - con.gap)
            ev.terminal, ev.direction = True, 1
            evs.append(ev)
        sol = solve_ivp(rhs, (t, t + 300.0), z, method="DOP853", rtol=1e-13, atol=1e-13,
                        events=evs)
        hit = [(te[0], i, ye[0]) for i, (te, ye) in enumerate(zip(sol.t_events, sol.y_events))
               if len(te)]
        assert hit, "no event within 300 time units"
        te, i, zb = min(hit, key=lambda h: h[0])
        con = cons[i]
        za = zb.copy()
        if i in S:
            kind = ct.EXIT
            S.discard(i)
        elif con.kind == "elastic":
            kind = ct.ENTRY
            S.add(i)
        else:
            kind = ct.IMPACT
            za[n:] = con.reset_matrix(Minv) @ zb[n:]
        out.append((kind, i, te, zb))
        t, z = te, za
    return out


def events(model, omega, z0, tau, n_events, **kw):
    out = []
    for ev in ct.walk(model, omega, z0, tau, **kw):
        out.append(ev)
        if len(out) == n_events or ev.kind not in (ct.IMPACT, ct.ENTRY, ct.EXIT):
            break
    return out


@pytest.mark.parametrize("model,omega,n_events,kinds", [
    (DUFFING, 1.3, 12, {ct.ENTRY, ct.EXIT}),
    (CHAIN, 1.2, 12, {ct.ENTRY, ct.EXIT, ct.IMPACT}),
])
def test_walk_matches_solve_ivp_on_the_piecewise_ode(model, omega, n_events, kinds):
    """Entry, exit and impact times and the states there agree with DOP853 (rtol 1e-13) on
    the piecewise ODE to 1e-9; so does the state at a time between events."""
    z0, tau = np.zeros(model.dim), 0.2
    ours = events(model, omega, z0, tau, n_events)
    ref = reference(model, omega, z0, tau, n_events)
    assert [e.kind for e in ours] == [r[0] for r in ref]
    assert [e.constraint for e in ours] == [r[1] for r in ref]
    assert kinds <= {e.kind for e in ours}
    for e, (_, _, te, zb) in zip(ours, ref):
        assert abs(e.t - te) < 1e-9 * max(1.0, te)
        np.testing.assert_allclose(e.before, zb, rtol=0, atol=1e-9)
    # the state at a time inside a contact phase (t_end cuts the walk there)
    e1, e2 = next((a, b) for a, b in zip(ours, ours[1:]) if a.kind == ct.ENTRY)
    T = 0.5 * (e1.t + e2.t)
    end = events(model, omega, z0, tau, 100, t_end=T)[-1]
    assert end.kind == ct.TIME and end.active == e1.active
    n = model.n
    c = np.array(model.constraints[e1.constraint].normal)
    # in contact: h > 0 there
    assert model.constraints[e1.constraint].sign * (c @ end.after[:n] - model.constraints[
        e1.constraint].gap) > 0


@pytest.mark.parametrize("lin,nl", [
    (Model(**_ONE), Model(**_ONE, nonlinear=["0*x1**3"])),
    (Model(**_TWO, stops=CHAIN.stops),
     Model(**_TWO, nonlinear=["0*beta*x1**3", "0"], parameters={"beta": 0.3},
           stops=CHAIN.stops)),
])
def test_nonlinearity_off_is_the_exact_linear_walk(lin, nl):
    """With the nonlinear coefficient 0 every event (kind, constraint, time, states before
    and after, contacts) equals the exact walk's of the linear model to 1e-12 relative."""
    z0, tau = np.zeros(lin.dim), 0.2
    a = events(lin, 1.2, z0, tau, 30)
    b = events(nl, 1.2, z0, tau, 30)
    assert len(a) == len(b) == 30
    assert [(e.kind, e.constraint, e.active) for e in a] == \
        [(e.kind, e.constraint, e.active) for e in b]
    for e, f in zip(a, b):
        assert abs(e.t - f.t) <= 1e-12 * e.t
        scale = np.max(np.abs(e.before))
        np.testing.assert_allclose(f.before, e.before, rtol=1e-12, atol=1e-12 * scale)
        np.testing.assert_allclose(f.after, e.after, rtol=1e-12, atol=1e-12 * scale)


def test_the_phase_field_is_the_contact_law():
    """The phase's field: M x'' = P sin + f_S - C_S v - K_S x - f(x, v), with K_S, C_S, f_S
    of the contact law (symvi.flow.linear.contact_matrices) and the model's forces."""
    z, t, w, tau = np.array([0.7, -0.4]), 0.3, 1.3, 0.2
    for S in ((), (0,)):
        got = nlcontact.phase(DUFFING, S).field(z, t, w, tau)
        lin = ct.phase(Model(**_ONE), S).field(z, t, w, tau)
        assert np.allclose(got, lin - [0.0, 0.5 * z[0] ** 3], rtol=0, atol=1e-13)
    # in contact the stop pushes back: k_s (x - g) + c_s v
    f = nlcontact.phase(DUFFING, (0,)).field(z, t, w, tau)[1]
    free = nlcontact.phase(DUFFING, ()).field(z, t, w, tau)[1]
    assert abs((free - f) - (50.0 * (0.7 - 0.5) + 0.5 * -0.4)) < 1e-13


def test_saltation_of_a_nonlinear_switch_has_determinant_one():
    """The elastic switch's saltation matrix (symvi.flow.contact.saltation) on the phases'
    nonlinear fields: no jump, det S = 1."""
    evs = events(DUFFING, 1.3, np.zeros(2), 0.2, 4)
    for e in evs:
        if e.kind in (ct.ENTRY, ct.EXIT):
            S = ct.saltation(DUFFING, e, 1.3)
            assert abs(np.linalg.det(S) - 1.0) < 1e-12


def test_a_start_not_leaving_its_guard_is_grazing():
    """A start on a guard that does not leave it, or at another guard (a corner), is a
    grazing at t = 0, as the exact walk says."""
    ph = nlcontact.phase(DUFFING, ())
    G, lv = ct.guards(DUFFING, ())
    hit = ph.motion(1.3, np.array([0.5, 0.2]), 0.0).first_event(G, lv, start=0)
    assert hit.status == ct.GRAZING and hit.t == 0.0
    hit = ph.motion(1.3, np.array([0.5, 0.2]), 0.0).first_event(G, lv)
    assert hit.status == ct.GRAZING and hit.t == 0.0
    hit = ph.motion(1.3, np.array([0.5, -0.2]), 0.0).first_event(G, lv, start=0)
    assert hit.status == "event" and hit.t > 0
