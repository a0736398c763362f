"""Faa di Bruno composition of jets to order 5 (n-p orbits' jets for l2) against SymPy."""
import itertools

import numpy as np
import pytest
import sympy as sp

from symvi.orbits.periodic import compose


def _jet(expr, xs, at, K):
    """Raw derivative tensors of a vector expression at a point, orders 1..K."""
    sub = dict(zip(xs, at))
    d = len(xs)
    out = []
    for k in range(1, K + 1):
        T = np.empty((len(expr),) + (d,) * k)
        for i, e in enumerate(expr):
            for idx in itertools.product(range(d), repeat=k):
                T[(i,) + idx] = float(sp.diff(e, *[xs[j] for j in idx]).subs(sub))
        out.append(T)
    return out


@pytest.mark.slow
def test_compose_to_order_5_matches_sympy():
    x, y = sp.symbols("x y")
    f = [sp.Rational(1, 2) * x + y ** 2 - x ** 3 / 3 + sp.sin(x * y) / 5,
         -y / 3 + x * y + sp.exp(x) / 7]
    g = [x * y + sp.cos(y) / 4 + x ** 2, y - x ** 3 / 2 + sp.Rational(1, 5) * x * y ** 2]
    p0 = (sp.Rational(1, 10), sp.Rational(-1, 5))
    p1 = tuple(e.subs({x: p0[0], y: p0[1]}) for e in f)
    gf = [e.subs({x: f[0], y: f[1]}, simultaneous=True) for e in g]
    ref = _jet(gf, (x, y), p0, 5)
    got = compose([tuple(_jet(f, (x, y), p0, 5)), tuple(_jet(g, (x, y), p1, 5))])
    for k, (a, b) in enumerate(zip(got, ref), start=1):
        assert np.allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max()), k


def test_compose_keeps_missing_orders_missing():
    J = np.eye(2)
    B = np.zeros((2, 2, 2))
    out = compose([(J, B, None), (J, B, None)])
    assert len(out) == 3 and out[2] is None and np.allclose(out[1], 0)
