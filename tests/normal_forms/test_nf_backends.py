"""float64 and mpmath backends run the same code and agree."""
import itertools

import mpmath
import numpy as np

from ._nf_maps import conjugated, family_dA
from symvi.paper.reduction import normal_form   # Kuznetsov and the paper's reduction

D0 = np.array([[0.3, -0.4], [0.5, 0.2]])


def test_float_vs_mpmath():
    f, c1, M = conjugated(1.1, -0.3 + 0.7j, D0, seed=2)
    dA = family_dA(M, 1.1)
    a = normal_form(*f, dA=dA)
    b = normal_form(*f, dA=dA, digits=40)
    assert b.backend == "mpmath" and isinstance(b.l1, mpmath.mpf)
    for name in ("c1", "l1", "wan_a", "f1_wan", "f1_printed", "dmod_dv", "lam"):
        x, y = complex(getattr(a, name)), complex(getattr(b, name))
        assert abs(x - y) <= 1e-11 * max(1, abs(y)), name
    for k in ("g20", "g11", "g02", "g21", "g30"):
        assert abs(a.paper.g[k] - complex(b.paper.g[k])) < 1e-11, k
    assert np.allclose(a.circle.half_widths(1e-3), b.circle.half_widths(1e-3), rtol=1e-11)


def test_mpmath_inputs_detected_and_exact():
    """mpmath jets at 50 digits: c1 recovered to ~45 digits (inputs exact to 50)."""
    with mpmath.workdps(50):
        th = mpmath.mpf(11) / 10
        lam = mpmath.expj(th)
        c = mpmath.mpc("-0.3", "0.7")
        # z -> lam z (1 + c|z|^2) in real coordinates, exactly
        A = [[lam.real, -lam.imag], [lam.imag, lam.real]]
        d3 = [[[[mpmath.mpf(0)] * 2 for _ in range(2)] for _ in range(2)] for _ in range(2)]
        # third derivatives of Re/Im of lam c z^2 conj(z) (z = u1 + i u2)
        k = lam * c
        # z^2 zbar = u1^3 + u1 u2^2 + i(u1^2 u2 + u2^3): its third derivative in the
        # direction with n1 entries equal to u2 is 6, 2 (real part) or 2, 6 (imaginary part)
        for (a, b_, cc) in itertools.product(range(2), repeat=3):
            n1 = (a, b_, cc).count(1)
            re = {0: 6, 2: 2}.get(n1, 0)
            im = {1: 2, 3: 6}.get(n1, 0)
            val = k * mpmath.mpc(re, im)
            d3[0][a][b_][cc] = val.real
            d3[1][a][b_][cc] = val.imag
        d2 = [[[mpmath.mpf(0)] * 2 for _ in range(2)] for _ in range(2)]
        nf = normal_form(A, d2, d3)
        assert nf.digits == 50
        # ||q|| = 1 gives c1 = 2 lam c
        assert abs(nf.c1 - 2 * lam * c) < mpmath.mpf(10) ** -45
        assert abs(nf.l1 - 2 * c.real) < mpmath.mpf(10) ** -45
