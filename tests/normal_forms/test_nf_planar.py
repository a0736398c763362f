"""Known-answer tests on planar maps: eq. (60) printed vs corrected, Wan, Kuznetsov, (A1)–(A3).

The map z -> lambda z (1 + c |z|^2), written in real coordinates and
conjugated by a quadratic+cubic near-identity change T and a linear M, has
c1 = 2 lambda c / ||M q_u||^2 and l1 = 2 Re(c) / ||M q_u||^2 exactly
(see ``_nf_maps``); its circle attracts iff Re(c) < 0.
"""

import numpy as np
import pytest

from ._nf_maps import base, conjugated, family_dA, linear
from symvi.errors import NearSingularWarning, ParameterError, SingularCaseError
from symvi.normal_forms.normal_form import eigen
from symvi.paper.reduction import normal_form   # Kuznetsov and the paper's reduction

THETA = 1.1


@pytest.mark.parametrize("c", [-0.3 + 0.7j, 0.25 - 0.4j, -1.0 + 0.0j])
@pytest.mark.parametrize("seed", [1, 2])
def test_planar_known_c1(c, seed):
    """Kuznetsov's c1, Wan's a and the corrected eq. (60) all return the constructed value."""
    f, c1, M = conjugated(THETA, c, seed=seed)
    nf = normal_form(*f)
    l1 = (np.exp(-1j * THETA) * c1).real
    assert abs(nf.c1 - c1) < 1e-10 * abs(c1)
    assert nf.l1 == pytest.approx(l1, rel=1e-10)
    # paper normalisation (||r1|| = 1, z = y1 + i y2 = 2 z_K): a = l1/4, f1 = -a
    assert nf.wan_a == pytest.approx(l1 / 4, rel=1e-10)
    assert nf.f1_wan == pytest.approx(-l1 / 4, rel=1e-10)
    assert nf.kind == ("supercritical" if c.real < 0 else "subcritical")


def test_eq60_printed_misses_quadratic_terms():
    """Eq. (60) as printed (conj(lambda0), not conj(lambda0)^2, in its first term) is wrong
    once the map has quadratic terms: it misses the constructed value by far more than
    rounding, while the corrected form hits it."""
    for seed in (1, 2, 3):
        f, c1, _ = conjugated(THETA, -0.3 + 0.7j, seed=seed)
        nf = normal_form(*f)
        want = -(np.exp(-1j * THETA) * c1).real / 4
        g = nf.paper.g
        assert abs(g["g20"] * g["g11"]) > 0.02          # the first term is really exercised
        assert nf.f1_wan == pytest.approx(want, rel=1e-10)
        assert abs(nf.f1_printed - want) > 1e-3 * abs(want)


def test_eq60_sign_convention():
    """Pure cubic map (no quadratic terms): printed and corrected (60) agree, and f1 > 0
    exactly when the circle attracts (Re c < 0) — the paper's convention, opposite to l1."""
    for c in (-0.5 + 0.2j, 0.5 + 0.2j):
        f = base(THETA, c)
        M = np.array([[1.3, 0.4], [-0.2, 0.9]])
        Mi = np.linalg.inv(M)
        A = M @ f[0] @ Mi
        d3 = np.einsum("ia,abcd,bj,ck,dl->ijkl", M, f[2], Mi, Mi, Mi)
        nf = normal_form(A, np.zeros((2, 2, 2)), d3)
        assert nf.f1_printed == pytest.approx(nf.f1_wan, rel=1e-12)
        assert (nf.f1_printed > 0) == (c.real < 0)
        assert (nf.l1 < 0) == (c.real < 0)
        # and the attracting case really attracts: iterate z -> 1.001 lambda z (1 + c|z|^2)
        lam, z = 1.001 * np.exp(1j * THETA), 0.01
        for _ in range(8000):
            z = lam * z * (1 + c * abs(z) ** 2)
            if abs(z) > 10:
                break
        assert (abs(abs(z) - np.sqrt(0.001 / -c.real)) < 1e-3) if c.real < 0 else abs(z) > 1


def test_dmod_A3():
    """(A1)–(A3) give d|lambda1|/dv = 1 for the family lambda(v) = (1 + v) e^{i theta}
    conjugated by M (omega0 in (A3) read as arg lambda0)."""
    th = 2.5
    f, _, M = conjugated(th, -0.3 + 0.7j, np.array([[0.2, 0.1], [-0.3, 0.4]]), seed=4)
    nf = normal_form(*f, dA=family_dA(M, th))
    assert nf.dmod_dv == pytest.approx(1.0, rel=1e-12)
    assert nf.dlam_dv == pytest.approx(np.exp(1j * th), rel=1e-12)
    # reading omega0 of (A3) as Im(lambda0) would give something else
    wrong = (nf.dlam_dv * np.exp(-1j * nf.lam.imag)).real
    assert abs(wrong - 1.0) > 0.05


def test_eigen_normalisation():
    """q: unit 2-norm, largest component real positive; p: adjoint, <p, q> = 1."""
    f, _, _ = conjugated(THETA, 0.1j, np.array([[0.2, 0.1], [-0.3, 0.4]]), seed=5)
    A = f[0]
    e = eigen(A)
    assert np.linalg.norm(e.q) == pytest.approx(1.0, abs=1e-14)
    j = np.argmax(abs(e.q))
    assert e.q[j].imag == 0 and e.q[j].real > 0
    assert np.allclose(A @ e.q, e.lam * e.q, atol=1e-13)
    assert np.allclose(A.T @ e.p, np.conj(e.lam) * e.p, atol=1e-13)
    assert np.vdot(e.p, e.q) == pytest.approx(1.0, abs=1e-13)
    assert np.vdot(e.p, np.conj(e.q)) == pytest.approx(0.0, abs=1e-13)
    assert e.lam.imag > 0 and abs(abs(e.lam) - 1) < 1e-13


def test_resonance_refused_and_warned():
    z2, z3 = np.zeros((2, 2, 2)), np.zeros((2, 2, 2, 2))
    A3 = base(2 * np.pi / 3, -1.0)[0]
    with pytest.raises(SingularCaseError, match="lambda1\\^3 = 1"):
        normal_form(A3, z2, z3)
    A4 = base(2 * np.pi / 4 + 1e-4, -1.0)[0]
    with pytest.warns(NearSingularWarning, match="strong resonance"):
        normal_form(A4, z2, z3)


def test_bad_input_is_named():
    with pytest.raises(SingularCaseError, match="no-complex-pair"):
        normal_form(np.diag([0.5, 0.2]), np.zeros((2, 2, 2)), np.zeros((2, 2, 2, 2)))
    with pytest.raises(ParameterError, match="d2/d3"):
        normal_form(np.eye(2), np.zeros((3, 3, 3)), np.zeros((2, 2, 2, 2)))
    with pytest.raises(ParameterError, match="A ="):
        normal_form(np.eye(1), np.zeros((1, 1, 1)), np.zeros((1, 1, 1, 1)))
    with pytest.raises(ParameterError, match="digits"):
        normal_form(*linear(np.eye(2)), digits=3)
    with pytest.raises(SingularCaseError, match="collision"):
        A = np.array([[0.5, 1.0], [-1.0, 0.5]])   # a Jordan block of a complex pair
        normal_form(np.block([[A, np.eye(2)], [np.zeros((2, 2)), A]]),
                    np.zeros((4, 4, 4)), np.zeros((4, 4, 4, 4)))
