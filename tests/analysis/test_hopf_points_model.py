"""hopf_points on any model: the damped 3-mass chain, the paper's model through
Model against the paper chain, and the 50-digit chains on the 3-mass chain."""
import warnings

import numpy as np
import pytest

from symvi import Params, hopf_points
from symvi.errors import NearSingularWarning
from symvi.model import Model
from symvi.studies.mpcheck import check_point

from tests.zoo import THREE_STOP2_GAP05


@pytest.fixture(scope="module")
def three():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        return hopf_points(THREE_STOP2_GAP05, 0.99, 1.06)


def test_two_ns_points_of_the_damped_chain(three):
    assert [p.branch for p in three.points] == ["+", "+"]
    for p in three.points:
        assert abs(abs(p.multiplier) - 1) < 1e-12 and p.h1 and p.h2
        # (A1)-(A3) on F11 against |lambda1| differentiated along the branch
        assert p.dmod_domega == pytest.approx(p.dmod_domega_branch, rel=1e-7)
        assert p.precision.digits >= 8 and p.trusted("l1")
        assert p.orbit.names == ("v2+", "x1", "x3", "v1", "v3", "tau")
    # the pair leaves the unit circle at the first point and comes back at the second
    assert three.points[0].dmod_domega > 0 > three.points[1].dmod_domega
    d = three.as_dict()
    assert d["model"]["stop"]["mass"] == 2 and len(d["points"]) == 2


def test_paper_model_through_Model_gives_the_paper_chains_points():
    """Params (the preset, with the paper's names and eq. (60)) and Model.luo_xie give the
    same points; the chain itself is held to the modal oracle and to 50-digit chain B
    elsewhere (tests/codegen/test_jets_model.py, tests/studies/test_mpcheck.py)."""
    p = Params(2, 5, 0, 1.5, 0.8)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        old = hopf_points(p, 0.70, 0.76)
        new = hopf_points(Model.luo_xie(2, 5, 0, 1.5, 0.8), 0.70, 0.76)
    assert len(old.points) == len(new.points) == 1
    a, b = old.points[0], new.points[0]
    assert abs(a.omega_c - b.omega_c) < 1e-12
    assert b.l1 == pytest.approx(a.l1, rel=1e-9)
    assert b.dmod_domega == pytest.approx(a.dmod_domega, rel=1e-9)
    assert [e.kind for e in old.events] == [e.kind for e in new.events]


@pytest.mark.slow
def test_damped_chain_against_both_50_digit_chains(three):
    """Chain A (mpmath orbit + generated jets + normal form) and chain B (finite
    differences of the mpmath map only, Kuznetsov's formula written out again)."""
    c = check_point(THREE_STOP2_GAP05, three.points[0], digits=50)
    for name in ("omega_c", "dmod_domega", "l1"):
        assert c.agreement[name]["A-B"] >= 40, (name, c.agreement)
        assert c.agreement[name]["float-A"] >= 12, (name, c.agreement)
    assert np.sign(float(c.chain_b.l1)) == np.sign(three.points[0].l1)
