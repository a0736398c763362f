"""Nonlinear forces in the model (issue 28, first step): ``Model(nonlinear=[...],
parameters={...})``, the model file's ``[model] nonlinear`` and ``[model.parameters]``,
the closed parser and its one-line refusals, the named parameters as lenses, and a linear
model left unchanged in every way."""
import pickle

import pytest
import sympy

from symvi.errors import ParameterError
from symvi.model import Model, ModelFileError, Stop, dumps, loads
from tests.fuzz._cli import cli

LIN = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
DUFFING = Model(**LIN, nonlinear=["beta*x1**3"], parameters={"beta": 0.5})

FILE = """[model]
mass = [1.0]
stiffness = [[1.0]]
damping = [[0.1]]
forcing = [1.0]
nonlinear = ["beta*x1**3"]
[model.parameters]
beta = 0.5

[stop]
mass = 1
gap = 0.5
restitution = 0.8
"""


def _one_line(exc):
    text = str(exc.value)
    assert "\n" not in text
    return text


def test_the_forces_are_sympy_expressions():
    x1, beta = sympy.symbols("x1 beta", real=True)
    assert DUFFING.nonlinear == (beta * x1 ** 3,)
    assert Model(**LIN).nonlinear is None
    # one force written two ways is one model
    assert Model(**LIN, nonlinear=["x1**3*beta"], parameters={"beta": 0.5}) == DUFFING
    assert Model(**LIN, nonlinear=["x1**3*beta"], parameters={"beta": 0.4}) != DUFFING


def test_a_linear_model_is_unchanged():
    m = Model(**LIN)
    assert m.key() == (((1.0,),), ((1.0,),), ((0.1,),), (1.0,), 1, 0.5, 0.8)
    assert repr(m) == ("Model(mass=[[1.0]], stiffness=[[1.0]], damping=[[0.1]], "
                       "forcing=[1.0], stop=Stop(mass=1, gap=0.5, restitution=0.8))")
    assert "nonlinear" not in m.as_dict() and "nonlinear" not in dumps(m)
    assert loads(dumps(m)) == m and "beta" not in m.parameter_names()
    assert m != DUFFING and hash(m) != hash(DUFFING)


def test_the_model_file_round_trip():
    m = loads(FILE)
    assert m == DUFFING and hash(m) == hash(DUFFING)
    assert loads(dumps(m)) == m
    assert "nonlinear=['beta*x1**3'], parameters={'beta': 0.5}" in repr(m)


def test_named_parameters_are_lenses():
    p = DUFFING.parameter("beta")
    assert p.get(DUFFING) == 0.5
    m2, w = p.set(DUFFING, 1.3, 0.7)
    assert w == 1.3 and m2.value("beta") == 0.7 and DUFFING.value("beta") == 0.5
    assert m2.nonlinear == DUFFING.nonlinear
    assert "beta" in DUFFING.parameter_names()
    m3 = DUFFING.with_(beta=0.2, gap=0.4)
    assert (m3.value("beta"), m3.value("gap")) == (0.2, 0.4)
    # another parameter keeps the forces
    assert DUFFING.with_(**{"stiffness[1,1]": 2.0}).value("beta") == 0.5
    assert pickle.loads(pickle.dumps(p)) == p
    with pytest.raises(ParameterError, match="parameters.beta"):
        p.apply(DUFFING, float("nan"))
    with pytest.raises(ParameterError, match="no tangent yet"):
        p.tangent(DUFFING)


@pytest.mark.parametrize("text, why", [
    ("beta*x2", "unknown symbol x2"),
    ("gamma*x1", "unknown symbol gamma"),
    ("Abs(x1)", "Abs is not smooth"),
    ("sign(v1)", "sign is not smooth"),
    ("Max(x1, 0)", "Max is not smooth"),
    ("Heaviside(x1)", "Heaviside is not smooth"),
    ("Piecewise((x1, x1 > 0))", "Piecewise is not smooth"),
    ("x1^3", "write powers as **"),
    ("beta*(x1", "syntax error"),
    ("x1 x1", "syntax error"),
    ("x1.real", "attribute access"),
    ("__import__('os')", "'__'"),
    ("'x1'", "syntax error"),
    ("x1; x1", "syntax error"),
    ("lambda: x1", "syntax error"),
    ("x1, x1", "not one expression"),
    ("", "empty"),
    ("1/0", "not finite"),
    ("1e999*x1", "finite numbers"),
    ("2**10**10", "numeric exponents"),
    ("x1" + "+x1" * 400, "at most 1000 characters"),
])
def test_bad_expressions_get_one_line_naming_the_key(text, why):
    with pytest.raises(ParameterError) as exc:
        Model(**LIN, nonlinear=[text], parameters={"beta": 0.5})
    msg = _one_line(exc)
    assert msg.startswith("nonlinear[1]") and why in msg


def test_sympy_never_sees_what_the_tokenizer_refuses(monkeypatch):
    import sympy.parsing.sympy_parser as sp

    def boom(*a, **k):
        raise AssertionError("parse_expr reached")
    monkeypatch.setattr(sp, "parse_expr", boom)
    for text in ("__import__('os').system('true')", "x1.__class__", "().__class__",
                 "open('f')", "eval('1')", "x1 if x1 else 0"):
        with pytest.raises(ParameterError):
            Model(**LIN, nonlinear=[text], parameters={"beta": 0.5})


@pytest.mark.parametrize("pars, key, why", [
    ({"omega": 1.0}, "parameters.omega", "clashes"),
    ({"gap": 1.0}, "parameters.gap", "clashes"),
    ({"x1": 1.0}, "parameters.x1", "clashes"),
    ({"v2": 1.0}, "parameters.v2", "clashes"),
    ({"sin": 1.0}, "parameters.sin", "clashes"),
    ({"beta": float("inf")}, "parameters.beta", "finite"),
    ({"beta": "0.5"}, "parameters.beta", "finite"),
    ({"beta": True}, "parameters.beta", "finite"),
    ({"a__b": 1.0}, "parameters.a__b", "letters"),
])
def test_bad_parameters(pars, key, why):
    with pytest.raises(ParameterError) as exc:
        Model(**LIN, nonlinear=["x1**3"], parameters=pars)
    msg = _one_line(exc)
    assert msg.startswith(key) and why in msg


def test_wrong_number_of_expressions_and_parameters_alone():
    with pytest.raises(ParameterError, match=r"^nonlinear = .*it has 2, not 1"):
        Model(**LIN, nonlinear=["x1", "x1"])
    with pytest.raises(ParameterError, match="^nonlinear"):
        Model(**LIN, nonlinear="x1**3")
    with pytest.raises(ParameterError, match="^parameters"):
        Model(**LIN, parameters={"beta": 0.5})


@pytest.mark.parametrize("old, new, key", [
    ("beta*x1**3", "Abs(x1)", "[model] nonlinear[1]"),
    ("beta*x1**3", "beta*y1", "[model] nonlinear[1]"),
    ('["beta*x1**3"]', '["x1", "x1"]', "[model] nonlinear"),
    ("beta = 0.5", "omega = 0.5", "[model.parameters] omega"),
    ("beta = 0.5", "beta = nan", "[model.parameters] beta"),
])
def test_a_bad_file_names_the_key_and_exits_2(tmp_path, old, new, key):
    text = FILE.replace(old, new)
    with pytest.raises(ModelFileError) as exc:
        loads(text, "m.toml")
    assert _one_line(exc).startswith(f"m.toml: {key}:")
    f = tmp_path / "m.toml"
    f.write_text(text)
    rc, out, err = cli("simulate", "--model", f, "--omega", "1.3", "--y0", "-0.3", "0.1",
                       "--out", tmp_path / "o.npz", "--json")
    assert rc == 2 and key in err and len(err.strip().splitlines()) == 1


def test_parameters_table_without_forces_is_refused():
    text = FILE.replace('nonlinear = ["beta*x1**3"]\n', "")
    with pytest.raises(ModelFileError, match=r"\[model.parameters\]"):
        loads(text, "m.toml")
