"""Invariant circle: simulated half-widths against the normal-form prediction (issue 5, item 6)."""
import numpy as np
import pytest

from symvi.studies import circle_check as cc

from ..conftest import EX1


def test_measurement_scales_as_sqrt_mu():
    """Measurement alone: past the Hopf point the circle's half-widths grow as
    sqrt(v - v_c); the inside and outside runs bracket the same size."""
    oc = 0.73687692          # Hopf point of example 1 to ~1e-8 (paper: 0.7368)
    a = cc.measure(EX1, oc + 1e-4)
    b = cc.measure(EX1, oc + 4e-4)
    assert a.converged and b.converged
    assert (a.spread <= 1e-4 * a.half_widths).all()
    ratio = b.half_widths / a.half_widths
    assert np.abs(ratio[1:] - 2).max() < 0.05          # sqrt(4) = 2, up to O(mu)
    assert a.half_widths[1] > 0.03                     # a real circle, not the fixed point


def test_below_hopf_no_circle():
    """Before the Hopf point the fixed point attracts: measured half-widths ~ 0."""
    m = cc.measure(EX1, 0.7360, block=2000)
    assert m.half_widths.max() < 1e-8


def test_circle_matches_normal_form():
    """Simulated half-widths match the predicted circle of symvi.hopf; the relative
    error shrinks with mu (leading order, O(mu) error); eq. (60) as printed
    would predict circles several times smaller than the simulated ones."""
    pytest.importorskip("symvi.analysis.hopf")
    point = cc.hopf_point(EX1, 0.72, 0.74)
    res = cc.check(EX1, point, [1e-4, 4e-4])
    e = np.abs(res.rel_error)
    assert all(res.converged)
    assert e[0].max() < 1e-2
    assert e[0].max() < 0.5 * e[1].max()
    if res.printed_scale is not None:
        assert np.abs(res.measured[0] / res.predicted_printed[0] - 1).min() > 0.5
