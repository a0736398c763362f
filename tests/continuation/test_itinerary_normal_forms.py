"""Exact jets and normal forms of orbits with several constraints (issue 25, item 4), set
against the compiled map (finite differences) and against simulation: the predicted
invariant circle of a supercritical Neimark-Sacker point and the stable doubled orbit of a
supercritical flip of a 3-mass chain with stops on masses 1 and 3."""
import math

import numpy as np
import pytest

from symvi import simulate
from symvi.continuation import continue_orbits
from symvi.flow import compiled as cf
from symvi.model import Model, Stop
from symvi.normal_forms.normal_form import normal_form
from symvi.orbits.periodic import Problem, detect_period
from tests.orbits.test_itinerary import SYM, TWO_FRAMES, _settled


def chain(g1, g3):
    """The worked example's chain (examples/contacts/chain3_two_stops.toml) at gaps g1, g3."""
    return Model(mass=[1.0, 1.5, 0.8],
                 stiffness=[[2.0, -1.0, 0.0], [-1.0, 2.7, -1.7], [0.0, -1.7, 2.7]],
                 damping=(0.03 * np.eye(3)).tolist(), forcing=[1.0, 0.0, 0.0],
                 stops=[Stop(mass=1, gap=g1, restitution=0.8),
                        Stop(mass=3, gap=g3, side="lower", restitution=0.7)])


def _map(model, orbit):
    """P^p of the orbit by the compiled map (each impact on its signature's stop)."""
    c = cf.constants(model, orbit.omega)

    def P(y):
        y = np.array(y, dtype=float)
        for i in range(orbit.p):
            st, t, y, *_, hit = cf.step(c, y, orbit.signature[i])
            assert hit == orbit.signature[(i + 1) % orbit.p]
        return y
    return P


@pytest.mark.parametrize("which", ["sym", "frames"])
def test_jets_against_the_compiled_map(which):
    model, w, y0 = ((SYM, 1.0, (-0.1, 0.0)) if which == "sym" else
                    (TWO_FRAMES, 1.5, (-0.2, 0.0, 0.0, 0.0)))
    o = _settled(model, w, y0)
    A, d2, d3 = o.jet(3)
    pr = Problem(model, o.n, o.p, omega=o.omega, signature=o.signature)
    _, Gu, _ = pr.evaluate(o.u, None)
    assert np.max(np.abs(A - pr.monodromy(o.u, Gu)[1])) < 1e-12 * (1 + np.max(np.abs(A)))
    P, y = _map(model, o), np.array(o.points[0])
    d, h = len(y), 1e-4
    E = np.eye(d) * h
    for j in range(d):
        for k in range(d):
            fd = (P(y + E[j] + E[k]) - P(y + E[j] - E[k]) - P(y - E[j] + E[k])
                  + P(y - E[j] - E[k])) / (4 * h * h)
            assert np.max(np.abs(fd - d2[:, j, k])) < 1e-5 * (1 + np.max(np.abs(d2)))
    # the third derivative along one direction: the jet's cubic term
    v = np.linspace(1.0, -0.5, d)
    v /= np.linalg.norm(v)
    h = 2e-3
    fd3 = (P(y + 2 * h * v) - 2 * P(y + h * v) + 2 * P(y - h * v) - P(y - 2 * h * v)) / (2 * h ** 3)
    want = np.einsum("ijkl,j,k,l->i", d3, v, v, v)
    assert np.max(np.abs(fd3 - want)) < 1e-3 * (1 + np.max(np.abs(want)))


@pytest.fixture(scope="module")
def ns_chain():
    m = chain(0.6, -0.3)
    brs = continue_orbits(m, "omega", 1.0, 2.0, start_omega=1.5)
    ns = [s for b in brs for s in b.special if s.kind == "ns"]
    return m, ns


def test_ns_of_a_two_stop_orbit_predicts_the_simulated_circle(ns_chain):
    """l1 < 0 at the NS point of a 1-2 orbit hitting stops on masses 1 and 3; just past it
    (on the side where the pair leaves the unit circle) the simulated attractor is a
    closed curve whose size is the normal form's 2 |w| max ||Re(e^{i phi} q)||, |w|^2 =
    -(|lambda| - 1) / l1, and grows as the square root of the distance."""
    m, ns = ns_chain
    assert len(ns) == 2 and all(s.coefficients["l1"] < 0 for s in ns)
    sp = ns[0]
    o = sp.orbit
    assert sorted(o.signature) == [0, 1]
    A, d2, d3 = o.jet(3)
    nf = normal_form(A, d2, d3)
    assert abs(float(nf.l1) - sp.coefficients["l1"]) < 1e-12
    q = np.asarray(nf.q, dtype=complex)
    phis = np.linspace(0, 2 * math.pi, 721)
    shape = max(np.linalg.norm((np.exp(1j * p) * q).real[:-1]) for p in phis)
    dmod = sp.coefficients["dmod_dparam"]
    radii = []
    for delta in (1e-3, 4e-3):
        w = sp.value + math.copysign(delta, dmod)
        sim = simulate(m, w, y0=tuple(np.array(o.points[0]) + 1e-3), n_impacts=4000,
                       transient=40000)
        assert sim.stop == "completed"
        pts = sim.on_stop(o.signature[0])[:, :-1]
        r = float(np.max(np.linalg.norm(pts - pts.mean(axis=0), axis=1)))
        want = 2 * math.sqrt(abs(dmod) * delta / -sp.coefficients["l1"]) * shape
        assert abs(r / want - 1) < 0.25, (delta, r, want)
        radii.append(r)
    assert 1.7 < radii[1] / radii[0] < 2.3


def test_supercritical_flip_of_a_two_stop_orbit_against_simulation():
    """c > 0 at a flip of the chain's 1-1 orbit (stop 1, stop 2 untouched): just past it
    a run settles on a stable 2-2 orbit next to the unstable 1-1 orbit, at a distance
    growing as the square root of the distance to the flip."""
    m = chain(0.4, -0.6)
    brs = continue_orbits(m, "omega", 1.0, 2.0, start_omega=1.5)
    flips = [s for b in brs[:2] for s in b.special if s.kind == "flip"]
    assert flips and all(s.coefficients["c"] > 0 for s in flips)
    sp = max(flips, key=lambda s: s.value)
    o = sp.orbit
    # the side where the 1-1 orbit is unstable: the branch's points beyond the flip
    br = next(b for b in brs if sp in b.special)
    side = next(pt.value - sp.value for pt in br.points if not pt.orbit.stable
                and pt.orbit.admissible and abs(pt.value - sp.value) < 0.05)
    dist = []
    for delta in (4e-4, 1.6e-3):
        w = sp.value + math.copysign(delta, side)
        sim = simulate(m, w, y0=tuple(np.array(o.points[0]) + 1e-4), n_impacts=400,
                       transient=60000)
        assert detect_period(sim) == (2, 2)
        a, b = sim.section[-1], sim.section[-2]
        dist.append(float(np.linalg.norm(a[:-1] - b[:-1])))
    assert 1.7 < dist[1] / dist[0] < 2.3


def _jet_at(orbit, y, order):
    """The composed jet of P^p at the point y of the orbit's first section (not a fixed
    point): the flights from y by the map (:func:`symvi.orbits.periodic.initial_guess`),
    then :meth:`PeriodicOrbit.jet` along them."""
    import dataclasses

    from symvi.orbits.periodic import initial_guess
    pr = Problem(orbit.model, orbit.n, orbit.p, omega=orbit.omega, signature=orbit.itinerary)
    u = initial_guess(pr, np.array(y, dtype=float))
    T = pr.split(u)[1]
    return dataclasses.replace(orbit, u=u, times=tuple(float(t) for t in T)).jet(order)


@pytest.mark.parametrize("which", ["sym", "frames", "elastic"])
def test_orders_4_and_5_across_sections(which):
    """The start variants of orders 4 and 5 (l2 of orbits with several constraints, and
    through contact phases): d4 and a d5 slice against central differences of the
    composed order-3 and order-4 jets at points moved along each coordinate."""
    from tests.orbits.test_elastic_orbits import ONE, _orbit
    orbit = {"sym": lambda: _settled(SYM, 1.0, (-0.1, 0.0)),
             "frames": lambda: _settled(TWO_FRAMES, 1.5, (-0.2, 0.0, 0.0, 0.0)),
             "elastic": lambda: _orbit(ONE, 1.2)}[which]()
    J5 = orbit.jet(5)
    assert len(J5) == 5 and all(t is not None for t in J5)
    J3 = orbit.jet(3)
    for a, b in zip(J5[:3], J3):
        assert np.allclose(a, b, rtol=1e-12, atol=1e-12)
    y = np.array(orbit.u[:2 * orbit.model.n])
    d = len(y)
    h = 1e-5
    for e in range(d):
        step = np.eye(d)[e] * h
        fd4 = (_jet_at(orbit, y + step, 3)[2] - _jet_at(orbit, y - step, 3)[2]) / (2 * h)
        scale = max(1.0, float(np.max(np.abs(J5[3]))))
        assert np.max(np.abs(fd4 - J5[3][..., e])) <= 1e-5 * scale, e
    fd5 = (_jet_at(orbit, y + np.eye(d)[0] * h, 4)[3]
           - _jet_at(orbit, y - np.eye(d)[0] * h, 4)[3]) / (2 * h)
    scale = max(1.0, float(np.max(np.abs(J5[4]))))
    assert np.max(np.abs(fd5 - J5[4][..., 0])) <= 1e-5 * scale
