"""An elastic stop's gap, stiffness and damping and an entry of M, K, C, P as series
variables of a model with elastic stops and nonlinear forces (issue 28): each contact
phase's field moves with them, K_S(p), C_S(p), M(p)^-1, P(p) and the contact force f_S(p)
(:meth:`symvi.flow.nlcontact.NonlinearPhase.rates`), and a gap moves the flights' ends
(the section, an entry's and an exit's level).

Checks that could fail: with the nonlinearity off, every flight's J, d2, d3 and its
parameter slots dP/dp, dJ/dp equal the exact linear phase's generated jets
(:meth:`symvi.flow.linear.LinearFlow.contact`, :func:`symvi.codegen.jets.flight_jet`),
and d2P/dp2 central differences of the linear flow's dP/dp; with beta != 0, dP/dp of the
entry-to-entry map against central differences of the walk (simulate: the phases' scalar
Taylor flow and its events, another path), dJ/dp, d2P/dp2 and d(d2)/dp against
differences of the series map at the perturbed parameter, and the shooting system's
dG/dp against central differences of G; ``symvi continue`` in an elastic stiffness."""
import json

import numpy as np
import pytest

from symvi.codegen.jets import flight_jet
from symvi.flow import nljet
from symvi.flow.linear import LinearFlow
from symvi.flow.nlcontact import view
from symvi.model import Model, Signature, dumps
from symvi.orbits.periodic import Problem
from symvi.simulations.simulation import simulate
from tests.flow.test_nonlinear_elastic import _ONE, _TWO, CHAIN, DUFFING
from tests.fuzz._cli import cli

LIN_ONE = Model(**_ONE)
OFF_ONE = Model(**_ONE, nonlinear=["beta*x1**3"], parameters={"beta": 0.0})
LIN_TWO = Model(**_TWO, stops=CHAIN.stops)
OFF_TWO = Model(**_TWO, nonlinear=["beta*x1**3", "0"], parameters={"beta": 0.0},
                stops=CHAIN.stops)
#: the elastic stop's numbers and one entry of each of M, K, C, P
ONE_NAMES = ("stop[1].gap", "stop[1].stiffness", "stop[1].damping", "mass[1]",
             "stiffness[1,1]", "damping[1,1]", "forcing[1]")
#: the chain: its elastic lower stop on mass 2 (stop 1), beside a rigid stop (stop 2)
TWO_NAMES = ("stop[1].gap", "stop[1].stiffness", "stop[1].damping", "mass[2]", "mass[1]",
             "stiffness[1,2]", "stiffness[2,2]", "damping[2,2]", "forcing[2]")
#: the starts of the walks (the first stop's section, entering it)
Y_ONE, Y_TWO = (0.8, 0.2), (-0.4, 0.1, 0.0, 0.3)
OMEGA = {1: 1.3, 2: 1.2}


def _rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(1.0, float(np.max(np.abs(b)))))


def _flights(model, omega, y0, n):
    """The first n flights of the walk of ``model`` from y0: (phase, y, te, start, end), one
    per pair of consecutive events (an entry, an exit, a rigid impact)."""
    ev = simulate(model, omega, y0=y0, n_impacts=n).events
    out = []
    for k in range(n):
        out.append((tuple(ev.active[k]), tuple(ev.section[k]), float(ev.t[k + 1] - ev.t[k]),
                    int(ev.hits[k]), int(ev.hits[k + 1])))
    return out


@pytest.fixture(scope="module")
def walks():
    """Flights of each model in every phase: the one-mass Duffing's entry -> exit (in
    contact) and exit -> entry (free); the chain's flights between its elastic stop's
    entries and exits and its rigid stop's impacts."""
    return {1: _flights(OFF_ONE, OMEGA[1], Y_ONE, 4), 2: _flights(OFF_TWO, OMEGA[2], Y_TWO, 8)}


@pytest.mark.parametrize("key, name", [(1, nm) for nm in ONE_NAMES] +
                         [(2, nm) for nm in TWO_NAMES])
def test_nonlinearity_off_equals_the_linear_phases(walks, key, name):
    """beta = 0: each flight's series map (J, d2, d3) and its parameter slots dP/dp and
    dJ/dp equal the exact linear phase's generated jets along the parameter's tangent (the
    contact phase's K_S, C_S and offset moved by :func:`symvi.codegen.layout.phase_tangent`)
    to 1e-10; d2P/dp2 of the series equals central differences (h = 1e-5) of the linear
    phase's dP/dp (at the impact time of p0 +- h) to 1e-7.  Both phases of each model are met, and the parameter moves some
    flight's map."""
    lin, off = (LIN_ONE, OFF_ONE) if key == 1 else (LIN_TWO, OFF_TWO)
    omega = OMEGA[key]
    par, lpar = off.parameter(name), lin.parameter(name)
    p0, h = lin.value(name), 1e-5
    moved, phases = 0.0, set()
    for S, y, te, start, end in walks[key]:
        phases.add(S)
        fl = LinearFlow.contact(lin, S)
        ref = flight_jet(fl, fl.forcing(omega), y, te, 3, start, end, lpar.tangent(lin))
        got = nljet.map_jet(view(off, S), omega, y, te, 3, start, end, param=par)
        for k in ("J", "d2", "d3", "dpP", "dpJ"):
            assert _rel(got[k], ref[k]) < 1e-10, (S, k, _rel(got[k], ref[k]))
        moved = max(moved, float(np.max(np.abs(ref["dpP"]))))
        # d2P/dp2: the series' second order in p against the linear flow's dP/dp at p +- h
        alg, P, _, _ = nljet.impact_series(view(off, S), omega, y, te, 2, start, end,
                                           param=par)
        d = []
        for s in (-1, 1):
            m = lpar.apply(lin, p0 + s * h)
            # the impact time at p0 + s h (the series' solve at that parameter), then the
            # exact linear phase's jets there
            t = nljet.impact_series(view(par.apply(off, p0 + s * h), S), omega, y, te, 1,
                                    start, end)[2]
            fs = LinearFlow.contact(m, S)
            d.append(flight_jet(fs, fs.forcing(omega), y, t, 2, start, end,
                                lpar.tangent(m))["dpP"])
        m = len(y)
        assert _rel(alg.tensor(P, 2)[:, m, m], (d[1] - d[0]) / (2 * h)) < 1e-7, S
    assert len(phases) == 2 and moved > 1e-3


def _walk(model, omega, y, n=4):
    """The events of the walk from entry point y (the scalar Taylor flow of each phase and
    its events): the first is the entry after the start's contact and free flight."""
    ev = simulate(model, omega, y0=y, n_impacts=n).events
    assert list(ev.hits[:3]) == [0, 0, 0] and ev.active[:2] == ((0,), ())
    return ev


@pytest.mark.parametrize("name", ONE_NAMES)
def test_derivatives_against_differences_of_the_map(name):
    """beta = 0.5, the impact Duffing oscillator with an elastic stop: the entry -> exit ->
    entry map's dP/dp (J_1 dP_0/dp + dP_1/dp from the two phases' series) against central
    differences (h = 1e-5) of the walk of simulate, the scalar Taylor flow of each phase
    with its events (1e-7); each flight's dJ/dp, d2P/dp2 and d(d2)/dp against central
    differences of its series map at p +- h (1e-7)."""
    omega = OMEGA[1]
    par = DUFFING.parameter(name)
    p0 = DUFFING.value(name)
    ev = _walk(DUFFING, omega, Y_ONE)
    y0, y1 = tuple(ev.section[0]), tuple(ev.section[1])
    t0, t1 = float(ev.t[1] - ev.t[0]), float(ev.t[2] - ev.t[1])
    jets = [nljet.map_jet(view(DUFFING, (0,)), omega, y0, t0, 3, 0, 0, param=par),
            nljet.map_jet(view(DUFFING, ()), omega, y1, t1, 3, 0, 0, param=par)]
    dP = jets[1]["J"] @ jets[0]["dpP"] + jets[1]["dpP"]
    h = 1e-5
    fd = [_walk(par.apply(DUFFING, p0 + s * h), omega, y0).section[0] for s in (-1, 1)]
    diff = (fd[1] - fd[0]) / (2 * h)
    diff[-1] = (fd[1][-1] - fd[0][-1] + np.pi) % (2 * np.pi) - np.pi   # tau mod 2 pi
    diff[-1] /= 2 * h
    assert _rel(dP, diff) < 1e-7, (dP, diff)
    assert np.max(np.abs(dP)) > 1e-3
    m = len(y0)
    for S, y, te in (((0,), y0, t0), ((), y1, t1)):
        alg, P, _, _ = nljet.impact_series(view(DUFFING, S), omega, y, te, 3, 0, 0, param=par)
        T2, T3 = alg.tensor(P, 2), alg.tensor(P, 3)
        lo, hi = (nljet.map_jet(view(par.apply(DUFFING, p0 + s * h), S), omega, y, te, 2, 0,
                                0, param=par) for s in (-1, 1))
        assert _rel((hi["J"] - lo["J"]) / (2 * h), T2[:, :m, m]) < 1e-7, S
        assert _rel((hi["dpP"] - lo["dpP"]) / (2 * h), T2[:, m, m]) < 1e-7, S
        assert _rel((hi["d2"] - lo["d2"]) / (2 * h), T3[:, :m, :m, m]) < 1e-7, S


@pytest.mark.parametrize("model, omega, names", [
    (DUFFING, 1.3, ONE_NAMES + ("beta",)),
    (CHAIN, 1.2, TWO_NAMES + ("beta", "stop[2].gap", "stop[2].restitution")),
])
def test_dG_dparam_against_central_differences(model, omega, names):
    """The shooting system at the attractor's orbit (the Duffing's 1-2 orbit, the chain's
    orbit of four events): dG/dp, the continued parameter's and :meth:`Problem.derivative`'s
    in a problem continued in omega (each flight in its own phase, as a curve's second
    parameter; it flew the free field before), against central differences of G (1e-8)."""
    from symvi.continuation import attractor_orbit
    o = attractor_orbit(model, omega)
    sig, u = Signature(o.signature, o.contact), np.append(np.ravel(o.points), o.times)
    n, p = o.n, o.p
    pw = Problem(model, n, p, omega=omega, param="omega", signature=sig)
    for name in names:
        lam = model.value(name)
        pr = Problem(model, n, p, omega=omega, param=name, signature=sig)
        got = pr.evaluate(u, lam, jac=False, dparam=True)[2]
        h = 1e-6 * max(1.0, abs(lam))
        fd = (pr.evaluate(u, lam + h, jac=False)[0] -
              pr.evaluate(u, lam - h, jac=False)[0]) / (2 * h)
        assert np.max(np.abs(got - fd)) < 1e-8 * max(1.0, np.max(np.abs(fd))), name
        assert np.max(np.abs(pw.derivative(u, omega, name) - got)) < 1e-12 * max(
            1.0, np.max(np.abs(got))), name
        assert np.max(np.abs(got)) > 1e-4, name


@pytest.mark.slow
def test_symvi_continue_in_an_elastic_stiffness(tmp_path):
    """``symvi continue`` in the elastic stop's stiffness at omega = 1.3 (beta = 0.5): the
    1-2 branch runs to k_s = 300 with a flip near 222.2; at that stiffness continuation in
    omega locates the flip at omega = 1.3 to 1e-8, with the same coefficient c (1e-6)."""
    f = tmp_path / "duffing.toml"
    f.write_text(dumps(DUFFING))
    rc, out, err = cli("continue", "--model", f, "--range", "stop[1].stiffness=50:300",
                       "--set", "omega=1.3", "--orbit", "1-2", "--max-points", "400",
                       "--json")
    assert rc == 0, err
    obj = json.loads(out)
    special = [s for s in obj["special"] if s["kind"] == "flip"]
    assert len(special) == 1 and abs(special[0]["value"] - 222.2) < 0.1, obj["special"]
    k, c = special[0]["value"], special[0]["coefficients"]["c"]
    g = tmp_path / "at_k.toml"
    g.write_text(dumps(DUFFING.parameter("stop[1].stiffness").apply(DUFFING, k)))
    rc, out, err = cli("continue", "--model", g, "--range", "omega=1.32:1.28", "--orbit",
                       "1-2", "--max-points", "400", "--json")
    assert rc == 0, err
    flips = [s for s in json.loads(out)["special"] if s["kind"] == "flip"]
    assert len(flips) == 1, flips
    assert abs(flips[0]["value"] - 1.3) < 1e-8, flips[0]["value"]
    assert abs(flips[0]["coefficients"]["c"] - c) < 1e-6 * abs(c)
