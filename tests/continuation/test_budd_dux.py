"""Budd & Dux's (1, n) orbits of the impact oscillator (the gallery page docs/gallery/budd_dux.md,
issue 26) against their closed form, read from the page's model file.

x'' + x = cos(omega t), x <= sigma, xdot -> -r xdot at x = sigma [C. Budd & F. Dux, Chattering
and related behaviour in impact oscillators, Phil. Trans. R. Soc. A 347 (1994) 365-389]: a
(1, n) orbit (one impact in n forcing periods) is symvi's n-1 orbit.  The closed form (derived
on the page): with T = 2 pi n / omega, C = 1 / (1 - omega^2), kappa = cot(T / 2), the impact
velocity V solves

    [(1+r)^2 kappa^2 + (1-r)^2 / omega^2] V^2 / 4 + sigma (1+r) kappa V + sigma^2 - C^2 = 0,

the forcing at the impact is cos(omega t + phi) with C cos phi = sigma + (1+r) V kappa / 2 and
C omega sin phi = -(1-r) V / 2 (symvi's tau = phi + pi/2: its forcing is sin(omega t + tau)),
and the impact map has det J = r^2, tr J = -2 r cos T + (1+r) sin T (cos phi - sigma) / V:
flips where 1 + r^2 + tr J = 0 (at sigma = 0: tan^2(pi n/omega) = omega^2 - 1 - ((1-r)/(1+r))^2),
folds where the discriminant vanishes,
(1+r)^2 omega^2 cot^2(pi n/omega) = (1-r)^2 (sigma^2 (omega^2-1)^2 - 1).  With damping
(:func:`closed_damped`) the same conditions are affine in V through the flow Phi(T), and
det J = r^2 exp(-2 zeta T).

Tolerances: an orbit is Newton's (its last correction below NEWTON_TOL = 1e-11 relative to
1 + max|u| <= 20, the error after it quadratically smaller: 1e-9 relative to V >= 0.1 leaves a
margin of 10^3 over that bound's worst case and of 10^5 over what is seen, ~1e-14); a special
point is located on the corrected branch (CORR_TOL = 1e-11 relative, located points moved by up
to ~4e-12), so 1e-9 in omega.  A wrong convention (r, the phase, the sign of sigma) is O(1) off.
"""
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

import symvi
from symvi.continuation import continue_orbits
from symvi.orbits.periodic import from_simulation

MODEL_FILE = Path(__file__).resolve().parents[2] / "docs" / "gallery" / "budd_dux.toml"


@pytest.fixture(scope="module")
def model():
    return symvi.load_model(MODEL_FILE)


# --------------------------------------------------------------------------- closed form
def closed_orbits(n, w, r, sigma):
    """[(V, phi), ...] of the (1, n) orbits at omega = w, larger V first."""
    C, k = 1 / (1 - w * w), 1 / math.tan(math.pi * n / w)
    a = ((1 + r) ** 2 * k * k + (1 - r) ** 2 / (w * w)) / 4
    b, c = sigma * (1 + r) * k, sigma * sigma - C * C
    disc = b * b - 4 * a * c
    if disc < 0:
        return []
    Vs = sorted({(-b + math.sqrt(disc)) / (2 * a), (-b - math.sqrt(disc)) / (2 * a)},
                reverse=True)
    return [(V, math.atan2(-V * (1 - r) / (2 * C * w), (sigma + V * (1 + r) * k / 2) / C))
            for V in Vs if V > 0]


def closed_trace(n, w, r, sigma, V, phi):
    T = 2 * math.pi * n / w
    return -2 * r * math.cos(T) + (1 + r) * math.sin(T) * (math.cos(phi) - sigma) / V


def _roots(f, lo, hi, m=2000):
    x = np.linspace(lo, hi, m + 1)
    y = np.array([f(v) for v in x])
    return [brentq(f, x[i], x[i + 1], xtol=1e-15, rtol=1e-15)
            for i in range(m) if y[i] * y[i + 1] < 0]


def closed_flips_at_rest(n, r, lo, hi):
    """sigma = 0: tan^2(pi n / omega) = omega^2 - 1 - q^2, times cos^2 to stay continuous."""
    q2 = ((1 - r) / (1 + r)) ** 2
    return _roots(lambda w: math.sin(math.pi * n / w) ** 2
                  - (w * w - 1 - q2) * math.cos(math.pi * n / w) ** 2, lo, hi)


def closed_folds(n, r, sigma, lo, hi):
    def f(w):
        t = math.pi * n / w
        return ((1 + r) ** 2 * w * w * math.cos(t) ** 2
                - (1 - r) ** 2 * (sigma ** 2 * (w * w - 1) ** 2 - 1) * math.sin(t) ** 2)
    return [w for w in _roots(f, lo, hi) if sigma / math.tan(math.pi * n / w) < 0]


def closed_damped(n, w, r, sigma, zeta):
    """[(V, phi), ...] with damping: periodicity (sigma, V) - y_p(0) = Phi(T) [(sigma, -r V) -
    y_p(0)] gives y_p(0) = alpha V + beta sigma, and the forced response's amplitude
    x_p(0)^2 + (xdot_p(0) / omega)^2 = |H|^2, H = 1 / (1 - omega^2 + 2 i zeta omega), a quadratic
    in V; x_p = |H| cos(omega t + phi + arg H)."""
    T, wd = 2 * math.pi * n / w, math.sqrt(1 - zeta ** 2)
    c, s = math.cos(wd * T), math.sin(wd * T)
    Phi = math.exp(-zeta * T) * np.array([[c + zeta / wd * s, s / wd],
                                          [-s / wd, c - zeta / wd * s]])
    K = np.linalg.inv(np.eye(2) - Phi)
    alpha = K @ (np.array([0.0, 1.0]) + r * Phi[:, 1])
    beta = K @ (np.array([1.0, 0.0]) - Phi[:, 0])
    H = 1 / complex(1 - w * w, 2 * zeta * w)
    S = np.diag([1.0, 1 / w ** 2])
    a, b = alpha @ S @ alpha, 2 * sigma * alpha @ S @ beta
    disc = b * b - 4 * a * (sigma ** 2 * beta @ S @ beta - abs(H) ** 2)
    roots = {(-b + math.sqrt(disc)) / (2 * a), (-b - math.sqrt(disc)) / (2 * a)} if disc >= 0 else ()
    out = []
    for V in sorted(roots, reverse=True):
        if V > 0:
            xp, vp = alpha * V + beta * sigma
            out.append((V, math.atan2(-vp / w, xp) - math.atan2(H.imag, H.real)))
    return out


# --------------------------------------------------------------------------- the tests
def test_the_model_file_is_budd_and_duxs_setting(model):
    """Undamped, r = 0.8, the stop at the rest position, unit forcing; not conservative."""
    assert model.value("restitution") == 0.8 and model.value("gap") == 0.0
    assert not model.damped and not model.conservative
    assert model.value("forcing[1]") == 1.0


@pytest.mark.parametrize("n, omegas", [(1, (1.6, 2.2)), (2, (3.6, 4.3)), (3, (5.6, 6.4))])
def test_impact_velocity_phase_and_multipliers_match_the_closed_form(model, n, omegas):
    """The n-1 orbit a run of the map settles on (no closed form in its guess): V, tau and
    the multipliers' sum and product against the closed form."""
    r = model.value("restitution")
    for w in omegas:
        sim = symvi.simulate(model, w, n_impacts=50, transient=2000)
        orb = from_simulation(sim)
        assert (orb.n, orb.p) == (n, 1) and orb.admissible and orb.stable
        (V, phi), = closed_orbits(n, w, r, 0.0)
        assert orb.impact_velocities[0] == pytest.approx(V, rel=1e-9)
        assert orb.y[0] == pytest.approx(-r * V, rel=1e-9)            # v1+ = -r V
        dtau = (orb.y[1] - (phi + math.pi / 2) + math.pi) % (2 * math.pi) - math.pi
        assert abs(dtau) < 1e-9                                      # tau = phi + pi/2
        mu = np.asarray(orb.multipliers)
        assert np.prod(mu).real == pytest.approx(r * r, rel=1e-9)
        assert np.sum(mu).real == pytest.approx(closed_trace(n, w, r, 0.0, V, phi),
                                                abs=1e-9)


def test_the_stable_1_2_window_is_bounded_by_the_closed_form_flips(model):
    """sigma = 0: the (1, 2) branch from omega = 4 has its flips where
    tan^2(2 pi / omega) = omega^2 - 1 - ((1-r)/(1+r))^2, and is stable between them."""
    r = model.value("restitution")
    brs = continue_orbits(model, "omega", 2.9, 5.5, orbit="2-1", start_omega=4.0)
    flips = sorted(s.value for b in brs for s in b.special if s.kind == "flip")
    expected = [w for w in closed_flips_at_rest(2, r, 2.9, 5.5)]
    assert len(flips) == len(expected) == 2
    assert flips == pytest.approx(expected, abs=1e-9)
    inside = [p for b in brs for p in b.points if expected[0] < p.value < expected[1]]
    assert inside and all(p.stable for p in inside)
    for b in brs:                                      # V along the whole branch
        for p in b.points[::10]:
            (V, _), = closed_orbits(2, p.value, r, 0.0)
            assert p.orbit.impact_velocities[0] == pytest.approx(V, rel=1e-9)


def test_no_fold_at_rest_and_the_fold_with_a_gap(model):
    """sigma = 0: one (1, n) orbit at each omega, no fold (the closed form has none and the
    branch shows none).  sigma = 0.1: the (1, 2) branch from a run at omega = 3.7 turns at
    the closed form's fold, where tr J = 1 + r^2 on the double root."""
    r = model.value("restitution")
    assert closed_folds(2, r, 0.0, 2.9, 5.5) == []
    gap = model.with_(gap=0.1)
    sim = symvi.simulate(gap, 3.7, [-1.0, 0.0], n_impacts=200, transient=3000)
    brs = continue_orbits(gap, "omega", 3.2, 4.2, orbit="2-1", simulation=sim)
    folds = [s.value for b in brs for s in b.special if s.kind == "fold"]
    expected = closed_folds(2, r, 0.1, 3.35, 4.2)
    assert len(folds) == len(expected) == 1
    assert folds[0] == pytest.approx(expected[0], abs=1e-9)
    # the derivation's own check: at the fold the two roots meet and the multiplier is +1
    w = expected[0]
    (Va, pa), (Vb, pb) = closed_orbits(2, w - 1e-7, r, 0.1)
    assert abs(Va - Vb) < 1e-2 * Va
    assert closed_trace(2, w - 1e-7, r, 0.1, Va, pa) == pytest.approx(1 + r * r, abs=1e-2)
    assert closed_orbits(2, w + 1e-7, r, 0.1) == []


def test_the_damped_closed_form_is_the_undamped_one_at_zeta_0():
    for n, w, sigma in [(1, 1.6, 0.0), (2, 4.3, 0.0), (2, 3.7, 0.1), (3, 5.5, 0.1)]:
        a, b = closed_orbits(n, w, 0.8, sigma), closed_damped(n, w, 0.8, sigma, 0.0)
        assert len(a) == len(b) >= 1
        for (Va, pa), (Vb, pb) in zip(a, b):
            assert Vb == pytest.approx(Va, rel=1e-12)
            assert abs((pa - pb + math.pi) % (2 * math.pi) - math.pi) < 1e-12


@pytest.mark.parametrize("n", [1, 2, 3])
def test_damped_orbits_match_the_closed_form(model, n):
    """zeta = 0.05 (the file's damping[1,1] is 2 zeta): at omega = 2n and 2n - 0.4 the orbit a
    run settles on has the closed form's V and tau, and det = r^2 exp(-2 zeta T)."""
    zeta, r = 0.05, model.value("restitution")
    damped = model.with_(**{"damping[1,1]": 2 * zeta})
    for w in (2.0 * n, 2.0 * n - 0.4):
        orb = from_simulation(symvi.simulate(damped, w, n_impacts=50, transient=2000))
        assert (orb.n, orb.p) == (n, 1)
        (V, phi), = closed_damped(n, w, r, 0.0, zeta)
        assert orb.impact_velocities[0] == pytest.approx(V, rel=1e-9)
        dtau = (orb.y[1] - (phi + math.pi / 2) + math.pi) % (2 * math.pi) - math.pi
        assert abs(dtau) < 1e-9
        T = 2 * math.pi * n / w
        assert np.prod(orb.multipliers).real == pytest.approx(r * r * math.exp(-2 * zeta * T),
                                                              rel=1e-9)
