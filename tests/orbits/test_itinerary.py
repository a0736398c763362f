"""Orbits with an itinerary (issue 25, item 3): n-p orbits whose impacts hit several
constraints, each point on the section of the constraint it lies on; symmetric orbits of
mirror-symmetric stops, their symmetry-breaking pitchfork and the asymmetric branch; grazing
with a constraint the orbit does not touch yet."""
import math

import numpy as np
import pytest

from symvi import simulate
from symvi.continuation import continue_orbits
from symvi.flow import compiled as cf
from symvi.model import Model, Stop
from symvi.orbits.periodic import Problem, from_simulation, orbit_of, periodic_orbit

#: 1-DOF between two rigid stops at +-0.5 (mirror-symmetric)
SYM = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
            stops=[Stop(mass=1, gap=0.5, restitution=0.9),
                   Stop(mass=1, gap=-0.5, side="lower", restitution=0.9)])
#: two masses, an upper stop on mass 1 and a lower one on mass 2: two section frames
TWO_FRAMES = Model(mass=[1.0, 1.0], stiffness=[[2.0, -1.0], [-1.0, 2.0]],
                   damping=[[0.1, 0.0], [0.0, 0.1]], forcing=[1.0, 0.0],
                   stops=[Stop(mass=1, gap=0.4, restitution=0.8),
                          Stop(mass=2, gap=-0.4, side="lower", restitution=0.7)])
#: one stop close, the other far: a 1-1 orbit on stop 1 that grazes stop 2 as it nears
FAR = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
            stops=[Stop(mass=1, gap=0.5, restitution=0.8),
                   Stop(mass=1, gap=-3.0, side="lower", restitution=0.8)])


def _settled(model, omega, y0):
    return from_simulation(simulate(model, omega, y0=y0, n_impacts=300, transient=3000))


@pytest.fixture(scope="module")
def sym_orbit():
    return _settled(SYM, 1.0, (-0.1, 0.0))


@pytest.fixture(scope="module")
def frames_orbit():
    return _settled(TWO_FRAMES, 1.5, (-0.2, 0.0, 0.0, 0.0))


def _map_around(model, orbit):
    """The orbit's points mapped once each by the compiled map P from their own stop's
    section (an independent check of P(y_i) = y_{i+1}): the largest mismatch."""
    c = cf.constants(model, orbit.omega)
    worst = 0.0
    for i, y in enumerate(orbit.points):
        st, t, nxt, _, _, _, hit = cf.step(c, np.array(y), orbit.signature[i])
        j = (i + 1) % orbit.p
        assert cf.STATUS_NAMES[st] == "impact" and hit == orbit.signature[j]
        d = np.array(nxt) - np.array(orbit.points[j])
        d[-1] = (d[-1] + math.pi) % (2 * math.pi) - math.pi
        worst = max(worst, float(np.max(np.abs(d))))
    return worst


def test_symmetric_orbit_is_a_fixed_point_with_its_symmetry(sym_orbit):
    o = sym_orbit
    assert (o.n, o.p) == (1, 2) and sorted(o.signature) == [0, 1]
    assert o.admissible and o.stable and o.residual < 1e-12
    assert _map_around(SYM, o) < 1e-10
    # y_1 = S y_0: the velocity negated, the phase advanced by pi
    (v0, t0), (v1, t1) = o.points
    assert abs(v0 + v1) < 1e-10 and abs((t1 - t0) % (2 * math.pi) - math.pi) < 1e-10
    assert o.symmetric is True and len(o.half_multipliers) == 2
    # the half map squared is the monodromy
    key = lambda z: (z.real, z.imag)           # noqa: E731
    sq = sorted((complex(z) ** 2 for z in o.half_multipliers), key=key)
    assert np.allclose(sorted(o.multipliers, key=key), sq, atol=1e-12)
    d = o.as_dict()
    assert d["signature"] == [f"stop{k + 1}" for k in o.signature] and d["symmetric"] is True


def test_two_section_frames(frames_orbit):
    """Impacts on stops of two masses: each point named in its own stop's frame."""
    o = frames_orbit
    assert sorted(o.signature) == [0, 1] and o.admissible
    assert o.symmetric is None                     # the stops are not mirror images
    names = dict(zip(o.signature, o.point_names))
    assert names[0] == ("v1+", "x2", "v2", "tau") and names[1] == ("v2+", "x1", "v1", "tau")
    assert _map_around(TWO_FRAMES, o) < 1e-10
    assert "point_names" in o.as_dict()


@pytest.mark.parametrize("which", ["sym", "frames"])
def test_determinant_identity(which, sym_orbit, frames_orbit):
    """det DP = prod r_i^2 exp(-tr(M^-1 C) n T) over the p impacts (rigid contacts)."""
    model, o = (SYM, sym_orbit) if which == "sym" else (TWO_FRAMES, frames_orbit)
    r = [model.constraints[k].restitution for k in o.signature]
    tr = np.trace(np.linalg.solve(np.array(model.mass), np.array(model.damping)))
    want = np.prod(np.square(r)) * math.exp(-tr * o.n * 2 * math.pi / o.omega)
    got = np.prod(np.array(o.multipliers)).real
    assert abs(got - want) <= 1e-12 * want


@pytest.mark.parametrize("param", ["omega", "stop[2].gap", "stop[1].restitution",
                                   "stop[2].restitution", "gap", "stiffness[1,2]"])
def test_compiled_equals_reference_and_finite_differences(param, frames_orbit):
    """G, G_u, dG/dparam of the several-constraint system: the compiled kernel against the
    numpy reference (to rounding) and G_u against central differences."""
    o = frames_orbit
    omega = None if param == "omega" else o.omega
    pr = Problem(TWO_FRAMES, o.n, o.p, omega=omega, param=param, signature=o.signature)
    lam = o.omega if param == "omega" else float(pr.parameter.get(TWO_FRAMES, o.omega))
    rng = np.random.default_rng(3)
    u = o.u + 1e-3 * rng.standard_normal(o.u.size)
    G, Gu, Gl = pr.evaluate(u, lam, dparam=True)
    pr.compiled = False
    pr._last = None
    G0, Gu0, Gl0 = pr.evaluate(u, lam, dparam=True)
    scale = 1 + np.max(np.abs(Gu0))
    assert np.max(np.abs(G - G0)) < 1e-12 * scale
    assert np.max(np.abs(Gu - Gu0)) < 1e-12 * scale
    assert np.max(np.abs(Gl - Gl0)) < 1e-12 * (1 + np.max(np.abs(Gl0)))
    pr.compiled = True
    h = 1e-6
    fd = np.empty_like(Gu)
    for j in range(u.size):
        e = np.zeros(u.size)
        e[j] = h
        fd[:, j] = (pr.evaluate(u + e, lam, jac=False)[0] - pr.evaluate(u - e, lam, jac=False)[0]) / (2 * h)
    assert np.max(np.abs(fd - Gu)) < 1e-6 * scale
    fl = (pr.evaluate(u, lam + h, jac=False)[0] - pr.evaluate(u, lam - h, jac=False)[0]) / (2 * h)
    assert np.max(np.abs(fl - Gl)) < 1e-6 * (1 + np.max(np.abs(Gl)))


def test_a_wrong_signature_is_refused_by_the_guess(sym_orbit):
    """A guess whose flight meets the other stop than the signature says: ConvergenceError
    naming both, never an orbit of another itinerary."""
    from symvi.orbits.periodic import ConvergenceError
    with pytest.raises(ConvergenceError, match="stop"):
        periodic_orbit(SYM, n=1, p=2, guess=sym_orbit.points[0], omega=1.0,
                       signature=(sym_orbit.signature[0],) * 2)


@pytest.fixture(scope="module")
def sym_branches():
    return continue_orbits(SYM, "omega", 1.0, 2.0, switch=True)


def test_symmetry_breaking_located_and_switched(sym_branches):
    main = sym_branches[0]
    assert all(pt.orbit.symmetric for pt in main.points)
    sb = [sp for sp in main.special if sp.kind == "symmetry-breaking"]
    assert len(sb) == 2
    for sp in sb:
        assert abs(sp.coefficients["half_multiplier"] + 1) < 1e-9
        # the symmetric orbit's monodromy has +1 there: a branch point, not a fold
        assert min(abs(z - 1) for z in sp.orbit.multipliers) < 1e-8
    # stable below the first point, unstable between them, stable again beyond
    stable = {round(pt.value, 3): pt.orbit.stable for pt in main.points}
    assert stable[1.0] and not any(v for k, v in stable.items() if sb[0].value + 0.01 < k
                                   < sb[1].value - 0.01)
    asym = [b for b in sym_branches[1:] if b.points[0].orbit.p == 2]
    assert asym, "no asymmetric branch switched to"
    for b in asym:
        inner = b.points[len(b) // 2].orbit
        assert inner.symmetric is False and inner.admissible
        (v0, _), (v1, _) = inner.points
        assert abs(v0 + v1) > 1e-3                # not mirror images of each other


def test_switched_asymmetric_orbit_against_simulation(sym_branches):
    """An asymmetric orbit of the switched branch is a stable fixed point of P^2 (simulated
    from a perturbed start it returns), and its mirror image is one too."""
    b = max(sym_branches[1:], key=len)
    pt = next(p for p in b.points[len(b) // 3:] if p.orbit.stable and p.orbit.admissible)
    o = pt.orbit
    assert _map_around(SYM, o) < 1e-10
    y0 = np.array(o.points[0]) + 1e-4
    sim = simulate(SYM, o.omega, y0=tuple(y0), n_impacts=4, transient=600)
    ends = sim.section[sim.hits == o.signature[0]]
    assert np.max(np.abs(ends[-1] - np.array(o.points[0]))) < 1e-7
    # the mirror image: S y with the other stop's section, tau + pi
    mirror = (-o.points[1][0], (o.points[1][1] + math.pi) % (2 * math.pi))
    m2 = periodic_orbit(SYM, n=1, p=2, guess=mirror, omega=o.omega,
                        signature=(o.signature[0], o.signature[1]))
    assert m2.residual < 1e-12 and abs(m2.points[0][0] - mirror[0]) < 1e-8


def test_grazing_with_an_untouched_constraint_is_located_and_simulated():
    """A 1-1 orbit on stop 1 while stop 2 moves in: its flight grazes stop 2 (named, the
    birth of a new impact); simulated on either side, stop 2 is never hit / is hit."""
    brs = continue_orbits(FAR, "stop[2].gap", -3.0, -0.5, omega=1.0)
    br = brs[0]
    assert br.points[0].orbit.signature == (0,)
    gz = [sp for sp in br.special if sp.kind == "grazing"]
    assert len(gz) == 1 and gz[0].coefficients["stop"] == 2
    assert "a new impact is born" in gz[0].detail
    g = gz[0].value
    o = gz[0].orbit
    # at the grazing point the flight's lowest point is the stop
    from symvi.flow.linear import LinearFlow
    model = o.model
    flow = LinearFlow.of(model)
    F = flow.forcing(o.omega)
    mo = flow.motion(F, np.array([0.5, o.points[0][0]]), o.points[0][1])
    from scipy.optimize import minimize_scalar
    r = minimize_scalar(lambda t: mo.state(t)[0], bounds=(0, o.times[0]), method="bounded",
                        options={"xatol": 1e-12})
    assert abs(r.fun - g) < 1e-9
    for dg, hits_two in ((-0.01, False), (0.01, True)):
        m = FAR.with_(**{"stop[2].gap": g + dg})
        sim = simulate(m, 1.0, y0=o.points[0], n_impacts=200, transient=200)
        assert (sim.impacts_per_stop()[1] > 0) == hits_two
    beyond = orbit_of(Problem(FAR.with_(**{"stop[2].gap": g + 0.01}), 1, 1, omega=1.0),
                      o.u, None)
    assert not beyond.admissible and "stop 2" in beyond.reason


def test_a_one_stop_model_with_the_same_matrices_first_does_not_leak_its_table():
    """Flows share their modal data across models whose matrices and first stop agree;
    the constraint table of the finder is the model's own (a one-stop model met first
    once left its one-row table to the two-stop model)."""
    from symvi.orbits import admissible_orbits
    one = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                stop=Stop(mass=1, gap=0.5, restitution=0.9))
    y = admissible_orbits(one, 1.0)[0].y
    periodic_orbit(one, n=1, p=1, guess=y, omega=1.0)          # the finder's base, one row
    o = _settled(SYM, 1.0, (-0.1, 0.0))
    assert o.admissible and sorted(o.signature) == [0, 1]
    beyond = orbit_of(Problem(FAR.with_(**{"stop[2].gap": -0.9}), 1, 1, omega=1.0),
                      _settled(FAR, 1.0, (-0.1, 0.0)).u, None)
    assert not beyond.admissible and "stop 2" in beyond.reason


@pytest.mark.parametrize("which", ["sym", "frames"])
def test_lyapunov_exponents_over_several_stops(which, sym_orbit, frames_orbit):
    """The QR method with each flight's DP from one stop's section to the next: on a
    periodic orbit the exponents are log|mu_i| / p, their sum log|det M| / p exactly."""
    from symvi.simulations.diagnostics import lyapunov
    model, o = (SYM, sym_orbit) if which == "sym" else (TWO_FRAMES, frames_orbit)
    sim = simulate(model, o.omega, y0=o.points[0], n_impacts=40 * o.p + 1, transient=0)
    assert tuple(sim.hits[:o.p]) == o.signature[1:] + o.signature[:1]   # P(y0) first
    L = lyapunov(sim)
    mu = np.array(o.multipliers)
    assert abs(sum(L.exponents) - math.log(abs(np.prod(mu))) / o.p) < 1e-10
    want = np.sort(np.log(np.abs(mu)) / o.p)[::-1]
    assert np.max(np.abs(np.asarray(L.exponents) - want)) < 0.02


#: the worked example's impact damper: a free mass in a cavity of the forced primary mass
DAMPER = Model(mass=[1.0, 0.1], stiffness=[[1.0, 0.0], [0.0, 0.0]],
               damping=[[0.05, 0.0], [0.0, 0.0]], forcing=[0.1, 0.0],
               stops=[Stop(between=(1, 2), gap=1.0, restitution=0.6),
                      Stop(between=(1, 2), gap=-1.0, side="lower", restitution=0.6)])


def test_impacts_between_masses_against_solve_ivp():
    """Stops between two grounded masses (s = x2 - x1): simulate's impacts, in the flow's
    frame (v2-v1+, x1, v1, tau), are those of DOP853 with events in mass coordinates and
    the momentum-conserving law v+ = v - (1 + r) q c.v / c.q, q = M^-1 c."""
    from scipy.integrate import solve_ivp
    g, w, r = 0.3, 1.5, 0.7
    m = Model(mass=[1.0, 0.5], stiffness=[[1.0, 0.0], [0.0, 2.0]],
              damping=[[0.1, 0.0], [0.0, 0.1]], forcing=[1.0, 0.0],
              stops=[Stop(between=(1, 2), gap=g, restitution=r),
                     Stop(between=(1, 2), gap=-g, side="lower", restitution=r)])
    sim = simulate(m, w, y0=(-0.2, 0.0, 0.0, 0.0), n_impacts=12, transient=0)
    M, K, C, P = (np.asarray(a) for a in (m.mass, m.stiffness, m.damping, m.forcing))
    Minv = np.linalg.inv(M)
    c = np.array([-1.0, 1.0])
    q = Minv @ c

    def rhs(t, z):
        return np.concatenate([z[2:], Minv @ (P * math.sin(w * t) - K @ z[:2] - C @ z[2:])])

    def up(t, z):
        return c @ z[:2] - g

    def lo(t, z):
        return -(c @ z[:2] + g)
    for e in (up, lo):
        e.terminal, e.direction = True, 1
    z, t = np.array([0.0, g, 0.0, -0.2]), 0.0
    for k in range(12):
        sol = solve_ivp(rhs, (t, t + 100), z, method="DOP853", rtol=1e-12, atol=1e-12,
                        events=(up, lo))
        hit = 0 if sol.t_events[0].size else 1
        t, z = sol.t[-1], sol.y[:, -1].copy()
        p_before = np.sum(M @ z[2:])                 # the pair's momentum
        z[2:] = z[2:] - (1 + r) * q * (c @ z[2:]) / (c @ q)
        assert abs(np.sum(M @ z[2:]) - p_before) < 1e-14
        assert sim.hits[k] == hit and abs(sim.t[k] - t) < 1e-8
        y = np.array([c @ z[2:], z[0], z[2], (w * t) % (2 * math.pi)])
        assert np.max(np.abs(sim.section[k] - y)) < 1e-7


def test_impact_damper_orbit_with_a_free_mass():
    """The impact damper's symmetric 1-2 orbit (one impact on each wall of the cavity per
    period): a fixed point of the compiled map, the determinant identity, and its jets
    (the free mode's Jordan block in Phi) equal to the shooting monodromy."""
    o = _settled(DAMPER, 1.0, (-0.5, 0.0, 0.0, 0.0))
    assert (o.n, o.p) == (1, 2) and o.symmetric and o.admissible
    assert o.point_names[0] == ("v2-v1+", "x1", "v1", "tau")
    assert _map_around(DAMPER, o) < 1e-10
    tr = np.trace(np.linalg.solve(DAMPER.mass, DAMPER.damping))
    want = 0.6 ** 4 * math.exp(-tr * 2 * math.pi / o.omega)
    assert abs(np.prod(np.array(o.multipliers)).real - want) < 1e-12 * want
    A = o.jet(1)[0]
    pr = Problem(DAMPER, o.n, o.p, omega=o.omega, signature=o.signature)
    _, Gu, _ = pr.evaluate(o.u, None)
    assert np.max(np.abs(A - pr.monodromy(o.u, Gu)[1])) < 1e-12


@pytest.mark.parametrize("param", ["stop[2].gap", "stop[1].restitution", "forcing[1]", "omega",
                                   "mass[2]", "mass[1]", "stiffness[1,1]", "damping[1,1]"])
def test_impact_damper_parameter_derivatives(param):
    """With a free mode, derivatives in a gap, a restitution or a forcing amplitude need no
    Frechet derivative of e^{At} (A does not move); one in a mass, stiffness or damping
    entry takes it at the Jordan block (the block-triangular exponential): dG/dparam
    against central differences."""
    o = _settled(DAMPER, 1.0, (-0.5, 0.0, 0.0, 0.0))
    omega = None if param == "omega" else o.omega
    pr = Problem(DAMPER, o.n, o.p, omega=omega, param=param, signature=o.signature)
    lam = o.omega if param == "omega" else float(pr.parameter.get(DAMPER, o.omega))
    Gl = pr.evaluate(o.u, lam, dparam=True)[2]
    h = 1e-6
    fd = (pr.evaluate(o.u, lam + h, jac=False)[0] - pr.evaluate(o.u, lam - h, jac=False)[0]) / (2 * h)
    assert np.max(np.abs(fd - Gl)) < 1e-6 * (1 + np.max(np.abs(Gl)))


#: two grounded masses impacting each other (stops between them, no free mode)
BETWEEN = Model(mass=[1.0, 0.5], stiffness=[[1.0, -0.2], [-0.2, 2.0]],
                damping=[[0.1, 0.0], [0.0, 0.1]], forcing=[1.0, 0.3],
                stops=[Stop(between=(1, 2), gap=0.3, restitution=0.7),
                       Stop(between=(1, 2), gap=-0.3, side="lower", restitution=0.8)])


@pytest.mark.parametrize("param", ["mass[2]", "stiffness[1,2]", "damping[2,2]", "stop[2].gap",
                                   "stop[1].restitution", "forcing[2]", "omega"])
def test_derivatives_in_the_frame_of_stops_between_masses(param):
    """dG/dparam of a model whose flow works in q = T x (the tangents carried into the
    frame: T^-T dM T^-1, T Q T^-1) against central differences, compiled and reference."""
    omega = 1.5
    sig = (0, 1)
    pr = Problem(BETWEEN, 1, 2, omega=None if param == "omega" else omega, param=param,
                 signature=sig)
    lam = omega if param == "omega" else float(pr.parameter.get(BETWEEN, omega))
    u = np.array([-0.6, 0.1, 0.2, 1.0, 0.5, -0.1, 0.3, 4.0, 2.0, 2.2])
    Gl = pr.evaluate(u, lam, dparam=True)[2]
    h = 1e-6
    fd = (pr.evaluate(u, lam + h, jac=False)[0] - pr.evaluate(u, lam - h, jac=False)[0]) / (2 * h)
    assert np.max(np.abs(fd - Gl)) < 1e-6 * (1 + np.max(np.abs(Gl)))
    pr.compiled = False
    pr._last = None
    assert np.max(np.abs(pr.evaluate(u, lam, dparam=True)[2] - Gl)) < 1e-11 * (
        1 + np.max(np.abs(Gl)))


def test_mass_derivative_of_a_one_stop_model_with_a_non_diagonal_mass_matrix():
    """The rigid impulse along M^-1 c moves with the masses: dG/dmass[1,2] includes dR/dM
    (it was missing before this session for a non-diagonal M), against central
    differences."""
    m = Model(mass=[[1.0, 0.2], [0.2, 0.8]], stiffness=[[2.0, -1.0], [-1.0, 1.5]],
              damping=[[0.05, 0.0], [0.0, 0.05]], forcing=[1.0, 0.0],
              stop=Stop(mass=1, gap=0.4, restitution=0.8))
    pr = Problem(m, 1, 1, omega=1.3, param="mass[1,2]")
    u = np.array([-0.7, 0.2, 0.1, 1.0, 4.5])
    Gl = pr.evaluate(u, 0.2, dparam=True)[2]
    h = 1e-6
    fd = (pr.evaluate(u, 0.2 + h, jac=False)[0] - pr.evaluate(u, 0.2 - h, jac=False)[0]) / (2 * h)
    assert np.max(np.abs(fd - Gl)) < 1e-6 * (1 + np.max(np.abs(Gl)))
