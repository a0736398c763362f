"""The one precision backend (symvi.numerics.backend): float64 and mpmath agree, mpmath at
50 digits beats float64 against a known answer, context() sets and restores mp.dps, and
is_mp recognises mpmath numbers and arrays."""
import cmath
from fractions import Fraction
from math import comb

import mpmath
import numpy as np
import pytest

from symvi.numerics.backend import FLOAT64, backend, is_mp

#: small test matrices: nonsymmetric real with a complex pair, and complex
A_REAL = [[0.9, -0.4, 0.1], [0.5, 0.7, -0.2], [0.05, 0.3, 0.6]]
A_CPLX = [[1 + 0.5j, 0.2, -0.3j], [0.1j, 0.8, 0.4], [0.3, -0.2 + 0.1j, 1.2]]
B = [1.0, -2.0, 0.5]
#: a mass and a stiffness matrix (positive definite) for eigh_pair
M_SPD = [[2.0, 0.3], [0.3, 1.0]]
K_SPD = [[3.0, -1.0], [-1.0, 1.5]]


def _c(x):
    """An array of Python complex numbers, from either backend."""
    return np.array([complex(v) for v in np.ravel(x)]).reshape(np.shape(x))


def _close(a, b, tol=1e-13):
    a, b = _c(a), _c(b)
    return np.max(np.abs(a - b)) <= tol * max(1.0, np.max(np.abs(b)))


MP30 = backend(30)


def _both(fn, *mats, kind="arr"):
    """fn(bk, *arrays) in float64 and in mpmath at 30 digits."""
    out = []
    for bk in (FLOAT64, MP30):
        with bk.context():
            out.append(fn(bk, *(getattr(bk, kind)(m) for m in mats)))
    return out


def _eig_sorted(bk, A):
    w, V = bk.ceig(A)
    order = sorted(range(len(w)), key=lambda i: (round(float(complex(w[i]).real), 9),
                                                  float(complex(w[i]).imag)))
    # each column scaled to its first component 1 (eigenvectors are defined up to a factor)
    V = np.array([[V[i, j] / V[0, j] for j in order] for i in range(len(w))], dtype=object)
    return [w[i] for i in order], V


@pytest.mark.parametrize("A", [A_REAL, A_CPLX])
def test_eig_agrees(A):
    (w64, V64), (w30, V30) = _both(_eig_sorted, A, kind="carr")
    assert _close(w64, w30) and _close(V64, V30, 1e-12)
    assert any(abs(complex(w).imag) > 0.1 for w in w30)          # a complex pair is in it


def test_eig_of_a_real_matrix_keeps_real_eigenvalues_real_in_mpmath():
    """eig gives what the library gives (a real eigenvalue of a real matrix is an mpf: the
    flow compares them), ceig makes them complex."""
    with MP30.context():
        w, _ = MP30.eig(MP30.arr([[2.0, 1.0], [0.0, 3.0]]))
        cw, cV = MP30.ceig(MP30.arr([[2.0, 1.0], [0.0, 3.0]]))
    assert all(isinstance(x, mpmath.mpf) for x in w)
    assert all(isinstance(x, mpmath.mpc) for x in list(cw) + list(cV.ravel()))
    w64, V64 = FLOAT64.ceig(np.array([[2.0, 1.0], [0.0, 3.0]]))
    assert w64.dtype == complex and V64.dtype == complex


@pytest.mark.parametrize("A", [A_REAL, A_CPLX])
def test_solve_and_inv_agree(A):
    kind = "carr" if A is A_CPLX else "arr"
    s64, s30 = _both(lambda bk, M, b: bk.solve(M, b), A, B, kind=kind)
    i64, i30 = _both(lambda bk, M: bk.inv(M), A, kind=kind)
    assert _close(s64, s30) and _close(i64, i30)
    c64, c30 = _both(lambda bk, M, b: bk.csolve(M, b), A, B, kind=kind)
    assert c64.dtype == complex and all(isinstance(x, mpmath.mpc) for x in c30)
    assert _close(c64, s30)


def test_eigh_pair_agrees():
    (w64, P64), (w30, P30) = _both(lambda bk, K, M: bk.eigh_pair(K, M), K_SPD, M_SPD)
    assert _close(w64, w30)
    # modes up to sign: psi^T M psi = I in both, and |psi| agrees
    assert _close(np.abs(_c(P64)), np.abs(_c(P30)))
    assert _close(_c(P64).T @ np.array(M_SPD) @ _c(P64), np.eye(2))
    assert float(w30[0]) < float(w30[1])                          # ascending


def test_elementwise_and_scalar_ops_agree():
    v = [0.3 + 1.2j, -0.5 + 0.0j, 2.0 - 0.7j]
    e64, e30 = _both(lambda bk, x: bk.vexp(x), v, kind="carr")
    assert _close(e64, e30) and _close(e64, [cmath.exp(z) for z in v])
    r64, r30 = _both(lambda bk, x: (bk.vreal(x), bk.vabs(x)), v, kind="carr")
    assert _close(r64[0], r30[0]) and _close(r64[1], r30[1])
    assert r64[0].dtype == float and all(isinstance(x, mpmath.mpf) for x in r30[0])
    for bk in (FLOAT64, MP30):
        with bk.context():
            z = bk.carr(0.6 + 0.8j) if bk is MP30 else 0.6 + 0.8j
            assert abs(complex(bk.cexp(1j * bk.arg(z))) - (0.6 + 0.8j)) < 1e-15
            assert abs(complex(bk.csqrt(bk.num(-4.0))) - 2j) < 1e-15
            assert abs(float(bk.sqrt(bk.num(2.0))) ** 2 - 2) < 1e-15
            assert abs(float(bk.atan2(bk.num(1.0), bk.num(1.0))) - float(bk.pi) / 4) < 1e-15
            assert float(bk.real(bk.carr([3 - 4j])[0] if bk is MP30 else 3 - 4j)) == 3.0
    assert isinstance(FLOAT64.sqrt(4.0), float) and isinstance(FLOAT64.csqrt(4.0), complex)


def _hilbert_inverse(n):
    """The exact inverse of the n x n Hilbert matrix 1 / (i + j + 1) (integers)."""
    return [[(-1) ** (i + j) * (i + j + 1) * comb(n + i, n - j - 1) * comb(n + j, n - i - 1)
             * comb(i + j, i) ** 2 for j in range(n)] for i in range(n)]


def test_mpmath_at_50_digits_beats_float64_on_a_known_answer():
    """inv(H_8), cond ~ 1e10: float64 keeps ~6 digits, mpmath at 50 digits ~40."""
    n, exact = 8, _hilbert_inverse(8)
    errs = {}
    for bk in (FLOAT64, backend(50)):
        with bk.context():
            H = bk.arr([[bk.num(1) / (i + j + 1) for j in range(n)] for i in range(n)])
            Hi = bk.inv(H)
            errs[bk.name] = max(abs(Fraction(str(Hi[i, j])) - exact[i][j]) / abs(exact[i][j])
                                for i in range(n) for j in range(n))
    assert errs["mpmath"] < 1e-35
    assert errs["float64"] > 1e-12                # float64 cannot do it: the test can fail
    assert errs["mpmath"] < 1e-20 * errs["float64"]


def test_context_sets_and_restores_dps():
    before = mpmath.mp.dps
    with backend(45).context():
        assert mpmath.mp.dps == 45
        assert backend(45).eps == mpmath.mp.eps            # read at the current precision
    assert mpmath.mp.dps == before
    with pytest.raises(RuntimeError):
        with backend(70).context():
            assert mpmath.mp.dps == 70
            raise RuntimeError
    assert mpmath.mp.dps == before
    with FLOAT64.context():
        assert mpmath.mp.dps == before


def test_one_constructor():
    assert backend() is FLOAT64 and backend(None) is FLOAT64
    assert backend(30) is backend(30) and backend(30).digits == 30
    assert FLOAT64.digits is None and (FLOAT64.name, backend(30).name) == ("float64", "mpmath")
    with mpmath.mp.workdps(40):
        like = backend(None, np.array([mpmath.mpf(1)], dtype=object))
    assert like.digits == 40
    assert backend(None, np.ones(2), 1.0) is FLOAT64


def test_is_mp():
    with mpmath.mp.workdps(30):
        yes = [mpmath.mpf(1), mpmath.mpc(1, 2), mpmath.matrix([[1]]),
               MP30.arr([1.0, 2.0]), MP30.carr([[1, 2], [3, 4]]), [mpmath.mpc(0, 1)],
               (mpmath.mpf(2), 1.0)]
    no = [1.0, 1j, np.ones(3), np.ones(2, dtype=complex), np.array([], dtype=object),
          [1.0, 2.0], (), np.array([1.0], dtype=object), "1"]
    assert all(is_mp(x) for x in yes)
    assert not any(is_mp(x) for x in no)


def test_array_constructors_say_real_or_complex():
    assert FLOAT64.arr([1, 2]).dtype == float and FLOAT64.carr([1, 2]).dtype == complex
    assert FLOAT64.ceye(2).dtype == complex and FLOAT64.czeros((2, 3)).shape == (2, 3)
    with MP30.context():
        a = MP30.arr([1, 2.5, 1j])                        # mpf, complex entries stay mpc
        c = MP30.carr([1, 2.5])
        assert [type(x) for x in a] == [mpmath.mpf, mpmath.mpf, mpmath.mpc]
        assert all(isinstance(x, mpmath.mpc) for x in c)
        assert all(isinstance(x, mpmath.mpc) for x in MP30.ceye(2).ravel())
        assert isinstance(MP30.carr(2.0), mpmath.mpc)
