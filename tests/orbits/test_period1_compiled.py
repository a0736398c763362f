"""The compiled period-1 solver (symvi.orbits._period1) against the numpy reference
(period1.COMPILED = False: _Line, Motion.first_impact, the generated order-1 jets) on
the five test models and the paper's model at r = 1: the same orbits to rounding,
the same branch names, admissibility flags and reasons, the same refusals."""
import math
import warnings

import numpy as np
import pytest

from symvi.errors import NearSingularWarning, SingularCaseError
from symvi.flow.linear import LinearFlow
from symvi.model import Model
from symvi.orbits import period1

from tests.zoo import N_MASS_SET

PAPER_R1 = Model.luo_xie(2, 5, 0, 1.5, 1.0)
GRIDS = {**{name: np.linspace(0.3, 3.0, 46) for name in N_MASS_SET},
         "paper-r1": np.linspace(0.9, 1.3, 21)[1:]}
MODELS = {**N_MASS_SET, "paper-r1": PAPER_R1}


def _orbits(model, omega, compiled, **kw):
    old = period1.COMPILED
    period1.COMPILED = compiled
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NearSingularWarning)
            return period1.period1_orbits(model, omega, **kw)
    except SingularCaseError as exc:
        return exc.kind
    finally:
        period1.COMPILED = old


def _same(ref, got, where):
    if isinstance(ref, str) or isinstance(got, str):
        assert ref == got, where
        return
    assert [o.branch for o in ref] == [o.branch for o in got], where
    for a, b in zip(ref, got):
        at = (*where, a.branch)
        assert (a.admissible, a.reason) == (b.admissible, b.reason), at
        top = max((abs(z) for z in a.multipliers), default=0)
        if abs(top - 1) > 1e-10:        # else (r = 1, no damping: |lambda| = 1) rounding decides
            assert a.stable == b.stable, at
        scale = 1 + max(abs(v) for v in a.y)
        assert max(abs(p - q) for p, q in zip(a.y[:-1], b.y[:-1])) < 1e-12 * scale, at
        assert abs(math.remainder(a.y[-1] - b.y[-1], 2 * math.pi)) < 1e-12, at
        assert 0 <= b.y[-1] < 2 * math.pi, at
        assert abs(a.impact_velocity - b.impact_velocity) < 1e-12 * scale, at
        assert len(a.multipliers) == len(b.multipliers), at
        # as multisets: at r = 1 without damping all have modulus 1 and their order is rounding
        big = 1 + max((abs(z) for z in a.multipliers), default=0)
        for z in a.multipliers:
            assert min(abs(z - x) for x in b.multipliers) < 1e-12 * big, at


@pytest.mark.parametrize("name", list(MODELS))
def test_compiled_orbits_equal_the_numpy_reference(name):
    """Both branches on a grid of omegas (admissible, inadmissible, no orbit, refusals)."""
    model = MODELS[name]
    kinds = set()
    for w in GRIDS[name]:
        ref, got = _orbits(model, float(w), False), _orbits(model, float(w), True)
        _same(ref, got, (name, float(w)))
        if isinstance(ref, str):
            kinds.add(ref)
        else:
            kinds.update({True: "admissible", False: "inadmissible"}[o.admissible] for o in ref)
            kinds.add("orbits" if ref else "none")
    assert {"admissible", "inadmissible"} <= kinds, kinds


def test_refusals_and_warning_are_the_reference_s():
    """omega = omega_2 / 2: not isolated (refused); just beside it: warned, same orbits."""
    model = N_MASS_SET["paper"]
    w = float(LinearFlow.of(model).omegas[1]) / 2
    for compiled in (False, True):
        period1.COMPILED, old = compiled, period1.COMPILED
        try:
            with pytest.raises(SingularCaseError, match="one-minus-cos"):
                period1.period1_orbits(model, w)
            with pytest.warns(NearSingularWarning, match="ill-conditioned"):
                period1.period1_orbits(model, w * (1 + 1e-6))
        finally:
            period1.COMPILED = old


def test_without_multipliers():
    model = N_MASS_SET["three"]
    for w in (0.95, 1.3, 2.2):
        ref, got = _orbits(model, w, False), _orbits(model, w, True, multipliers=False)
        assert all(o.multipliers == () and not o.stable for o in got)
        assert [(o.y, o.reason) for o in got] == [(o.y, o.reason) for o in _orbits(
            model, w, True)]
        _same([_strip(o) for o in ref], got, ("three", w))


def _strip(o):
    import dataclasses
    return dataclasses.replace(o, multipliers=(), stable=False)
