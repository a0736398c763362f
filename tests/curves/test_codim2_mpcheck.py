"""Codimension-two points of the paper model's curves re-solved at 50 digits by finite
differences of the mpmath map (issue 13, item 3: :mod:`symvi.codim2_check`).

Kind 3 reference values (an independent method): the finite-difference chain uses neither
the generated jets nor the continuation code; kind 2 (identities): the PDNS point of the
NS curve and of the flip curve are one point, located from two different defining systems.
"""
import itertools
import math
from types import SimpleNamespace

import mpmath
import numpy as np
import pytest

import symvi
from symvi.curves import curve_from_interval
from symvi.errors import ParameterError
from symvi.studies.codim2_check import _jet_on, check_codim2, working_dps
from tests.zoo import PAPER_EX1

BOUNDS_R = {"omega": (0.5, 1.0), "r": (0.05, 1.0)}
BOUNDS_B = {"omega": (0.5, 1.0), "b": (0.5, 3.0)}


@pytest.fixture(scope="module")
def curve_r():
    return curve_from_interval(PAPER_EX1, 0.70, 0.76, ("omega", "r"), bounds=BOUNDS_R)[0]


@pytest.fixture(scope="module")
def curve_b():
    return curve_from_interval(PAPER_EX1, 0.70, 0.76, ("omega", "b"), bounds=BOUNDS_B)[0]


def _point(curve, kind, **near):
    pts = [s for s in curve.special if s.kind == kind]
    assert pts, f"no {kind} point on the curve"
    return min(pts, key=lambda s: sum(abs(s.params[k] - v) for k, v in near.items()))


# --------------------------------------------------------------------------- fast
def test_stencil_grid_recovers_the_derivatives_of_a_polynomial_map():
    """Central mixed differences on one grid, Richardson-extrapolated: every derivative of
    orders 1..5 of a polynomial 2-D map of degree 6 to O(h^4) = 1e-24 (h = 1e-6)."""
    rng = np.random.default_rng(3)
    n, order = 2, 5
    with mpmath.workdps(60):
        coef = {e: mpmath.mpf(float(rng.normal())) for e in
                itertools.product(range(6), repeat=n) if sum(e) <= 6}
        y0 = [mpmath.mpf(v) for v in (0.3, -0.7)]

        def f(x, i):
            return mpmath.fsum(c * (i + 1) * mpmath.fprod(x[k] ** e[k] for k in range(n))
                               for e, c in coef.items())

        def deriv(axes, i):
            cnt = [axes.count(k) for k in range(n)]
            tot = 0
            for e, c in coef.items():
                if all(e[k] >= cnt[k] for k in range(n)):
                    tot += c * (i + 1) * mpmath.fprod(
                        math.perm(e[k], cnt[k]) * y0[k] ** (e[k] - cnt[k]) for k in range(n))
            return tot

        h = mpmath.mpf(10) ** -6
        jets = _jet_on(lambda d: [f([y0[k] + h * d[k] for k in range(n)], i) for i in range(n)],
                       n, order, h)
        for k, T in enumerate(jets, start=1):
            for axes in itertools.combinations_with_replacement(range(n), k):
                for i in range(n):
                    exact = deriv(axes, i)
                    assert abs(T[(i,) + axes] - exact) <= mpmath.mpf(10) ** -20 * (1 + abs(exact))


def test_working_precision_balances_truncation_and_rounding():
    assert working_dps(50, 1) == 80
    assert working_dps(50, 3) == 105
    assert working_dps(50, 5) == 135


def test_refuses_what_is_not_a_codim2_point_it_can_solve():
    curve = SimpleNamespace(kind="ns", special=(SimpleNamespace(kind="grazing"),))
    with pytest.raises(ParameterError, match="digits"):
        check_codim2(curve, SimpleNamespace(kind="CH"), digits=20)
    with pytest.raises(ParameterError, match="point"):
        check_codim2(curve, 1)
    with pytest.raises(ParameterError, match="CH"):
        check_codim2(curve, 0)


# --------------------------------------------------------------------------- slow
@pytest.mark.slow
@pytest.mark.parametrize("r", [0.6969, 0.2762])
def test_chenciner_points_at_50_digits(curve_r, r):
    """Both CH points of example 1 in (omega, r): location to >= 9 digits, l1 = 0, and l2
    (float64, generated order-5 jets) to >= 8 digits (issue 13 target) against the chain;
    codim2's c1 and l1 agree with the independent kuznetsov_l1 to 40 digits."""
    pt = _point(curve_r, "CH", r=r)
    res = check_codim2(curve_r, pt, digits=50)
    assert res.location["omega"] >= 9 and res.location["r"] >= 9
    c = res.coefficients
    assert abs(c["l1"]) < 1e-40 * abs(c["c1"])
    assert abs(res.tests["g1"]) < 1e-50 and abs(res.tests["g2"]) < 1e-50
    assert c["l2"] < 0 and c["l2"] == c["l2_matcont"]
    assert res.agreement["l2"] >= 8 and res.agreement["c2"] >= 8
    assert res.agreement["c1"] >= 9 and res.agreement["l1"] >= 9
    assert res.internal["c1: codim2 vs kuznetsov_l1"] >= 40
    assert res.internal["l1: codim2 vs kuznetsov_l1 (rel. |c1|)"] >= 40


@pytest.mark.slow
def test_r4_point_at_50_digits(curve_r):
    """R4 of example 1 in (omega, r): lambda = i at the chain's point; A = -i c1/|d1|."""
    res = check_codim2(curve_r, _point(curve_r, "R4"), digits=50)
    with mpmath.workdps(50):
        assert abs(res.coefficients["lam"] - 1j) < 1e-45
    assert res.location["omega"] >= 9 and res.location["r"] >= 9
    for k in ("c1", "d1", "A"):
        assert res.agreement[k] >= 9, k
    assert res.internal["c1: codim2 vs kuznetsov_l1"] >= 40


@pytest.mark.slow
def test_r3_point_at_50_digits(curve_b):
    """R3 of example 1 in (omega, b): lambda^3 = 1 at the chain's point."""
    res = check_codim2(curve_b, _point(curve_b, "R3"), digits=50)
    with mpmath.workdps(50):
        assert abs(res.coefficients["lam"] ** 3 - 1) < 1e-45
    assert res.location["omega"] >= 9 and res.location["b"] >= 9
    # coef = (lambda^2 c1/|b1|^2 - 1)/3 ~ 100: its real part (~1.6) keeps ~2 digits fewer
    for k, d in (("b1", 9), ("c1", 9), ("coef", 9), ("re", 7), ("im", 9)):
        assert res.agreement[k] >= d, k


@pytest.mark.slow
def test_pdns_point_at_50_digits_and_from_the_flip_curve(curve_b):
    """PDNS of example 1 in (omega, b): located on the NS curve (|mu1 mu2| = 1,
    det(J + I) = 0) and on the flip curve (det(J + I) = 0, the pair on the circle), the
    chain finds one point to 45 digits; the coefficients do not depend on the step."""
    res = check_codim2(curve_b, _point(curve_b, "PDNS"), digits=50, verify=True)
    assert res.location["omega"] >= 9 and res.location["b"] >= 9
    for k in ("f111", "g210", "g021", "lam"):
        assert res.agreement[k] >= 10, k
    # f300 ~ -6e-8 is small against the O(1) terms it is made of: float64 keeps ~8 digits
    assert res.agreement["f300"] >= 7
    assert min(v for k, v in res.internal.items() if k.startswith("verify:")) >= 40
    assert res.internal["c1: codim2 vs kuznetsov_l1"] >= 40

    flip = curve_from_interval(PAPER_EX1, 0.70, 0.76, ("omega", "b"), kind="flip",
                               bounds=BOUNDS_B)[0]
    res2 = check_codim2(flip, _point(flip, "PDNS"), digits=50)
    with mpmath.workdps(50):
        for nm in ("omega", "b"):
            assert abs(res.params[nm] - res2.params[nm]) < 1e-45
        for k in ("f300", "f111", "g021"):
            assert abs(res.coefficients[k] - res2.coefficients[k]) < \
                1e-40 * abs(res.coefficients["f111"])
    assert res2.internal["c1: codim2 vs kuznetsov_l1"] >= 40


@pytest.mark.slow
def test_lpns_point_of_the_fold_curve_at_50_digits():
    """LPNS of the fold curve of example 1 in (omega, b) near grazing: a multiplier 1 makes
    the fixed point a double root at fixed parameters, so the chain solves (y, omega, b)
    jointly on P(y) = y, det(J - I) = 0 and the pair on the circle."""
    fold = curve_from_interval(PAPER_EX1, 1.4, 1.6, ("omega", "b"), kind="fold",
                               bounds={"omega": (0.5, 3.0), "b": (0.3, 3.0)})[0]
    res = check_codim2(fold, _point(fold, "LPNS"), digits=50)
    assert abs(res.tests["g1"]) < 1e-50 and abs(res.tests["g2"]) < 1e-50
    with mpmath.workdps(50):
        assert min(abs(z - 1) for z in res.multipliers) < 1e-45
    assert res.location["omega"] >= 9 and res.location["b"] >= 9
    for k in ("f200", "f011", "g110", "f300", "f111", "g210", "g021"):
        assert res.agreement[k] >= 9, k
