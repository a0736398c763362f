"""Orders 4 and 5 of the impact map (issue 13, l2): d4 and d5 against central finite
differences of the order-3 d3 at 60 digits, symmetry, float64 against mpmath, the
input layout, freshness, and that no other job imports them."""
import itertools
import json
import math
import os
import subprocess
import sys
import warnings
from pathlib import Path

import mpmath
import numpy as np
import pytest

import symvi._generated as gen
from symvi.codegen import layout
from symvi.codegen.high import HighJet, high_jet
from symvi.codegen.jets import evaluate
from symvi.errors import ParameterError
from symvi.flow.linear import LinearFlow
from symvi.maps.impact import poincare_map
from symvi.orbits import admissible_orbits
from tests.zoo import ONE_UNDAMPED, PAPER_EX1, THREE_STOP2_GAP05

GEN = Path(gen.__file__).parent
#: the paper's example 1 next to its Neimark-Sacker point (paper, Sec. 4: v_c = 0.7368)
W_PAPER = 0.7369
DPS = 60


def _orbit(model, w):
    o = admissible_orbits(model, w)[0]
    return o.y, 2 * math.pi / w


class _D3:
    """d3 of the order-3 module at 60 digits at any y, its flight time found anew
    (the first impact of the mpmath flow: te moves with y)."""

    def __init__(self, model, w):
        self.model, self.w = model, mpmath.mpf(w)
        self.flow = LinearFlow.of(model, DPS)
        self.F = self.flow.forcing(self.w)

    def __call__(self, y):
        s = poincare_map(self.model, self.w, y, digits=DPS)
        assert s.status == "impact"
        return evaluate(self.flow, self.F, tuple(y), s.t, 3)["d3"]


def _te(model, w, y):
    """The flight time from y at 60 digits: the jet at y assumes g(y, te) = 0, and
    2 pi / omega in float64 would be off by ~1e-16 (10^-14 in d4)."""
    return poincare_map(model, w, y, digits=DPS).t


def _fd_d4_d5(model, w, y, h=mpmath.mpf("1e-12")):
    """Central differences of d3: d4[..., j] (O(h^2)) and d5[..., j, k] (O(h^2))."""
    d = len(y)
    with mpmath.mp.workdps(DPS):
        y = [mpmath.mpf(v) for v in y]
        f = _D3(model, w)

        def at(*steps):
            z = list(y)
            for j, s in steps:
                z[j] += s * h
            return f(z)
        d4 = [(at((j, 1)) - at((j, -1))) / (2 * h) for j in range(d)]
        d5 = {}
        for j, k in itertools.combinations_with_replacement(range(d), 2):
            d5[j, k] = (at((j, 1), (k, 1)) - at((j, 1), (k, -1)) - at((j, -1), (k, 1))
                        + at((j, -1), (k, -1))) / (4 * h * h)
        return d4, d5


def _rel(a, b):
    a, b = np.asarray(a, dtype=object), np.asarray(b, dtype=object)
    return max(abs(x - y) for x, y in zip(a.ravel(), b.ravel())) / max(abs(x) for x in b.ravel())


@pytest.mark.parametrize("model, w", [(PAPER_EX1, W_PAPER), (ONE_UNDAMPED, 1.3)], ids=["paper", "one"])
def test_d4_d5_agree_with_finite_differences_of_d3(model, w):
    y, _ = _orbit(model, w)
    jet = high_jet(model, w, y, _te(model, w, y), digits=DPS)
    fd4, fd5 = _fd_d4_d5(model, w, y)
    with mpmath.mp.workdps(DPS):
        for j, a in enumerate(fd4):
            assert _rel(jet.d4[..., j], a) < 1e-18, j
        for (j, k), a in fd5.items():
            assert _rel(jet.d5[..., j, k], a) < 1e-18, (j, k)


def test_tensors_are_symmetric_and_lower_orders_match_order_3():
    y, te = _orbit(PAPER_EX1, W_PAPER)
    jet = high_jet(PAPER_EX1, W_PAPER, y, te)
    for t in (jet.d2, jet.d3, jet.d4, jet.d5):
        m = t.ndim - 1
        for perm in itertools.permutations(range(1, m + 1)):
            assert np.array_equal(t, t.transpose((0, *perm)))
    j3 = evaluate(*_flow_forcing(PAPER_EX1, W_PAPER), tuple(y), te, 3)
    for name, mine in (("J", jet.jacobian), ("d2", jet.d2), ("d3", jet.d3),
                       ("theta1", jet.theta1)):
        np.testing.assert_allclose(mine, j3[name], rtol=1e-12, atol=1e-12 * abs(j3[name]).max())
    four = high_jet(PAPER_EX1, W_PAPER, y, te, order=4)
    assert four.d5 is None and np.allclose(four.d4, jet.d4, rtol=1e-13)
    assert isinstance(jet, HighJet) and jet.digits is None and jet.d5.shape == (4,) * 6


def _flow_forcing(model, w):
    flow = LinearFlow.of(model)
    return flow, flow.forcing(w)


@pytest.mark.parametrize("model, w", [(PAPER_EX1, W_PAPER), (ONE_UNDAMPED, 1.3)], ids=["paper", "one"])
def test_float64_and_mpmath_backends_agree(model, w):
    y, te = _orbit(model, w)
    f, m = high_jet(model, w, y, te), high_jet(model, w, y, te, digits=30)
    assert m.digits == 30 and m.d5.dtype == object
    for name in ("jacobian", "d2", "d3", "d4", "d5", "theta1"):
        a, b = getattr(f, name), getattr(m, name).astype(float)
        assert np.max(np.abs(a - b)) <= 1e-10 * np.max(np.abs(b)), name


def test_input_checks_are_those_of_jet_at():
    y, te = _orbit(PAPER_EX1, W_PAPER)
    for bad in (dict(order=3), dict(order=6)):
        with pytest.raises(ParameterError):
            high_jet(PAPER_EX1, W_PAPER, y, te, **bad)
    with pytest.raises(ParameterError):
        high_jet(PAPER_EX1, W_PAPER, y, -1.0)
    with pytest.raises(ParameterError):
        high_jet(PAPER_EX1, W_PAPER, y[:-1], te)


def test_assembled_inputs_match_each_order_and_no_parameter_slots_above_3():
    from symvi._derivations import impact_jets as ij
    flow, F = _flow_forcing(PAPER_EX1, W_PAPER)
    y, te = _orbit(PAPER_EX1, W_PAPER)
    for K in range(1, 6):
        mod, _ = layout.module(2, K)
        assert len(layout.assemble(flow, F, y, te, K)) == len(mod.INPUTS) == len(ij.inputs(2, K))
        assert ij.has_parameters(K) == (K in layout.PARAMETER_ORDERS)
    assert not any(s.startswith(("dU", "pE", "pR", "plevel")) for s in layout.module(2, 5)[0].INPUTS)


def test_orders_4_5_fresh_in_the_manifest_and_regenerate_identically(tmp_path):
    from symvi._derivations import impact_jets as ij
    assert ij.check(GEN, ns=ij.NS_HIGH, orders=ij.HIGH_ORDERS) == []
    committed = json.loads((GEN / ij.MANIFEST).read_text())
    written, _ = ij.generate(tmp_path, ns=(1,), orders=ij.HIGH_ORDERS, force=True)
    assert written == ["impact_n1_order4.py", "impact_n1_order5.py"]
    for f in written:
        assert ij.file_hash(tmp_path / f) == committed["files"][f], f
    assert not (GEN / "impact_n3_order4.py").exists()
    assert "DO NOT EDIT" in (GEN / "impact_n2_order5.py").read_text().splitlines()[0]


def test_regenerate_jobs_cover_the_shipped_set(tmp_path):
    from symvi._derivations import impact_jets as ij
    from symvi.codegen.regenerate import jobs
    from symvi.model import dumps

    def orders(**kw):
        return [(job.folder, job.orders, job.ns) for job in jobs(**kw)]
    plain = orders()
    assert (GEN, (4, 5), ij.NS_HIGH) in plain and (GEN, (1, 2, 3), ij.NS_SHIPPED) in plain
    assert all(max(k) <= 3 for _, k, _ in orders(order=3))
    f = tmp_path / "m3.toml"
    f.write_text(dumps(THREE_STOP2_GAP05))
    # --model: each order where the loader looks for it (N = 3 above order 3: the cache)
    assert orders(model=str(f)) == [(GEN, (1, 2, 3), (3,))]
    assert orders(model=str(f), order=5) == [(GEN, (1, 2, 3), (3,)),
                                             (layout._user_dir(), (4, 5), (3,))]


def test_ordinary_jobs_never_import_orders_4_5():
    code = ("import sys, math, symvi; from symvi.codegen.jets import jet_at;"
            "from symvi.orbits import admissible_orbits;"
            "m = symvi.Model.luo_xie(2, 5, 0, 1.5, 0.8); w = 0.7369;"
            "symvi.hopf_points(m, 0.73, 0.745);"
            "o = admissible_orbits(m, w)[0]; jet_at(m, w, o.y, 2 * math.pi / w, 3);"
            "high = lambda: sorted(k for k in sys.modules if k.endswith(('order4', 'order5')));"
            "print(high());"
            "from symvi.codegen.high import high_jet; high_jet(m, w, o.y, 2 * math.pi / w);"
            "print(high())")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       env=dict(os.environ))
    assert r.returncode == 0, r.stderr
    before, after = r.stdout.splitlines()[-2:]
    assert before == "[]"
    assert after == "['symvi._generated.impact_n2_order5']"


@pytest.mark.slow
def test_three_masses_damped_order_4_from_the_user_cache(tmp_path, monkeypatch):
    """N = 3 is not shipped at order 4: generated on first use (with the warning),
    then checked against finite differences of the shipped order-3 d3."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(layout, "_LOADED", {})
    w = 0.95
    y, _ = _orbit(THREE_STOP2_GAP05, w)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        jet = high_jet(THREE_STOP2_GAP05, w, y, _te(THREE_STOP2_GAP05, w, y), order=4, digits=DPS)
    assert any("generating the order-4 jets of the 3-mass" in str(c.message) for c in caught)
    man = json.loads((tmp_path / "symvi" / "generated" / "impact_manifest.json").read_text())
    assert list(man["files"]) == ["impact_n3_order4.py"]
    h = mpmath.mpf("1e-12")
    with mpmath.mp.workdps(DPS):
        f = _D3(THREE_STOP2_GAP05, w)
        yy = [mpmath.mpf(v) for v in y]
        for j in range(len(yy)):
            zp, zm = list(yy), list(yy)
            zp[j] += h
            zm[j] -= h
            assert _rel(jet.d4[..., j], (f(zp) - f(zm)) / (2 * h)) < 1e-18, j
