"""Bad input to the any-model API: one clear ParameterError naming the argument."""
import math

import pytest

from symvi import hopf_points
from symvi.codegen.jets import jacobian_at, jet_at, parameter_derivatives
from symvi.errors import ParameterError
from symvi.maps.impact import poincare_map
from symvi.orbits import period1_orbits

from tests.zoo import THREE_STOP2_GAP05

Y = [-0.7, 0.0, -1.8, 0.9, 4.2, 3.5]
T = 2 * math.pi / 0.95


@pytest.mark.parametrize("call,name", [
    (lambda: jet_at(THREE_STOP2_GAP05, 0.95, Y[:3], T), "y"),
    (lambda: jet_at(THREE_STOP2_GAP05, 0.95, Y, T, order=4), "order"),
    (lambda: jacobian_at(THREE_STOP2_GAP05, 0.95, Y, -1.0), "te"),
    (lambda: jacobian_at(THREE_STOP2_GAP05, 0.95, Y[:-1] + [math.nan], T), "y"),
    (lambda: poincare_map(THREE_STOP2_GAP05, 0.95, Y[:2]), "y"),
    (lambda: poincare_map("chain", 0.95, Y), "model"),
    (lambda: jet_at(THREE_STOP2_GAP05, -1.0, Y, T), "omega"),
    (lambda: parameter_derivatives(THREE_STOP2_GAP05, 0.95, Y, T, "speed"), "parameter"),
    (lambda: parameter_derivatives(THREE_STOP2_GAP05, 0.95, Y, T, "mu_m"), "parameter"),
    (lambda: period1_orbits(THREE_STOP2_GAP05, "fast"), "omega"),
    (lambda: period1_orbits(THREE_STOP2_GAP05, 0.95, digits=5), "digits"),
    (lambda: hopf_points(THREE_STOP2_GAP05, 1.0, 0.9), "omega_max"),
    (lambda: hopf_points("chain", 0.9, 1.0), "params"),
])
def test_bad_input_names_the_argument(call, name):
    with pytest.raises(ParameterError) as e:
        call()
    assert e.value.name == name and "valid range" in str(e.value)
