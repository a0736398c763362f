"""The compiled first-impact finder of any model against dense sampling of
x_k(t) and against the reference finder :meth:`symvi.flow.linear.Motion.first_impact`."""
import math

import numpy as np
import pytest

from symvi.flow import compiled as cf
from symvi.flow.linear import GRAZING, IMPACT, NO_IMPACT, LinearFlow
from tests.zoo import FOUR_STOP3, ONE_DAMPED_GAP02, THREE_STOP2_GAP12

from .gap_reference import Gap, random_states, tangent_states, z0_of

T_MAX = 20.0          # finder horizon
T_GRID = 30.0         # dense-sampling horizon, beyond the finder's
DT = 0.002

#: N = 1, 3 and 4, stops on masses 1, 2 and 3
CASES = [(ONE_DAMPED_GAP02, 0.8), (THREE_STOP2_GAP12, 0.4), (FOUR_STOP3, 1.3)]


def _states(model, omega, n, rng):
    """n random states, the first third near-grazing: the first approach to the stop
    is a local max of h at height -delta (delta from 1e-2 down to -1e-5)."""
    ys = random_states(model, n, rng)
    n_graze = n // 3
    cand, ts = tangent_states(model, omega, random_states(model, 12 * n_graze, rng), rng)
    # keep those whose first approach to the stop is the constructed tangency
    first = Gap(model, omega, cand).first_crossing(T_GRID, DT) > ts - 0.05
    assert first.sum() >= n_graze
    ys[:n_graze] = cand[first][:n_graze]
    return ys


def _compiled(model, omega, ys):
    c = cf.constants(model, omega, t_max=T_MAX)
    res = [cf.first_impact_from(c, y, T_MAX) for y in ys]
    return np.array([r[0] for r in res]), np.array([r[1] for r in res]), res


def _check_dense(model, omega, n, seed):
    rng = np.random.default_rng(seed)
    ys = _states(model, omega, n, rng)
    g = Gap(model, omega, ys)
    tb = g.first_crossing(T_GRID, DT)
    st, tf, _ = _compiled(model, omega, ys)
    assert (st == cf.IMPACT).sum() > 0.6 * len(ys)
    assert (st == cf.GRAZING).sum() >= 3            # the near-grazing set does graze
    imp = st == cf.IMPACT
    assert np.abs(g.at(tf[imp], rows=imp)).max() < 1e-11     # a reported impact is a root
    assert (g.at(tf[imp], 1, rows=imp) > 0).all()
    # never later than the dense-sampling crossing: no missed impact
    assert (tf[imp] <= tb[imp] + 1e-9).all()
    # earlier only where the grid stepped over a short excursion above the stop:
    # only in the near-grazing third, and h really is positive just after t_f
    early = imp & (tf < tb - 1e-9)
    assert not early[n // 3:].any()
    v = np.abs(g.at(tf[early], 1, rows=early))
    assert (g.at(tf[early] + 1e-3 * v / 5, rows=early) > 0).all()
    gr = st == cf.GRAZING
    assert (tb[gr] >= tf[gr] - 1e-3).all()
    assert np.abs(g.at(tf[gr], rows=gr)).max() < 1e-9
    no = st == cf.NO_IMPACT
    assert (tb[no] > T_MAX - 1e-9).all()


@pytest.mark.parametrize("model, omega", CASES, ids=["N1", "N3", "N4"])
def test_finder_agrees_with_dense_sampling(model, omega):
    """300 random and near-grazing states per model: every reported impact is a
    root of h, none is later than the dense-sampling first crossing, grazing and
    no-impact answers have no crossing before them."""
    _check_dense(model, omega, 300, 2024)


@pytest.mark.slow
@pytest.mark.parametrize("model, omega", CASES, ids=["N1", "N3", "N4"])
def test_finder_agrees_with_dense_sampling_1e4(model, omega):
    """As above on 10^4 states over the three models (3334 each)."""
    _check_dense(model, omega, 3334, 12345)


@pytest.mark.parametrize("model, omega", CASES, ids=["N1", "N3", "N4"])
def test_finder_matches_reference(model, omega):
    """Same status and time as the reference Motion.first_impact on 90 states a model
    (a third near-grazing); the state at the impact agrees to 1e-9."""
    rng = np.random.default_rng(7)
    ys = _states(model, omega, 90, rng)
    flow = LinearFlow.of(model)
    fo = flow.forcing(omega)
    st, tf, res = _compiled(model, omega, ys)
    names = {IMPACT: cf.IMPACT, GRAZING: cf.GRAZING, NO_IMPACT: cf.NO_IMPACT}
    z0, tau = z0_of(model, ys)
    agree = 0
    for i in range(len(ys)):
        ref = flow.motion(fo, z0[i], tau[i]).first_impact(t_max=T_MAX)
        # a tangency time is defined only to about sqrt(eps)
        tol = 1e-9 if st[i] == cf.IMPACT else 1e-6
        if names[ref.status] == st[i] and (st[i] == cf.NO_IMPACT
                                           or abs(tf[i] - ref.t) <= tol * tf[i]):
            agree += 1
            if st[i] == cf.IMPACT:
                assert np.abs(res[i][2] - ref.state).max() < 1e-9
    # borderline near-grazing cases (|h| within eps_h of 0) may be decided differently
    assert agree >= len(ys) - 2
    assert (st == cf.IMPACT).sum() > 45


def test_decaying_bound_steps_fewer_than_reference():
    """The tight, decaying bound needs fewer evaluations than the global one."""
    model, omega = THREE_STOP2_GAP12, 0.4
    rng = np.random.default_rng(3)
    ys = random_states(model, 40, rng)
    flow = LinearFlow.of(model)
    fo = flow.forcing(omega)
    z0, tau = z0_of(model, ys)
    ref = sum(flow.motion(fo, z0[i], tau[i]).first_impact(t_max=T_MAX).steps
              for i in range(len(ys)))
    ours = sum(r[4] for r in _compiled(model, omega, ys)[2])
    assert ours < 0.7 * ref
    assert math.isfinite(ours)
