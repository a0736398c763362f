"""Jets of a nonlinear flight and of its impact map on truncated power series (issue 28,
:mod:`symvi.flow.tps`, :mod:`symvi.flow.nljet`): the series arithmetic against identities
that hold exactly in the truncated algebra, the nonlinearity off against the exact linear
flow's generated jets (orders 1 to 5, parameter derivatives), and the nonlinear jets
against finite differences of the map."""
import math

import numpy as np
import pytest

from symvi.codegen.high import high_jet
from symvi.codegen.jets import jet_at, parameter_derivatives
from symvi.flow import nljet, tps
from symvi.flow.nljet import FlowView
from symvi.model import Model, Stop
from symvi.orbits.period1 import admissible_orbits

ONE = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
TWO = dict(mass=[1.0, 2.0], stiffness=[[2.0, -1.0], [-1.0, 1.5]],
           damping=[[0.05, 0.0], [0.0, 0.05]], forcing=[1.0, 0.3],
           stop=Stop(mass=2, gap=0.3, restitution=0.7))


def _rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(1.0, float(np.max(np.abs(b)))))


# --------------------------------------------------------------------------- the algebra
def _ops(alg):
    K = alg.K
    L = alg.L
    w = [np.zeros(L) for _ in range(4)]
    c = np.zeros(K + 1)

    def mul(a, b):
        out = np.zeros(L)
        tps.mul(a, b, out, *alg.mul)
        return out

    def f(k, a):
        out = np.zeros(L)
        tps.apply(k, a, out, w[0], w[1], c, K, *alg.mul)
        return out

    return mul, f


@pytest.mark.parametrize("d, K", [(1, 7), (2, 5), (3, 3)])
def test_series_identities_hold_in_the_truncated_algebra(d, K):
    """Identities of smooth functions hold order by order in R[delta]/(deg > K): a wrong
    coefficient of any function, product or power breaks one of them."""
    alg = tps.algebra(d, K)
    mul, f = _ops(alg)
    rng = np.random.default_rng(3)
    a = rng.uniform(-1, 1, alg.L)
    a[0] = 0.7
    one = np.zeros(alg.L)
    one[0] = 1.0
    tol = 1e-12
    assert _rel(mul(f(tps.SIN, a), f(tps.SIN, a)) + mul(f(tps.COS, a), f(tps.COS, a)), one) < tol
    assert _rel(mul(f(tps.COSH, a), f(tps.COSH, a)) - mul(f(tps.SINH, a), f(tps.SINH, a)),
                one) < tol
    assert _rel(f(tps.EXP, f(tps.LOG, a)), a) < tol
    assert _rel(mul(f(tps.SQRT, a), f(tps.SQRT, a)), a) < tol
    assert _rel(mul(f(tps.TAN, a), f(tps.COS, a)), f(tps.SIN, a)) < tol
    assert _rel(mul(f(tps.TANH, a), f(tps.COSH, a)), f(tps.SINH, a)) < tol
    assert _rel(f(tps.ATAN, f(tps.TAN, a)), a) < tol
    assert _rel(mul(f(tps.RECIP, a), a), one) < tol
    assert _rel(mul(f(tps.EXP, a), f(tps.EXP, -a)), one) < tol


def test_products_are_truncated_polynomial_products():
    """d = 1: the series product is numpy's polynomial product cut at degree K."""
    alg = tps.algebra(1, 6)
    mul = _ops(alg)[0]
    rng = np.random.default_rng(1)
    a, b = rng.normal(size=7), rng.normal(size=7)
    assert np.allclose(mul(a, b), np.convolve(a, b)[:7], rtol=1e-14, atol=1e-14)


def test_tensors_are_raw_derivatives():
    """f = exp(d1) sin(d2): d^3 f / d1^2 d2 at 0 = cos(0) = 1, d^2 f / d2^2 = 0, ..."""
    alg = tps.algebra(2, 3)
    mul, f = _ops(alg)
    e = f(tps.EXP, alg.var(0))
    s = f(tps.SIN, alg.var(1))
    g = mul(e, s)
    d2 = alg.tensor(g, 2)
    d3 = alg.tensor(g, 3)
    assert abs(d2[0, 1] - 1) < 1e-15 and abs(d2[1, 1]) < 1e-15 and abs(d2[0, 0]) < 1e-15
    assert abs(d3[0, 0, 1] - 1) < 1e-15 and abs(d3[1, 1, 1] + 1) < 1e-15


# --------------------------------------------------------------------------- the map
def _pair(kw, forces):
    lin = Model(**kw)
    nl = Model(**kw, nonlinear=forces, parameters={"beta": 0.0})
    return lin, nl


@pytest.mark.parametrize("kw, forces, omega", [
    (ONE, ["beta*x1**3"], 1.3),
    (TWO, ["beta*x1**3", "beta*x2*v2**2 + beta*sin(x1)"], 1.1),
])
def test_nonlinearity_off_jets_equal_the_generated_linear_jets(kw, forces, omega):
    """beta = 0: the series map's jets to order 5 are the exact flow's generated ones to
    1e-12 relative (issue 28, "Nonlinearity off"), at an admissible period-1 point."""
    lin, nl = _pair(kw, forces)
    o = admissible_orbits(lin, omega)[0]
    te = 2 * math.pi / omega
    ref = jet_at(lin, omega, o.y, te, order=3)
    hi = high_jet(lin, omega, o.y, te, order=5)
    got = nljet.map_jet(FlowView(nl), omega, o.y, te, 5)
    assert _rel(got["P"][:-1], np.array(o.y)[:-1]) < 1e-12
    assert abs(got["te"] - te) < 1e-12 * te
    for k, want in ((1, ref.jacobian), (2, ref.d2), (3, ref.d3), (4, hi.d4), (5, hi.d5)):
        have = got["J"] if k == 1 else got[f"d{k}"]
        assert _rel(have, want) < 1e-11, k


@pytest.mark.parametrize("name", ["omega", "stiffness[1,1]", "mass[1]", "forcing[1]", "damping[1,1]"])
def test_nonlinearity_off_parameter_derivatives(name):
    """dP/dp and dJ/dp at fixed y equal the linear flow's exact ones (omega through the
    phase, a stiffness, a mass through M(p)^-1, a forcing amplitude)."""
    lin, nl = _pair(ONE, ["beta*x1**3"])
    omega = 1.3
    o = admissible_orbits(lin, omega)[0]
    te = 2 * math.pi / omega
    ref = parameter_derivatives(lin, omega, o.y, te, name, fixed_point=False)
    got = nljet.map_jet(FlowView(nl), omega, o.y, te, 2, param=nl.parameter(name))
    assert _rel(got["dpP"], ref.dP) < 1e-11
    assert _rel(got["dpJ"], ref.dJ) < 1e-11


DUFFING = Model(**ONE, nonlinear=["beta*x1**3"], parameters={"beta": 0.5})


def test_nonlinear_jets_against_finite_differences_of_the_map():
    """beta = 0.5: J by central differences of P (h = 1e-5: error ~1e-10), d2 by central
    differences of J and d3 by those of d2; the beta-derivative by differences in beta."""
    view = FlowView(DUFFING)
    flow = view.nl
    y = (-1.25, 1.65)
    st, te, _, _ = flow.first_impact(1.3, np.array([0.5, y[0]]), y[1], just_hit=0)
    assert st == "impact"
    got = nljet.map_jet(view, 1.3, y, te, 3, param=DUFFING.parameter("beta"))
    h = 1e-5
    for j in range(2):
        e = np.zeros(2)
        e[j] = h
        lo = nljet.map_jet(view, 1.3, np.add(y, -e), te, 2)
        hi = nljet.map_jet(view, 1.3, np.add(y, e), te, 2)
        assert _rel((hi["P"] - lo["P"]) / (2 * h), got["J"][:, j]) < 1e-8
        assert _rel((hi["J"] - lo["J"]) / (2 * h), got["d2"][:, :, j]) < 1e-8
        lo3 = nljet.map_jet(view, 1.3, np.add(y, -e), te, 3)
        hi3 = nljet.map_jet(view, 1.3, np.add(y, e), te, 3)
        assert _rel((hi3["d2"] - lo3["d2"]) / (2 * h), got["d3"][..., j]) < 1e-7
    par = DUFFING.parameter("beta")
    lo = nljet.map_jet(FlowView(par.apply(DUFFING, 0.5 - h)), 1.3, y, te, 1)["P"]
    hi = nljet.map_jet(FlowView(par.apply(DUFFING, 0.5 + h)), 1.3, y, te, 1)["P"]
    assert _rel((hi - lo) / (2 * h), got["dpP"]) < 1e-8
    # the image is the flow's own: the run of NonlinearFlow from y lands on it
    code, sec, t, *_ = flow.run(1.3, np.array(y), 1)
    assert _rel(sec[0][:-1], got["P"][:-1]) < 1e-12
    assert abs((got["P"][-1] - sec[0][-1] + math.pi) % (2 * math.pi) - math.pi) < 1e-12


def test_an_impact_without_approach_speed_is_refused():
    """No smooth impact time where the approach speed is not positive (eq. (30)): just
    after leaving the stop the mass moves away from it, so a flight "ending" there is
    refused in one line, never given a jet."""
    from symvi.errors import SingularCaseError
    with pytest.raises(SingularCaseError, match="approach speed"):
        nljet.map_jet(FlowView(DUFFING), 1.3, (-0.6, 0.3), 0.05, 2)


def test_nonlinearity_off_jets_between_two_stops():
    """A two-sided clearance (stops on mass 1 above and below): the series jet of a flight
    from the upper stop's section to the lower one's equals the generated several-
    constraint jet of the exact flow (symvi.codegen.jets.flight_jet) to 1e-11."""
    from symvi.codegen.jets import flight_jet
    from symvi.flow.linear import LinearFlow
    kw = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
              stops=[Stop(mass=1, gap=0.4, restitution=0.8),
                     Stop(mass=1, gap=-0.4, side="lower", restitution=0.7)])
    lin = Model(**kw)
    nl = Model(**kw, nonlinear=["beta*x1**3"], parameters={"beta": 0.0})
    view = FlowView(nl)
    omega, y = 1.2, (-1.5, 2.0)
    st, te, c, _ = view.nl.first_impact(omega, np.array([0.4, y[0]]), y[1], just_hit=0)
    assert st == "impact" and c == 1
    flow = LinearFlow.free(lin)
    ref = flight_jet(flow, flow.forcing(omega), y, te, 3, 0, 1)
    got = nljet.map_jet(view, omega, y, te, 3, 0, 1)
    for k in ("J", "d2", "d3"):
        assert _rel(got[k], ref[k]) < 1e-11, k


# --------------------------------------------------------------------------- Taylor on series
@pytest.mark.slow
def test_series_jets_against_the_chain_at_omega_1_3():
    """The long flight (t_e = 4.83, ~26 Taylor steps on series) at the period-1 orbit of
    the Duffing oscillator at omega = 1.3: the order-3 jets against the independent
    40-digit chain's differences (5e-15 relative observed; the DOP853 series it replaced
    agreed with them to ~1e-13)."""
    from symvi.orbits.periodic import periodic_orbit
    from symvi.studies.nonlinear_check import NonlinearChain
    orbit = periodic_orbit(DUFFING, n=1, p=1, guess=(-1.2407, 1.6538), omega=1.3)
    got = orbit.jet(3)
    ref = NonlinearChain(DUFFING, 1.3).jets(orbit.y, order=3)
    for k, (a, b) in enumerate(zip(got, ref), start=1):
        assert _rel(a, np.array(b, dtype=float)) < 1e-13, k


FUNCTIONS = Model(**ONE, nonlinear=[
    "beta*(sin(x1) + cos(v1)*tanh(x1) + exp(v1/4) + log(2 + x1) + sqrt(3 + x1) "
    "+ sinh(x1/2)*cosh(v1/3) + atan(v1) + tan(x1/4) + 1/(2 + x1) + (2 + x1)**1.5)"],
    parameters={"beta": 0.1})


def test_every_function_on_series_against_differences_of_the_flow():
    """Each function's recurrence on series (sin, cos, tan, exp, log, sqrt, sinh, cosh,
    tanh, atan, a reciprocal, a real power): the series map's J and d2 against central
    differences of the map, whose flights are the scalar Taylor method's
    (:class:`symvi.flow.nonlinear.NonlinearFlow`, another code path); the image equals
    that flow's to 1e-12.  (Against the 40-digit chain, not run here for its 70 s: 1e-15,
    9e-16, 3e-15 relative for J, d2, d3.)"""
    view = FlowView(FUNCTIONS)
    flow = view.nl
    omega, y = 1.3, (-1.25, 1.65)
    st, te, _, _ = flow.first_impact(omega, np.array([0.5, y[0]]), y[1], just_hit=0)
    assert st == "impact"
    got = nljet.map_jet(view, omega, y, te, 3)

    def image(u):
        code, sec, *_ = flow.run(omega, np.array(u), 1)
        return np.array(sec[0])

    assert _rel(image(y)[:-1], got["P"][:-1]) < 1e-12
    h = 1e-5
    for j in range(2):
        e = np.zeros(2)
        e[j] = h
        lo, hi = image(np.add(y, -e)), image(np.add(y, e))
        assert _rel((hi - lo) / (2 * h), got["J"][:, j]) < 1e-8
        lo = nljet.map_jet(view, omega, np.add(y, -e), te, 2)
        hi = nljet.map_jet(view, omega, np.add(y, e), te, 2)
        assert _rel((hi["J"] - lo["J"]) / (2 * h), got["d2"][:, :, j]) < 1e-8
        assert _rel((hi["d2"] - lo["d2"]) / (2 * h), got["d3"][..., j]) < 1e-6


@pytest.mark.parametrize("name", ["omega", "beta", "mass[1]"])
def test_parameter_series_against_differences(name):
    """The series in a parameter (omega in the phase, a force parameter in the tape, a
    mass through M(p)^-1 as a series) with functions in the forces: dP/dp and dJ/dp at
    fixed y against central differences of the map's P and J in p."""
    view = FlowView(FUNCTIONS)
    omega, y = 1.3, (-1.25, 1.65)
    st, te, _, _ = view.nl.first_impact(omega, np.array([0.5, y[0]]), y[1], just_hit=0)
    par = FUNCTIONS.parameter(name)
    got = nljet.map_jet(view, omega, y, te, 2, param=par)
    h = 1e-6
    if par.is_forcing_frequency:
        lo = nljet.map_jet(view, omega - h, y, te, 1)
        hi = nljet.map_jet(view, omega + h, y, te, 1)
    else:
        p0 = par.get(FUNCTIONS)
        lo = nljet.map_jet(FlowView(par.apply(FUNCTIONS, p0 - h)), omega, y, te, 1)
        hi = nljet.map_jet(FlowView(par.apply(FUNCTIONS, p0 + h)), omega, y, te, 1)
    assert _rel((hi["P"] - lo["P"]) / (2 * h), got["dpP"]) < 1e-8
    assert _rel((hi["J"] - lo["J"]) / (2 * h), got["dpJ"]) < 1e-7


def test_a_backward_series_flight_is_refused():
    """The series flights run forward only: a negative time is refused by name, never
    answered with the start (what it gave before)."""
    from symvi.errors import SingularCaseError
    m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.5, restitution=0.8), nonlinear=["beta*x1**3"],
              parameters={"beta": 0.5})
    v = FlowView(m)
    F = v.forcing(1.3)
    z = v.flight(F, np.array([0.1, 0.2]), 0.3, 0.5)[0]
    assert np.max(np.abs(z - [0.1, 0.2])) > 1e-3
    with pytest.raises(SingularCaseError, match="forward only"):
        v.flight(F, np.array([0.1, 0.2]), 0.3, -0.1)
