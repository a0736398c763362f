"""The Taylor method of the nonlinear flow (:mod:`symvi.flow.taylor`): the forces' series
against SymPy's, one step against the exact solution, a flight against mpmath at 30 digits,
and the events on the solution's polynomial: a short excursion past the gap is found, a
near miss is not, and the hull's bracket is the first root's."""
import math

import mpmath
import numpy as np
import pytest
import sympy

from symvi.flow import _hull
from symvi.flow import nonlinear as nl
from symvi.flow import taylor
from symvi.model import Model, Stop

ONE = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
TWO = dict(mass=[1.0, 2.0], stiffness=[[2.0, -1.0], [-1.0, 1.5]],
           damping=[[0.05, 0.0], [0.0, 0.05]], forcing=[1.0, 0.3],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
FORCES = ["beta*x1**3 - x2**-2*exp(-v1) + sqrt(1 + v2**2)*atan(x1) + x1**2.5",
          "tanh(v1)*cosh(x2)/sinh(1 + x1**2) + log(2 + cos(x1))*tan(v2/3) + pi*v1**3"
          " + x2**v2"]


def _series_of(flow, X):
    """The Taylor coefficients of each force along the state's series X (2N, p + 1)."""
    tp, vals, roots = flow.tape
    tj = taylor.work(tp, vals, roots, X.shape[0], order=X.shape[1] - 1)
    S, A = tj[3], tj[4]
    u = flow._system(1.0, 0.0)[6]
    for k in range(X.shape[1]):
        taylor._series(tp, vals, k, S, A, X, u, X.shape[0])
    return S[roots]


def test_the_forces_series_are_mpmaths():
    """Every operation of the program (products, integer and real powers, a power with a
    variable exponent, each function) on series: the coefficients of f(x(t), v(t)) for
    polynomial x(t), v(t), to order 10, against mpmath.taylor of the SymPy expression at
    40 digits: 1e-13 relative."""
    m = Model(**TWO, nonlinear=FORCES, parameters={"beta": 0.3})
    flow = nl.NonlinearFlow(m)
    X = np.array([[0.3, 0.5, -0.2, 0.1], [0.7, -0.4, 0.3, 0.0],
                  [-0.2, 0.6, 0.1, -0.3], [0.4, 0.2, -0.5, 0.2]])
    p = 10
    Xp = np.zeros((4, p + 1))
    Xp[:, :4] = X
    got = _series_of(flow, Xp)
    syms = sympy.symbols("x1 x2 v1 v2 beta", real=True)
    for i, e in enumerate(m.nonlinear):
        f = sympy.lambdify(syms, e, "mpmath")
        with mpmath.workdps(40):
            def along(t):
                return f(*[sum(mpmath.mpf(c) * t ** k for k, c in enumerate(row))
                           for row in X], mpmath.mpf("0.3"))
            ref = np.array([float(c) for c in mpmath.taylor(along, 0, p)])
        assert np.allclose(got[i], ref, rtol=1e-13, atol=1e-13 * np.abs(ref).max()), i


def test_an_integer_power_at_zero_is_zero():
    """x**3 along x(t) = t: the series t^3, no NaN (a product, not exp(3 log x))."""
    flow = nl.NonlinearFlow(Model(**ONE, nonlinear=["x1**3"]))
    X = np.zeros((2, 8))
    X[0, 1] = 1.0
    assert np.array_equal(_series_of(flow, X)[0], [0, 0, 0, 1, 0, 0, 0, 0])


def test_the_step_rule_and_one_step_reach_the_unit_roundoff():
    """On the undamped, unforced linear oscillator x'' + x = 0 from (1, 0) the last two
    coefficients are 1/p! and 1/(p-1)!, so the step is exp(-0.7/(p-1)) min_j (TOL j!)^(1/j)
    over j = p-1, p (module docstring); one step of that size lands on (cos h, -sin h) to
    4e-16 though h > 2."""
    m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.0]], forcing=[0.0],
              stop=Stop(mass=1, gap=5.0, restitution=0.8), nonlinear=["0*x1"])
    flow = nl.NonlinearFlow(m)
    tj = flow._taylor_work()
    X = tj[8]
    sy = flow._system(1.0, 0.0)
    taylor._prepare(sy, tj)
    taylor._coefficients(sy, tj, 0.0, np.array([1.0, 0.0]), X)
    h = taylor._jorba_zou_h(X, 10.0)
    p = taylor.FLOW_ORDER
    rule = math.exp(-0.7 / (p - 1)) * min(math.exp((math.log(taylor.TOL) + math.lgamma(j + 1))
                                                   / j) for j in (p - 1, p))
    assert h == pytest.approx(rule, rel=1e-13) and h > 2.0
    y = np.empty(2)
    taylor._at(X, h, y, None)
    assert abs(y[0] - math.cos(h)) < 4e-16 and abs(y[1] + math.sin(h)) < 4e-16


@pytest.mark.parametrize("kw, forces, pars", [
    (ONE, ["2*beta*x1**3 + sin(beta)*v1 + 0.3*exp(beta)"], {"beta": 0.7}),
    (TWO, ["beta*(x1 - x2)**3 + cos(2*beta)", "-beta*(x1 - x2)**3 + x2*v2**2"],
     {"beta": 0.7}),
    (TWO, ["eta1*x1**3 + 0.05*eta2*(x1-x2)**3", "0.05*eta2*(x2-x1)**3"],
     {"eta1": 0.1, "eta2": 0.3})])
def test_the_coefficients_solve_the_equations_of_motion(kw, forces, pars):
    """The kernel's series (state rows in the tape, constant rows at order 0 only, the
    linear part as one map; one mass and two) satisfy (k + 1) M v_{k+1} = P s_k - C v_k -
    K x_k - f_k and (k + 1) x_{k+1} = v_k to order 19, f_k the forces' coefficients by
    mpmath.taylor of the SymPy expressions along the series at 30 digits: 1e-13.  The
    absorber's forces: two parameters, whose slots are not their rows."""
    m = Model(**kw, nonlinear=forces, parameters=pars)
    flow = nl.NonlinearFlow(m)
    n, omega, tau, t0 = m.n, 1.3, 0.4, 0.2
    y0 = np.array([0.3, -0.2, 0.5, 0.1][:n] + [0.5, 0.1, -0.4, 0.2][:n])
    tj = taylor.work(*flow.tape, 2 * n, order=20)
    X = tj[8]
    sy = flow._system(omega, tau)
    taylor._prepare(sy, tj)
    taylor._coefficients(sy, tj, t0, y0, X)
    syms = sympy.symbols([f"x{i + 1}" for i in range(n)] + [f"v{i + 1}" for i in range(n)]
                         + list(pars))
    M, C, K, P = (np.asarray(a, dtype=float) for a in (m.mass, m.damping, m.stiffness,
                                                         m.forcing))
    with mpmath.workdps(30):
        fk = []
        for e in m.nonlinear:
            f = sympy.lambdify(syms, e, "mpmath")
            fk.append([float(c) for c in mpmath.taylor(
                lambda t: f(*[sum(mpmath.mpf(c) * t ** k for k, c in enumerate(row))
                              for row in X], *map(mpmath.mpf, pars.values())), 0, 19)])
        sk = [float(c) for c in mpmath.taylor(lambda t: mpmath.sin(omega * (t0 + t) + tau),
                                              0, 19)]
    fk = np.array(fk)
    for k in range(20):
        lhs = (k + 1) * M @ X[n:, k + 1]
        rhs = P * sk[k] - C @ X[n:, k] - K @ X[:n, k] - fk[:, k]
        scale = 1e-13 * max(1.0, np.abs(rhs).max(), np.abs(lhs).max())
        assert np.abs(lhs - rhs).max() < scale, k
        assert np.abs((k + 1) * X[:n, k + 1] - X[n:, k]).max() < 1e-15 * max(
            1.0, np.abs(X[n:, k]).max()), k


@pytest.mark.slow
def test_a_flight_with_every_function_against_mpmath():
    """A flight of 1.5 time units with transcendental forces against mpmath.odefun at 25
    digits: 1e-13 relative."""
    forces = ["0.3*x1**3 + 0.1*sin(x1)*exp(-v1**2) + 0.05*atan(v1)*sqrt(2 + cos(x1))"]
    m = Model(**ONE, nonlinear=forces)
    omega, tau, z0, T = 1.3, 0.4, (0.2, -0.5), 1.5
    z = nl.NonlinearFlow(m).state(omega, z0, tau, T)
    with mpmath.workdps(25):
        def f(t, y):
            x, v = y
            g = (mpmath.mpf("0.3") * x ** 3 + mpmath.mpf("0.1") * mpmath.sin(x) *
                 mpmath.exp(-v ** 2) + mpmath.mpf("0.05") * mpmath.atan(v) *
                 mpmath.sqrt(2 + mpmath.cos(x)))
            return [v, mpmath.sin(omega * t + tau) - mpmath.mpf("0.1") * v - x - g]
        ref = np.array([float(c) for c in mpmath.odefun(f, 0, [mpmath.mpf(c) for c in z0])(T)])
    assert np.max(np.abs(z - ref) / np.maximum(1.0, np.abs(ref))) < 1e-13


@pytest.mark.parametrize("delta", [1e-9, 1e-12])
def test_a_short_excursion_past_the_gap_is_found(delta):
    """x'' + x = 0 with amplitude 0.5 + delta: the guard is above 0 for a time of about
    2 sqrt(2 delta) (9e-5, 3e-6) inside one step; the contact is found at the exact
    time asin(0.5 / A) - phase, and a peak 1e-9 below the gap gives no contact."""
    m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.0]], forcing=[0.0],
              stop=Stop(mass=1, gap=0.5, restitution=0.8), nonlinear=["0*x1"])
    flow = nl.NonlinearFlow(m)
    A = 0.5 + delta
    phase = -0.7                               # x = A sin(t + phase)
    z0 = (A * math.sin(phase), A * math.cos(phase))
    st, te, con, ze = flow.first_impact(1.0, z0, 0.0, t_max=3.0)
    exact = math.asin(0.5 / A) - phase
    assert st == "impact" and con == 0
    assert abs(te - exact) < 1e-15 / math.sqrt(delta)       # a near-double root: dx / v
    assert abs(ze[0] - 0.5) < 1e-15 and ze[1] > 0
    A = 0.5 - 1e-9
    z0 = (A * math.sin(phase), A * math.cos(phase))
    assert flow.first_impact(1.0, z0, 0.0, t_max=3.0)[0] == "no-impact"


def test_the_bracket_search():
    """One sign change of the hull: one root, the search stops at once; two roots: the
    bracket of the first; a hull staying below 0: none."""
    stack, lohi, br = np.empty((96, 21)), np.empty((96, 2)), np.empty(2)

    def bern(roots, lead=-1.0):
        p = np.zeros(21)
        c = np.polynomial.polynomial.polyfromroots(roots) * lead
        p[:len(c)] = c
        b = np.empty(21)
        _hull._bernstein(p, b)
        return b
    assert _hull._first_bracket(bern([0.37], 1.0), stack, lohi, br) == 2 and tuple(br) == (0, 1)
    assert _hull._first_bracket(bern([0.2, 0.25, 0.7, 0.9]), stack, lohi, br) == 2
    assert br[0] <= 0.2 < br[1] <= 0.25
    g = np.zeros(21)
    g[:3] = [-1e-9 - 0.09, 0.6, -1.0]         # max -1e-9 at 0.3
    b = np.empty(21)
    _hull._bernstein(g, b)
    assert _hull._first_bracket(b, stack, lohi, br) == 0


@pytest.mark.parametrize("force", ["sqrt(x1)", "log(x1)", "1/x1", "x1**0.5", "x1**(-2)"])
def test_forces_singular_on_the_stop_end_as_non_finite(force):
    """A force that is not finite (or has no derivatives) where the motion goes -- here at
    the stop x1 = 0 and below it -- ends a flight as "non-finite" and a run with that stop
    reason: the series' divisions by a zero leading coefficient give inf/nan in the
    kernels (numpy's error model), never a ZeroDivisionError out of them."""
    import symvi
    model = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                  stop=Stop(mass=1, gap=0.0, restitution=0.8),
                  nonlinear=[f"beta*{force}"], parameters={"beta": 1.0})
    flow = nl.NonlinearFlow(model)
    st, _, c, _ = flow.first_impact(2.6, np.array([0.0, -0.5]), 0.3, just_hit=0)
    assert (st, c) == ("non-finite", -2)
    run = symvi.simulate(model, 2.6, y0=(-0.5, 0.3), n_impacts=5)
    assert run.stop == "non-finite"
