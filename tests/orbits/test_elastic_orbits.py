"""Orbits through contact phases (issue 25, elastic stops): the shooting system with each
flight in its phase's exact flow (LinearFlow.contact), checked against the contact walk
of symvi.flow.contact (an independent integration of the same law), central differences,
the elastic determinant identity and continuation with symmetry breaking."""
import math

import numpy as np
import pytest

from symvi.continuation import continue_orbits
from symvi.flow import contact as ct
from symvi.flow.linear import LinearFlow
from symvi.model import Model, Signature, Stop
from symvi.orbits._phases import event_run
from symvi.orbits.periodic import Problem, detect_period, periodic_orbit

#: one mass, an elastic upper stop with contact damping
ONE = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
            stop=Stop(mass=1, gap=0.5, stiffness=50.0, damping=0.3))
#: an elastic upper stop and a rigid lower one
MIX = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.3],
            stops=[Stop(mass=1, gap=0.5, stiffness=80.0, damping=0.2),
                   Stop(mass=1, gap=-0.5, side="lower", restitution=0.8)])
#: two masses: an elastic stop on mass 2, a rigid lower stop on mass 1 (two frames)
CHAIN = Model(mass=[[1.0, 0.0], [0.0, 1.3]], stiffness=[[2.0, -1.0], [-1.0, 2.5]],
              damping=[[0.1, 0.0], [0.0, 0.05]], forcing=[1.0, 0.5],
              stops=[Stop(mass=2, gap=0.4, stiffness=60.0, damping=0.3),
                     Stop(mass=1, gap=-0.5, side="lower", restitution=0.8)])
#: a 1-DOF oscillator between two elastic stops at +-0.5 (mirror-symmetric)
SYM = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
            stops=[Stop(mass=1, gap=0.5, stiffness=50.0, damping=0.2),
                   Stop(mass=1, gap=-0.5, side="lower", stiffness=50.0, damping=0.2)])

CASES = {"one": (ONE, 1.2), "mix": (MIX, 1.3), "chain-1-6": (CHAIN, 0.9),
         "chain-1-3": (CHAIN, 1.3)}


def _orbit(model, omega):
    run = event_run(model, omega)
    found = detect_period(run)
    assert run.stop == "completed" and found is not None
    n, p = found
    return periodic_orbit(model, n=n, p=p, guess=run, omega=omega)


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request):
    model, omega = CASES[request.param]
    return model, _orbit(model, omega)


def _state(model, orbit, i):
    """(mass-order state, tau) of point i of the orbit (on its event's section)."""
    flow = LinearFlow.contact(model)
    N = model.n
    k = orbit.signature[i]
    pr = Problem(model, orbit.n, orbit.p, signature=orbit.itinerary)
    zf = np.empty(2 * N)
    zf[pr.positions[k]] = model.constraints[k].gap
    zf[pr.frames[k]] = np.array(orbit.points[i][:-1])
    perm = list(flow.perm)
    zm = np.empty(2 * N)
    zm[perm], zm[[N + j for j in perm]] = zf[:N], zf[N:]
    return zm, orbit.points[i][-1]


def test_the_orbit_is_a_periodic_walk(case):
    """From point 0 the contact walk (an independent integration: symvi.flow.contact)
    meets the signature's events in order, at the orbit's times, and returns to point 0
    after n forcing periods."""
    model, orbit = case
    z0, tau = _state(model, orbit, 0)
    phases = orbit.itinerary.phases(model)
    walk = ct.walk(model, orbit.omega, z0, tau, active=phases[0], start=orbit.signature[0])
    kinds = orbit.itinerary.kinds(model)
    t = 0.0
    for i in range(orbit.p):
        ev = next(walk)
        j = (i + 1) % orbit.p
        assert ev.constraint == orbit.signature[j]
        assert ev.kind == kinds[j]
        assert ev.t - t == pytest.approx(orbit.times[i], rel=1e-9, abs=1e-10)
        t = ev.t
    assert t * orbit.omega / (2 * math.pi) == pytest.approx(orbit.n, rel=1e-10)
    assert np.allclose(ev.after, z0, atol=1e-9)


def test_elastic_determinant_identity(case):
    """det DP^p = prod r_i^2 exp(-tr(M^-1 C) n T - sum over contacts c_s c^T M^-1 c (time
    in contact)) over the rigid impacts i and the elastic contacts: the switches'
    saltation matrices have determinant 1 (symvi.flow.contact)."""
    model, orbit = case
    Minv = np.linalg.inv(np.array(model.mass, dtype=float))
    phases = orbit.itinerary.phases(model)
    expo = -np.trace(Minv @ np.array(model.damping)) * orbit.n * 2 * math.pi / orbit.omega
    for S, T in zip(phases, orbit.times):
        for k in S:
            con = model.constraints[k]
            c = np.array(con.normal)
            expo -= con.damping * (c @ Minv @ c) * T
    for k in orbit.signature:
        if model.constraints[k].kind == "rigid":
            expo += 2 * math.log(model.constraints[k].restitution)
    assert abs(np.prod(orbit.multipliers)) == pytest.approx(math.exp(expo), rel=1e-9)


@pytest.mark.parametrize("param", ["omega", "stop[1].gap", "stop[1].stiffness",
                                   "stop[1].damping", "damping[1,1]", "mass[1]", "forcing[1]"])
def test_shooting_derivatives_against_central_differences(case, param):
    """G_u and dG/dparam through the contact phases (K_S, C_S and the offset zs move with
    the stop's gap, stiffness and damping) against central differences."""
    model, orbit = case
    pr = Problem(model, orbit.n, orbit.p, omega=orbit.omega, param=param,
                 signature=orbit.itinerary)
    lam = orbit.omega if param == "omega" else pr.parameter.get(model)
    G, Gu, Gl = pr.evaluate(orbit.u, lam, dparam=True)
    assert np.max(np.abs(G)) < 1e-10
    h = 1e-6 * max(1.0, abs(lam))
    fd = (pr.evaluate(orbit.u, lam + h, jac=False)[0]
          - pr.evaluate(orbit.u, lam - h, jac=False)[0]) / (2 * h)
    assert np.max(np.abs(Gl - fd)) <= 1e-7 * max(1.0, np.max(np.abs(fd)))
    if param == "omega":
        J = np.empty_like(Gu)
        for j in range(len(orbit.u)):
            e = np.zeros(len(orbit.u))
            e[j] = 1e-6
            J[:, j] = (pr.evaluate(orbit.u + e, lam, jac=False)[0]
                       - pr.evaluate(orbit.u - e, lam, jac=False)[0]) / 2e-6
        assert np.max(np.abs(Gu - J)) <= 1e-7 * max(1.0, np.max(np.abs(J)))


def _map(model, orbit, y):
    """P^p of the point y of the orbit's first section by the contact walk, tau unwrapped
    and n periods taken off (the map whose jet the orbit gives)."""
    pr = Problem(model, orbit.n, orbit.p, omega=orbit.omega, signature=orbit.itinerary)
    flow = LinearFlow.contact(model)
    N, k0 = model.n, orbit.signature[0]
    zf = np.empty(2 * N)
    zf[pr.positions[k0]] = model.constraints[k0].gap
    zf[pr.frames[k0]] = y[:-1]
    perm = list(flow.perm)
    zm = np.empty(2 * N)
    zm[perm], zm[[N + j for j in perm]] = zf[:N], zf[N:]
    walk = ct.walk(model, orbit.omega, zm, y[-1] % (2 * math.pi),
                   active=orbit.itinerary.phases(model)[0], start=k0)
    for _ in range(orbit.p):
        ev = next(walk)
    za = np.concatenate([ev.after[:N][perm], ev.after[N:][perm]])
    return np.append(za[pr.frames[k0]], y[-1] + orbit.omega * ev.t - 2 * math.pi * orbit.n)


@pytest.mark.parametrize("which", ["one", "chain-1-3"])
def test_exact_jets_through_contact_phases(which):
    """The generated jets of each flight, fed the phase's flow in z - zs (a translation),
    composed over the orbit: J is the monodromy, d2 and a d3 direction agree with central
    differences of the walk's map."""
    model, omega = CASES[which]
    orbit = _orbit(model, omega)
    A, d2, d3 = orbit.jet(3)
    pr = Problem(model, orbit.n, orbit.p, omega=omega, signature=orbit.itinerary)
    _, Gu, _ = pr.evaluate(orbit.u, None)
    assert np.max(np.abs(A - pr.monodromy(orbit.u, Gu)[1])) < 1e-12
    y = np.array(orbit.points[0])
    d = len(y)
    h = 1e-3
    for a, b in [(0, 0), (0, d - 1), (d - 1, d - 1)]:
        ea, eb = np.eye(d)[a] * h, np.eye(d)[b] * h
        fd = (_map(model, orbit, y + ea + eb) - _map(model, orbit, y + ea - eb)
              - _map(model, orbit, y - ea + eb) + _map(model, orbit, y - ea - eb)) / (4 * h * h)
        assert np.max(np.abs(fd - d2[:, a, b])) <= 1e-4 * max(1.0, np.max(np.abs(d2)))
    e = np.eye(d)[0] * h
    fd3 = (_map(model, orbit, y + 2 * e) - 2 * _map(model, orbit, y + e)
           + 2 * _map(model, orbit, y - e) - _map(model, orbit, y - 2 * e)) / (2 * h ** 3)
    assert np.max(np.abs(fd3 - d3[:, 0, 0, 0])) <= 1e-3 * max(1.0, np.max(np.abs(d3)))


def test_signature_phases_and_names():
    """Each elastic event toggles its stop: the phases follow from what is in contact
    during flight 0; an odd count of one elastic stop's events, or a rigid stop named in
    contact, is refused in one line."""
    sig = Signature((0, 1, 1, 0))
    assert sig.phases(MIX) == ((), (), (), (0,))
    assert sig.names(MIX) == ["stop1:exit", "stop2", "stop2", "stop1:entry"]
    assert Signature((0, 0), contact=(0,)).names(ONE) == ["stop1:entry", "stop1:exit"]
    with pytest.raises(Exception, match="even number"):
        Signature((0, 1)).phases(MIX)
    with pytest.raises(Exception, match="elastic"):
        Signature((0, 1, 1, 0), contact=(1,)).phases(MIX)


@pytest.fixture(scope="module")
def sym_branches():
    return continue_orbits(SYM, "omega", 2.0, 0.5, switch=True, max_points=3000)


def test_symmetric_elastic_orbit_breaks_symmetry(sym_branches):
    """Between two elastic stops the symmetric 1-4 orbit (entry and exit on each) loses
    its symmetry at pitchforks located on the branch (a multiplier of the half map through
    -1); the switched branches are asymmetric, and a point of one is the walk's attractor
    (simulated from the orbit's own point, it stays)."""
    sym = sym_branches[0]
    assert sym.points[0].orbit.symmetric
    assert sym.points[0].orbit.signature_names == ["stop2:entry", "stop2:exit",
                                                   "stop1:entry", "stop1:exit"]
    sb = [sp for sp in sym.special if sp.kind == "symmetry-breaking"]
    assert len(sb) == 2
    for sp in sb:
        H = np.array(sp.orbit.half_multipliers)
        assert np.min(np.abs(H + 1)) < 1e-6
    asym = [br for br in sym_branches[1:] if not br.points[len(br) // 2].orbit.symmetric]
    assert asym
    o = asym[0].points[len(asym[0]) // 2].orbit
    assert o.admissible
    stable = [pt.orbit for br in asym for pt in br.points if pt.orbit.stable]
    if stable:                                  # a stable asymmetric orbit is an attractor
        s = stable[len(stable) // 2]
        z0, tau = _state(SYM, s, 0)
        run = event_run(SYM, s.omega, z0, tau, events=8 * s.p, transient=40 * s.p,
                        active=s.itinerary.phases(SYM)[0], start=s.signature[0])
        assert detect_period(run) == (s.n, s.p)


def _next_event(model, orbit, i, y):
    """(time, point) from point y of event i's section to the next event, by the walk (the
    orbit's signature rotated to start at event i)."""
    from symvi.orbits._phases import flights
    hits = orbit.signature[i:] + orbit.signature[:i]
    sig = Signature(hits, orbit.itinerary.phases(model)[i])
    pr = Problem(model, orbit.n, orbit.p, omega=orbit.omega, signature=sig)
    flow = LinearFlow.free(model)
    Y, T = flights(pr, flow, flow.forcing(orbit.omega), [np.array(y)])
    return T[0], Y[1]


@pytest.mark.parametrize("param", ["stop[1].stiffness", "stop[1].gap", "stop[1].damping",
                                   "mass[1]", "damping[1,1]"])
def test_parameter_jets_through_contact_phases(param):
    """dJ/dp and dP/dp of each flight's map (the generated parameter slots fed the phase's
    tangent, K_S, C_S and the offset's motion, corrected for the moving translation)
    against central differences of J and of the walk's end point at p +- h."""
    from symvi.codegen.jets import flight_jet
    model, omega = CASES["chain-1-3"]
    orbit = _orbit(model, omega)
    par = model.parameter(param)
    v, tan = par.get(model), par.tangent(model)
    phases = orbit.itinerary.phases(model)
    Y = orbit.u[:orbit.p * 2 * model.n].reshape(orbit.p, -1)
    h = 1e-6 * max(1.0, abs(v))
    for i in range(orbit.p):
        ka, kb = orbit.signature[i], orbit.signature[(i + 1) % orbit.p]
        fi = LinearFlow.contact(model, phases[i])
        val = flight_jet(fi, fi.forcing(omega), tuple(Y[i]), orbit.times[i], 2, ka, kb, tan)
        J, P = [], []
        for s in (1.0, -1.0):
            mp = par.apply(model, v + s * h)
            te, nxt = _next_event(mp, orbit, i, Y[i])
            fp = LinearFlow.contact(mp, phases[i])
            J.append(flight_jet(fp, fp.forcing(omega), tuple(Y[i]), te, 1, ka, kb)["J"])
            P.append(nxt)
        fd = (J[0] - J[1]) / (2 * h)
        assert np.max(np.abs(val["dpJ"] - fd)) <= 2e-6 * max(1.0, np.max(np.abs(fd))), i
        fdP = (P[0] - P[1]) / (2 * h)
        assert np.max(np.abs(val["dpP"] - fdP)) <= 2e-6 * max(1.0, np.max(np.abs(fdP))), i


def test_a_contact_that_shrinks_to_a_touch_is_located():
    """Along omega the one-stop elastic orbit's contact shrinks until the mass only touches
    the stop: located as grazing of stop 1 (interpolated, the shooting system is singular
    there) with the entry speed and the contact time both 0, once (not again as the exit's
    speed, nor as a fold of the virtual branch beyond)."""
    br = continue_orbits(ONE, "omega", 1.2, 2.5)[0]
    touch = [sp for sp in br.special if sp.kind == "grazing"]
    assert len(touch) == 1 and not [sp for sp in br.special if sp.kind == "unlocated"]
    c = touch[0].coefficients
    assert c["stop"] == 1 and abs(c["impact_velocity"]) < 1e-8 and abs(c["contact_time"]) < 1e-8
    # the last admissible point before it has a short contact, entered slowly
    last = [pt.orbit for pt in br.points if pt.orbit.admissible][-1]
    assert 0 < min(last.times) < 0.05 and 0 < min(last.impact_velocities) < 0.2


#: an impact damper with rubber-coated walls: a free mass (on no spring) in a cavity of
#: clearance +-1, elastic contacts between the masses
DAMPER = Model(mass=[1.0, 0.1], stiffness=[[1.0, 0.0], [0.0, 0.0]],
               damping=[[0.05, 0.0], [0.0, 0.0]], forcing=[0.1, 0.0],
               stops=[Stop(between=(1, 2), gap=1.0, stiffness=200.0, damping=0.5),
                      Stop(between=(1, 2), gap=-1.0, side="lower", stiffness=200.0,
                           damping=0.5)])


@pytest.mark.parametrize("param", ["omega", "stop[1].stiffness", "stop[2].gap",
                                   "stop[1].damping", "forcing[1]"])
def test_elastic_impact_damper_with_a_free_mass(param):
    """Contacts between masses and a mass on no spring: the free phase has the drift of a
    Jordan block, each contact phase none (the contact acts on the free mode).  The
    symmetric orbit is a periodic walk with the elastic determinant identity, and its
    shooting derivatives agree with central differences."""
    orbit = _orbit(DAMPER, 1.0)
    assert orbit.symmetric and orbit.p == 4
    flow = LinearFlow.contact(DAMPER)
    assert flow.free and not LinearFlow.contact(DAMPER, (0,)).free
    # the walk from point 0 meets the four events at the orbit's times and closes
    pr = Problem(DAMPER, orbit.n, orbit.p, omega=1.0, param=param, signature=orbit.itinerary)
    k0 = orbit.signature[0]
    zf = np.empty(4)
    zf[pr.positions[k0]] = DAMPER.constraints[k0].gap
    zf[pr.frames[k0]] = orbit.points[0][:-1]
    z0 = flow.to_mass(zf)
    walk = ct.walk(DAMPER, 1.0, z0, orbit.points[0][-1], active=pr.phases[0], start=k0)
    t = 0.0
    for i in range(orbit.p):
        ev = next(walk)
        assert ev.constraint == orbit.signature[(i + 1) % orbit.p]
        assert ev.t - t == pytest.approx(orbit.times[i], rel=1e-9)
        t = ev.t
    assert np.allclose(ev.after, z0, atol=1e-9)
    # det: the contact damping acts on s = x2 - x1 with c^T M^-1 c = 1 + 10
    expo = -0.05 * 2 * math.pi - sum(0.5 * 11.0 * T for S, T in zip(pr.phases, orbit.times)
                                     if S)
    assert abs(np.prod(orbit.multipliers)) == pytest.approx(math.exp(expo), rel=1e-9)
    lam = 1.0 if param == "omega" else pr.parameter.get(DAMPER)
    G, Gu, Gl = pr.evaluate(orbit.u, lam, dparam=True)
    h = 1e-6 * max(1.0, abs(lam))
    fd = (pr.evaluate(orbit.u, lam + h, jac=False)[0]
          - pr.evaluate(orbit.u, lam - h, jac=False)[0]) / (2 * h)
    assert np.max(np.abs(Gl - fd)) <= 1e-7 * max(1.0, np.max(np.abs(fd)))


def test_simulate_the_rubber_walled_damper():
    """simulate runs elastic contacts between masses (the flow's frame q = T x): from the
    symmetric orbit's entry into stop 1 it records the orbit's entries, on each stop's
    section, period after period (the start itself is not a record)."""
    from symvi import simulate
    orbit = _orbit(DAMPER, 1.0)
    names = orbit.signature_names
    i = names.index("stop1:entry")
    sim = simulate(DAMPER, 1.0, y0=orbit.points[i], n_impacts=20)
    assert sim.stop == "completed" and list(sim.hits[:4]) == [1, 0, 1, 0]
    j = names.index("stop2:entry")
    for k, row in enumerate(sim.section):
        want = np.array(orbit.points[j if k % 2 == 0 else i])
        assert np.allclose(row[:-1], want[:-1], atol=1e-8)
        assert abs((row[-1] - want[-1] + math.pi) % (2 * math.pi) - math.pi) < 1e-8
