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
