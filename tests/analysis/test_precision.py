"""symvi.precision: error estimates that bound the true error, automatic mpmath recomputation,
and untrustworthy results that are never bare numbers (issue 7, item 3)."""
import warnings

import mpmath
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import symvi
from symvi.analysis import precision as pr
from symvi.errors import NearSingularWarning, SingularCaseError, SymviError

EX1 = symvi.Params(2, 5, 0, 1.5, 0.8)
EX2 = symvi.Params(4, 2, 0, 1.8, 0.8)


def _f(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


params_typical = st.builds(symvi.Params, mu_m=_f(0.2, 6), mu_k=_f(0.2, 8), f2=_f(0, 1),
                           b=_f(-2, 3), r=_f(0.05, 1))


def true_errors(params, o, digits=40):
    """Normwise relative errors of y* and the multipliers against mpmath at ``digits``."""
    ref = [q for q in symvi.period1_orbits(params, o.omega, digits=digits)
           if q.branch == o.branch][0]
    ey = max(abs(float(a) - float(b)) for a, b in zip(o.y, ref.y)) / \
        max(abs(float(b)) for b in ref.y)
    m = pr._match(ref.multipliers, o.multipliers)
    el = max(abs(complex(a) - b) for a, b in zip(o.multipliers, m)) / max(abs(b) for b in m)
    return ey, el


@settings(max_examples=25, deadline=None,
          suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
@given(params_typical, _f(0.15, 3.5))
def test_orbit_estimate_bounds_true_error(params, omega):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        try:
            orbits = [o for o in symvi.period1_orbits(params, omega) if o.admissible]
        except SymviError:
            orbits = []
        assume(orbits)
        for o in orbits:
            est = pr.estimate_orbit(params, o)
            ey, el = true_errors(params, o)
            assert ey <= est.y.rel_err, (ey, est.y)
            assert el <= est.multipliers.rel_err, (el, est.multipliers)


def test_orbit_estimate_is_not_vacuous():
    """Over a sample, the estimate is within 10^4 of the true error (median)."""
    rng = np.random.default_rng(3)
    ratios = []
    while len(ratios) < 15:
        p = symvi.Params(rng.uniform(0.2, 6), rng.uniform(0.2, 8), rng.uniform(0, 1),
                         rng.uniform(-2, 3), rng.uniform(0.05, 1))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NearSingularWarning)
            try:
                orbs = [o for o in symvi.period1_orbits(p, rng.uniform(0.15, 3.5))
                        if o.admissible]
            except SymviError:
                continue
        for o in orbs[:1]:
            ey, _ = true_errors(p, o)
            ratios.append(pr.estimate_orbit(p, o).y.rel_err / max(ey, 2.0 ** -53))
    assert np.median(ratios) < 1e4, sorted(ratios)


def test_well_conditioned_orbit_stays_float64():
    (a,) = [x for x in pr.auto_orbits(EX1, 0.7368) if x.orbit.admissible]
    assert a.digits_used is None and a.estimate.trusted
    assert a.estimate.y.digits >= 12 and a.estimate.multipliers.digits >= 11
    assert not a.estimate.y.recomputed


def test_near_resonance_estimate_tracks_the_loss():
    """omega_1 (1 + 1e-5): ~12 true digits; the estimate is below the truth, above 8."""
    p = EX1
    w = symvi.modal(p).omega1 * (1 + 1e-5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        o = [o for o in symvi.period1_orbits(p, w) if o.branch == "+"][0]
        est = pr.estimate_orbit(p, o)
        ey, _ = true_errors(p, o, 60)
    assert ey <= est.y.rel_err and 8 <= est.y.digits <= 12


@pytest.mark.parametrize("dist", [1e-7])
def test_near_resonance_recomputes_with_mpmath(dist):
    """omega within dist (relative) of omega_1: A_1 and cot(pi omega_1/omega) blow up and
    cancel, float64 loses ~log10(1/dist) digits and at 1e-7 calls the orbit grazing; the
    estimate sees the loss, auto settles the grazing verdict with mpmath, and agrees with
    a 60-digit reference."""
    p = EX1
    w = symvi.modal(p).omega1 * (1 + dist)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        res = {a.orbit.branch: a for a in pr.auto_orbits(p, w)}
        f64 = {o.branch: o for o in symvi.period1_orbits(p, w)}
        ref = {o.branch: o for o in symvi.period1_orbits(p, w, digits=60)}
    assert ref["+"].admissible
    a = res["+"]
    est = pr.estimate_orbit(p, f64["+"])                       # float64 estimate saw the loss
    true = max(abs(float(x) - float(y)) for x, y in zip(f64["+"].y, ref["+"].y)) / \
        max(abs(float(y)) for y in ref["+"].y)
    assert est.y.condition > 1e5 and true <= est.y.rel_err < 1e-7
    assert a.digits_used is not None and a.digits_used > 16
    assert "recomputed with mpmath" in a.note and a.estimate.y.recomputed
    assert a.orbit.admissible                                   # the right verdict
    err = max(abs(float(x) - float(y)) for x, y in zip(a.orbit.y, ref["+"].y)) / \
        max(abs(float(y)) for y in ref["+"].y)
    assert err < 1e-8
    if dist == 1e-7:
        assert not f64["+"].admissible and "admissibility corrected" in a.note


def test_untrusted_is_never_a_bare_number():
    """Too close to resonance for the precision cap: flagged, value None, float() raises."""
    p = EX1
    w = symvi.modal(p).omega1 * (1 + 1e-7)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        res = pr.auto_orbits(p, w, min_digits=8, max_digits=17)
    flagged = [a for a in res if not a.estimate.trusted]
    assert flagged
    for a in flagged:
        e = a.estimate.y
        assert e.value is None and e.digits == 0 and "untrusted" in a.note
        assert e.as_dict()["value"] is None
        assert "UNTRUSTED" in e.text()
        with pytest.raises(SingularCaseError):
            float(e)


def _reference_hopf(params, omega_c, digits=60):
    w = pr.refine_omega_c(params, omega_c, digits=digits)
    return pr.estimate_hopf_point(params, w, digits=digits)


@pytest.mark.parametrize("params,omega0", [(EX1, 0.7368769), (EX2, 0.4905195)])
def test_hopf_estimate_bounds_error_and_meets_targets(params, omega0):
    """Paper, Sec. 4: v_c ~ 0.7368 (ex. 1) and 0.4906 (ex. 2); our float64 chain and its
    estimate against a 60-digit reference of the same generated chain."""
    wc = pr.refine_omega_c(params, omega0)
    est = pr.estimate_hopf_point(params, wc)
    ref = _reference_hopf(params, wc)
    for e, r in ((est.omega_c, ref.omega_c), (est.dmod_domega, ref.dmod_domega),
                 (est.l1, ref.l1)):
        true = abs(float(e.value) - float(r.value)) / abs(float(r.value))
        assert true <= e.rel_err, (e.name, true, e.rel_err)
        assert r.digits >= 40
    assert est.omega_c.digits >= 11 and est.dmod_domega.digits >= 11 and est.l1.digits >= 8


def test_auto_hopf_point_escalates_when_asked_for_more_digits():
    wc = pr.refine_omega_c(EX1, 0.7368769)
    a = pr.auto_hopf_point(EX1, wc, min_digits=20)
    assert a.trusted and a.digits >= 20
    assert a.omega_c.recomputed and "recomputed with mpmath" in a.l1.note
    ref = _reference_hopf(EX1, wc)
    with mpmath.mp.workdps(60):
        for e, r in ((a.omega_c, ref.omega_c), (a.dmod_domega, ref.dmod_domega),
                     (a.l1, ref.l1)):
            assert abs(e.value - r.value) / abs(r.value) < 1e-20, e.name


def test_mp_omega_not_rounded():
    """period1_orbits(digits=...) keeps an mpf omega unrounded (was rounded via check_omega)."""
    with mpmath.mp.workdps(50):
        w0 = mpmath.mpf("0.7368")
        a = symvi.period1_orbits(EX1, w0, digits=50)[0]
        b = symvi.period1_orbits(EX1, w0 + mpmath.mpf("1e-30"), digits=50)[0]
        assert a.tau0 != b.tau0


def test_estimate_json_and_text():
    (a,) = [x for x in pr.auto_orbits(EX1, 0.7368) if x.orbit.admissible]
    d = a.estimate.y.as_dict()
    assert set(d) >= {"value", "rel_err", "digits", "backend", "trusted", "recomputed", "note"}
    assert d["backend"] == "float64" and len(d["value"]) == 4
    assert "digits" in a.estimate.y.text()


def test_auto_rejects_unknown_kind():
    with pytest.raises(SymviError):
        pr.auto("nonsense", EX1, 0.7)
