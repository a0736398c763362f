"""The paper's Params and Model.luo_xie give the same answers (issue 24: a new user's
curve_from_interval(symvi.Params(...)) said 'no admissible ns point' while the Model
found it: period1_branches swallowed the type error as 'no orbit at this end')."""
import warnings

import pytest

import symvi
from symvi.continuation import period1_branches
from symvi.curves.start import curve_from_interval
from symvi.errors import ParameterError, SymviError


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield


def test_params_and_model_find_the_same_ns_start_and_curve():
    got = []
    for s in (symvi.Params(2, 5, 0, 1.5, 0.8), symvi.Model.luo_xie(2, 5, 0, 1.5, 0.8)):
        curve, sp = curve_from_interval(s, 0.70, 0.76, ("omega", "b"), max_points=10)
        got.append((sp.value, len(curve.points), curve.points[-1].params["b"]))
    assert abs(got[0][0] - 0.7368769220905931) < 1e-9
    assert got[0] == got[1]


def test_bad_interval_end_is_an_error_not_no_branch():
    """An end outside the valid omega range is bad input, not 'no orbit there'."""
    with pytest.raises(ParameterError):
        period1_branches(symvi.Params(2, 5, 0, 1.5, 0.8), 0.70, 1e9)
    with pytest.raises(SymviError):
        period1_branches("not a model", 0.70, 0.76)
