"""The compiled shooting system (symvi.orbits._shooting, symvi.flow._steady) against its
numpy reference: residual, Jacobian, parameter derivatives, monodromy, steady state, the
compiled finder's constants and the admissibility it decides."""
import math

import numpy as np
import pytest

from symvi.continuation import continue_branch
from symvi.flow import compiled
from symvi.flow.linear import LinearFlow
from symvi.orbits import admissible_orbits
from symvi.orbits.periodic import Problem, orbit_of, periodic_orbit
from tests.zoo import N_MASS_SET, ONE_DAMPED_GAP0


#: agreement of compiled and numpy results, relative to the largest entry
REL = 1e-13


def _close(a, b):
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    assert np.max(np.abs(a - b)) <= REL * max(1.0, np.max(np.abs(b)))


def _pair(model, n, p, param, omega=None):
    fast = Problem(model, n, p, omega=omega, param=param)
    ref = Problem(model, n, p, omega=omega, param=param)
    ref.compiled = False
    return fast, ref


def _orbit_u(model, w):
    """u of an admissible period-1 orbit at omega = w, and of a 2-2 orbit of ONE_DAMPED."""
    o = admissible_orbits(model, w, multipliers=False)[0]
    return periodic_orbit(model, n=1, p=1, guess=o.y, omega=w).u


def _u_2_2():
    # the stable 2-2 orbit of ONE_DAMPED at omega = 2.69 (cf. test_periodic), from its points
    guess = [[-0.368460, 4.129866], [-0.350514, 4.976955]]
    return periodic_orbit(ONE_DAMPED_GAP0, n=2, p=2, guess=guess, omega=2.69).u


CASES = {
    "three (damped, N = 3)": (N_MASS_SET["three"], 1, 1, 1.3, None),
    "paper": (N_MASS_SET["paper"], 1, 1, 1.15, None),
    "2-2 of a damped oscillator": (ONE_DAMPED_GAP0, 2, 2, 2.69, "2-2"),
}


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request):
    model, n, p, w, kind = CASES[request.param]
    u = _u_2_2() if kind == "2-2" else _orbit_u(model, w)
    # off the orbit too: the system, not only its zero
    off = u + 1e-3 * np.cos(np.arange(len(u)))
    return model, n, p, w, u, off


def test_residual_jacobian_and_omega_derivative(case):
    model, n, p, w, u, off = case
    fast, ref = _pair(model, n, p, "omega")
    for x in (u, off):
        for got, want in zip(fast.evaluate(x, w, dparam=True), ref.evaluate(x, w, dparam=True)):
            _close(got, want)
        assert fast.evaluate(x, w, jac=False)[1] is None
        _close(fast.derivative(x, w, "omega"), ref.derivative(x, w, "omega"))
        _close(fast.monodromy(x, fast.evaluate(x, w)[1])[1],
               ref.monodromy(x, ref.evaluate(x, w)[1])[1])
        for a, b in zip(fast.flights(x, w)[0], ref.flights(x, w)[0]):
            for ga, gb in zip(a, b):
                _close(ga, gb)


def test_named_parameter_derivatives(case):
    model, n, p, w, u, off = case
    name = "restitution" if n == 2 else "gap"
    fast, ref = _pair(model, n, p, name, omega=w)
    lam = model.value(name)
    for got, want in zip(fast.evaluate(off, lam, dparam=True),
                         ref.evaluate(off, lam, dparam=True)):
        _close(got, want)
    _close(fast.derivative(off, lam, "omega"), ref.derivative(off, lam, "omega"))


@pytest.mark.parametrize("name", sorted(N_MASS_SET))
def test_steady_state_against_numpy_solve(name):
    flow = LinearFlow.of(N_MASS_SET[name])
    for w in (0.31, 0.93, 1.7, 3.2):
        F = flow.forcing(w)
        D = flow.K - w * w * flow.M + 1j * w * flow.C
        X = np.linalg.solve(D, flow.P)
        dX = np.linalg.solve(D, (2 * w * flow.M - 1j * flow.C) @ X)
        for got, want in ((F.U, X.real), (F.V, X.imag), (F.dU, dX.real), (F.dV, dX.imag)):
            _close(got, want)


def test_finder_constants_equal_the_compiled_flow_s():
    from symvi.orbits._shooting import finder_constants
    for model in (N_MASS_SET["paper"], N_MASS_SET["three"], N_MASS_SET["paper"].with_(gap=0.7, restitution=0.6)):
        flow = LinearFlow.of(model)
        for w in (0.8, 1.3):
            got = finder_constants(flow, flow.forcing(w))
            assert np.array_equal(got, compiled.constants(model, w))


def test_admissibility_by_the_compiled_finder_equals_the_reference():
    """Through the grazing and interior-contact boundaries of the paper's branch."""
    br = continue_branch(N_MASS_SET["paper"], "omega", 1.3, 0.9, through=True, locate=False)
    fast, ref = br.problem, Problem(br.problem.model, 1, 1, param="omega")
    ref.compiled = False
    flags = set()
    for X in br.states:
        a, b = orbit_of(fast, X[:-1], X[-1]), orbit_of(ref, X[:-1], X[-1])
        assert (a.admissible, a.reason) == (b.admissible, b.reason)
        assert a.multipliers == pytest.approx(b.multipliers, rel=1e-12, abs=1e-12)
        flags.add(a.admissible)
    assert flags == {True, False}
    assert math.isfinite(br.states[-1][-1])


def test_newton_solve_and_initial_guess_agree_with_the_reference(monkeypatch):
    """The whole n-p solve (flight times of the guess by the compiled map, Newton, orbit)."""
    guess = [[-0.3685, 4.1299], [-0.3505, 4.9770]]
    fast = periodic_orbit(ONE_DAMPED_GAP0, n=2, p=2, guess=guess, omega=2.69)
    monkeypatch.setattr(Problem, "compiled", False)
    ref = periodic_orbit(ONE_DAMPED_GAP0, n=2, p=2, guess=guess, omega=2.69)
    _close(fast.u, ref.u)
    assert (fast.admissible, fast.reason, fast.stable) == (ref.admissible, ref.reason, ref.stable)
    assert fast.multipliers == pytest.approx(ref.multipliers, rel=1e-12, abs=1e-12)
