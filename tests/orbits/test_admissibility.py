"""check_flight (symvi.orbits.admissibility): a finder that gives up decides nothing."""
from symvi.flow.linear import IMPACT, NO_IMPACT, FirstImpact
from symvi.orbits.admissibility import check_flight


def _finder(status, t, steps=100000):
    return lambda t_max: FirstImpact(status, t, None, steps)


def test_finder_that_gives_up_before_the_end_is_undecided():
    """NO_IMPACT before t_max means the step limit ran out: not admissible, 'undecided'
    (it was read as 'no early contact', so the flight passed unchecked)."""
    ok, why = check_flight(_finder(NO_IMPACT, 0.3), 2.0, -0.5, 0.7, mass=1)
    assert not ok and "undecided" in why


def test_no_contact_up_to_t_max_and_own_impact_are_admissible():
    assert check_flight(_finder(NO_IMPACT, 2.5, 40), 2.0, -0.5, 0.7, mass=1) == (True, "")
    assert check_flight(_finder(IMPACT, 2.0, 40), 2.0, -0.5, 0.7, mass=1) == (True, "")
    ok, why = check_flight(_finder(IMPACT, 1.0, 40), 2.0, -0.5, 0.7, mass=1)
    assert not ok and "penetrate" in why
