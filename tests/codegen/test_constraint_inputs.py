"""The generated jets take the constraint's guard (normal g, level) and reset R as inputs
(issue 24, item 3): one structure per N and order serves a stop on any mass, either side,
and the rigid impulse along M^-1 c of a non-diagonal M.  Checked against central finite
differences of the impact map through the interface (:mod:`symvi.maps.impact`)."""
import math
import warnings

import mpmath
import numpy as np
import pytest

from symvi.codegen.high import high_jet
from symvi.codegen.jets import evaluate
from symvi.codegen.layout import assemble, module
from symvi.flow.linear import IMPACT, LinearFlow
from symvi.maps.impact import step
from symvi.model import Constraint, Model, Stop

MASS = [[1.0, 0.0], [0.0, 2.0]]
STIFF = [[1.0, -1.0], [-1.0, 6.0]]
DAMP = [[0.02, -0.01], [-0.01, 0.03]]


class _Constrained(Model):
    """A model whose one constraint is given (the model files cannot state a lower side or
    a rigid impulse yet: issue 25); its key holds the constraint, so caches keep apart."""

    __slots__ = ("_con",)

    def __init__(self, con, **kw):
        object.__setattr__(self, "_con", con)
        super().__init__(**kw)
        object.__setattr__(self, "_hash", hash(self.key()))

    def key(self):
        return super().key() + (self._con,)

    @property
    def constraints(self):
        return (self._con,)


def _model(k, gap, r, side="upper", impulse="stop", mass=MASS, n=2):
    e = tuple(1.0 if i == k - 1 else 0.0 for i in range(n))
    con = Constraint(normal=e, gap=gap, restitution=r, side=side,
                     impulse=e if impulse == "stop" else None)
    return _Constrained(con, mass=mass, stiffness=STIFF, damping=DAMP, forcing=[1.0, 0.3],
                        stop=Stop(mass=k, gap=gap, restitution=r))


#: (model, omega, starting section point): the point's flight ends in an impact
CASES = {
    "stop-mass1": (lambda **kw: _model(1, 0.6, 0.8, **kw), 1.1, (-0.4, 0.1, -0.2, 0.7)),
    "stop-mass2": (lambda **kw: _model(2, 0.3, 0.7, **kw), 1.1, (-0.2, -0.1, 0.3, 1.9)),
    "lower-side": (lambda **kw: _model(1, -0.6, 0.8, side="lower", **kw), 1.1,
                   (0.4, 0.1, -0.2, 0.7)),
    "nondiagonal-rigid": (lambda **kw: _model(2, 0.3, 0.7, impulse=None,
                                              mass=[[1.0, 0.3], [0.3, 2.0]], **kw), 1.1,
                          (-0.2, -0.1, 0.3, 1.9)),
}


def _P(model, omega, y):
    """P(y) with tau unwrapped (smooth), and the flight time."""
    fl = LinearFlow.of(model)
    s = step(fl, fl.forcing(omega), tuple(y))
    assert s.status == IMPACT
    out = np.array(s.y[:-1] + (s.tau_unwrapped,))
    # the damped flow's complex modes sum to a real state, up to rounding
    assert np.abs(np.imag(out)).max() < 1e-12 * max(1.0, np.abs(out).max())
    return np.real(out).astype(float), float(s.t)


def _jet(model, omega, y, K, tangent=None):
    fl = LinearFlow.of(model)
    _, te = _P(model, omega, y)
    return evaluate(fl, fl.forcing(omega), tuple(float(v) for v in y), te, K, tangent)


def _case(name, **kw):
    make, omega, y = CASES[name]
    return make, make(**kw), omega, np.array(y)


def test_one_structure_for_stops_on_different_masses():
    """A stop on mass 1 and one on mass 2 of the same system run through the same generated
    module; the constraint reaches it as inputs only (g, level, R of the flow)."""
    _, m1, w, y = _case("stop-mass1")
    _, m2, _, _ = _case("stop-mass2")
    mod = module(2, 3)[0]
    for m in (m1, m2):
        fl = LinearFlow.of(m)
        inp = dict(zip(mod.INPUTS, assemble(fl, fl.forcing(w), tuple(y), 5.0, 3)))
        assert [inp["g0"], inp["level"]] == [1.0, m.constraints[0].gap]
        assert [inp["R0_0"], inp["R1_0"]] == [-m.constraints[0].restitution, 0.0]
    # the two stops differ in their frame (the stop's mass first), not in the structure
    assert LinearFlow.of(m1).perm == (0, 1) and LinearFlow.of(m2).perm == (1, 0)
    assert not np.allclose(_jet(m1, w, y, 1)["J"], _jet(m2, w, y, 1)["J"])


@pytest.mark.parametrize("name", list(CASES))
def test_jets_against_finite_differences(name):
    """J, d2 against central differences of P through the interface; d3 against central
    differences of the generated d2 (each at its own flight time)."""
    _, model, w, y = _case(name)
    v = _jet(model, w, y, 3)
    assert v["g_theta"] > 0           # dh/dtheta > 0: h = sign (s - g) crosses 0 upwards, either side
    d = len(y)
    h = 1e-5
    J = np.column_stack([(_P(model, w, y + h * e)[0] - _P(model, w, y - h * e)[0]) / (2 * h)
                         for e in np.eye(d)])
    assert np.abs(v["J"] - J).max() < 1e-7 * max(1.0, np.abs(J).max())
    h = 1e-4
    E = np.eye(d)
    d2 = np.empty((d, d, d))
    for j in range(d):
        for k in range(d):
            pp, pm = _P(model, w, y + h * E[j] + h * E[k])[0], _P(model, w, y + h * E[j] - h * E[k])[0]
            mp_, mm = _P(model, w, y - h * E[j] + h * E[k])[0], _P(model, w, y - h * E[j] - h * E[k])[0]
            d2[:, j, k] = (pp - pm - mp_ + mm) / (4 * h * h)
    assert np.abs(v["d2"] - d2).max() < 1e-5 * max(1.0, np.abs(d2).max())
    d3 = np.stack([(_jet(model, w, y + h * e, 3)["d2"] - _jet(model, w, y - h * e, 3)["d2"])
                   / (2 * h) for e in E], axis=-1)
    assert np.abs(v["d3"] - d3).max() < 1e-6 * max(1.0, np.abs(d3).max())


def _with(name, **change):
    """The case's model with its constraint's gap or restitution, or its mass, moved."""
    make, model, _, _ = _case(name)
    con = model.constraints[0]
    k = con.coordinate + 1
    gap, r = change.get("gap", con.gap), change.get("r", con.restitution)
    kw = {"mass": change["mass"]} if "mass" in change else {}
    side, imp = con.side, ("stop" if con.impulse is not None else None)
    return _model(k, gap, r, side=side, impulse=imp, **({"mass": model.mass.tolist()} | kw))


@pytest.mark.parametrize("name", list(CASES))
def test_parameter_slots_against_finite_differences(name):
    """dP/dp and dJ/dp for the gap and the restitution (the level and R slots), and for a
    mass entry where the rigid impulse q = M^-1 c moves R; dP/domega."""
    _, model, w, y = _case(name)
    con = model.constraints[0]
    h = 1e-6
    params = [("gap", dict(gap=con.gap + h), dict(gap=con.gap - h)),
              ("restitution", dict(r=con.restitution + h), dict(r=con.restitution - h))]
    if con.impulse is None:
        M = np.array(model.mass)
        dM = np.array([[0.0, 1.0], [1.0, 0.0]])
        params.append(("mass[1,2]", dict(mass=(M + h * dM).tolist()),
                       dict(mass=(M - h * dM).tolist())))
    for pname, up, down in params:
        v = _jet(model, w, y, 2, model.tangent(pname))
        mu, md = _with(name, **up), _with(name, **down)
        dP = (_P(mu, w, y)[0] - _P(md, w, y)[0]) / (2 * h)
        assert np.abs(v["dpP"] - dP).max() < 1e-6 * max(1.0, np.abs(dP).max()), pname
        dJ = (_jet(mu, w, y, 1)["J"] - _jet(md, w, y, 1)["J"]) / (2 * h)
        assert np.abs(v["dpJ"] - dJ).max() < 1e-6 * max(1.0, np.abs(dJ).max()), pname
    v = _jet(model, w, y, 2)
    dP = (_P(model, w + h, y)[0] - _P(model, w - h, y)[0]) / (2 * h)
    assert np.abs(v["dwP"] - dP).max() < 1e-6 * max(1.0, np.abs(dP).max())


@pytest.mark.parametrize("name", ["lower-side", "nondiagonal-rigid"])
def test_mpmath_backend_and_high_orders(name):
    """The mpmath backend assembles the same guard and reset (parameter slots included) as
    float64; orders 4, 5 (state derivatives only) take them too: d4 against differences of d3."""
    _, model, w, y = _case(name)
    fl = LinearFlow.of(model)
    _, te = _P(model, w, y)
    tan = model.tangent("restitution")
    v64 = evaluate(fl, fl.forcing(w), tuple(y), te, 3, tan)
    with mpmath.mp.workdps(30):
        flm = LinearFlow.of(model, 30)
        vmp = evaluate(flm, flm.forcing(mpmath.mpf(w)), tuple(mpmath.mpf(float(c)) for c in y),
                       mpmath.mpf(te), 3, tan)
    for key in ("J", "d2", "d3", "dpP", "dpJ"):
        ref = np.array(vmp[key], dtype=float)
        assert np.abs(v64[key] - ref).max() < 1e-11 * max(1.0, np.abs(ref).max()), key
    h = 1e-4
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        hj = high_jet(model, w, tuple(y), te, order=4)
        d4 = np.stack([(_jet(model, w, y + h * e, 3)["d3"] - _jet(model, w, y - h * e, 3)["d3"])
                       / (2 * h) for e in np.eye(len(y))], axis=-1)
    assert np.abs(hj.d4 - d4).max() < 1e-5 * max(1.0, np.abs(d4).max())
    assert np.abs(hj.d3 - v64["d3"]).max() < 1e-12 * max(1.0, np.abs(hj.d3).max())


def test_guard_normal_without_a_section_coordinate_is_refused():
    """A guard off the section's first coordinate, or a reset that is not the identity
    but for column 0 (no rigid reset of the interface), is refused by name."""
    from symvi.codegen.layout import jet_constraint
    from symvi.errors import ParameterError
    fl = LinearFlow.of(_case("stop-mass1")[1])
    import copy
    bad = copy.copy(fl)
    bad.guard = np.array([0.0, 1.0])
    with pytest.raises(ParameterError, match="constraint.normal"):
        jet_constraint(bad)
    bad = copy.copy(fl)
    bad.reset = np.array([[-0.8, 0.1], [0.0, 1.0]])
    with pytest.raises(ParameterError, match="constraint.impulse"):
        jet_constraint(bad)
    assert math.isfinite(jet_constraint(fl)[1])


def test_a_cache_of_the_old_layout_is_refused():
    """A per-user cache module written for the r, b inputs (before the guard and reset
    were inputs) is never run: its input hash is not the generator's, and a module that
    claimed the new hash with the old INPUTS would be refused for its INPUTS."""
    import os

    import symvi._generated as g
    from symvi._derivations import impact_jets as ij
    from symvi.codegen import _usercache as uc
    text = open(os.path.join(os.path.dirname(g.__file__), "impact_n1_order1.py")).read()
    assert uc.verify(text, 1, 1) is None
    new = "'omega', 'g0', 'level', 'R0_0',"
    assert new in text and ij.inputs(1, 1)[-7:-3] == ["omega", "g0", "level", "R0_0"]
    old_inputs = text.replace(new, "'omega', 'r', 'b',")
    assert "other INPUTS" in uc.verify(old_inputs, 1, 1)
    old_hash = old_inputs.replace(f"# input-hash: {ij.input_hash()}", "# input-hash: " + "0" * 64)
    assert "other inputs" in uc.verify(old_hash, 1, 1)


def test_checked_constraint_follows_a_new_gap_and_restitution():
    """Flows of models that differ in the stop's gap or restitution share their modal data
    (a copy with a new constraint); the constraint the jets read is the copy's, never the
    one checked first."""
    mod = module(2, 1)[0]
    for gap, r in ((0.61, 0.8), (0.62, 0.8), (0.62, 0.75), (0.61, 0.8)):
        m = _model(1, gap, r)
        fl = LinearFlow.of(m)
        inp = dict(zip(mod.INPUTS, assemble(fl, fl.forcing(1.1), (-0.4, 0.1, -0.2, 0.7), 5.0, 1)))
        assert (inp["level"], inp["R0_0"]) == (gap, -r)
