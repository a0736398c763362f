"""No crash, hang or NaN escapes over the whole valid space (issue 7, item 4).

Every call either returns finite numbers or raises a :class:`symvi.SymviError`
with a one-line message; nothing else (ValueError, OverflowError,
ZeroDivisionError, numpy LinAlgError ...) and no NaN in a returned result.
"""
import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import symvi
from symvi.paper import jets
from symvi.errors import NearSingularWarning, SymviError
from symvi.normal_forms import normal_form as nf

from .strategies import omega_typical, omega_wide, params_typical, params_wide

SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow])


def finite(x):
    a = np.asarray(x, dtype=complex) if not isinstance(x, (float, int)) else np.asarray(x)
    return bool(np.all(np.isfinite(a)))


def clean(exc):
    assert isinstance(exc, SymviError), f"{type(exc).__name__}: {exc}"
    assert str(exc).strip() and "\n" not in str(exc).strip(), str(exc)


def chain(params, omega):
    """Orbit -> jet(3) -> normal form; returns the number of admissible orbits analysed."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        warnings.simplefilter("error", RuntimeWarning)    # numpy overflow etc. must not leak
        try:
            orbits = symvi.period1_orbits(params, omega)
        except Exception as exc:   # noqa: BLE001 - the property is about the type
            clean(exc)
            return 0
        n = 0
        for o in orbits:
            assert all(finite(float(v)) for v in o.y), o
            if not o.admissible:
                assert o.reason
                continue
            assert all(finite(complex(z)) for z in o.multipliers), o.multipliers
            try:
                j = jets.jet(params, omega, order=3, orbit=o)
                for arr in (j.jacobian, j.d2, j.d3, j.dA):
                    assert finite(arr)
                r = nf.normal_form(j.jacobian, j.d2, j.d3, j.dA)
                assert finite(r.l1) and finite(r.dmod_dv) and finite(r.c1)
            except Exception as exc:   # noqa: BLE001
                clean(exc)
            n += 1
    return n


@settings(max_examples=300, **SETTINGS)
@given(params_wide, omega_wide)
# hypothesis seed 3 (issue 23, defect 4): the stop's mass gets no steady forcing
# (an anti-resonance of the forced mass at omega = 2): ZeroDivisionError in the solve
@example(symvi.Params(1 / 3, 1 / 3, 0.0, 0.0, 1.0), 2.0)
def test_chain_wide(params, omega):
    chain(params, omega)


@settings(max_examples=200, **SETTINGS)
@given(params_typical, omega_typical)
def test_chain_typical(params, omega):
    chain(params, omega)


@settings(max_examples=15, **SETTINGS)
@given(params_typical, omega_typical, st.floats(1.001, 1.2))
def test_hopf_points_never_crash(params, omega, factor):
    hopf = pytest.importorskip("symvi.analysis.hopf")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        try:
            res = hopf.hopf_points(params, omega, omega * factor)
        except Exception as exc:   # noqa: BLE001
            clean(exc)
            return
    for pt in res.points:
        assert math.isfinite(pt.omega_c) and math.isfinite(pt.l1)
    # never a hang: the scan's work is bounded by its budget of orbit evaluations (a count,
    # not a wall-clock time; MAX_SAMPLES plus SAMPLES_PER_CUT per cut)
    assert res.samples <= hopf.MAX_SAMPLES + hopf.SAMPLES_PER_CUT * hopf.MAX_SINGULAR


@pytest.mark.parametrize("args", [
    (symvi.Params(2, 5, 0, 0.0, 0.8), 0.73),        # b = 0
    (symvi.Params(2, 5, 0, -1.5, 0.8), 0.73),       # b < 0
    (symvi.Params(2, 5, 0, 1.5, 1.0), 0.73),        # r = 1
    (symvi.Params(2, 5, 0, 1.5, 0.05), 0.73),       # r small
    (symvi.Params(2, 5, 0, 1.5, 0.8), 1e-3),        # very small omega
    (symvi.Params(2, 5, 0, 1.5, 0.8), 1e2),         # very large omega
    (symvi.Params(2, 5, 1.0, 1.5, 0.8), 0.73),      # force on mass 2 only
])
def test_edges(args):
    chain(*args)
