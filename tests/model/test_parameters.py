"""Parameters as objects (issue 24, item 2): a name parsed once into a lens on the point
(model, omega): get, set, tangent."""
import numpy as np
import pytest

from symvi.errors import ParameterError
from symvi.model import Model, Stop, parameters
from symvi.orbits.periodic import Problem
from tests.zoo import (FOUR_STOP3, ONE_DAMPED_GAP02, ONE_UNDAMPED, PAPER_DAMPED, PAPER_EX1,
                       THREE_STOP2_GAP12, TWO_OVERDAMPED)

MODELS = {"one": ONE_UNDAMPED, "one-damped": ONE_DAMPED_GAP02, "paper": PAPER_EX1,
          "paper-damped": PAPER_DAMPED, "two-overdamped": TWO_OVERDAMPED,
          "three": THREE_STOP2_GAP12, "four": FOUR_STOP3}


def _cases():
    for label, model in MODELS.items():
        for name in model.parameter_names():
            yield pytest.param(model, name, id=f"{label}-{name}")


def _moved(par, v):
    """A nearby value that keeps the model valid: off-diagonal couplings shrink, the rest
    grows a little (restitution shrinks: it is at most 1)."""
    if par.kind == "restitution":
        return v * 0.99
    if isinstance(par, parameters.EntryParameter) and par.i != par.j:
        return v * 0.99
    return v + 1e-3 * (1 + abs(v))


def _data(model):
    s = model.stop
    return (model.mass, model.stiffness, model.damping, model.forcing, s.gap, s.restitution)


@pytest.mark.parametrize("model, name", _cases())
def test_get_set_round_trip(model, name):
    par = model.parameter(name)
    v = par.get(model)
    assert v == model.value(name)
    w = _moved(par, v)
    new, omega = par.set(model, 0.8, w)
    assert omega == 0.8
    assert par.get(new) == w
    assert new == model.with_(**{name: w}) and hash(new) == hash(model.with_(**{name: w}))
    back = par.apply(new, v)
    assert back == model and hash(back) == hash(model)
    # the same numbers as the full constructor (the fast path skips only checks)
    d = new.as_dict()
    d.pop("preset", None)
    d["stop"] = Stop(**d["stop"])
    assert Model(**d).key() == new.key()


@pytest.mark.parametrize("model, name", _cases())
def test_tangent_against_finite_differences(model, name):
    """The tangent is d(M, K, C, P, b, r)/dp; the data are linear in p, so the central
    difference equals it to rounding."""
    if name.startswith("damping") and not model.damped:      # both sides must be valid
        d = model.as_dict()
        d.pop("preset", None)
        model = Model(**dict(d, damping=np.eye(model.n).tolist(), stop=Stop(**d["stop"])))
    par = model.parameter(name)
    v = par.get(model)
    h = 1e-4 * (1 + abs(v)) if par.kind != "restitution" else 1e-4
    lo, hi = par.apply(model, v - h), par.apply(model, v + h)
    t = par.tangent(model)
    for a, b, d in zip(_data(hi), _data(lo), (t.dM, t.dK, t.dC, t.dP, t.db, t.dr)):
        np.testing.assert_allclose((np.asarray(a) - np.asarray(b)) / (2 * h), d, atol=1e-8)
    assert not t.zero
    assert t is par.tangent(model)                       # built once
    with pytest.raises(ValueError):
        t.dM[0, 0] = 5.0                                 # shared, so read-only


def test_omega_is_a_parameter_beside_the_model():
    m = THREE_STOP2_GAP12
    om = m.parameter("omega")
    assert om.is_forcing_frequency and not m.parameter("gap").is_forcing_frequency
    assert om.get(m, 0.9) == 0.9
    new, w = om.set(m, 0.9, 1.1)
    assert new is m and w == 1.1
    assert om.tangent(m).zero and m.tangent("omega").zero
    with pytest.raises(ParameterError, match="forcing frequency"):
        om.apply(m, 1.1)
    with pytest.raises(ParameterError):
        m.value("omega")                                 # not a field of the model
    # the orbit problem continued in omega reads it through the object
    pr = Problem(m, 1, 1, param="omega")
    assert pr.parameter is om and pr.param == "omega"
    model, flow, F = pr.at(0.9)
    assert model is m and F.omega == 0.9


def test_preset_parameters():
    m = PAPER_EX1
    mu = m.parameter("mu_m")
    new = mu.apply(m, 3.0)
    assert new.preset["mu_m"] == 3.0 and new.mass[1, 1] == 3.0
    assert m.parameter("b").apply(m, 1.2).preset["b"] == 1.2
    with pytest.raises(ParameterError, match="mu_m"):
        mu.apply(m, -1.0)                                # the preset's range
    assert m.parameter("stiffness[1,2]").apply(m, -0.9).preset is None
    with pytest.raises(ParameterError, match="Luo-Xie preset only"):
        ONE_UNDAMPED.parameter("mu_m")


def test_set_validates_what_the_change_can_break():
    m = THREE_STOP2_GAP12
    with pytest.raises(ParameterError, match="restitution"):
        m.parameter("restitution").apply(m, 1.5)
    with pytest.raises(ParameterError, match="gap"):
        m.parameter("gap").apply(m, float("nan"))
    with pytest.raises(ParameterError, match="stiffness.*positive definite"):
        m.parameter("stiffness[2,2]").apply(m, 0.1)
    with pytest.raises(ParameterError, match="damping.*semi-definite"):
        m.parameter("damping[1,1]").apply(m, -1.0)
    with pytest.raises(ParameterError, match="forcing"):
        m.parameter("forcing[1]").apply(m, 1e300)


@pytest.mark.parametrize("name, why", [("stiffness[9,9]", ""), ("bogus", ""),
                                       ("stiffness[1]", "needs two indices"),
                                       ("forcing[1,2]", ""), (3, "")])
def test_bad_name_one_line_naming_the_valid_names(name, why):
    with pytest.raises(ParameterError) as exc:
        THREE_STOP2_GAP12.parameter(name)
    msg = str(exc.value)
    assert "\n" not in msg and "valid range: omega, gap, restitution" in msg and why in msg
    with pytest.raises(ParameterError) as old:
        THREE_STOP2_GAP12.value(name)
    assert str(old.value) == msg


def test_bad_name_refused_once_at_the_boundary():
    from symvi.continuation import continue_branch
    before = parameters.PARSES[0]
    with pytest.raises(ParameterError, match="^param = 'bogus'"):
        continue_branch(THREE_STOP2_GAP12, "bogus", 1.0, 1.2, omega=1.0)
    assert parameters.PARSES[0] - before == 1


def test_parsed_once_per_shape():
    a, b = THREE_STOP2_GAP12, THREE_STOP2_GAP12.with_(gap=0.7)
    assert a.parameter("stiffness[1,2]") is b.parameter("stiffness[1,2]")
    assert a.parameter("gap") is not ONE_UNDAMPED.parameter("gap")     # another shape
    p = a.parameter("gap")
    assert a.parameter(p) is p and hash(p) == hash(b.parameter("gap")) and p == b.parameter("gap")
    import pickle
    assert pickle.loads(pickle.dumps(p)) is p
    # a parameter of the preset does not fit a general model: named as today
    with pytest.raises(ParameterError, match="preset only"):
        PAPER_DAMPED.parameter(PAPER_EX1.parameter("mu_k"))


@pytest.mark.parametrize("name", ["gap", "restitution", "stiffness[1,2]", "forcing[2]"])
def test_corrector_loop_neither_parses_nor_rebuilds(name, monkeypatch):
    """A corrector step sets the parameter: no name is parsed, and a gap, a restitution or a
    forcing never runs the whole model validation (a matrix entry checks its matrix only)."""
    m = THREE_STOP2_GAP12
    pr = Problem(m, 1, 1, omega=1.0, param=name)
    v0 = m.value(name)
    built = []
    init = Model.__init__
    monkeypatch.setattr(Model, "__init__", lambda self, **kw: (built.append(1), init(self, **kw)))
    before = parameters.PARSES[0]
    for k in range(50):
        model = pr.at(v0 * (1 + 1e-4 * k), check=False)[0]
        assert model.value(name) == v0 * (1 + 1e-4 * k)
    assert parameters.PARSES[0] == before
    assert built == []


def test_branch_in_gap_does_not_parse_in_its_loop(monkeypatch):
    """A whole branch in the gap: the name is parsed (at most) once, no Model is built."""
    from symvi.continuation import continue_branch
    parameters._parse.cache_clear()
    built = []
    init = Model.__init__
    monkeypatch.setattr(Model, "__init__", lambda self, **kw: (built.append(1), init(self, **kw)))
    before = parameters.PARSES[0]
    br = continue_branch(ONE_DAMPED_GAP02, "gap", 0.2, 0.3, omega=1.3, max_points=40)
    assert len(br.points) > 5
    assert parameters.PARSES[0] - before <= 2           # gap (and omega where it is looked up)
    assert built == []
