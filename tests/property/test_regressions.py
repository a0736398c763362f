"""Bugs found by the property tests in other modules, kept as regression tests.

Each was first an ``xfail(strict=True)`` test; the marker goes when the owner's fix lands.
"""
import numpy as np
import symvi
from symvi.paper import jets


def test_jet_multiplier_one_false_alarm():
    """jets._solve refused I - J by det(I - J) < 1e-12 max|I - J|^4 (scale-dependent): here no
    multiplier is within 1.3 of 1 but |J| ~ 5e3, and jet(order >= 2) raised 'multiplier-one'.
    Fixed in ccaffeb (fold check by multipliers)."""
    p, w = symvi.Params(4.0, 0.25, 1.0, 0.0, 1.0), 3.0
    o = [x for x in symvi.period1_orbits(p, w) if x.admissible][0]
    assert min(abs(1 - complex(z)) for z in o.multipliers) > 1.0
    j = jets.jet(p, w, order=2, orbit=o)
    assert np.all(np.isfinite(j.dA))
