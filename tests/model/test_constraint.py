"""The constraint and signature interfaces (symvi.model.Constraint, Signature), and the
layers that read them: the stop's constraint is c = e_k with today's law v_k+ = -r v_k-,
and the map, its tangent and the shooting residual computed through the interface equal
the hand-written law on the zoo."""
import numpy as np
import pytest

from symvi.errors import ParameterError
from symvi.flow import compiled as fc
from symvi.flow.linear import LinearFlow
from symvi.maps.impact import poincare_map
from symvi.model import Constraint, Model, Signature, Stop
from symvi.orbits.period1 import period1_orbits
from symvi.orbits.periodic import Problem
from tests.zoo import FOUR_STOP3, N_MASS_SET, PAPER_EX1, THREE_STOP2_GAP05, TWO_OVERDAMPED

#: a non-diagonal mass matrix: the rigid impulse along M^-1 c moves both velocities
OFFDIAG = Model(mass=[[1.0, 0.2], [0.2, 1.5]], stiffness=[[2.0, -1.0], [-1.0, 2.0]],
                damping=[[0.02, 0.0], [0.0, 0.02]], forcing=[1.0, 0.3],
                stop=Stop(mass=2, gap=0.4, restitution=0.8))


@pytest.mark.parametrize("k, n", [(1, 1), (2, 3), (3, 4)])
def test_stop_constraint_is_the_unit_normal(k, n):
    con = Stop(mass=k, gap=0.7, restitution=0.6).constraint(n)
    assert con.normal == tuple(np.eye(n)[k - 1])
    assert (con.gap, con.restitution, con.side, con.coordinate) == (0.7, 0.6, "upper", k - 1)
    x = np.arange(1.0, n + 1)
    assert con.s(x) == x[k - 1] and con.guard(x) == x[k - 1] - 0.7
    assert con.approach(x) == x[k - 1]


def test_model_constraints_is_its_stop():
    m = THREE_STOP2_GAP05
    assert m.constraints == (m.stop.constraint(3),)
    assert m.constraints is m.constraints                      # built once
    assert m.with_(gap=0.9).constraints[0].gap == 0.9
    assert m.with_(restitution=0.5).constraints[0].restitution == 0.5


@pytest.mark.parametrize("r", [0.8, 0.3, 1.0, 0.123456789])
@pytest.mark.parametrize("masses", [(1.0, 1.0, 1.0), (1.3, 0.7, 2.9), (1e-3, 3.7e5, 0.1)])
def test_stop_reset_is_todays_law_bit_for_bit(r, masses):
    """The stop's impulse is along M^-1 c; for a diagonal M, q = e_k / m_k and
    Q = q c^T / (c^T q) = e_k e_k^T exactly, so R has entries exactly 1, 0 and -r: R v gives
    v_k+ = -r v_k- and leaves the rest, bit for bit."""
    con = Stop(mass=2, gap=0.0, restitution=r).constraint(3)
    assert con.impulse is None and con.kind == "rigid"
    Minv = np.linalg.inv(np.diag(masses))
    assert np.array_equal(con.projector(Minv), np.diag([0.0, 1.0, 0.0]))
    R = con.reset_matrix(Minv)
    expect = np.eye(3)
    expect[1, 1] = -r
    assert np.array_equal(R, expect)
    v = np.array([0.3, -1.7, 2.9])
    assert np.array_equal(con.reset(v, Minv), [0.3, -r * -1.7, 2.9])


def test_rigid_reset_on_diagonal_mass_is_todays_law():
    """The impulse along M^-1 c (the stop's, impulse=None) equals the old impulse along e_k
    bit for bit where M is diagonal, and sends c^T v to -r c^T v."""
    M = np.diag([1.0, 2.5, 0.7])
    stop = Stop(mass=3, gap=0.1, restitution=0.8).constraint(3)
    old = Constraint(normal=stop.normal, gap=0.1, restitution=0.8, impulse=stop.normal)
    Minv = np.linalg.inv(M)
    assert np.array_equal(stop.reset_matrix(Minv), old.reset_matrix())
    v = np.array([0.4, -0.2, 1.3])
    assert stop.s(stop.reset(v, Minv)) == pytest.approx(-0.8 * stop.s(v), rel=1e-15)


def test_stop_on_a_non_diagonal_mass_is_the_rigid_impulse():
    """With a non-diagonal M the stop's reset is the impulse along M^-1 c (issue 25): the
    momentum M v changes along c only, and c^T v goes to -r c^T v; the old law (along e_k)
    did not conserve momentum orthogonal to c."""
    M = np.asarray(OFFDIAG.mass)
    con = OFFDIAG.constraints[0]
    Minv = np.linalg.inv(M)
    v = np.array([0.7, -1.1])
    vp = con.reset(v, Minv)
    dp = M @ (vp - v)                                  # the impulse, along c = e_2
    assert abs(dp[0]) < 1e-15 and dp[1] != 0
    assert con.s(vp) == pytest.approx(-0.8 * con.s(v), rel=1e-15)
    assert vp[0] != v[0]                               # the other mass moves too


def test_rigid_reset_between_two_masses_conserves_momentum():
    """c = e_2 - e_1 (an impact between two masses): the reset along M^-1 c conserves
    the total momentum and sends the relative velocity to -r times itself."""
    M = np.diag([1.0, 3.0])
    con = Constraint(normal=(-1.0, 1.0), gap=0.2, restitution=0.6)
    v = np.array([0.5, 1.5])
    vp = con.reset(v, np.linalg.inv(M))
    assert (M @ vp).sum() == pytest.approx((M @ v).sum(), rel=1e-15)
    assert con.s(vp) == pytest.approx(-0.6 * con.s(v), rel=1e-15)
    assert con.coordinate is None


def test_lower_side_guard():
    con = Constraint(normal=(0.0, 1.0), gap=-0.5, restitution=0.9, side="lower")
    assert con.sign == -1.0
    assert con.guard([0.0, 0.0]) == -0.5          # s = 0 >= g = -0.5: off the stop
    assert con.guard([0.0, -0.6]) == pytest.approx(0.1)
    assert con.approach([0.0, -2.0]) == 2.0       # moving down, towards a lower stop


@pytest.mark.parametrize("bad", [dict(normal=(0.0, 0.0)), dict(side="left"),
                                 dict(impulse=(1.0, 0.0))])
def test_constraint_refuses_bad_data(bad):
    kw = dict(normal=(0.0, 1.0), gap=0.1, restitution=0.5) | bad
    with pytest.raises(ParameterError):
        Constraint(**kw)


def test_signature():
    assert Signature.single(3).hits == (0, 0, 0) and Signature.single(3).p == 3
    assert Signature([0, 0]).check(PAPER_EX1).hits == (0, 0)
    assert Signature((0,)).constraints(PAPER_EX1) == PAPER_EX1.constraints
    with pytest.raises(ParameterError, match="signature"):
        Signature((0, 1)).check(PAPER_EX1)
    for bad in ((), "0", (-1,), (True,)):
        with pytest.raises(ParameterError):
            Signature(bad)


def test_problem_signature():
    assert Problem(PAPER_EX1, 1, 2, omega=0.7).signature == Signature((0, 0))
    with pytest.raises(ParameterError, match="signature"):
        Problem(PAPER_EX1, 1, 2, omega=0.7, signature=(0,))
    with pytest.raises(ParameterError, match="signature"):
        Problem(PAPER_EX1, 1, 1, omega=0.7, signature=(1,))


@pytest.mark.parametrize("model", [*N_MASS_SET.values(), TWO_OVERDAMPED, FOUR_STOP3, OFFDIAG],
                         ids=[*N_MASS_SET, "overdamped", "four-stop3", "offdiag"])
def test_flow_and_constants_carry_the_constraint(model):
    """The flow holds the guard e_0 and the reset in its order; the compiled constants
    hold the same blocks; with a diagonal M the reset is today's law bit for bit, with a
    non-diagonal M the impulse along M^-1 c."""
    flow = LinearFlow.of(model)
    n = model.n
    assert np.array_equal(flow.guard, np.eye(n)[0]) and flow.level == model.stop.gap
    expect = np.eye(n)
    expect[0, 0] = -model.stop.restitution
    if model is OFFDIAG:
        expect = _rigid_reset(model)
        assert np.abs(flow.reset - expect).max() < 1e-15 and expect[1, 0] != 0
        expect = flow.reset
    assert np.array_equal(flow.reset, expect)
    c = fc.constants(model, 1.3)
    og = fc._offsets(n)[3] + fc._CB
    orr = og + n
    assert np.array_equal(c[og:og + n], flow.guard)
    assert np.array_equal(c[orr:orr + n * n], expect.ravel())
    assert len(c) == fc.size(n)


def _rigid_reset(model):
    """R = I - (1 + r) q c^T / (c^T q), q = M^-1 c, written out in the flow's order."""
    p = list(LinearFlow.of(model).perm)
    M = np.asarray(model.mass)[np.ix_(p, p)]
    c = np.eye(model.n)[0]
    q = np.linalg.solve(M, c)
    return np.eye(model.n) - (1 + model.stop.restitution) * np.outer(q, c) / q[0]


def _law_by_hand(model, omega, y):
    """P(y) with the law written out: the first impact's state, then v_k+ = -r v_k- (the
    rigid impulse along M^-1 c where M is not diagonal)."""
    c = fc.constants(model, omega)
    st, t, z, _, _, _ = fc.first_impact_from(c, y)
    n = model.n
    tau = (y[-1] + omega * t) % (2 * np.pi)
    if model is OFFDIAG:
        v = _rigid_reset(model) @ z[n:]
        return np.array([v[0], *z[1:n], *v[1:], tau]), z[n]
    return np.array([-model.stop.restitution * z[n], *z[1:n], *z[n + 1:], tau]), z[n]


@pytest.mark.parametrize("model, omega", [(PAPER_EX1, 0.75), (THREE_STOP2_GAP05, 1.1),
                                          (FOUR_STOP3, 1.3), (TWO_OVERDAMPED, 1.2),
                                          (OFFDIAG, 1.4)])
def test_map_through_the_interface_is_the_law(model, omega):
    """The compiled step and the Python map (both through the constraint's reset) equal
    the hand-written law v_k+ = -r v_k- at period-1 points and nearby, to 1e-14."""
    orbs = [o for o in period1_orbits(model, omega) if o.admissible]
    assert orbs, "no admissible period-1 orbit to start from"
    for o in orbs:
        y = np.array(o.y) + 1e-3
        y[0] = 1.01 * o.y[0]                       # still leaving the stop
        want, vk = _law_by_hand(model, omega, y)
        st, t, got, vm, _, _, _ = fc.step(fc.constants(model, omega), y)
        assert fc.STATUS_NAMES[st] == "impact"
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-14 * (1 + abs(want).max()))
        assert vm == vk
        ref = poincare_map(model, omega, y)
        np.testing.assert_allclose(ref.y, want, rtol=0, atol=1e-9 * (1 + abs(want).max()))


@pytest.mark.parametrize("model, omega", [(PAPER_EX1, 0.75), (FOUR_STOP3, 1.3)])
def test_shooting_compiled_equals_reference_through_the_interface(model, omega):
    """The compiled shooting kernel and the numpy reference, both reading the reset R and
    the guard, agree to rounding (residual, Jacobian, omega- and r-derivatives)."""
    o = period1_orbits(model, omega)[0]
    u = np.concatenate([o.y, [2 * np.pi / omega]])
    out = []
    for compiled in (True, False):
        pr = Problem(model, 1, 1, omega=omega)
        pr.compiled = compiled
        G, Gu, _ = pr.evaluate(u, None)
        out.append((G, Gu, pr.derivative(u, None, "omega"),
                    pr.derivative(u, None, "restitution")))
    for a, b in zip(*out):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * (1 + np.abs(b).max()))
    # the r-derivative of the residual is -v_k- in the reset's row (h_0 = -r v_k- - y_0)
    assert out[1][3][0] == pytest.approx(-o.impact_velocity, rel=1e-12)


def test_a_model_with_another_gap_carries_the_same_constraint_at_that_gap():
    """Model.with_(gap=...) (a curve's corrector step) derives its constraint from the old
    one without checking the normal again; it equals the one built from scratch."""
    m = PAPER_EX1
    m.constraints                                   # built once
    for g, r in ((1.2, 0.8), (1.5, 0.5)):
        new = m.with_(gap=g, restitution=r)
        fresh = Model(mass=np.asarray(m.mass), stiffness=np.asarray(m.stiffness),
                      damping=np.asarray(m.damping), forcing=list(m.forcing),
                      stop=Stop(mass=m.stop.mass, gap=g, restitution=r))
        assert new.constraints == fresh.constraints
        assert new.constraints[0].gap == g and new.constraints[0].restitution == r
