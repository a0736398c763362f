"""simulate over several constraints (issue 25): the constraint of each impact is kept,
and a start inside another stop is refused in one line."""
import numpy as np
import pytest

from symvi.errors import ParameterError
from symvi.simulations.simulation import simulate
from tests.flow.test_compiled_constraints import _one_dof, _two_mass


def test_simulate_keeps_the_constraint_of_each_impact():
    model = _one_dof(0.5, -0.4, 0.8, 0.7, 0.05, 1.3)
    sim = simulate(model, 1.1, y0=(-0.3, 0.4), n_impacts=2000, transient=100)
    assert sim.stop == "completed" and sim.n == 2000
    assert sim.hits.shape == (2000,) and set(np.unique(sim.hits)) == {0, 1}
    # the velocity just after an impact points away from the stop hit
    signs = np.where(sim.hits == 0, -1.0, 1.0)
    assert np.all(signs * sim.section[:, 0] > 0)
    assert np.all(sim.impact_velocity > 0)


def test_one_stop_hits_are_all_the_stop():
    from symvi import Model
    sim = simulate(Model.luo_xie(2, 5, 0, 1.5, 0.8), 0.7372, n_impacts=500)
    assert np.array_equal(sim.hits, np.zeros(500, dtype=np.int64))


def test_a_start_inside_another_stop_is_refused():
    model = _two_mass(0.6, -0.5, 0.85, 0.75)
    # y = (v1+, x2, v2, tau): x2 = -0.7 lies past the lower stop on mass 2 (x2 >= -0.5)
    with pytest.raises(ParameterError, match=r"y0.*stop 2: s = -0.7 is at or past its gap -0.5"):
        simulate(model, 1.2, y0=(-0.3, -0.7, 0.0, 0.4), n_impacts=10)
    sim = simulate(model, 1.2, y0=(-0.3, -0.2, 0.0, 0.4), n_impacts=200)
    assert sim.stop == "completed" and set(np.unique(sim.hits)) <= {0, 1}


def test_several_stops_need_a_start():
    model = _one_dof(0.5, -0.4, 0.8, 0.7, 0.05, 1.3)
    with pytest.raises(ParameterError, match=r"y0 = None.*first stop's section \(v1\+, tau\)"):
        simulate(model, 1.1, n_impacts=10)


def test_a_lower_stop_mirrors_an_upper_one():
    """x -> -x: a lower stop at -g with forcing -P runs the mirror image of an upper stop
    at g with P (section points negated but the phase), to rounding."""
    from symvi import Model, Stop
    mats = dict(mass=[[1.0, 0], [0, 1.3]], stiffness=[[2.0, -1.0], [-1.0, 2.5]],
                damping=[[0.03, 0], [0, 0.02]])
    up = Model(**mats, forcing=[0.8, 1.1], stop=Stop(mass=1, gap=0.6, restitution=0.85))
    lo = Model(**mats, forcing=[-0.8, -1.1],
               stops=[Stop(mass=1, gap=-0.6, side="lower", restitution=0.85)])
    a = simulate(up, 1.2, y0=(-0.3, 0.1, 0.2, 0.4), n_impacts=300)
    b = simulate(lo, 1.2, y0=(0.3, -0.1, -0.2, 0.4), n_impacts=300)
    assert a.stop == b.stop == "completed"
    np.testing.assert_allclose(b.section[:, :3], -a.section[:, :3], atol=1e-9)
    np.testing.assert_allclose(b.section[:, 3], a.section[:, 3], atol=1e-9)
    np.testing.assert_allclose(b.t, a.t, rtol=1e-12)
    with pytest.raises(ParameterError, match=r"v1\+ > 0: the mass must leave the stop"):
        simulate(lo, 1.2, y0=(-0.3, -0.1, -0.2, 0.4), n_impacts=10)
