"""4-D maps with a known, curved centre manifold: W_ij, g_ij, eqs. (44)–(54), (A4)–(A17)."""
import numpy as np
import pytest

from ._nf_maps import conjugated, eval_poly, family_dA
from dataclasses import replace

from symvi.normal_forms.normal_form import transform_jet
from symvi.paper.reduction import appendix_printed, normal_form   # with the reduction
from symvi.paper.audit import printed_W

THETA = 1.1
D0 = np.array([[0.3, -0.4], [0.5, 0.2]])          # a stable complex pair
D0_REAL = np.array([[0.6, 0.0], [0.3, -0.45]])   # stable real multipliers


@pytest.mark.parametrize("D", [D0, D0_REAL])
@pytest.mark.parametrize("seed", [1, 7])
def test_4d_known_l1(D, seed):
    """The reduction returns the constructed c1, and the W_ij terms are what makes it right."""
    f, c1, _ = conjugated(THETA, -0.3 + 0.7j, D, seed=seed)
    nf = normal_form(*f)
    l1 = (np.exp(-1j * THETA) * c1).real
    assert abs(nf.c1 - c1) < 1e-10 * abs(c1)
    assert nf.f1_wan == pytest.approx(-l1 / 4, rel=1e-10)
    # without the centre-manifold terms of eq. (54) the answer is far off
    pr = nf.paper
    assert abs(pr.g["g21"] - pr.G["G21"]) > 0.05 * abs(pr.g["g21"])


def _series(W, z, key02="W02", key30="W30"):
    zb = np.conj(z)
    return (W["W20"] * z * z / 2 + W["W11"] * z * zb + W[key02] * zb * zb / 2
            + W[key30] * z ** 3 / 6 + W["W21"] * z * z * zb / 2
            + np.conj(W["W21"]) * z * zb * zb / 2 + np.conj(W[key30]) * zb ** 3 / 6)


def _residuals(f, pr, lam, eps, key02="W02", key30="W30", phi=0.37):
    """Residuals of eq. (44) (W part) and of the reduced map (51)–(53) at |z| = eps."""
    z = eps * np.exp(1j * phi)
    zb = np.conj(z)
    w = _series(pr.W, z, key02, key30).real
    Y = np.concatenate([[z.real, z.imag], w])
    Yp = pr.Pinv.real @ eval_poly(f, pr.P.real @ Y)
    zp = Yp[0] + 1j * Yp[1]
    g = pr.g
    zred = (lam * z + g["g20"] * z * z / 2 + g["g11"] * z * zb + g["g02"] * zb * zb / 2
            + g["g30"] * z ** 3 / 6 + g["g21"] * z * z * zb / 2 + g["g12"] * z * zb * zb / 2
            + g["g03"] * zb ** 3 / 6)
    return np.linalg.norm(Yp[2:] - _series(pr.W, zp, key02, key30).real), abs(zp - zred)


def test_invariance_residual_order():
    """Corrected W_ij solve eq. (44) to O(|z|^4) and the g_ij reproduce the restricted map to
    O(|z|^4); the printed W_02 of (A10) fails at O(|z|^2), the printed W_30 of (46) at O(|z|^3)."""
    f, _, _ = conjugated(THETA, -0.3 + 0.7j, D0, seed=1)
    nf = normal_form(*f)
    pr, lam = nf.paper, nf.lam
    order = lambda r1, r2: np.log2(r1 / r2)              # noqa: E731  (eps halved)
    (w1, z1), (w2, z2) = (_residuals(f, pr, lam, e) for e in (2e-2, 1e-2))
    assert order(w1, w2) > 3.8 and order(z1, z2) > 3.8
    # reality of the manifold needs W02 = conj(W20); the printed (A10) breaks it
    assert np.allclose(pr.W["W02"], np.conj(pr.W["W20"]), atol=1e-13)
    # the errata variants live with the audit (symvi.paper), off the production path
    assert "W02_printed" not in pr.W and "W30_printed" not in pr.W
    pr = replace(pr, W={**pr.W, **printed_W(pr, lam)})
    assert not np.allclose(pr.W["W02_printed"], np.conj(pr.W["W20"]), atol=1e-3)
    (w1, _), (w2, _) = (_residuals(f, pr, lam, e, key02="W02_printed") for e in (2e-2, 1e-2))
    assert 1.8 < order(w1, w2) < 2.2
    (w1, _), (w2, _) = (_residuals(f, pr, lam, e, key30="W30_printed") for e in (2e-2, 1e-2))
    assert 2.8 < order(w1, w2) < 3.2


def test_printed_appendix_matches_wirtinger():
    """Eqs. (A4)–(A9), (A11), (A12), (A14)–(A16) as printed equal the Wirtinger derivatives."""
    f, _, _ = conjugated(THETA, -0.3 + 0.7j, D0, seed=3)
    nf = normal_form(*f)
    pr = nf.paper
    d2Y = transform_jet(pr.Pinv, pr.P, f[1].astype(complex)).real
    d3Y = transform_jet(pr.Pinv, pr.P, f[2].astype(complex)).real
    ap = appendix_printed(d2Y, d3Y)
    pairs = {"g11": pr.G["G11"], "g02": pr.G["G02"], "g20": pr.G["G20"], "G21": pr.G["G21"],
             "G30": pr.G["G30"], "G03": pr.G["G03"], "H11": pr.H["H11"], "H20": pr.H["H20"],
             "H30": pr.H["H30"], "G10": pr.G["G10"], "G01": pr.G["G01"]}
    for k, v in pairs.items():
        assert np.allclose(np.asarray(ap[k], complex), v, rtol=1e-12, atol=1e-12), k
    # and DF(0) has the block form of eq. (41)
    AY = pr.Pinv @ f[0] @ pr.P
    assert np.allclose(AY[:2, :2], [[nf.lam.real, -nf.lam.imag], [nf.lam.imag, nf.lam.real]])
    assert np.allclose(AY[:2, 2:], 0, atol=1e-13) and np.allclose(AY[2:, :2], 0, atol=1e-13)


def test_circle_prediction_by_iteration():
    """Iterating the cubic map of the family (d|lambda|/d rate = 1) past the bifurcation:
    the measured half-widths match circle.half_widths(mu) to 0.5 %."""
    f, _, M = conjugated(THETA, -0.3 + 0.7j, D0, seed=1)
    nf = normal_form(*f, dA=family_dA(M, THETA))
    circle = nf.circle
    assert circle.side == 1 and circle.stable
    mu = 1e-3
    fm, _, _ = conjugated(THETA, -0.3 + 0.7j, D0, seed=1, M=M, rate=mu)
    x = np.array([1e-3, 0, 0, 0])
    for _ in range(12000):
        x = eval_poly(fm, x)
    xs = []
    for _ in range(3000):
        x = eval_poly(fm, x)
        xs.append(x)
    xs = np.array(xs)
    measured = (xs.max(0) - xs.min(0)) / 2
    assert np.allclose(measured, circle.half_widths(mu), rtol=5e-3)
    assert circle.radius_paper(mu) == pytest.approx(2 * circle.radius(mu))
    with pytest.raises(Exception, match="mu"):
        circle.radius(-mu)
