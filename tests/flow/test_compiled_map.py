"""The compiled map step of any model against the reference map
:func:`symvi.maps.impact.poincare_map`, and the packed constants."""
import math

import numpy as np
import pytest

from symvi import ParameterError, SingularCaseError
from symvi.flow import compiled as cf
from symvi.flow.linear import LinearFlow
from symvi.maps.impact import poincare_map
from tests.zoo import FOUR_STOP3, ONE_DAMPED_GAP02, PAPER_EX1, THREE_STOP2_GAP12, TWO_OVERDAMPED

from .gap_reference import random_states

CASES = [(ONE_DAMPED_GAP02, 0.8), (PAPER_EX1, 0.7372), (THREE_STOP2_GAP12, 0.4), (FOUR_STOP3, 1.3), (TWO_OVERDAMPED, 0.9)]
IDS = ["N1", "paper", "N3", "N4", "overdamped"]


def _wrap(d):
    return (d + math.pi) % (2 * math.pi) - math.pi


@pytest.mark.parametrize("model, omega", CASES, ids=IDS)
def test_step_equals_reference_map(model, omega):
    """P(y) and t_e from the kernels equal poincare_map (numpy, all 2N modes) to
    1e-12 (relative to the state's size) on 60 random states."""
    rng = np.random.default_rng(11)
    c = cf.constants(model, omega)
    n_imp = 0
    for y in random_states(model, 60, rng):
        ref = poincare_map(model, omega, y)
        st, t, y1, vm, acc, steps, _ = cf.step(c, y)
        assert cf.STATUS_NAMES[st] == ref.status
        if ref.status != "impact":
            continue
        n_imp += 1
        scale = max(1.0, np.abs(y).max(), t)
        assert abs(t - ref.t) < 1e-12 * scale
        d = np.subtract(y1, ref.y)
        d[-1] = _wrap(d[-1])
        assert np.abs(d).max() < 1e-12 * scale
        assert vm == pytest.approx(ref.impact_velocity, rel=1e-12, abs=1e-12 * scale)
        assert 0 <= y1[-1] < 2 * math.pi
    assert n_imp >= 50


def test_conjugate_pairs_kept_once():
    """Undamped and underdamped models keep N modes of weight 2; the overdamped
    one keeps its pair once and both real eigenvalues (weights sum to 2N)."""
    for model, kept in ((PAPER_EX1, 2), (THREE_STOP2_GAP12, 3), (FOUR_STOP3, 4), (ONE_DAMPED_GAP02, 1), (TWO_OVERDAMPED, 3)):
        c = cf.constants(model, 1.1)
        m = int(c[1])
        assert m == kept
        w = c[cf._HDR:cf._HDR + 3 * m].reshape(m, 3)[:, 2]
        assert w.sum() == 2 * model.n
    w = cf.constants(TWO_OVERDAMPED, 1.1)[cf._HDR:cf._HDR + 9].reshape(3, 3)
    assert sorted(w[:, 2]) == [1.0, 1.0, 2.0] and (w[w[:, 2] == 1.0, 1] == 0).all()


def test_pairing_fallback_is_all_modes():
    """When eigenvalues do not pair, every mode is kept with weight 1."""
    lam = np.array([1j, -1j, 2j, -1.5j])
    assert cf._modes(lam) == [(j, 1.0) for j in range(4)]
    assert cf._modes(np.array([1j, -2.0, -1j, -3.0])) == [(0, 2.0), (1, 1.0), (3, 1.0)]


def test_all_modes_fallback_gives_the_same_map(monkeypatch):
    """Kept with weight 1 each (the fallback when pairing fails), all 2N modes give
    the same map as the paired form."""
    rng = np.random.default_rng(2)
    ys = random_states(FOUR_STOP3, 20, rng)
    paired = [cf.step(cf.constants(FOUR_STOP3, 1.3), y) for y in ys]
    monkeypatch.setattr(cf, "_modes", lambda lam: [(j, 1.0) for j in range(len(lam))])
    c = cf.constants(FOUR_STOP3, 1.3)
    assert int(c[1]) == 8
    for y, p in zip(ys, paired):
        q = cf.step(c, y)
        assert q[0] == p[0] and abs(q[1] - p[1]) < 1e-12 * max(1, p[1])
        assert np.abs(_wrap(q[2] - p[2])).max() < 1e-11


def test_constants_checks_omega():
    with pytest.raises(ParameterError, match="omega"):
        cf.constants(THREE_STOP2_GAP12, float("nan"))
    with pytest.raises(ParameterError, match="omega"):
        cf.constants(THREE_STOP2_GAP12, -1.0)
    w1 = float(LinearFlow.of(PAPER_EX1).omegas[0])
    with pytest.raises(SingularCaseError):
        cf.constants(PAPER_EX1, w1)
    assert len(cf.constants(FOUR_STOP3, 1.0)) == cf.size(4)


def test_run_batch_mixed_models_equals_run():
    """A batch mixing N = 1, 3 and 4 (padded constants and start points) gives the
    runs of :func:`run`, bit for bit."""
    rng = np.random.default_rng(5)
    rows = [(ONE_DAMPED_GAP02, 0.8), (THREE_STOP2_GAP12, 0.4), (FOUR_STOP3, 1.3), (THREE_STOP2_GAP12, 0.8)]
    C = cf.pack([cf.constants(m, w) for m, w in rows])
    Y0 = np.zeros((len(rows), 8))
    for i, (m, _) in enumerate(rows):
        Y0[i, :m.dim] = random_states(m, 1, rng)[0]
    codes, counts, sec, t, vimp, steps = cf.run_batch(C, Y0, 200, transient=50)
    for i, (m, w) in enumerate(rows):
        code, s, ti, vi, st = cf.run(cf.constants(m, w), Y0[i, :m.dim], 200, transient=50)
        assert codes[i] == code and counts[i] == len(s) and steps[i] == st
        assert np.array_equal(sec[i, :len(s), :m.dim], s)
        assert np.isnan(sec[i, :, m.dim:]).all()
        assert np.array_equal(t[i, :len(s)], ti) and np.array_equal(vimp[i, :len(s)], vi)
