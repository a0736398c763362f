"""simulate with elastic stops (issue 25): records of rigid impacts and contact entries
against solve_ivp with events (entry times and speeds, exit times and speeds), the layout
of the compiled run (a rigid-only model through the same Python walk gives the compiled
run's numbers), and the one-line refusals."""
import math

import numpy as np
import pytest

from symvi import Model, Stop
from symvi.errors import ParameterError
from symvi.simulations.simulation import _simulate_contacts, simulate
from tests.flow.test_compiled_constraints import _two_mass
from tests.flow.test_contact_flow import BETWEEN, CHAIN, CHAIN_MIX, ONE, reference


def _start(model, omega, y0, n):
    """The reference's events from the state of section point y0 of the first stop."""
    con = model.constraints[0]
    k, nn = con.coordinate, model.n
    rest = [j for j in range(nn) if j != k]
    z = np.empty(2 * nn)
    z[k], z[nn + k] = con.gap, y0[0]
    z[rest], z[[nn + j for j in rest]] = y0[1:nn], y0[nn:2 * nn - 1]
    return reference(model, omega, z, y0[-1], n,
                     active=(0,) if con.kind == "elastic" else ())[0]


@pytest.mark.parametrize("model,omega,y0", [
    (ONE, 1.3, (0.8, 0.2)),
    (BETWEEN, 1.1, (0.8, 0.2)),
    (CHAIN, 1.2, (-0.4, 0.1, 0.0, 0.3)),          # lower stop on mass 2: (v2, x1, v1, tau)
    (CHAIN_MIX, 1.2, (0.5, -0.1, 0.0, 0.3)),
])
def test_records_match_solve_ivp(model, omega, y0):
    """Each record (a rigid impact or a contact entry) matches DOP853's event: time,
    approach speed, section point; a contact's exit time and speed too (1e-8)."""
    sim = simulate(model, omega, y0=y0, n_impacts=8)
    assert sim.stop == "completed" and sim.n == 8
    ref = _start(model, omega, y0, 40)
    recs = [r for r in ref if r[0] != "exit"][:8]
    np.testing.assert_array_equal(sim.hits, [r[1] for r in recs])
    np.testing.assert_allclose(sim.t, [r[2] for r in recs], rtol=0, atol=1e-8)
    n = model.n
    for j, (kind, i, te, zb) in enumerate(recs):
        con = model.constraints[i]
        assert abs(sim.impact_velocity[j] - con.approach(zb[n:])) < 1e-8
        assert sim.impact_velocity[j] > 0
        if kind == "entry":
            # the section point at an entry keeps the velocity (no jump): moving into the stop
            k = con.coordinate
            assert abs(sim.section[j, 0] - zb[n + k]) < 1e-8 and con.sign * sim.section[j, 0] > 0
            ex = next(r for r in ref if r[0] == "exit" and r[1] == i and r[2] > te)
            assert abs(sim.exit_t[j] - ex[2]) < 1e-8
            assert abs(sim.exit_velocity[j] - con.approach(ex[3][n:])) < 1e-8
            assert sim.exit_velocity[j] < 0
        else:
            assert math.isnan(sim.exit_t[j]) and math.isnan(sim.exit_velocity[j])
            assert con.sign * sim.section[j, 0] < 0       # leaving the rigid stop
    assert sim.impacts_per_stop() == [int(np.sum(sim.hits == k)) for k in range(sim.stops)]


def test_transient_and_counts():
    full = simulate(BETWEEN, 1.1, y0=(0.8, 0.2), n_impacts=30)
    part = simulate(BETWEEN, 1.1, y0=(0.8, 0.2), n_impacts=20, transient=10)
    assert part.n == 20 and part.transient == 10
    np.testing.assert_array_equal(part.section, full.section[10:])
    np.testing.assert_array_equal(part.exit_t, full.exit_t[10:])
    assert set(np.unique(full.hits)) == {0, 1}
    assert np.all(np.isnan(full.exit_t) == (full.hits == 1))
    np.testing.assert_array_equal(full.on_stop(0), full.section[full.hits == 0])


def test_a_rigid_model_through_the_walk_gives_the_compiled_run():
    """The walk (Python) and the compiled run agree on a rigid two-stop chain to rounding:
    the same records in the same section layout; simulate keeps rigid-only models on the
    compiled path (no exit fields)."""
    model = _two_mass(0.6, -0.5, 0.85, 0.75)
    y0 = (-0.3, -0.2, 0.0, 0.4)
    a = simulate(model, 1.2, y0=y0, n_impacts=200)
    b = _simulate_contacts(model, 1.2, y0, 200, 0)
    assert a.exit_t is None and a.stop == b.stop == "completed"
    np.testing.assert_array_equal(a.hits, b.hits)
    assert set(np.unique(a.hits)) == {0, 1}
    np.testing.assert_allclose(b.section, a.section, rtol=0, atol=1e-11)
    np.testing.assert_allclose(b.t, a.t, rtol=1e-13)
    np.testing.assert_allclose(b.impact_velocity, a.impact_velocity, rtol=0, atol=1e-11)


def test_a_contact_that_never_ends_is_sticking():
    """An upper elastic stop below the mass's rest position: once in contact, the damped
    motion settles inside the stop and never leaves it."""
    model = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.5]], forcing=[0.01],
                  stop=Stop(mass=1, gap=-0.2, stiffness=10.0, damping=1.0))
    sim = simulate(model, 1.0, y0=(0.3, 0.0), n_impacts=5)
    assert sim.stop == "sticking" and 1 <= sim.n < 5
    assert np.isnan(sim.exit_t[-1]) and np.all(np.isfinite(sim.exit_t[:-1]))


@pytest.mark.parametrize("kw,words", [
    (dict(y0=None), r"y0 = None .*first stop's section \(v1\+, tau\).*elastic stop"),
    (dict(y0=(-0.3, 0.2)), r"v1\+ > 0: the section of an elastic stop is the entry into contact"),
    (dict(y0=(0.3,)), r"y0 = \(0.3,\) is invalid"),
])
def test_refusals(kw, words):
    with pytest.raises(ParameterError, match=words) as e:
        simulate(ONE, 1.3, n_impacts=5, **kw)
    assert "\n" not in str(e.value)


def test_refusals_of_the_model():
    # a start inside the other stop (x2 = -0.7 is past the lower stop's gap -0.5)
    with pytest.raises(ParameterError, match=r"stop 2: s = -0.7 is at or past its gap -0.5"):
        simulate(CHAIN_MIX, 1.2, y0=(0.5, -0.7, 0.0, 0.3), n_impacts=5)


def test_the_free_flight_resonance_is_refused():
    from symvi.errors import SingularCaseError
    with pytest.raises(SingularCaseError, match="natural frequency omega_1"):
        simulate(ONE.with_(**{"damping[1,1]": 0.0}), 1.0, y0=(0.8, 0.2), n_impacts=5)
