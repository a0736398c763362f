"""Elastic stops (issue 25): the contact phases of :mod:`symvi.flow.contact` against
solve_ivp with events (DOP853, rtol = atol = 1e-12) on each constraint kind and a mix; the
elastic stop tends to the rigid one with r = 1 as its stiffness grows (rates measured and
asserted); the effective restitution of a damped contact; and the elastic counterpart of
the determinant identity det DP = prod r_i^2 exp(-tr(M^-1 C) T)."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from symvi.errors import ParameterError
from symvi.flow import contact as ct
from symvi.model import Model, Stop

#: one mass, an upper elastic stop with damping
ONE = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
            stop=Stop(mass=1, gap=0.5, stiffness=50.0, damping=0.3))
#: one mass between an elastic upper stop and a rigid lower one
BETWEEN = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.3],
                stops=[Stop(mass=1, gap=0.5, stiffness=80.0, damping=0.2),
                       Stop(mass=1, gap=-0.4, side="lower", restitution=0.8)])
_CHAIN = dict(mass=[[1.0, 0], [0, 1.3]], stiffness=[[2.0, -1.0], [-1.0, 2.5]],
              forcing=[0.8, 1.1])
#: two masses in a chain, an elastic lower stop with damping on mass 2
CHAIN = Model(**_CHAIN, damping=[[0.03, 0], [0, 0.02]],
              stop=Stop(mass=2, gap=-0.3, side="lower", stiffness=40.0, damping=0.5))
#: the same chain undamped (the closed-form modes in every phase): an elastic upper stop on
#: mass 1 without damping and a rigid lower stop on mass 2
CHAIN_MIX = Model(**_CHAIN, stops=[Stop(mass=1, gap=0.4, stiffness=60.0),
                                   Stop(mass=2, gap=-0.5, side="lower", restitution=0.9)])
CASES = {"one": (ONE, 1.3), "between": (BETWEEN, 1.1), "chain": (CHAIN, 1.2),
         "chain-mix": (CHAIN_MIX, 1.2)}


def reference(model, omega, z0, tau, n_events, active=()):
    """The events (kind, constraint, t, state before) of the same motion by DOP853 with one
    terminal event per guard (h_i outside a contact, -h_i inside, each rising through 0),
    and z(t) from the dense outputs: independent of symvi's flow."""
    n = model.n
    M, K0, C0 = (np.array(a, dtype=float) for a in (model.mass, model.stiffness, model.damping))
    P, Minv = np.array(model.forcing, dtype=float), np.linalg.inv(np.array(model.mass))
    cons = model.constraints
    S, t, z, out, pieces = set(active), 0.0, np.array(z0, dtype=float), [], []
    while len(out) < n_events:
        K, C, f = K0.copy(), C0.copy(), np.zeros(n)
        for i in S:
            c = np.array(cons[i].normal)
            K += cons[i].stiffness * np.outer(c, c)
            C += (cons[i].damping or 0.0) * np.outer(c, c)
            f += cons[i].stiffness * cons[i].gap * c

        def rhs(s, y, K=K, C=C, f=f):
            return np.concatenate([y[n:], Minv @ (P * math.sin(omega * s + tau) + f
                                                  - C @ y[n:] - K @ y[:n])])
        evs = []
        for i, con in enumerate(cons):
            sg = -con.sign if i in S else con.sign

            def ev(s, y, sg=sg, con=con):
                return sg * (np.array(con.normal) @ y[:n] - con.gap)
            ev.terminal, ev.direction = True, 1
            evs.append(ev)
        sol = solve_ivp(rhs, (t, t + 300.0), z, method="DOP853", rtol=1e-12, atol=1e-12,
                        events=evs, dense_output=True)
        hit = [(te[0], i) for i, te in enumerate(sol.t_events) if len(te)]
        assert hit, "no event within 300 time units"
        te, i = min(hit)
        zb = sol.sol(te)
        pieces.append((t, te, sol.sol))
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

    def state(s):
        for a, b, f in pieces:
            if a <= s <= b:
                return f(s)
        raise ValueError(s)
    return out, state


def events(model, omega, z0, tau, n_events, **kw):
    out = []
    for ev in ct.walk(model, omega, z0, tau, **kw):
        out.append(ev)
        if len(out) == n_events or ev.kind not in (ct.IMPACT, ct.ENTRY, ct.EXIT):
            break
    return out


@pytest.mark.parametrize("name", list(CASES))
def test_walk_matches_solve_ivp_with_events(name):
    """Event kinds, constraints, times and states (velocities at entry and exit included)
    agree with DOP853 to 1e-8 over 12 events; so does the state between events."""
    model, omega = CASES[name]
    z0, tau = np.zeros(model.dim), 0.2
    ours = events(model, omega, z0, tau, 12)
    ref, state = reference(model, omega, z0, tau, 12)
    assert [e.kind for e in ours] == [r[0] for r in ref]
    assert [e.constraint for e in ours] == [r[1] for r in ref]
    kinds = {e.kind for e in ours}
    assert ct.ENTRY in kinds and ct.EXIT in kinds
    if name in ("between", "chain-mix"):
        assert ct.IMPACT in kinds                      # the mix meets both kinds
    for e, (_, _, te, zb) in zip(ours, ref):
        assert abs(e.t - te) < 1e-8 * max(1.0, te)
        np.testing.assert_allclose(e.before, zb, rtol=0, atol=1e-8)
    for T in np.linspace(0.1, ours[-1].t - 0.05, 7):   # the trajectory between events
        end = events(model, omega, z0, tau, 100, t_end=float(T))[-1]
        assert end.kind == ct.TIME and end.t == T
        np.testing.assert_allclose(end.after, state(T), rtol=0, atol=1e-8)


def test_the_contact_force_pushes_out_of_either_side():
    """x -> -x: a lower elastic stop at -g with forcing -P moves as the mirror image of an
    upper one at g with P (the force -(k_s (s - g) + c_s s') c, the same on both sides)."""
    up = ONE
    lo = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[-1.0],
               stop=Stop(mass=1, gap=-0.5, side="lower", stiffness=50.0, damping=0.3))
    a = events(up, 1.3, np.zeros(2), 0.2, 10)
    b = events(lo, 1.3, np.zeros(2), 0.2, 10)
    assert [e.kind for e in a] == [e.kind for e in b] == [ct.ENTRY, ct.EXIT] * 5
    for ea, eb in zip(a, b):
        assert abs(ea.t - eb.t) < 1e-12 * ea.t
        np.testing.assert_allclose(eb.before, -ea.before, atol=1e-12)
    ph = ct.phase(lo, (0,))
    np.testing.assert_allclose(ph.zs[:1], [50.0 * -0.5 / 51.0])    # K_S xs = k_s g c
    assert ph.K[0, 0] == 51.0 and ph.C[0, 0] == 0.35


@pytest.mark.parametrize("model,active", [(CHAIN_MIX, ()), (CHAIN_MIX, (0,)), (CHAIN, (0,)),
                                          (BETWEEN, (0,))])
def test_phase_flow_is_the_matrix_exponential(model, active):
    """Phi_S(t) of a phase (closed-form modes when undamped, eigenvectors of A_S when
    damped) is expm(A_S t); A_S carries K + k_s c c^T and C + c_s c c^T."""
    from scipy.linalg import expm
    ph = ct.phase(model, active)
    for t in (0.3, 2.7, 11.0):
        np.testing.assert_allclose(ph.phi(t), expm(ph.A * t), rtol=0, atol=1e-12)
    n, K = model.n, np.array(model.stiffness)
    for i in active:
        c = np.array(model.constraints[i].normal)
        K = K + model.constraints[i].stiffness * np.outer(c, c)
    np.testing.assert_allclose(-ph.A[n:, :n], np.linalg.solve(np.array(model.mass), K))


def test_a_contact_phase_at_its_own_resonance_is_refused():
    """omega at the natural frequency sqrt((k + k_s) / m) of an undamped contact phase:
    its steady response is infinite; the free flight at that omega is fine."""
    from symvi.errors import SingularCaseError
    model = Model(mass=[1.0], stiffness=[[1.0]], forcing=[1.0],
                  stop=Stop(mass=1, gap=0.5, stiffness=3.0))
    ct.phase(model, ()).forcing(2.0)
    with pytest.raises(SingularCaseError, match="contact phase \\[0\\]"):
        ct.phase(model, (0,)).forcing(2.0)


def test_a_phase_refuses_a_rigid_constraint():
    with pytest.raises(ParameterError, match="elastic constraints"):
        ct.Phase(BETWEEN, (1,))


# ---- the elastic stop tends to the rigid one with r = 1 ----------------------------------
def _slope(ks, err):
    return float(np.polyfit(np.log(ks), np.log(err), 1)[0])


def _first_contact(stop, T=3.0):
    m = Model(mass=[1.0], stiffness=[[1.0]], forcing=[1.0], stop=stop)
    return events(m, 1.3, np.zeros(2), 0.2, 100, t_end=T)


def test_elastic_tends_to_rigid_with_r_one():
    """c_s = 0, k_s -> infinity: the contact lasts pi / sqrt(k_s + k) + O(1 / k_s); the exit
    speed tends to the entry speed with error O(1 / k_s) (a constant force over the contact
    changes no speed: energy about the shifted equilibrium; only its variation over the
    contact time delta ~ k_s^-1/2 acts, delta^2); the state at a later time tends to the
    rigid one with r = 1 as O(k_s^-1/2) (the contact delays the motion by delta).
    Measured orders: -1.0, -1.0, -0.5."""
    rigid = _first_contact(Stop(mass=1, gap=0.5, restitution=1.0))
    assert [e.kind for e in rigid] == [ct.IMPACT, ct.TIME]
    ks = np.array([1e3, 1e4, 1e5, 1e6])
    dur, speed, state = [], [], []
    for k in ks:
        ev = _first_contact(Stop(mass=1, gap=0.5, stiffness=float(k)))
        assert [e.kind for e in ev] == [ct.ENTRY, ct.EXIT, ct.TIME]
        entry, out, end = ev
        dur.append(abs(out.t - entry.t - math.pi / math.sqrt(k + 1.0)))
        speed.append(abs(out.before[1] + entry.before[1]))
        state.append(np.abs(end.after - rigid[-1].after).max())
    assert abs(_slope(ks, dur) + 1.0) < 0.1
    assert abs(_slope(ks, speed) + 1.0) < 0.1
    assert abs(_slope(ks, state) + 0.5) < 0.05
    assert state[-1] < 3e-3 and speed[-1] < 1e-5


def test_damped_contact_has_the_oscillator_restitution():
    """With c_s = 2 zeta sqrt(k_s m) the contact is a damped oscillator: entering at s = g
    with speed v it leaves at s = g after half a damped period pi / omega_d with speed
    v exp(-zeta omega_n pi / omega_d) = v exp(-zeta pi / sqrt(1 - zeta^2)): the effective
    restitution, reached as k_s -> infinity at zeta fixed (error O(k_s^-1/2), measured)."""
    zeta = 0.1
    r_eff = math.exp(-zeta * math.pi / math.sqrt(1 - zeta ** 2))
    ks = np.array([1e4, 1e5, 1e6])
    err = []
    for k in ks:
        entry, out, _ = _first_contact(Stop(mass=1, gap=0.5, stiffness=float(k),
                                            damping=2 * zeta * math.sqrt(k)))
        err.append(abs(-out.before[1] / entry.before[1] - r_eff))
        wd = math.sqrt(k) * math.sqrt(1 - zeta ** 2)
        assert abs((out.t - entry.t) * wd / math.pi - 1) < 20 / math.sqrt(k)
    assert abs(_slope(ks, err) + 0.5) < 0.1
    assert err[-1] < 5e-4


# ---- the determinant identity, elastic counterpart ---------------------------------------
def _trace_integral(model, evs, T):
    """int_0^T tr A(t) dt = -tr(M^-1 C) T - sum over contacts c_s c^T M^-1 c (contact time)."""
    Minv = np.linalg.inv(np.array(model.mass))
    total = -np.trace(Minv @ np.array(model.damping)) * T
    opened = {}
    for e in evs:
        if e.kind == ct.ENTRY:
            opened[e.constraint] = e.t
        elif e.kind == ct.EXIT:
            con = model.constraints[e.constraint]
            c = np.array(con.normal)
            total -= (con.damping or 0.0) * (c @ Minv @ c) * (e.t - opened.pop(e.constraint))
    for i, t0 in opened.items():
        con = model.constraints[i]
        c = np.array(con.normal)
        total -= (con.damping or 0.0) * (c @ Minv @ c) * (T - t0)
    return total


@pytest.mark.parametrize("model,omega", [(ONE, 1.3), (CHAIN, 1.2)])
def test_saltation_determinant_and_the_monodromy(model, omega):
    """Over [0, T] with several contacts: the state's monodromy is the product of the
    phases' flow matrices and the saltation matrices S = I + (F+ - F-) grad h^T /
    (grad h . F-) of the switches; det S = 1 (h depends on x alone and x' = v on both
    sides, though the damping force jumps: S != I); so det Phi_total = exp(int tr A dt),
    int tr A = -tr(M^-1 C) T - sum c_s c^T M^-1 c (time in contact).  Phi_total is checked
    against central differences of the walk's fixed-time map."""
    z0, tau, T = np.array([0.05] * model.n + [0.1] * model.n), 0.3, 14.0
    evs = events(model, omega, z0, tau, 1000, t_end=T)
    assert evs[-1].kind == ct.TIME and sum(e.kind == ct.ENTRY for e in evs) >= 2
    Phi, t0, active = np.eye(model.dim), 0.0, ()
    for e in evs:
        Phi = ct.phase(model, active).phi(e.t - t0) @ Phi
        if e.kind in (ct.ENTRY, ct.EXIT):
            S = ct.saltation(model, e, omega)
            assert abs(np.linalg.det(S) - 1) < 1e-13
            assert np.abs(S - np.eye(model.dim)).max() > 1e-2          # the damping jump
            Phi = S @ Phi
        t0, active = e.t, e.active
    tr = _trace_integral(model, evs, T)
    assert tr < -0.5
    assert abs(np.linalg.det(Phi) / math.exp(tr) - 1) < 1e-11
    h = 1e-6
    J = np.empty((model.dim, model.dim))
    for j in range(model.dim):
        d = np.eye(model.dim)[j] * h
        zp = events(model, omega, z0 + d, tau, 1000, t_end=T)[-1].after
        zm = events(model, omega, z0 - d, tau, 1000, t_end=T)[-1].after
        J[:, j] = (zp - zm) / (2 * h)
    np.testing.assert_allclose(J, Phi, rtol=0, atol=1e-6 * np.abs(Phi).max())
    assert abs(np.linalg.det(J) / math.exp(tr) - 1) < 1e-5


def test_section_map_determinant():
    """The elastic counterpart of det DP = prod r_i^2 exp(-tr(M^-1 C) T): for the map from
    one entry section to the p-th next entry (coordinates: s = g dropped, the phase tau
    kept), the flux through the sections is carried by the flow, so

        det DP^p = exp(int tr A dt) h'(start) / h'(end),

    h' = sign c^T v the entry speed (det S = 1 at every switch).  On a periodic orbit the
    speeds cancel and each contact contributes exp(-c_s c^T M^-1 c t_c), which for one
    mass with zeta = c_s / (2 sqrt(k_s m)) and t_c -> pi / omega_d is
    exp(-2 zeta pi / sqrt(1 - zeta^2)) = r_eff^2: the rigid r^2 in the limit.
    Checked against central differences of the walk's section map, for one mass and the
    chain."""
    for model, omega, p in ((ONE, 1.3, 3), (CHAIN, 1.2, 2)):
        n = model.n
        con = model.constraints[0]
        k = con.coordinate
        first = events(model, omega, np.zeros(model.dim), 0.2, 100)
        entry = next(e for e in first if e.kind == ct.ENTRY)
        rest = [j for j in range(n) if j != k]

        def section(z, tau):                        # (v_k, x_rest, v_rest, tau unwrapped)
            return np.concatenate([[z[n + k]], z[rest], z[[n + j for j in rest]], [tau]])

        def run(y):
            z = np.empty(2 * n)
            z[k], z[n + k] = con.gap, y[0]
            z[rest], z[[n + j for j in rest]] = y[1:n], y[n:2 * n - 1]
            evs, seen = [], 0
            for e in ct.walk(model, omega, z, y[-1], active=(0,), start=0):
                evs.append(e)
                seen += e.kind == ct.ENTRY
                if seen == p:
                    return section(e.before, y[-1] + omega * e.t), evs, e.t
                assert e.kind in (ct.ENTRY, ct.EXIT)
        y0 = section(entry.before, entry.tau)
        y1, evs, T = run(y0)
        # the contact open at the start is closed within the first events
        tr = _trace_integral(model, [ct.Event(ct.ENTRY, 0, 0.0, 0.0, None, None, (0,))] + evs, T)
        expected = math.exp(tr) * (con.sign * y0[0]) / (con.sign * y1[0])
        h = 1e-7
        J = np.empty((model.dim, model.dim))
        for j in range(model.dim):
            d = np.eye(model.dim)[j] * h
            J[:, j] = (run(y0 + d)[0] - run(y0 - d)[0]) / (2 * h)
        assert abs(np.linalg.det(J) / expected - 1) < 1e-5
        assert abs(expected - math.exp(tr)) > 1e-3 * expected     # the speeds matter here
