"""Generated jets, eqs. (33)-(38), against finite differences of the numeric map P."""
import itertools
import math
import subprocess
import sys

import mpmath
import numpy as np
import pytest

from symvi import Params, period1_orbits
from symvi.paper.jets import jet
from symvi.paper.params import modal
from symvi.paper.modal_map import step
from symvi.numerics.backend import backend

from ..conftest import EX1, EX2, OWN

#: parameter points: both examples, and f2 != 0 with another gap (generality)
POINTS = [(EX1, 0.7369, None), (EX2, 0.4917, None), (OWN, 1.2, "+"),
          (Params(3.0, 1.0, -0.4, 0.5, 0.6), 0.9, None)]


def _orbit(params, omega, branch):
    orbs = [o for o in period1_orbits(params, omega) if o.admissible
            and (branch is None or o.branch == branch)]
    assert len(orbs) == 1
    return orbs[0]


def _P_mp(params, omega, y, dps=40):
    """Numeric map P in mpmath, tau unwrapped (a smooth function of y and omega)."""
    bk = backend(dps)
    with bk.context():
        m = modal(params, bk)
        s = step(m, bk.num(omega), bk.num(params.b), bk.num(params.r),
                 tuple(bk.num(v) for v in y), bk)
        return [*s.y[:3], s.tau_unwrapped]


def _fd(params, omega, y, idx, h, domega=0):
    """Mixed central difference of P over the state indices ``idx`` (mpmath)."""
    with mpmath.mp.workdps(40):
        h = mpmath.mpf(h)
        tot = [mpmath.mpf(0)] * 4
        for signs in itertools.product((1, -1), repeat=len(idx)):
            z = [mpmath.mpf(v) for v in y]
            for k, s in zip(idx, signs):
                z[k] += s * h
            val = _P_mp(params, omega, z)
            sg = math.prod(signs)
            tot = [t + sg * v for t, v in zip(tot, val)]
        return np.array([float(t / (2 * h) ** len(idx)) for t in tot])


@pytest.mark.slow
@pytest.mark.parametrize("params,omega,branch", POINTS)
def test_tensors_match_finite_differences_of_P(params, omega, branch):
    """F01, F02, F03 by mixed central differences of P (40 digits, h = 1e-7:
    truncation error O(h^2) ~ 1e-14 relative), F11 and dP/domega along omega."""
    o = _orbit(params, omega, branch)
    J = jet(params, omega, 3, orbit=o)
    y = [mpmath.mpf(v) for v in o.y]
    scale = lambda a: max(1.0, float(np.abs(a).max()))
    for j in range(4):
        assert np.allclose(_fd(params, omega, y, [j], 1e-7), J.jacobian[:, j],
                           atol=1e-10 * scale(J.jacobian))
    for j, k in itertools.combinations_with_replacement(range(4), 2):
        assert np.allclose(_fd(params, omega, y, [j, k], 1e-7), J.d2[:, j, k],
                           atol=1e-8 * scale(J.d2))
    for j, k, l in itertools.combinations_with_replacement(range(4), 3):
        assert np.allclose(_fd(params, omega, y, [j, k, l], 1e-6), J.d3[:, j, k, l],
                           atol=1e-7 * scale(J.d3))
    # explicit dP/domega at fixed y
    dw = 1e-8
    dP = (np.array(_P_mp(params, omega + dw, y), float) -
          np.array(_P_mp(params, omega - dw, y), float)) / (2 * dw)
    assert np.allclose(dP, J.dP_domega, atol=1e-6 * scale(J.dP_domega))
    # F11: the Jacobian along the branch, differenced in omega (orbit moves with omega)
    dw = 1e-6
    Jp = jet(params, omega + dw, 1, orbit=_orbit(params, omega + dw, branch)).jacobian
    Jm = jet(params, omega - dw, 1, orbit=_orbit(params, omega - dw, branch)).jacobian
    assert np.allclose((Jp - Jm) / (2 * dw), J.dA, atol=1e-7 * scale(J.dA))


@pytest.mark.parametrize("params,omega,branch", POINTS[:2])
def test_float64_and_mpmath_backends_agree(params, omega, branch):
    """The two backends of the same expressions agree to >= 12 significant digits."""
    f = jet(params, omega, 3)
    m = jet(params, omega, 3, digits=50)
    for name in ("jacobian", "d2", "d3", "dA"):
        a, b = getattr(f, name), getattr(m, name).astype(float)
        assert np.max(np.abs(a - b)) <= 1e-12 * np.abs(b).max(), name


def test_paper_scaled_tensors():
    """F02 = d2 / 2 and F03 = d3 / 6, eq. (34)."""
    j = jet(EX1, 0.7369, 3)
    assert np.array_equal(j.F02, j.d2 / 2) and np.array_equal(j.F03, j.d3 / 6)
    assert j.F01 is j.jacobian and j.F11 is j.dA
    assert jet(EX1, 0.7369, 1).d2 is None


def test_symmetry_of_tensors():
    j = jet(EX1, 0.7369, 3)
    assert np.array_equal(j.d2, j.d2.transpose(0, 2, 1))
    for perm in itertools.permutations((1, 2, 3)):
        assert np.array_equal(j.d3, j.d3.transpose(0, *perm))


def test_multiplier_job_never_imports_higher_orders():
    """A multiplier-only job imports no generated code above order 1: in float64 the
    multipliers come from the compiled monodromy, in mpmath from order 1 of the N = 2
    structure."""
    code = ("import sys, symvi; p = symvi.Params(2,5,0,1.5,0.8);"
            "symvi.period1_orbits(p, 0.7369); a = sorted(m for m in sys.modules "
            "if m.startswith('symvi._generated.'));"
            "symvi.period1_orbits(p, 0.7369, digits=20); b = sorted(m for m in sys.modules "
            "if m.startswith('symvi._generated.')); print(a, b)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[] ['symvi._generated.impact_n2_order1']"


def test_bad_order():
    from symvi import ParameterError
    with pytest.raises(ParameterError, match="order"):
        jet(EX1, 0.7369, 4)


def test_near_fold_warns_and_fold_refuses():
    """dy*/domega = (I - J)^{-1} dP/domega: a multiplier near 1 is said, at 1 refused."""
    from symvi import NearSingularWarning, SingularCaseError
    from symvi.codegen.jets import fixed_point_motion
    rng = np.random.default_rng(0)
    V = rng.normal(size=(4, 4))
    for gap, expect in [(1e-8, "warn"), (1e-12, "refuse"), (0.3, "quiet")]:
        J = V @ np.diag([1 - gap, 0.5, -0.3, 0.2]) @ np.linalg.inv(V)
        M = np.eye(4) - J
        if expect == "refuse":
            with pytest.raises(SingularCaseError, match="multiplier-one"):
                fixed_point_motion(J, np.ones(4), False)
        elif expect == "warn":
            with pytest.warns(NearSingularWarning, match="fold"):
                x = fixed_point_motion(J, np.ones(4), False)
            assert np.allclose(M @ x, np.ones(4), atol=1e-6 * np.abs(x).max())
        else:
            import warnings
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                fixed_point_motion(J, np.ones(4), False)
