"""The independent 40-digit chain of a model with nonlinear forces (issue 28,
:mod:`symvi.studies.nonlinear_check`): against the exact linear map and its generated jets
(beta = 0), solve_ivp, symvi's NonlinearFlow, an identity of the multipliers, and a
contact the step ends would not see."""
import math

import mpmath
import numpy as np
import pytest

import symvi
from symvi.codegen.jets import jet_at
from symvi.errors import ParameterError, SingularCaseError
from symvi.flow.nonlinear import NonlinearFlow
from symvi.maps.impact import poincare_map
from symvi.model import Model, Stop
from symvi.normal_forms.normal_form import flip_coefficient, kuznetsov
from symvi.studies.nonlinear_check import NonlinearChain

LIN = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
DUFFING = Model(**LIN, nonlinear=["beta*x1**3"], parameters={"beta": 0.5})
OMEGA = 1.5
Y = (-1.2, 1.3)                          # a section point (v1+, tau), not a fixed point


def _rel(a, b):
    """max |a - b| / max |b| over two arrays of mpf (or numbers)."""
    a, b = np.asarray(a, dtype=object).ravel(), np.asarray(b, dtype=object).ravel()
    return max(abs(u - v) for u, v in zip(a, b)) / max(abs(v) for v in b)


@pytest.fixture(scope="module")
def linear():
    """beta = 0: the chain (which still runs the force's recurrences) and the exact map."""
    model = Model(**LIN, nonlinear=["beta*x1**3"], parameters={"beta": 0.0})
    return NonlinearChain(model, OMEGA), Model(**LIN)


@pytest.fixture(scope="module")
def duffing():
    return NonlinearChain(DUFFING, OMEGA)


def test_beta_zero_map_is_the_exact_linear_map(linear):
    chain, lin = linear
    y1 = chain.map(Y)
    step = poincare_map(lin, OMEGA, Y, digits=40)
    with mpmath.workdps(40):
        assert _rel(y1, step.y) < 1e-35
        t, _ = chain.flight([0.5, Y[0]], Y[1])
        assert abs(t - step.t) < 1e-35


def test_beta_zero_jets_are_the_generated_jets(linear):
    """J, d2, d3 of the chain (differences at 40 digits) against the exact generated jets
    at 40 digits, at a point that is not a fixed point (te from the flight); 2e-25, 2e-24,
    5e-24 observed."""
    chain, lin = linear
    te = poincare_map(lin, OMEGA, Y, digits=40).t
    jt = jet_at(lin, OMEGA, Y, te, order=3, digits=40)
    J, d2, d3 = chain.jets(Y, 3)
    with mpmath.workdps(40):
        for mine, exact in ((J, jt.jacobian), (d2, jt.d2), (d3, jt.d3)):
            assert _rel(mine, exact) < 1e-20


@pytest.mark.slow
def test_order_five_jets_against_differences_of_the_exact_d3(linear):
    """d4 and d5 (the chain's stencils of accuracy 6) against central differences
    (accuracy 4, step 1e-5) of the generated d3 along each coordinate; also J, d2, d3 of
    the order-5 call."""
    chain, lin = linear
    jets = chain.jets(Y, 5)
    h = mpmath.mpf("1e-5")
    with mpmath.workdps(50):
        def d3_at(m, o):
            y = [mpmath.mpf(v) for v in Y]
            y[m] += o * h
            return jet_at(lin, OMEGA, y, poincare_map(lin, OMEGA, y, digits=50).t,
                          order=3, digits=50).d3
        base = jet_at(lin, OMEGA, Y, poincare_map(lin, OMEGA, Y, digits=50).t, order=3,
                      digits=50)
        for mine, exact in zip(jets[:3], (base.jacobian, base.d2, base.d3)):
            assert _rel(mine, exact) < 1e-20
        for m in range(2):
            pts = {o: d3_at(m, o) for o in (-2, -1, 1, 2)}
            d4 = (pts[-2] - 8 * pts[-1] + 8 * pts[1] - pts[2]) / (12 * h)
            d5 = (-pts[-2] + 16 * pts[-1] - 30 * base.d3 + 16 * pts[1] - pts[2]) / (12 * h * h)
            assert _rel(jets[3][..., m], d4) < 1e-15           # ~2e-20 observed
            # d5[..., m, m]: every entry of a symmetric 5-tensor in 2 variables has a repeat
            assert _rel(jets[4][..., m, m], d5) < 1e-15


@pytest.mark.slow
def test_normal_form_coefficients_match_the_generated_jets(linear):
    """Kuznetsov's c1, l1 at the linear period-1 orbit (a complex pair) from the chain's
    jets, against kuznetsov() on the generated jets."""
    chain, lin = linear
    orbit = symvi.period1_orbits(lin, OMEGA)[0]
    fp = chain.fixed_point(orbit.y)
    with mpmath.workdps(40):
        assert abs(fp.times[0] - 2 * mpmath.pi / OMEGA) < 1e-35
    nf = chain.normal_form(fp.y)
    jt = jet_at(lin, OMEGA, fp.y, 2 * mpmath.pi / OMEGA, order=3, digits=40)
    c1, l1 = kuznetsov(jt.jacobian, jt.d2, jt.d3, digits=40)
    assert nf.flip is None
    assert abs(nf.c1 - c1) < 1e-12 * abs(c1) and abs(nf.l1 - l1) < 1e-12 * abs(l1)


def test_flip_coefficient_matches_the_generated_jets():
    """At omega = 1.0 the linear orbit has real multipliers (-0.63, -0.54): the chain's
    flip coefficient (float64 from its 40-digit jets) against flip_coefficient on the
    generated jets."""
    lin = Model(**LIN)
    orbit = symvi.period1_orbits(lin, 1.0)[0]
    chain = NonlinearChain(Model(**LIN, nonlinear=["beta*x1**3"], parameters={"beta": 0.0}),
                           1.0)
    nf = chain.normal_form(orbit.y)
    jt = jet_at(lin, 1.0, orbit.y, 2 * math.pi, order=3, digits=40)
    c = flip_coefficient(*(np.array(a.tolist(), dtype=float)
                           for a in (jt.jacobian, jt.d2, jt.d3)))[0]
    assert nf.c1 is None and nf.flip is not None
    assert abs(nf.flip - c) < 1e-9 * abs(c)


def _duffing_rhs(t, z, tau):
    return [z[1], math.sin(OMEGA * t + tau) - 0.1 * z[1] - z[0] - 0.5 * z[0] ** 3]


@pytest.mark.parametrize("z0, tau", [((0.5, -1.33555366), 1.74584428),   # from the stop
                                     ((0.0, 0.3), 0.7)])                 # off it
def test_flight_against_solve_ivp(duffing, z0, tau):
    from scipy.integrate import solve_ivp

    def hit(t, z, tau):
        return z[0] - 0.5
    hit.terminal, hit.direction = True, 1
    sol = solve_ivp(_duffing_rhs, (0, 60), z0, method="DOP853", rtol=1e-13, atol=1e-14,
                    events=hit, args=(tau,))
    te, ze = duffing.flight(z0, tau)
    assert abs(float(te) - sol.t_events[0][0]) < 1e-11
    assert np.abs(np.array(ze, dtype=float) - sol.y_events[0][0]).max() < 1e-11


def test_map_against_the_nonlinear_flow(duffing):
    y = (-1.3, 1.7)
    _, sec, _, _, _, _ = NonlinearFlow(DUFFING).run(OMEGA, np.array(y), 3)
    for p in (1, 3):
        assert np.abs(np.array(duffing.map_n(y, p), dtype=float) - sec[p - 1]).max() < 1e-12
    assert duffing.map(y) == duffing.map_n(y, 1)


def test_map_of_two_masses_against_the_nonlinear_flow():
    """A stop on mass 2 (the section's order is (v2+, x1, v1, tau)), a force with sin and
    a velocity: two impacts."""
    model = Model(mass=[1.0, 2.0], stiffness=[[3.0, -1.0], [-1.0, 1.0]],
                  damping=[[0.1, 0.0], [0.0, 0.05]], forcing=[0.0, 1.0],
                  stop=Stop(mass=2, gap=0.4, restitution=0.7),
                  nonlinear=["0", "beta*(x2-x1)**3 + gamma*sin(x1)*v2"],
                  parameters={"beta": 0.5, "gamma": 0.1})
    y = (-1.35885456, -0.13632017, 0.28919907, 2.06676566)
    _, sec, _, _, _, _ = NonlinearFlow(model).run(1.1, np.array(y), 2)
    got = NonlinearChain(model, 1.1).map_n(y, 2)
    assert np.abs(np.array(got, dtype=float) - sec[1]).max() < 1e-12


#: a force with every recurrence of the chain: exp, log, sqrt, a real power, a quotient,
#: tan, tanh, atan, sin / sinh, cos / cosh, products with a velocity
EVERY = ("g*(exp(x1/4) - 1) + g*tanh(v1) + g*atan(x1) + g*cos(x1) + g*log(2 + x1)"
         " + g*sqrt(2 + x1) + g*tan(x1/4) + g*cosh(v1) + g/(2 + x1) + g*(2 + x1)**1.5"
         " + g*sinh(x1)*x1**2")


@pytest.mark.slow
@pytest.mark.parametrize("force, side, y", [(EVERY, "upper", (-1.3, 1.7)),
                                            ("g*x1**3", "lower", (1.3, 1.7))],
                         ids=["every-function-upper", "cubic-lower"])
def test_forces_and_sides_against_the_nonlinear_flow(force, side, y):
    model = Model(**{**LIN, "stop": Stop(mass=1, gap=0.5 if side == "upper" else -0.5,
                                         restitution=0.8, side=side)},
                  nonlinear=[force], parameters={"g": 0.05})
    _, sec, _, _, _, _ = NonlinearFlow(model).run(OMEGA, np.array(y), 1)
    got = NonlinearChain(model, OMEGA).map(y)
    assert np.abs(np.array(got, dtype=float) - sec[0]).max() < 1e-12


@pytest.mark.slow
def test_duffing_period1_orbit():
    """The Duffing impact oscillator x'' + 0.1 x' + x + 0.5 x^3 = sin(1.5 t + tau), stop
    at 0.5 with r = 0.8: the period-1 orbit a simulation settles on, at 40 digits.

    Identity: on the section x = b with coordinates (v, t) the flight maps the flux
    measure |v| dv dt with the factor exp(-c t_e) (Liouville: div = -c, the force
    depends on x only) and the reset multiplies v by -r, so det DP = r |v+| / |v-|
    exp(-c t_e) = r^2 exp(-c t_e) at a fixed point (|v+| = r |v-|)."""
    sim = symvi.simulate(DUFFING, OMEGA, y0=(-0.5, 0.0), n_impacts=4, transient=400)
    guess = sim.section[-1]
    assert np.abs(sim.section[-1] - sim.section[-2]).max() < 1e-9
    chain = NonlinearChain(DUFFING, OMEGA)
    fp = chain.fixed_point(guess)
    with mpmath.workdps(45):
        assert fp.periods == 1 and fp.residual < 1e-40
        assert abs(fp.times[0] - 2 * mpmath.pi / OMEGA) < 1e-38
        assert np.abs(np.array(fp.y, dtype=float) - guess).max() < 1e-10
        assert _rel(chain.map(fp.y), fp.y) < 1e-38
        lam = fp.multipliers
        det = lam[0] * lam[1]
        r = mpmath.mpf(0.8)
        assert abs(det - r * r * mpmath.exp(-mpmath.mpf(0.1) * fp.times[0])) < 1e-28
        # a stable focus: what the simulation settled on
        assert abs(lam[0]) < 1 and mpmath.im(lam[0]) > 0.1
        assert abs(lam[1] - mpmath.conj(lam[0])) < 1e-30


def test_a_shallow_contact_inside_a_step_is_found():
    """Unforced and undamped, x'' = -x - 0.5 x^3 keeps E = v^2/2 + V(x), V = x^2/2 +
    x^4/8: from 1e-10 below the stop, rising so that the apex V^-1(E) passes the stop by
    1e-20, the contact lies ~2e-5 into the first step and lasts ~4e-10 (energy is kept: there is
    no other); with the apex 1e-20 below the stop there is none there."""
    model = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.0]], forcing=[0.0],
                  stop=Stop(mass=1, gap=0.5, restitution=0.8), nonlinear=["beta*x1**3"],
                  parameters={"beta": 0.5})
    chain = NonlinearChain(model, OMEGA)
    with mpmath.workdps(50):
        b, d = mpmath.mpf(0.5), mpmath.mpf("1e-10")

        def V(x):
            return x * x / 2 + x ** 4 / 8
        depth = mpmath.mpf("1e-20")
        te, ze = chain.flight([b - d, mpmath.sqrt(2 * (V(b + depth) - V(b - d)))], 0)
        assert te < 1e-4 and abs(ze[0] - b) < 1e-45
        # the contact's speed: sqrt(2 (V(apex) - V(b)))
        assert abs(ze[1] - mpmath.sqrt(2 * (V(b + depth) - V(b)))) < 1e-35
        with pytest.raises(SingularCaseError, match="no-impact"):
            chain.flight([b - d, mpmath.sqrt(2 * (V(b - depth) - V(b - d)))], 0, t_max=10)


def test_refusals(duffing):
    with pytest.raises(SingularCaseError, match="grazing"):
        duffing.flight([0.5, 0.2], 0.0)                  # on the stop, moving into it
    with pytest.raises(ParameterError, match="z0"):
        duffing.flight([0.6, -1.0], 0.0)                 # inside the stop
    with pytest.raises(ParameterError, match="contact"):
        duffing.map(Y, contact=(0,))                     # stop 1 is rigid: no contact phase
    with pytest.raises(ParameterError, match="on"):
        duffing.map(Y, on=1)                             # one stop: index 0 only
    with pytest.raises(ParameterError, match="order"):
        duffing.jets(Y, 6)


# --------------------------------------------------------------------------- symvi's jets
def test_series_jets_against_the_chain():
    """symvi's jets of the nonlinear map (series flights, :mod:`symvi.flow.nljet`) against
    the chain's 40-digit differences at a period-1 orbit of the Duffing oscillator, orders
    1 to 5 (1.1e-14, 4.2e-14, 4.4e-14, 6.6e-14, 1.2e-13 relative observed)."""
    from symvi.orbits.periodic import periodic_orbit
    orbit = periodic_orbit(DUFFING, n=1, p=1, guess=(-1.3355, 1.7458), omega=OMEGA)
    got = orbit.jet(5)
    ref = NonlinearChain(DUFFING, OMEGA).jets(orbit.y, order=5)
    for k, (a, b) in enumerate(zip(got, ref), start=1):
        b = np.array(b, dtype=float)
        assert np.max(np.abs(a - b)) < 1e-12 * np.max(np.abs(b)), k


def test_flip_coefficient_against_the_chain():
    """The flip a branch of the Duffing impact oscillator (beta = 0.2, c = 0.05, stop at 0)
    locates, and its cubic coefficient, against the chain at the flip's omega: the chain's
    fixed point there has a multiplier -1 to the location's accuracy and its coefficient
    (same normalisation: ||q|| = 1, <p, q> = 1) is the branch's."""
    from symvi.continuation.branch import continue_branch
    from symvi.orbits.periodic import periodic_orbit
    m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.0, restitution=0.8), nonlinear=["beta*x1**3"],
              parameters={"beta": 0.2})
    sim = symvi.simulate(m, 2.6, n_impacts=50, transient=3000)
    o = periodic_orbit(m, n=1, p=1, guess=sim, omega=2.6)
    flip = [s for s in continue_branch(m, "omega", 2.6, 2.8, orbit=o).special
            if s.kind == "flip"][0]
    chain = NonlinearChain(m, flip.value)
    fp = chain.fixed_point(flip.orbit.y)
    assert min(abs(complex(z) + 1) for z in fp.multipliers) < 1e-9
    nf = chain.normal_form(fp.y)
    assert abs(nf.flip - flip.coefficients["c"]) < 1e-7 * abs(nf.flip)


def test_symvi_continue_digits_checks_each_special_point(tmp_path):
    """``symvi continue --digits``: each fold, flip and NS point of the branch re-derived by
    the chain (check_special): the folds' multiplier is 1 at symvi's orbit, the flip's -1
    at the chain's own orbit, and c agrees; a bad --digits is one line, exit 2."""
    import json

    from symvi.model import dumps
    from tests.fuzz._cli import cli
    duffing = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                    stop=Stop(mass=1, gap=0.0, restitution=0.8), nonlinear=["beta*x1**3"],
                    parameters={"beta": 0.2})
    f = tmp_path / "duffing.toml"
    f.write_text(dumps(duffing))
    rc, out, err = cli("continue", "--model", f, "--range", "omega=2.4:3.0", "--digits",
                       "30", "--json")
    assert rc == 0, err
    special = json.loads(out)["special"]
    assert sorted(s["kind"] for s in special) == ["flip", "fold", "fold"]
    for s in special:
        ch = s["chain"]
        assert ch["reason"] == "" and ch["critical_error"] < 1e-10, s
        assert ch["distance"] < 1e-12
        if s["kind"] == "flip":
            assert ch["coefficient"] == "c" and ch["agreement"] >= 10
            assert abs(ch["multiplier"][0] + 1) < 1e-10
    rc, out, err = cli("continue", "--model", f, "--range", "omega=2.4:3.0", "--digits", "8")
    assert rc == 2 and err.startswith("symvi: error: --digits = 8") and err.count("\n") == 1


# --------------------------------------------------------------------------- several stops
TWO_SIDED = Model(**{k: v for k, v in LIN.items() if k != "stop"},
                  stops=[Stop(mass=1, gap=0.5, restitution=0.8),
                         Stop(mass=1, gap=-0.5, restitution=0.8, side="lower")],
                  nonlinear=["beta*x1**3"], parameters={"beta": 0.5})


def _absorber():
    from pathlib import Path
    return symvi.load_model(Path(__file__).resolve().parents[2] / "docs/gallery/absorber.toml")


@pytest.mark.parametrize("which", ["two-sided", "absorber"])
def test_several_stops_map_against_symvi(which):
    """With several stops (a two-sided clearance on one mass; the absorber's two stops
    between masses, in the frame x2 - x1) the chain's own contact search over every guard
    meets the stop symvi's flow meets, at the same time and state: three impacts from
    each stop's section, against :class:`symvi.flow.nljet.FlowView` (float64, 1e-12)."""
    from symvi.flow.nljet import FlowView
    model, omega = (TWO_SIDED, 1.5) if which == "two-sided" else (_absorber(), 1.5)
    view = FlowView.of(model)
    forcing = view.forcing(omega)
    chain = NonlinearChain(model, omega, 30)
    run = symvi.simulate(model, omega, n_impacts=6, transient=50)
    met = set()
    for y, k in zip(run.section[:4], run.hits[:4]):
        y, k = tuple(float(v) for v in y), int(k)
        for _ in range(3):
            st, _, y1, c = view.step(forcing, np.array(y), k)
            assert st == "impact"
            with mpmath.workdps(40):
                got, _, hits, _ = chain._map_u(y, 1, k)
            assert hits == [c]
            got = [float(v) for v in got]
            got[-1] = math.remainder(got[-1] - y1[-1], 2 * math.pi) + y1[-1]
            assert np.allclose(got, y1, rtol=1e-12, atol=1e-12)
            met.add(c)
            y, k = tuple(y1), c
    assert met == {0, 1}                                  # both stops met


def test_several_stops_refuse_a_map_between_two_sections():
    """P^p whose last impact is on another stop than the start's has no fixed point on
    one section: the chain's jets refuse it by name."""
    chain = NonlinearChain(TWO_SIDED, 1.5)
    run = symvi.simulate(TWO_SIDED, 1.5, n_impacts=4, transient=50)
    y, k = tuple(run.section[0]), int(run.hits[0])
    with pytest.raises(SingularCaseError, match="ends on stop"):
        chain.jets(y, 1, p=1, on=k)                      # the next impact: the other stop


@pytest.fixture(scope="module")
def absorber_branch():
    from symvi.continuation import continue_orbits
    model = _absorber()
    run = symvi.simulate(model, 1.5, n_impacts=40, transient=1000)
    return continue_orbits(model, "omega", 1.0, 2.2, simulation=run, max_points=400)


def _absorber_point(branches, kind):
    return [s for b in branches for s in b.special if s.kind == kind][0]


def test_absorber_fold_checked_by_the_chain(absorber_branch):
    """The absorber's fold (1-2 orbit, impacts on both stops between the masses): at 30
    digits the chain's P^2 maps symvi's orbit to itself within 1e-13 and has a
    multiplier 1 there within 1e-11 (symvi located the fold)."""
    from symvi.studies.nonlinear_check import check_special
    sp = _absorber_point(absorber_branch, "fold")
    got = check_special(sp, 30)
    assert got.reason == ""
    assert got.distance < 1e-13
    assert got.critical_error < 1e-11


@pytest.mark.slow
def test_absorber_ns_l1_checked_by_the_chain(absorber_branch):
    """The absorber's subcritical NS point of the 1-2 orbit: the chain (20 digits, its
    own Newton and order-3 differences over both stops) gives the same multipliers on the
    unit circle and l1 to 8 digits or more (9.9 observed; 14.2 at 30 digits)."""
    from symvi.studies.nonlinear_check import check_special
    sp = _absorber_point(absorber_branch, "ns")
    got = check_special(sp, 20)
    assert got.reason == ""
    assert got.critical_error < 1e-12
    assert got.chain > 0 and got.agreement >= 8
