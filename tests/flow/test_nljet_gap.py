"""A stop's gap or restitution as a series variable of the nonlinear impact map's jets
(issue 28, :mod:`symvi.flow.nljet`): the gap moves the start's section and the guard's
level, the restitution (and the masses, for an impulse along M^-1 c) the reset.

Checks that could fail: with the nonlinearity off, the jets and their parameter slots
equal the exact linear flow's generated ones, and every derivative to order 3 in (y, p)
equals differences of the exact flow's map at 40 digits; with beta != 0, the derivatives
in gap and r against central differences of the map (the scalar Taylor run of
NonlinearFlow, and the series map at the perturbed parameter)."""
import itertools
import math

import mpmath
import numpy as np
import pytest

from symvi.codegen.jets import flight_jet, jet_at
from symvi.errors import ParameterError
from symvi.flow import nljet
from symvi.flow.linear import LinearFlow
from symvi.flow.nljet import FlowView
from symvi.model import Model, Stop

ONE = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
TWO = dict(mass=[1.0, 2.0], stiffness=[[2.0, -1.0], [-1.0, 1.5]],
           damping=[[0.05, 0.0], [0.0, 0.05]], forcing=[1.0, 0.3],
           stop=Stop(mass=2, gap=0.3, restitution=0.7))
#: a two-sided clearance: the flight from the upper stop's section to the lower one's
SIDES = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
             stops=[Stop(mass=1, gap=0.4, restitution=0.8),
                    Stop(mass=1, gap=-0.4, side="lower", restitution=0.7)])
#: an impact between the masses: the flow's frame is T x, the impulse along M^-1 c
BETWEEN = dict(mass=[1.0, 2.0], stiffness=[[2.0, -1.0], [-1.0, 1.5]],
               damping=[[0.05, 0.0], [0.0, 0.05]], forcing=[1.0, 0.3],
               stop=Stop(between=(1, 2), gap=0.3, restitution=0.7))

#: (model, forces, omega, section point, start, end): flights that end in an impact
CASES = {
    "one": (ONE, ["beta*x1**3"], 1.3, (-1.25, 1.65), 0, 0),
    "two": (TWO, ["beta*x1**3", "beta*(x2 - x1)**3"], 1.1, None, 0, 0),
    "sides": (SIDES, ["beta*x1**3"], 1.2, (-1.5, 2.0), 0, 1),
    "between": (BETWEEN, ["beta*x1**3", "beta*x2**3"], 1.1,
                (-0.5881259, -0.0920835, -0.1213647, 5.7105734), 0, 0),
}


def _rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(1.0, float(np.max(np.abs(b)))))


def _case(key, beta):
    kw, forces, omega, y, start, end = CASES[key]
    lin = Model(**kw)
    nl = Model(**kw, nonlinear=forces, parameters={"beta": beta})
    if y is None:                              # the period-1 orbit of the linear part
        from symvi.orbits.period1 import admissible_orbits
        y = tuple(admissible_orbits(lin, omega)[0].y)
    view = FlowView(nl)
    st, te, y1, c = view.step(view.forcing(omega), np.array(y, float), start)
    assert st == "impact" and c == end
    return lin, nl, view, omega, y, te, start, end


@pytest.mark.parametrize("key, name", [
    ("one", "gap"), ("one", "restitution"), ("two", "gap"), ("two", "restitution"),
    ("sides", "stop[1].gap"), ("sides", "stop[2].gap"), ("sides", "stop[2].restitution"),
    ("between", "gap"), ("between", "restitution"), ("between", "mass[1]"),
])
def test_nonlinearity_off_equals_the_generated_jets(key, name):
    """beta = 0: the series map's J, d2, d3 and its slots dP/dp, dJ/dp along a gap or a
    restitution equal the exact linear flow's generated jets with that parameter's tangent
    (:func:`symvi.codegen.jets.flight_jet`) to 1e-10: a gap of the start's stop (one,
    two, stop[1] of sides), of the end's (stop[2]), a restitution of the end's, a stop
    between masses (a frame T x), and a mass, which moves that stop's reset R(M)."""
    lin, nl, view, omega, y, te, start, end = _case(key, 0.0)
    flow = LinearFlow.free(lin) if len(lin.constraints) > 1 else LinearFlow.of(lin)
    ref = flight_jet(flow, flow.forcing(omega), y, te, 3, start, end,
                     lin.parameter(name).tangent(lin))
    got = nljet.map_jet(view, omega, y, te, 3, start, end, param=nl.parameter(name))
    for k, want in (("J", "J"), ("d2", "d2"), ("d3", "d3"), ("dpP", "dpP"), ("dpJ", "dpJ")):
        assert _rel(got[k], ref[want]) < 1e-10, k
    assert np.max(np.abs(ref["dpP"])) > 0.1          # the parameter moves the map


# --------------------------------------------------------------------------- order 3 in p
#: the step of the 40-digit differences: a power of 2, so p +- k h is exact in float64
H = 2.0 ** -23


def _exact_map(lin, view, name, value, omega, y, te0):
    """(P, J, d2, d3) of the exact linear flow's map at ``name`` = value, 40 digits: the
    impact time by Newton on the guard, P from the flight, J, d2, d3 the generated jets
    (``view``: the section's layout, the linear part's)."""
    m = lin.parameter(name).apply(lin, value)
    flow = LinearFlow.of(m, 40)
    n = m.n
    F = flow.forcing(mpmath.mpf(omega))
    pa, fa = view.positions[0], view.frames[0]
    z0 = np.empty(2 * n, dtype=object)
    z0[pa] = mpmath.mpf(m.constraints[0].gap)
    z0[fa] = [mpmath.mpf(v) for v in y[:-1]]
    tau = mpmath.mpf(y[-1])
    g, level = flow.guard, flow.level
    t = mpmath.mpf(te0)
    for _ in range(8):
        z, _, _, dzdt = flow.flight(F, z0, tau, t)
        t -= (g @ z[:n] - level) / (g @ dzdt[:n])
    z = flow.flight(F, z0, tau, t)[0]
    z[n:] = flow.reset @ z[n:]
    P = np.array(list(z[fa]) + [tau + F.omega * t], dtype=object)
    jet = jet_at(m, omega, y, t, 3, digits=40)
    return P, jet.jacobian, jet.d2, jet.d3


def _differences(f, k):
    """The k-th derivative (k = 0..3) of f at 0 from f(j H), j = -2..2 (error ~H^2)."""
    if k == 0:
        return f[0]
    if k == 1:
        return (f[1] - f[-1]) / (2 * H)
    if k == 2:
        return (f[1] - 2 * f[0] + f[-1]) / H ** 2
    return (f[2] - 2 * f[1] + 2 * f[-1] - f[-2]) / (2 * H ** 3)


@pytest.mark.parametrize("name", ["gap", "restitution"])
def test_every_derivative_to_order_three_against_the_exact_flow(name):
    """beta = 0, one mass: each derivative of P of total order 1..3 in (v, tau, p), the
    mixed ones and d^2P/dp^2, d^3P/dp^3 included, against the exact flow's map at 40
    digits: its generated J, d2, d3 in y and 40-digit differences in p (step 2^-23, error
    ~1e-14) of P, J, d2, at each p its impact time solved again; 1e-10 relative."""
    lin, nl, view, omega, y, te, start, end = _case("one", 0.0)
    p0 = lin.value(name)
    with mpmath.mp.workdps(40):
        vals = {j: _exact_map(lin, view, name, p0 + j * H, omega, y, te)
                for j in range(-2, 3)}
        pieces = [{j: v[k] for j, v in vals.items()} for k in range(4)]   # P, J, d2, d3
        m = len(y)
        alg, P, _, _ = nljet.impact_series(view, omega, y, te, 3, 0, 0,
                                           param=nl.parameter(name))
        for order in (1, 2, 3):
            got = alg.tensor(P, order)
            want = np.empty_like(got, dtype=object)
            for idx in itertools.product(range(m + 1), repeat=order):
                ys = [i for i in idx if i < m]
                kp = order - len(ys)
                # d^kp/dp^kp of the y-tensor of order len(ys)
                der = _differences(pieces[len(ys)], kp)
                want[(slice(None),) + idx] = der[(slice(None),) + tuple(ys)]
            err = float(np.max(np.abs(np.array(got, dtype=object) - want)))
            scale = max(1.0, float(np.max(np.abs(want))))
            assert err < 1e-10 * scale, (order, err)


# --------------------------------------------------------------------------- beta != 0
@pytest.mark.parametrize("key, name", [
    ("one", "gap"), ("one", "restitution"), ("sides", "stop[1].gap"),
    ("sides", "stop[2].gap"), ("sides", "stop[2].restitution"), ("between", "gap"),
    ("between", "mass[1]"),
])
def test_derivatives_in_gap_and_r_against_differences_of_the_map(key, name):
    """beta = 0.5: dP/dp against central differences of the map that NonlinearFlow runs
    (FlowView.step: the scalar Taylor method and its events, another code path), and the
    series' dJ/dp, d2P/dp2, d(d2)/dp, d3P/dp3 against differences of the series map at the
    perturbed parameter (p +- h: its impact time solved again there)."""
    lin, nl, view, omega, y, te, start, end = _case(key, 0.5)
    par = nl.parameter(name)
    p0 = nl.value(name)
    got = nljet.map_jet(view, omega, y, te, 3, start, end, param=par)
    alg, P, _, _ = nljet.impact_series(view, omega, y, te, 3, start, end, param=par)
    m = len(y)
    T2, T3 = alg.tensor(P, 2), alg.tensor(P, 3)

    def at(value, order=3):
        v = FlowView(par.apply(nl, value))
        img = v.step(v.forcing(omega), np.array(y, float), start)[2]
        return img, nljet.map_jet(v, omega, y, te, order, start, end, param=par)

    h = 1e-5
    (lo_img, lo), (hi_img, hi) = at(p0 - h), at(p0 + h)
    assert _rel((hi_img - lo_img) / (2 * h), got["dpP"]) < 1e-8
    assert _rel((hi["J"] - lo["J"]) / (2 * h), got["dpJ"]) < 1e-8
    assert _rel((hi["dpP"] - lo["dpP"]) / (2 * h), T2[:, m, m]) < 1e-8
    assert _rel((hi["d2"] - lo["d2"]) / (2 * h), T3[:, :m, :m, m]) < 1e-7
    h = 1e-3
    lo, mid, hi = (at(p0 + s * h, 2)[1]["dpP"] for s in (-1, 0, 1))
    assert _rel((hi - 2 * mid + lo) / h ** 2, T3[:, m, m, m]) < 1e-5
    assert np.max(np.abs(got["dpP"])) > 0.1


def test_what_the_series_take_has_one_owner():
    """What the series take has one owner (:func:`nljet.check_parameter`): an elastic stop's
    gap, stiffness and damping and an entry of M, K, C, P too (the contact phases' fields
    move with them: tests/flow/test_nonlinear_elastic_params.py); a parameter the model
    does not have (a rigid stop's restitution on an elastic stop) is refused in one line
    naming it and what the series take."""
    el = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
               stop=Stop(mass=1, gap=0.0, stiffness=50.0, damping=0.1),
               nonlinear=["beta*x1**3"], parameters={"beta": 0.2})
    for name in ("gap", "stop[1].stiffness", "stop[1].damping", "mass[1]",
                 "stiffness[1,1]", "damping[1,1]", "forcing[1]", "beta", "omega"):
        assert nljet.check_parameter(el, el.parameter(name)).name == name
    rigid = Model(**ONE).parameter("restitution")
    with pytest.raises(ParameterError, match=r"^param = 'restitution'.*elastic stop's gap, "
                       "stiffness or damping") as e:
        nljet.check_parameter(el, rigid)
    assert "\n" not in str(e.value)
