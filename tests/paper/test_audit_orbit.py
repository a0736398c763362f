"""Printed eqs. (11)-(16), (21)-(24) beside the derivation from conditions (10)."""
import math

import numpy as np

from symvi import Params, period1_orbits
from symvi.paper import audit_orbit as au
from symvi.paper.modal_flow import motion_from
from symvi.paper.params import modal

from ..conftest import EX1, OWN


def test_corrected_11_12_reproduce_the_orbit_printed_do_not():
    for p, omega in [(EX1, 0.7369), (OWN, 1.2), (Params(4, 2, 0, 1.8, 0.8), 0.49)]:
        orbs = period1_orbits(p, omega, multipliers=False)
        cos_mine = sorted(math.cos(o.tau0) for o in orbs)
        cos_corr = sorted(au.cos_tau0_corrected(p, omega, s) for s in (1, -1))
        assert np.allclose(cos_mine, cos_corr, atol=1e-11)
        # the printed pair differs (missing b and s2)
        cos_prn = [au.cos_tau0_printed(p, omega, s) for s in (1, -1)]
        assert any(c is None for c in cos_prn) or not np.allclose(sorted(cos_prn), cos_mine,
                                                                  atol=1e-6)


def test_b_zero_corrected_11_gives_tau0():
    p = Params(2, 5, 0, 0.0, 0.8)
    for o in period1_orbits(p, 0.73, multipliers=False):
        assert abs(math.tan(o.tau0) - au.tan_tau0bar_corrected(p, 0.73)) < 1e-9
    assert abs(au.tan_tau0bar_printed(p, 0.73) - au.tan_tau0bar_corrected(p, 0.73)) > 1e-3


def test_13_to_15_agree():
    for p, omega in [(EX1, 0.7369), (OWN, 1.2)]:
        for o in period1_orbits(p, omega, multipliers=False):
            b1 = au.b1_printed(p, omega, o.tau0)
            b2 = au.b2_printed(p, omega, b1)
            a1, a2 = au.a_printed(p, omega, b1, b2)
            assert np.allclose([b1, b2, a1, a2], [*o.b, *o.a], rtol=1e-11, atol=1e-12)


def test_21_to_24_agree_with_flow():
    p, omega = OWN, 1.2
    o = period1_orbits(p, omega, multipliers=False)[0]
    dX = (0.01, -0.02, 0.03, 0.04)
    m = modal(p)
    mot = motion_from(m, omega, (p.b, o.x20 + dX[1]), (o.v1_plus + dX[0], o.x20_dot + dX[2]),
                      o.tau0 + dX[3])
    got = au.modal_constants_printed(p, omega, o.y, o.tau0, dX)
    assert np.allclose(got, [*mot.a, *mot.b], rtol=1e-12, atol=1e-13)


def test_auto_orbits_in_the_papers_terms():
    """``symvi orbit``'s one call: the paper's Params give the paper's Orbit, with the
    numbers and estimates of the model's orbits; a Model gives its own; omega is checked
    first, by the paper's rule for the paper's Params."""
    import pytest

    from symvi.analysis.precision import auto_model_orbits
    from symvi.errors import ParameterError
    from symvi.paper.orbit import Orbit, auto_orbits
    p = EX1
    paper, model = auto_orbits(p, 0.74), auto_model_orbits(p.as_model(), 0.74)
    assert paper and all(isinstance(a.orbit, Orbit) for a in paper)
    assert [list(a.orbit.y) for a in paper] == [list(a.orbit.y) for a in model]
    assert [a.estimate.y.as_dict() for a in paper] == [a.estimate.y.as_dict() for a in model]
    mine = auto_orbits(p.as_model(), 0.74)
    assert [type(a.orbit) for a in mine] == [type(a.orbit) for a in model]
    for system in (p, p.as_model()):
        with pytest.raises(ParameterError, match="omega"):
            auto_orbits(system, -1.0)
