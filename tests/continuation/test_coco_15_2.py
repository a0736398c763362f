"""COCO's impact oscillator (Dankowicz & Schilder, Recipes for Continuation, Example 15.2;
the gallery page docs/gallery/coco_15_2.md): the impacting period-1 orbit continued in the
forcing amplitude ends at its grazing point, which has a closed form.

At a grazing impact the velocity is zero, the reset the identity, so the orbit is the
non-impacting harmonic response x_h = A/|D| sin(omega t + tau - arg D), D = k - omega^2 +
i c omega, touching the stop x = d at its maximum:

    A_GR = d |D|,    tau_GR = pi/2 + arg D  (mod 2 pi).

Near grazing, (A - A_GR)/|D| = kappa v- + O(v-^2) with kappa = (1 + e) G_T(0), G_T the
T-periodic response to unit impulses (derived on the gallery page): the arrival speed v-
grows linearly in A - A_GR, and where kappa < 0 the branch reaches grazing from below,
after a fold.
"""
import cmath
import math
from pathlib import Path

import pytest

import symvi
from symvi.continuation import continue_orbits

MODEL_FILE = Path(__file__).resolve().parents[2] / "docs" / "gallery" / "coco_15_2.toml"
#: below, at and above the natural frequency 1 (kappa > 0, < 0, < 0)
OMEGAS = (0.7, 1.0, 1.2)


@pytest.fixture(scope="module")
def model():
    return symvi.load_model(MODEL_FILE)


def _constants(model):
    """(m, k, c, d, e) of the model file."""
    return (model.value("mass[1]"), model.value("stiffness[1,1]"),
            model.value("damping[1,1]"), model.value("gap"), model.value("restitution"))


def _D(model, w):
    """k - m w^2 + i c w: the harmonic response is A / |D| sin(w t + tau - arg D)."""
    m, k, c, _, _ = _constants(model)
    return k - m * w * w + 1j * c * w


def _a_gr(model, w):
    return model.value("gap") * abs(_D(model, w))


@pytest.fixture(scope="module")
def branches(model):
    return {w: continue_orbits(model, "forcing[1]", 1.2 * _a_gr(model, w),
                               0.01 * _a_gr(model, w), omega=w) for w in OMEGAS}


def test_the_model_file_is_cocos(model):
    """demo.m: p0 = [k c A w d e] = [1 0.1 1 1 1 0.8], the stop at x1 = d."""
    assert _constants(model) == (1.0, 1.0, 0.1, 1.0, 0.8)
    assert model.value("forcing[1]") == 1.0


@pytest.mark.parametrize("w", OMEGAS)
def test_the_branch_ends_at_the_closed_form_grazing_point(model, branches, w):
    """The one branch ends where it stops being admissible, at its located grazing point:
    an impact arriving with zero velocity, at A_GR to 1e-10 relative (the corrector's
    tolerance is 1e-11 and the locator's 1e-14 in arclength; the docs promise about 1e-10
    in the parameter; measured: a few 1e-15)."""
    (br,) = branches[w]
    assert "stops being admissible" in br.end
    (g,) = [s for s in br.special if s.kind == "grazing"]
    assert g.orbit.admissible
    assert abs(g.coefficients["impact_velocity"]) < 1e-10
    assert abs(g.orbit.y[0]) < 1e-10                       # v1+ = -e v-, COCO's 'graze'
    a = _a_gr(model, w)
    assert abs(g.value - a) <= 1e-10 * a


@pytest.mark.parametrize("w", OMEGAS)
def test_the_grazing_orbit_is_the_harmonic_response_at_its_maximum(model, branches, w):
    """The forcing phase at the grazing impact is pi/2 + arg D: the forcing is
    A sin(omega t + tau) (COCO's A cos x3 with tau = x3 + pi/2)."""
    (br,) = branches[w]
    (g,) = [s for s in br.special if s.kind == "grazing"]
    tau = math.pi / 2 + cmath.phase(_D(model, w))
    assert abs(cmath.phase(cmath.exp(1j * (g.orbit.y[1] - tau)))) < 1e-9


def _kappa(model, w):
    """(1 + e) G_T(0) = (1 + e) Im(q / (1 - q)) / (m beta), q = exp((-alpha + i beta) T)."""
    m, k, c, _, e = _constants(model)
    alpha = c / (2 * m)
    beta = math.sqrt(k / m - alpha ** 2)
    q = cmath.exp((-alpha + 1j * beta) * 2 * math.pi / w)
    return (1 + e) * (q / (1 - q)).imag / (m * beta)


@pytest.mark.parametrize("w", OMEGAS)
def test_the_arrival_speed_grows_linearly_with_slope_kappa(model, w):
    """On the period-1 orbit at A = A_GR (1 + eps sign(kappa)), (A - A_GR)/(|D| v-) is kappa
    up to O(v-): the relative error shrinks tenfold from eps = 1e-5 to 1e-6 (a square-root
    law v- ~ sqrt(A - A_GR) would make the ratio tend to 0 instead)."""
    d, e = model.value("gap"), model.value("restitution")
    a, kap = _a_gr(model, w), _kappa(model, w)
    err = []
    for eps in (1e-5, 1e-6):
        A = a * (1 + math.copysign(eps, kap))
        orbits = symvi.period1_orbits(model.with_(**{"forcing[1]": A}), w)
        v_plus = max(o.y[0] for o in orbits if o.y[0] < 0)
        err.append(((A - a) / (a / d) / (-v_plus / e)) / kap - 1)
    assert abs(err[1]) < 1e-2
    assert abs(err[1]) < 0.2 * abs(err[0])


@pytest.mark.parametrize("w", OMEGAS)
def test_the_branch_grazes_from_kappas_side(model, branches, w):
    """kappa < 0 (omega = 1, 1.2): impacting orbits near grazing lie below A_GR, so the
    branch coming down from 1.2 A_GR turns at a fold below A_GR and grazes from below;
    kappa > 0 (omega = 0.7): no fold, it grazes from above."""
    (br,) = branches[w]
    a = _a_gr(model, w)
    folds = [s for s in br.special if s.kind == "fold"]
    assert (_kappa(model, w) < 0) == any(s.value < a and s.orbit.admissible for s in folds)
    before = [pt for pt in br.points if pt.admissible][-1]   # the last before grazing
    assert not br.points[-1].admissible and br.points[-2] is before
    if _kappa(model, w) > 0:
        assert before.value > a
