"""Automatic precision of period-1 orbits of any model: the estimate bounds the true
error (40-digit reference) near forcing resonance and near 1 - cos -> 0, and an
orbit float64 cannot resolve is recomputed in mpmath."""
import math
import warnings

import numpy as np
import pytest

from symvi import Params
from symvi.paper.modal_orbit import period1_orbits as paper_orbits  # the modal oracle
from symvi.errors import NearSingularWarning
from symvi.flow.linear import LinearFlow
from symvi.orbits import period1_orbits
from symvi.precision import auto_model_orbits

from ..nmodel.models import PAPER, THREE

W1, W2 = (float(w) for w in LinearFlow.of(PAPER).omegas)
HARD = [W1 * (1 + 1e-7), W1 * (1 + 1e-5), W1 * (1 + 1e-3), W2 / 2 * (1 + 1e-7),
        W2 / 2 * (1 + 1e-5), 0.7369]


@pytest.mark.slow
@pytest.mark.parametrize("w", HARD)
def test_float64_estimate_bounds_the_true_error(w):
    from symvi.precision import estimate_model_orbit
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        ref = {o.branch: o for o in paper_orbits(Params(2, 5, 0, 1.5, 0.8), w, digits=40)}
        for o in period1_orbits(PAPER, w):
            est = estimate_model_orbit(PAPER, o)
            r = ref[o.branch]
            true = (max(abs(float(a) - float(b)) for a, b in zip(o.y, r.y))
                    / max(abs(float(v)) for v in r.y))
            assert true <= est.y.rel_err, (w, o.branch, true, est.y.rel_err)
            assert est.y.rel_err < 1e4 * max(true, 1e-16)     # and is not absurdly loose


@pytest.mark.slow
def test_unresolvable_orbit_is_recomputed_in_mpmath():
    w = W1 * (1 + 1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        autos = auto_model_orbits(PAPER, w)
        ref = {o.branch: o for o in paper_orbits(Params(2, 5, 0, 1.5, 0.8), w, digits=40)}
    for a in autos:
        assert a.digits_used is not None and "mpmath" in a.note
        assert a.estimate.y.digits >= 8
        r = ref[a.orbit.branch]
        assert max(abs(float(x) - float(z)) for x, z in zip(a.orbit.y, r.y)) < 1e-12


def test_benign_orbit_stays_float64_with_its_digits():
    a = [x for x in auto_model_orbits(THREE, 0.95) if x.orbit.admissible][0]
    assert a.digits_used is None and a.estimate.y.digits > 11
    assert a.estimate.multipliers.digits > 10
    assert np.isfinite(a.estimate.multipliers.rel_err)


def test_escalation_ends_untrusted_at_an_infinite_condition(monkeypatch):
    """A recomputation at d digits that meets a singular case (an infinite condition) ends
    the escalation untrusted, saying why.  It once raised OverflowError: hypothesis found a
    near-grazing NS point of a random N = 4 model (tests/property/test_models_random.py)."""
    from symvi.analysis import precision as pr

    def est(cond, note=""):
        return pr.HopfEstimate(*(pr._make(n, 1.0, 1e-3, cond, None, note)
                                 for n in ("omega_c", "dmod_domega", "l1")), "+")
    monkeypatch.setattr(pr, "_hopf_estimate",
                        lambda *a, **k: est(math.inf, "gap: near-singular-map"))
    out = pr._escalate_hopf(None, 1.0, "+", est(1e10), 8, 160, refine=lambda d: 1.0)
    assert not out.omega_c.trusted and out.omega_c.value is None
    assert "mpmath-" in out.omega_c.note and "near-singular-map" in out.omega_c.note
