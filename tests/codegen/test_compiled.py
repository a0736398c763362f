"""The numba-compiled generated evaluators (symvi.paper.jets.compiled) against the Python ones."""
import subprocess
import sys

import numba as nb
import numpy as np
import pytest

from symvi import ParameterError
from symvi.paper.jets import _gen, compiled, jacobian_at, jet_inputs
from symvi.simulations.simulation import simulate

from ..conftest import EX1
from .test_jets import POINTS, _orbit


def _general_points():
    """Section points off the periodic orbit (a transient from a perturbed start)."""
    sim = simulate(EX1, 0.745, n_impacts=40, perturbation=(0.05, 0.05, 0.05, 0.05))
    return [(EX1, 0.745, y, te) for y, te in zip(sim.section[:-1], np.diff(sim.t))][:20]


def _cases():
    out = [(p, w, o.y, 2 * np.pi / w) for p, w, br in POINTS for o in [_orbit(p, w, br)]]
    return out + _general_points()


@pytest.mark.parametrize("order", [1, pytest.param(2, marks=pytest.mark.slow),
                                   pytest.param(3, marks=pytest.mark.slow)])
def test_compiled_equals_python_evaluator(order):
    """Same expressions, same IEEE operations: agreement to a few ulps of each output's scale."""
    cj = compiled(order)
    mod, _ = _gen(order)
    assert cj.inputs == tuple(mod.INPUTS) and cj.layout == mod.LAYOUT
    for p, w, y, te in _cases():
        inp = jet_inputs(p, w, y, te)
        a, b = np.array(cj.kernel(inp)), np.array(mod.f64(inp))
        assert a.shape == b.shape and np.all(np.isfinite(a))
        assert np.max(np.abs(a - b)) <= 1e-12 * max(1.0, np.max(np.abs(b)))


def test_compiled_kernel_is_callable_from_user_numba_code():
    """A user's njit loop over section points gets the same Jacobians as jacobian_at."""
    cj = compiled(1)
    kernel, J = cj.kernel, np.array(cj.layout["J"])

    @nb.njit
    def jacobians(inps, idx):
        out = np.empty((len(inps), 4, 4))
        for n in range(len(inps)):
            flat = kernel(inps[n])
            for i in range(4):
                for j in range(4):
                    out[n, i, j] = flat[idx[i, j]]
        return out

    pts = _general_points()
    got = jacobians(nb.typed.List([jet_inputs(*c) for c in pts]), J)
    for g, c in zip(got, pts):
        np.testing.assert_allclose(g, jacobian_at(*c), rtol=1e-12, atol=1e-12)


def test_compiled_order1_never_imports_higher_orders():
    code = ("import sys; from symvi.paper.jets import compiled; compiled(1);"
            "print(sorted(m for m in sys.modules if m.startswith('symvi._generated.order')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "['symvi._generated.order1']"


def test_compiled_bad_order():
    with pytest.raises(ParameterError, match="order"):
        compiled(0)


@pytest.mark.parametrize("bad", [(1.0,) * 15, (1.0,) * 15 + (float("nan"),), ("a",) * 16, 3.0])
def test_compiled_call_checks_its_input(bad):
    with pytest.raises(ParameterError, match="inp"):
        compiled(1)(bad)


def test_compiled_call_equals_kernel():
    cj = compiled(1)
    inp = jet_inputs(*_general_points()[0])
    assert cj(inp) == cj.kernel(inp)


@pytest.mark.parametrize("kw,name", [
    (dict(y=(0.1, 0.2, 0.3)), "y"), (dict(y=(0.1, 0.2, float("inf"), 0.3)), "y[2]"),
    (dict(t_e=0.0), "t_e"), (dict(t_e=float("nan")), "t_e"), (dict(omega=-1.0), "omega"),
    (dict(params=(2, 5, 0, 1.5, 0.8)), "params")])
def test_jet_inputs_names_the_bad_parameter(kw, name):
    args = dict(params=EX1, omega=0.745, y=(-0.3, 0.1, 0.2, 1.0), t_e=8.0)
    args.update(kw)
    with pytest.raises(ParameterError) as e:
        jet_inputs(**args)
    assert e.value.name == name
