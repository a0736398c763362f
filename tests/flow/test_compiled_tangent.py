"""The compiled tangent map DP v of :mod:`symvi.flow.compiled` against the exact
Jacobian of the generated jets, and the determinant identity at period-1 orbits."""
import math

import numpy as np
import pytest

from symvi.codegen.jets import jacobian_at
from symvi.flow import compiled as cf
from symvi.simulations import simulation
from tests.zoo import FOUR_STOP3, PAPER_EX1, THREE_STOP2_GAP12, TWO_OVERDAMPED

from .gap_reference import random_states

CASES = [(PAPER_EX1, 0.70), (PAPER_EX1, 0.7369), (THREE_STOP2_GAP12, 0.4), (THREE_STOP2_GAP12, 1.3), (FOUR_STOP3, 1.3), (TWO_OVERDAMPED, 0.9)]
IDS = ["paper-0.70", "paper-0.7369", "N3-0.4", "N3-1.3", "N4", "overdamped"]


@pytest.mark.parametrize("model, omega", CASES, ids=IDS)
def test_jacobian_equals_generated(model, omega):
    """jacobian_tangent (variation of the modal flow, O(dim^2)) equals jacobian_at (the
    generated closed-form derivatives) to 1e-9 relative at random points, and the
    image of step_tangent is step's, bit for bit."""
    rng = np.random.default_rng(5)
    c = cf.constants(model, omega)
    done = 0
    for y in random_states(model, 12, rng):
        st, te, y1, *_ = cf.step(c, y)
        if st != cf.IMPACT:
            continue
        J = cf.jacobian_tangent(c, y)
        ref = np.asarray(jacobian_at(model, omega, y, te), dtype=float)
        assert np.abs(J - ref).max() <= 1e-9 * np.abs(ref).max()
        st2, te2, y2, v2, _ = cf.step_tangent(c, y, np.ones(model.dim))
        assert st2 == st and te2 == te and np.array_equal(y2, y1)
        assert np.allclose(v2, J.sum(axis=1), rtol=1e-12, atol=1e-12 * np.abs(J).max())
        done += 1
    assert done >= 6


def _trace(model):
    """tr(M^-1 C) = -tr A."""
    return float(np.trace(np.linalg.solve(np.asarray(model.mass, dtype=float),
                                          np.asarray(model.damping, dtype=float))))


@pytest.mark.parametrize("model, omega", [(PAPER_EX1, 0.7369), (PAPER_EX1, 0.70), (THREE_STOP2_GAP12, 0.5),
                                          (THREE_STOP2_GAP12, 1.3), (FOUR_STOP3, 1.1), (TWO_OVERDAMPED, 1.3)],
                         ids=["paper-0.7369", "paper-0.70", "N3-0.5", "N3-1.3", "N4", "over"])
def test_determinant_at_period1(model, omega):
    """det DP = r^2 exp(-tr(M^-1 C) 2 pi / omega) at the period-1 orbit, to 1e-10."""
    y = np.array(simulation.fixed_point(model, omega))
    c = cf.constants(model, omega)
    st, te, *_ = cf.step(c, y)
    assert st == cf.IMPACT and abs(te * omega / (2 * math.pi) - 1) < 1e-10
    want = model.stop.restitution ** 2 * math.exp(-_trace(model) * 2 * math.pi / omega)
    det = np.linalg.det(cf.jacobian_tangent(c, y))
    assert abs(det - want) <= 1e-10 * want


@pytest.mark.parametrize("model, omega", CASES, ids=IDS)
def test_determinant_anywhere(model, omega):
    """det DP(y) = r |v_k+| / |v_k-(t_e)| exp(-tr(M^-1 C) t_e) at any point: Liouville
    along the flight, the section's flux (volume times normal speed) conserved, the
    reset scaling v_k by r.  The period-1 identity is the case |v_k+| = r |v_k-|."""
    rng = np.random.default_rng(8)
    c = cf.constants(model, omega)
    for y in random_states(model, 8, rng):
        st, te, _, vm, *_ = cf.step(c, y)
        if st != cf.IMPACT or te > 50:
            continue
        want = model.stop.restitution * abs(y[0]) / abs(vm) * math.exp(-_trace(model) * te)
        det = np.linalg.det(cf.jacobian_tangent(c, y))
        assert abs(det - want) <= 1e-9 * want


def test_no_impact_leaves_v():
    """Without an impact DP is undefined: v is returned unchanged and
    jacobian_tangent refuses."""
    c = cf.constants(PAPER_EX1, 0.7369, t_max=1e-3)
    y = np.array(simulation.fixed_point(PAPER_EX1, 0.7369))
    v = np.arange(1.0, 5.0)
    st, _, _, v1, _ = cf.step_tangent(c, y, v)
    assert st == cf.NO_IMPACT and np.array_equal(v1, v)
    with pytest.raises(ValueError, match="no impact"):
        cf.jacobian_tangent(c, y)
