"""The independent chain with elastic stops (issue 28, :mod:`symvi.studies.nonlinear_check`):
its map through contact phases against symvi's walk (an impact Duffing oscillator with an
elastic stop; a mixed model with an elastic and a rigid stop), against the exact linear
phases with the nonlinearity off (float64 walk and the closed form at 50 digits), the
Liouville identity of its multipliers, a flip of an elastic + nonlinear branch re-derived,
and ``symvi continue --digits``."""
import math

import mpmath
import numpy as np
import pytest

from symvi import Model
from symvi.errors import ParameterError, SingularCaseError
from symvi.flow.linear import LinearFlow
from symvi.numerics.backend import backend
from symvi.orbits._phases import event_run, state_of
from symvi.studies.nonlinear_check import NonlinearChain, check_special
from tests.flow.test_nonlinear_elastic import _ONE, CHAIN, DUFFING

#: a start on the elastic stop's section entering it (v1 > 0): in contact during flight 0
Y_ONE = (0.8, 0.2)
#: the chain's lower elastic stop on mass 2 (layout (v2, x1, v1, tau)), entering it
Y_TWO = (-0.4, 0.1, 0.0, 0.3)


def _walk(model, omega, y, k, contact, n):
    """symvi's walk (:func:`symvi.orbits._phases.event_run`, each phase on its own flow)
    from point y of constraint k's section with ``contact`` in contact: n events."""
    z0 = state_of(LinearFlow.contact(model.linear_part), k, y)
    run = event_run(model, omega, z0, y[-1], events=n, transient=0, active=contact, start=k)
    assert run.stop == "completed"
    return run


def _chain_events(chain, y, k, contact, n):
    """The chain's map event by event: (section points, constraints met, contacts)."""
    pts, hits, acts = [], [], []
    for _ in range(n):
        with mpmath.workdps(chain.dps):
            img, _, (j,), S = chain._map_u(y, 1, k, contact)
            img[-1] = img[-1] % (2 * mpmath.pi)
        pts.append([float(v) for v in img])
        hits.append(j)
        acts.append(S)
        y, k, contact = img, j, S
    return np.array(pts), hits, acts


def _err(a, b):
    """max |a - b| of section points, tau compared modulo 2 pi."""
    d = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
    d[..., -1] = np.remainder(d[..., -1] + math.pi, 2 * math.pi) - math.pi
    return np.abs(d).max()


@pytest.mark.parametrize("model, omega, y, n, kinds", [
    (DUFFING, 1.3, Y_ONE, 6, {0}),
    (CHAIN, 1.2, Y_TWO, 8, {0, 1}),
], ids=["elastic-duffing", "elastic-and-rigid"])
def test_map_against_symvis_walk(model, omega, y, n, kinds):
    """Every event of the chain's map (its own Taylor series of each phase's field, its
    own entry and exit search) against symvi's walk (the phases' Taylor flow of
    :mod:`symvi.flow.nlcontact`): the same constraints and contacts, the section points to
    1e-12 (2e-15 and 1.3e-15 observed).  The mixed model meets its rigid stop (a reset)
    and its elastic one (entries and exits)."""
    chain = NonlinearChain(model, omega, 30)
    pts, hits, acts = _chain_events(chain, y, 0, (0,), n)
    ref = _walk(model, omega, y, 0, (0,), n)
    assert hits == list(ref.hits) and acts == list(ref.active)
    assert set(hits) == kinds
    assert _err(pts, ref.section) < 1e-12
    # map_n is the same composition (tau mod 2 pi at the end)
    assert _err([chain.map_n(y, n, contact=(0,))], ref.section[-1:]) < 1e-12


def test_beta_zero_is_the_exact_linear_walk():
    """With beta = 0 the chain's events are those of the exact linear phases (symvi's
    walk of :mod:`symvi.flow.contact`: each phase in closed form, float64) to 1e-13
    (4.9e-15 observed)."""
    lin = Model(**_ONE)
    off = Model(**_ONE, nonlinear=["beta*x1**3"], parameters={"beta": 0.0})
    pts, hits, acts = _chain_events(NonlinearChain(off, 1.3, 30), Y_ONE, 0, (0,), 6)
    ref = _walk(lin, 1.3, Y_ONE, 0, (0,), 6)
    assert hits == list(ref.hits) and acts == list(ref.active)
    assert _err(pts, ref.section) < 1e-13


def test_beta_zero_phases_are_the_closed_form_at_50_digits():
    """With beta = 0 each flight of the chain (40 digits; a contact phase: M x'' + (C +
    c_s) x' + (K + k_s) x = P sin + k_s g) ends where the exact flow of its phase
    (:class:`symvi.flow.linear.LinearFlow` at 50 digits, modal form) is at the chain's
    event time: states to 1e-35, so the event time too (the guard is 0 there).  The
    model's numbers are binary fractions so that K + k_s, C + c_s are exact in float64,
    where symvi sums the contact law."""
    ex = dict(_ONE, damping=[[0.125]])
    lin = Model(**ex)
    chain = NonlinearChain(Model(**ex, nonlinear=["beta*x1**3"], parameters={"beta": 0.0}),
                           1.3, 40)
    with mpmath.workdps(50):
        bk = backend(50)
        flows = {S: LinearFlow(lin, bk, S) for S in ((), (0,))}
        z, tau, S = [mpmath.mpf(0.5), mpmath.mpf(0.8)], mpmath.mpf(0.2), (0,)
        for _ in range(4):
            t, ze, j = chain.first_contact(z, tau, on=0, contact=S)
            fl = flows[S]
            got, *_ = fl.flight(fl.forcing(mpmath.mpf(1.3)),
                                bk.arr(fl.to_flow(np.array(z, dtype=object))), tau, t)
            exact = fl.to_mass(got)
            assert max(abs(a - b) for a, b in zip(exact, ze)) < 1e-35
            assert abs(exact[0] - mpmath.mpf(0.5)) < 1e-35 and abs(exact[1]) > 0.1
            z, tau, S = ze, tau + chain.omega * t, tuple(sorted(set(S) ^ {j}))


@pytest.fixture(scope="module")
def branch():
    """The 1-2 orbits (an entry and an exit per forcing period) of the elastic Duffing
    oscillator from omega = 1.3 down: two flips (omega = 1.2375, 1.2071)."""
    from symvi.continuation import continue_orbits
    (br,) = continue_orbits(DUFFING, "omega", 1.3, 0.9, orbit="1-2", max_points=400)
    return br


def test_fixed_point_and_the_liouville_identity(branch):
    """The chain's own Newton (40 digits) from symvi's orbit at the branch's first point:
    the same orbit (1e-12) and multipliers (1e-10), and det DP^2 = exp(-c T - c_s t_c)
    (the force depends on x only, so div = -tr M^-1 C_S in each phase; the approach speeds
    of the start and the end cancel at a fixed point, :mod:`symvi.flow.contact`), t_c the
    contact flight, to 1e-25."""
    o = branch.points[0].orbit
    assert o.contact == (0,) and tuple(o.signature) == (0, 0)
    chain = NonlinearChain(DUFFING, o.omega, 40)
    fp = chain.fixed_point(o.points[0], p=2, contact=o.contact)
    with mpmath.workdps(chain.dps):
        assert fp.hits == (0, 0) and fp.periods == 1 and fp.residual < 1e-38
        assert _err([fp.y], [o.points[0]]) < 1e-12
        assert abs(sum(fp.times) - 2 * mpmath.pi / chain.omega) < 1e-38
        assert abs(float(fp.times[0]) - o.times[0]) < 1e-12
        mine = sorted((complex(z) for z in fp.multipliers), key=lambda z: (z.real, z.imag))
        theirs = sorted(o.multipliers, key=lambda z: (z.real, z.imag))
        assert np.abs(np.array(mine) - np.array(theirs)).max() < 1e-10
        det = fp.multipliers[0] * fp.multipliers[1]
        c, cs = mpmath.mpf(0.05), mpmath.mpf(0.5)
        want = mpmath.exp(-c * sum(fp.times) - cs * fp.times[0])
        assert abs(det - want) < 1e-25


def test_a_flip_of_the_elastic_branch_checked_by_the_chain(branch):
    """check_special at 30 digits on the branch's first flip: the chain's fixed point
    (its residual < 1e-28) lies within 1e-12 of symvi's, its multiplier is -1 within 1e-8
    (4.4e-16 observed), and the flip coefficient c agrees to 10 digits or more (15.3)."""
    flip = next(s for s in branch.special if s.kind == "flip")
    got = check_special(flip, 30)
    assert got.reason == "", got.reason
    assert got.residual < 1e-28 and got.distance < 1e-12
    assert abs(got.multiplier + 1) < 1e-8 and got.critical_error < 1e-8
    assert got.coefficient == "c" and got.agreement >= 10


def test_a_fold_of_a_mixed_model_checked_by_the_chain():
    """The 2-DOF model with an elastic and a rigid stop (a cubic spring): its 1-4 orbits
    (an exit, two rigid impacts, an entry) fold at omega ~ 1.22 and 1.29; at 30 digits
    the chain's P^4 maps symvi's orbit at a fold to itself within 1e-12 and has a
    multiplier 1 there within 1e-10 (2.5e-15, 2e-15 observed; its flips, 60 s each, give
    c to 13 and 14 digits)."""
    from symvi.continuation import continue_orbits
    branches = continue_orbits(CHAIN, "omega", 1.0, 1.6, start_omega=1.2, max_points=400)
    fold = next(s for b in branches for s in b.special if s.kind == "fold")
    assert fold.orbit.itinerary.names(CHAIN) == ["stop1:exit", "stop2", "stop2", "stop1:entry"]
    got = check_special(fold, 30)
    assert got.reason == "", got.reason
    assert got.distance < 1e-12 and got.critical_error < 1e-10


def test_contact_refusals():
    """A contact naming a rigid stop, a start in the wrong phase, and a P^p that ends in
    another phase are refused by name."""
    chain = NonlinearChain(CHAIN, 1.2, 20)
    with pytest.raises(ParameterError, match="contact"):
        chain.map(Y_TWO, contact=(1,))                   # stop 2 is rigid
    with pytest.raises(ParameterError, match="z0"):       # inside the stop, not in contact
        chain.first_contact([0.0, -0.4, 0.0, 0.0], 0.0)
    with pytest.raises(SingularCaseError, match="grazing"):
        chain.map(Y_TWO)                                 # an exit start moving into the stop
    with pytest.raises(SingularCaseError, match="in contact with"):
        chain.jets(Y_TWO, 1, p=1, contact=(0,))          # its exit: on stop 1, free


@pytest.mark.slow
def test_symvi_continue_digits_on_an_elastic_nonlinear_model(tmp_path):
    """``symvi continue --digits 30`` on the elastic Duffing oscillator: exit 0, each of the
    branch's two flips printed with the chain's check (multiplier -1, c's agreement)."""
    import re

    from symvi.model import dumps
    from tests.fuzz._cli import cli
    f = tmp_path / "elastic.toml"
    f.write_text(dumps(DUFFING))
    rc, out, err = cli("continue", "--model", f, "--range", "omega=1.3:0.9", "--orbit", "1-2",
                       "--max-points", "400", "--digits", "30")
    assert rc == 0, err
    checks = [line for line in out.splitlines() if "chain (30 digits)" in line]
    assert len(checks) == 2, out
    for line in checks:
        assert "not checked" not in line and "critical multiplier -1 " in line
        assert float(re.search(r"\(([\d.]+) digits of agreement", line).group(1)) >= 10
