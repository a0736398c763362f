"""Automatic precision of period-1 orbits of any model: the estimate bounds the true
error (40-digit reference) near forcing resonance and near 1 - cos -> 0, and an
orbit float64 cannot resolve is recomputed in mpmath."""
import math
import warnings

import mpmath
import numpy as np
import pytest

from symvi import Params
from symvi.analysis.precision import auto_model_orbits, estimate_model_orbit
from symvi.errors import NearSingularWarning
from symvi.flow.linear import LinearFlow
from symvi.orbits import period1_orbits
from symvi.paper.modal_orbit import period1_orbits as paper_orbits  # the modal oracle

from tests.zoo import PAPER_EX1, THREE_STOP2_GAP05

W1, W2 = (float(w) for w in LinearFlow.of(PAPER_EX1).omegas)
HARD = [W1 * (1 + 1e-7), W1 * (1 + 1e-5), W1 * (1 + 1e-3), W2 / 2 * (1 + 1e-7),
        W2 / 2 * (1 + 1e-5), 0.7369]


@pytest.mark.slow
@pytest.mark.parametrize("w", HARD)
def test_float64_estimate_bounds_the_true_error(w):
    from symvi.analysis.precision import estimate_model_orbit
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        ref = {o.branch: o for o in paper_orbits(Params(2, 5, 0, 1.5, 0.8), w, digits=40)}
        for o in period1_orbits(PAPER_EX1, w):
            est = estimate_model_orbit(PAPER_EX1, o)
            r = ref[o.branch]
            true = (max(abs(float(a) - float(b)) for a, b in zip(o.y, r.y))
                    / max(abs(float(v)) for v in r.y))
            assert true <= est.y.rel_err, (w, o.branch, true, est.y.rel_err)
            assert est.y.rel_err < 1e4 * max(true, 1e-16)     # and is not absurdly loose


@pytest.mark.slow
def test_unresolvable_orbit_is_recomputed_in_mpmath():
    w = W1 * (1 + 1e-8)          # float64: ~7.3 digits (1e-9: the same at 4x the cost)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        autos = auto_model_orbits(PAPER_EX1, w)
        ref = {o.branch: o for o in paper_orbits(Params(2, 5, 0, 1.5, 0.8), w, digits=40)}
    for a in autos:
        assert a.digits_used is not None and "mpmath" in a.note
        assert a.estimate.y.digits >= 8
        r = ref[a.orbit.branch]
        assert max(abs(float(x) - float(z)) for x, z in zip(a.orbit.y, r.y)) < 1e-12


def test_benign_orbit_stays_float64_with_its_digits():
    a = [x for x in auto_model_orbits(THREE_STOP2_GAP05, 0.95) if x.orbit.admissible][0]
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


# ---- a stiff mode (issue 23, defect 5) ---------------------------------------------------
#: the README's chain3 with a light first mass: an overdamped mode at lambda ~ -1.5e6
STIFF = THREE_STOP2_GAP05.with_(**{"mass[1]": 1e-8})
STIFF_TOML = """[model]
mass = [1e-8, 1.5, 0.8]
stiffness = [[1.0, -1.0, 0.0], [-1.0, 1.7, -0.7], [0.0, -0.7, 2.7]]
damping = [[0.015, -0.005, 0.0], [-0.005, 0.0235, -0.0035], [0.0, -0.0035, 0.0215]]
forcing = [1.0, 0.5, 0.0]
[stop]
mass = 2
gap = 0.5
restitution = 0.8
"""


def test_flow_condition_sees_the_rounding_of_a_stiff_mode():
    """The float64 e^{At} of the stiff chain is good to ~1e-10 only (the eigen-decomposition
    rounds at eps ||A||, ||A|| ~ 1e8): the flow condition predicts that error (4x, within
    a factor 2) where the input conditions (~80) see nothing."""
    from symvi.analysis.precision import EPS64, _flow_condition
    t = 2 * math.pi / 0.95
    phi = LinearFlow.of(STIFF).phi(t)
    with mpmath.workdps(40):
        ref = np.array(LinearFlow.of(STIFF, digits=40).phi(mpmath.mpf(t)).tolist(), dtype=float)
    true = np.abs(phi - ref).max() / np.abs(ref).max()
    pred = _flow_condition(STIFF, t) * EPS64 / 4
    assert true > 1e-11 and true / 2 <= pred <= 2 * true, (true, pred)
    assert _flow_condition(PAPER_EX1, t) < 1e3          # a benign model: within C_EVAL's range


def test_an_uncomputable_condition_makes_the_estimate_untrusted(monkeypatch):
    """A condition number that cannot be computed (NaN) is no reason to trust a result: it
    once was, because max() drops NaN (float64 overflow in the Fréchet derivative of
    e^{At}); the estimate now says untrusted and why, with no numpy warning."""
    from symvi.analysis import precision as pr
    from symvi.codegen import jets

    real = jets.parameter_derivatives

    def nan_for_gap(model, w, y, te, name, **kw):
        if name != "gap":
            return real(model, w, y, te, name, **kw)
        d = real(model, w, y, te, name)            # NaN in float64 and in mpmath alike
        if name == "gap":
            d = jets.ParameterDerivative(name, d.dP * np.nan, d.dJ, d.dy * np.nan,
                                         d.dJ_branch * np.nan)
        return d
    monkeypatch.setattr(jets, "parameter_derivatives", nan_for_gap)
    o = [x for x in period1_orbits(PAPER_EX1, 0.7368) if x.admissible][0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        est = pr.estimate_model_orbit(PAPER_EX1, o)
    assert not est.y.trusted and est.y.value is None and est.y.digits == 0
    assert "gap" in est.y.note and "not finite" in est.y.note
    assert not est.multipliers.trusted
    assert pr._worst([1.0, float("nan"), 2.0]) == math.inf == pr._worst([float("nan")])
    assert not pr._make("x", 1.0, 1e-10, float("nan"), None, "").trusted


@pytest.mark.slow
def test_stiff_chain_orbit_claims_no_more_digits_than_it_has(tmp_path):
    """``symvi orbit`` on the stiff chain: it claimed ~13.1 digits where float64 has ~10.2
    (every input condition was NaN, and max() dropped them), and leaked
    "symvi: warning: overflow encountered in expm1".  Now every claim is at most the true
    digits against a 40-digit reference, and stderr is empty."""
    import json

    from ..fuzz._cli import cli
    (tmp_path / "stiff.toml").write_text(STIFF_TOML)
    rc, out, err = cli("orbit", "--model", "stiff.toml", "--omega", "0.95", "--json",
                       cwd=tmp_path)
    assert rc == 0 and err == "", err
    ref = {o.branch: o for o in period1_orbits(STIFF, 0.95, digits=40)}
    f64 = {o.branch: o for o in period1_orbits(STIFF, 0.95)}
    for o in json.loads(out)["orbits"]:
        prec = o["precision"]["y"]
        r = ref[o["branch"]]
        # the float64 y*, whatever the escalation did, against the reference
        true64 = (max(abs(float(a) - float(b)) for a, b in zip(f64[o["branch"]].y, r.y))
                  / max(abs(float(b)) for b in r.y))
        assert true64 > 1e-11                                 # float64 has ~10 digits
        if prec["backend"] == "float64":
            assert prec["digits"] <= -math.log10(true64), (o["branch"], prec)
        else:                                                 # recomputed: at most the truth
            y = o["y"]
            err_mp = max(abs(a - float(b)) for a, b in zip(y, r.y)) / \
                max(abs(float(b)) for b in r.y)
            assert prec["trusted"] and err_mp < 1e-15
    est = estimate_model_orbit(STIFF, f64["+"])               # the float64 claim itself
    true = (max(abs(float(a) - float(b)) for a, b in zip(f64["+"].y, ref["+"].y))
            / max(abs(float(b)) for b in ref["+"].y))
    assert true <= est.y.rel_err < 100 * true, (true, est.y.rel_err)
