"""continue_orbits where the start has no admissible period-1 orbit (issue 25, item 5): it
searches [start, stop] for the first value with one, starts there and says so."""
import warnings

import pytest

from symvi import Model
from symvi.continuation import continue_orbits
from symvi.continuation.start import SEARCH_SAMPLES, first_admissible
from symvi.errors import ParameterError
from symvi.orbits.period1 import admissible_orbits

EX1 = Model.luo_xie(2, 5, 0, 1.5, 0.8)


def _admissible(model, w):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return admissible_orbits(model, w, multipliers=False)


def test_omega_branch_starts_where_an_orbit_first_exists():
    """Example 1 has no admissible period-1 orbit on [0.46, 0.58]: from 0.5 the branch
    starts at the edge of the first window, where one exists and just before which none
    does, and its note says so."""
    assert not _admissible(EX1, 0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        branches = continue_orbits(EX1, "omega", 0.5, 0.8)
    assert branches
    first = min(b.values.min() for b in branches)
    assert 0.5 < first < 0.6
    assert _admissible(EX1, first) and not _admissible(EX1, first - 1e-9)
    note = branches[0].notes[-1]
    assert note.startswith("no admissible period-1 orbit at omega = 0.5")
    assert f"{SEARCH_SAMPLES} values towards 0.8" in note


def test_gap_search_and_nothing_found():
    """In the gap at omega = 0.5: the first admissible gap above 1.5 is found (admissible
    there, not just below); below 1.5 down to 0.2 there is none, and the command's error
    says where it looked."""
    v, ys = first_admissible(EX1, EX1.parameter("gap"), 1.5, 3.0, 0.5)
    assert 1.5 < v < 3.0 and ys
    assert _admissible(EX1.with_(gap=v), 0.5)
    assert not _admissible(EX1.with_(gap=v - 1e-9 * v), 0.5)
    assert first_admissible(EX1, EX1.parameter("gap"), 1.5, 0.2, 0.5) is None
    with pytest.raises(ParameterError, match=r"start = 0.46 .*nor at 200 values of "
                                             r"\[0.46, 0.58\]"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            continue_orbits(EX1, "omega", 0.46, 0.58)
