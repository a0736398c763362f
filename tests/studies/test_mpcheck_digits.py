"""High-digit runs of the two mpmath chains (``symvi hopf --digits N``, N = 30..500):
issue 23, defect 7.  findroot's fixed residual tolerance was unreachable from ~125
digits (ValueError), and float(eps) underflowed to 0 from ~324 (ZeroDivisionError)."""
import mpmath
import numpy as np
import pytest

from symvi import Params
from symvi.errors import SingularCaseError
from symvi.normal_forms.normal_form import normal_form
from symvi.studies import mpcheck as mc


def _noisy(root, digits, floor):
    """f(w) = (w - root)(1 + (w - root)) plus a deterministic noise of size 10^-floor that
    changes at the working precision, like rounding: what |lambda1|^2 - 1 of chain B
    looks like (finite differences good to ~4/5 of the working digits)."""
    def f(w):
        u = mpmath.frac(w * mpmath.mpf(10) ** (digits + 15) * mpmath.sqrt(2))
        return (w - root) * (1 + (w - root)) + (2 * u - 1) * mpmath.mpf(10) ** (-floor)
    return f


@pytest.mark.parametrize("digits", [130, 330, 500])
def test_secant_stops_at_the_noise_floor_of_f(digits):
    with mpmath.workdps(digits + 20):
        root = mpmath.mpf(0.7368769220905924) + mpmath.mpf(10) ** -20 / 3
        floor = int(0.8 * digits)
        f = _noisy(root, digits, floor)
        w = mc._secant_root(f, 0.7368769220905924, digits, "B")
        assert abs(w - root) < mpmath.mpf(10) ** (3 - floor)
        # the old stopping rule: |f|^2 <= 10^(-2 digits) cannot be met above the floor
        w0 = mpmath.mpf(0.7368769220905924)
        with pytest.raises(ValueError, match="Could not find root"):
            mpmath.findroot(f, (w0, w0 + mpmath.mpf("1e-9")), solver="secant",
                            tol=mpmath.mpf(10) ** (-2 * digits), maxsteps=60)


def test_secant_at_a_flat_noise_floor_does_not_divide_by_zero():
    """f quantised near the root (f1 = f0): the secant step would divide by zero."""
    with mpmath.workdps(60):
        root = mpmath.mpf(1) / 3
        q = mpmath.mpf(10) ** -30

        def f(w):
            return mpmath.floor((w - root) / q) * q
        w = mc._secant_root(f, 0.3333, 50, "A")
        assert abs(w - root) < 1e-28


def test_secant_that_cannot_converge_says_so():
    with mpmath.workdps(40), pytest.raises(SingularCaseError, match="did not converge"):
        mc._secant_root(lambda w: 1 + w * w, 0.5, 30, "A", maxsteps=8)


def test_normal_form_past_324_digits():
    """At 330 digits eps = 1e-329 is 0.0 as a float: the eigenmatrix test divided by it."""
    th = 0.9
    A = np.array([[np.cos(th), -np.sin(th), 0], [np.sin(th), np.cos(th), 0], [0, 0, 0.3]])
    d2 = np.zeros((3, 3, 3))
    d3 = np.zeros((3, 3, 3, 3))
    d3[0, 0, 0, 0] = d3[1, 1, 1, 1] = -1.0
    nf = normal_form(A, d2, d3, np.eye(3), digits=330)
    assert nf.l1 < 0 and abs(abs(nf.lam) - 1) < mpmath.mpf(10) ** -300


@pytest.mark.slow
def test_chain_a_at_500_digits_on_the_papers_example():
    """The paper's example 1 at omega_c = 0.73687692209...: chain A runs at 500 digits and
    agrees with itself at 60 to 58+ digits (it raised ZeroDivisionError from ~324)."""
    p = Params(2, 5, 0, 1.5, 0.8)
    w0, lam0 = 0.7368769220905924, complex(-0.8068410381928645, 0.590768600289366)
    a500 = mc.chain_a(p, w0, "+", 500, lam0)
    a60 = mc.chain_a(p, w0, "+", 60, lam0)
    with mpmath.workdps(500):
        for x, y in ((a500.omega_c, a60.omega_c), (a500.l1, a60.l1),
                     (a500.dmod_domega, a60.dmod_domega)):
            assert mc.digits_of_agreement(x, y) > 55
        assert abs(abs(a500.lam) - 1) < mpmath.mpf(10) ** -490


def test_secant_on_a_flat_or_nan_function_says_so():
    with mpmath.workdps(40):
        for f in (lambda w: mpmath.mpf(1), lambda w: mpmath.nan):
            with pytest.raises(SingularCaseError, match="did not converge"):
                mc._secant_root(f, 0.5, 30, "A")


def test_check_points_refuses_digits_out_of_range_before_any_work():
    from symvi.errors import ParameterError
    p = Params(2, 5, 0, 1.5, 0.8)
    assert mc.check_points(p, [], digits=30) == []
    for bad in (29, 501, 50.0, True):
        with pytest.raises(ParameterError, match="digits"):
            mc.check_points(p, [object()], digits=bad)
