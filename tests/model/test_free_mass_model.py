"""A positive semi-definite stiffness (issue 25, free masses): a mass on no spring is a
model; an indefinite or nearly singular stiffness is refused in one line naming
``stiffness`` and the valid range."""
import numpy as np
import pytest

from symvi.errors import ParameterError
from symvi.model import Model, Stop
from symvi.model._checks import null_dim
from symvi.model._file import loads

STOP = Stop(mass=1, gap=0.5, restitution=0.8)
DAMPER_TOML = """[model]
mass = [1.0, 0.2]
stiffness = [[1.0, 0.0], [0.0, 0.0]]
damping = [[0.05, 0.0], [0.0, 0.0]]
forcing = [1.0, 0.0]

[[stop]]
mass = 2
gap = 0.4
restitution = 0.8

[[stop]]
mass = 2
gap = -0.4
side = "lower"
restitution = 0.8
"""


@pytest.mark.parametrize("K, free", [
    ([[0.0]], 1),
    ([[2.0, -2.0], [-2.0, 2.0]], 1),
    ([[1.0, 0.0], [0.0, 0.0]], 1),
    ([[0.0, 0.0], [0.0, 0.0]], 2),
    ([[1.1, -1.1, 0.0], [-1.1, 1.1, 0.0], [0.0, 0.0, 0.0]], 2),
    ([[2.0, -1.0], [-1.0, 2.0]], 0),
])
def test_a_semi_definite_stiffness_is_a_model(K, free):
    n = len(K)
    m = Model(mass=[1.0] * n, stiffness=K, forcing=[1.0] + [0.0] * (n - 1), stop=STOP)
    assert null_dim(m.stiffness) == free


def test_a_model_file_with_a_free_mass_loads():
    m = loads(DAMPER_TOML)
    assert null_dim(m.stiffness) == 1 and len(m.stops) == 2


@pytest.mark.parametrize("K, why", [
    ([[1.0, -1.5], [-1.5, 1.0]], "indefinite"),
    ([[-1.0, 0.0], [0.0, 1.0]], "indefinite"),
    ([[1.0, -1.0], [-1.0, 1.000000000001]], "nearly singular"),
])
def test_an_indefinite_or_nearly_singular_stiffness_is_refused(K, why):
    with pytest.raises(ParameterError) as e:
        Model(mass=[1.0, 1.0], stiffness=K, forcing=[1.0, 0.0], stop=STOP)
    text = str(e.value)
    assert e.value.name == "stiffness" and "\n" not in text
    assert "positive semi-definite" in text and why in text
    with pytest.raises(ParameterError, match="stiffness.*" + why):
        loads(DAMPER_TOML.replace("[[1.0, 0.0], [0.0, 0.0]]", str(K)))


def test_the_stiffness_parameter_may_free_a_mass_but_not_unstabilise_it():
    m = Model(mass=[1.0, 1.0], stiffness=[[2.0, -1.0], [-1.0, 2.0]], forcing=[1.0, 0.0],
              stop=STOP)
    lens = m.parameter("stiffness[2,2]")
    free = lens.apply(m, 0.5)                        # [[2, -1], [-1, 0.5]]: singular
    assert null_dim(free.stiffness) == 1
    np.testing.assert_array_equal(np.asarray(free.stiffness), [[2.0, -1.0], [-1.0, 0.5]])
    with pytest.raises(ParameterError, match="stiffness.*indefinite"):
        lens.apply(m, 0.4)
