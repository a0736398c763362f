"""Bugs found by the property tests in other modules (reported to the lead).

Each is ``xfail(strict=True)``: it fails today and turns into an XPASS (and so a
failure to notice) when the owner fixes it; then remove the marker.
"""
import numpy as np
import pytest

import symvi
from symvi import jets


@pytest.mark.xfail(strict=True, reason="jets._solve refuses I - J by det(I - J) < 1e-12 "
                   "max|I - J|^4, which is scale-dependent: here no multiplier is within "
                   "1.3 of 1 but |J| ~ 5e3, and jet(order >= 2) raises 'multiplier-one'")
def test_jet_multiplier_one_false_alarm():
    p, w = symvi.Params(4.0, 0.25, 1.0, 0.0, 1.0), 3.0
    o = [x for x in symvi.period1_orbits(p, w) if x.admissible][0]
    assert min(abs(1 - complex(z)) for z in o.multipliers) > 1.0
    j = jets.jet(p, w, order=2, orbit=o)
    assert np.all(np.isfinite(j.dA))
