"""Model, Stop, named parameters, tangents and model files."""
import numpy as np
import pytest

from symvi.errors import ParameterError
from symvi.model import Model, ModelFileError, Stop, dumps, load_model

GOOD = dict(mass=[1.0, 1.5, 0.8],
            stiffness=[[1.0, -1.0, 0.0], [-1.0, 1.7, -0.7], [0.0, -0.7, 2.7]],
            damping=[[0.015, -0.005, 0.0], [-0.005, 0.0235, -0.0035], [0.0, -0.0035, 0.0215]],
            forcing=[1.0, 0.0, 0.0])
STOP = Stop(mass=1, gap=1.2, restitution=0.8)


def test_construct_diagonal_or_full_mass_and_freeze():
    a = Model(**GOOD, stop=STOP)
    b = Model(**{**GOOD, "mass": np.diag(GOOD["mass"]).tolist()}, stop=STOP)
    assert a == b and hash(a) == hash(b)
    assert a.n == 3 and a.dim == 6 and a.damped and not a.conservative
    with pytest.raises(AttributeError):
        a.stop = STOP
    with pytest.raises(ValueError):
        a.mass[0, 0] = 2.0


@pytest.mark.parametrize("change,field", [
    ({"stiffness": [[1.0, -1.0, 0.0], [-1.1, 1.7, -0.7], [0.0, -0.7, 2.7]]}, "stiffness"),
    ({"mass": [1.0, -1.0, 0.8]}, "mass"),
    # singular is a free mass (accepted); indefinite is refused
    ({"stiffness": [[1.0, -1.2, 0.0], [-1.2, 1.0, 0.0], [0.0, 0.0, 1.0]]}, "stiffness"),
    ({"damping": [[-0.1, 0, 0], [0, 0, 0], [0, 0, 0]]}, "damping"),
    ({"forcing": [1.0, 0.0]}, "forcing"),
    ({"forcing": [1.0, float("nan"), 0.0]}, "forcing"),
    ({"mass": [[1.0, 0.0], [0.0, 1.0]]}, "stiffness"),
    ({"mass": [1.0] * 9, "stiffness": np.eye(9).tolist(), "damping": None,
      "forcing": [1.0] * 9}, "mass"),
])
def test_invalid_models_name_the_field(change, field):
    with pytest.raises(ParameterError) as e:
        Model(**{**GOOD, **change}, stop=STOP)
    assert e.value.name == field
    assert "valid range" in str(e.value)


@pytest.mark.parametrize("kw,field", [({"mass": 4}, "stop.mass"), ({"mass": 0}, "stop.mass"),
                                      ({"restitution": 1.5}, "stop.restitution"),
                                      ({"restitution": 0}, "stop.restitution"),
                                      ({"gap": float("inf")}, "stop.gap")])
def test_invalid_stop(kw, field):
    with pytest.raises(ParameterError) as e:
        Model(**GOOD, stop=Stop(**{"mass": 1, "gap": 1.0, "restitution": 0.8, **kw}))
    assert e.value.name == field


def test_named_parameters_with_and_tangent():
    m = Model(**GOOD, stop=STOP)
    assert m.value("stiffness[2,3]") == -0.7 and m.value("mass[2]") == 1.5
    m2 = m.with_(**{"stiffness[2,3]": -0.5, "forcing[1]": 0.3, "gap": 1.0})
    assert m2.value("stiffness[3,2]") == -0.5 and m2.value("forcing[1]") == 0.3
    assert m2.stop.gap == 1.0 and m.value("stiffness[2,3]") == -0.7
    t = m.tangent("damping[1,2]")
    assert t.dC[0, 1] == t.dC[1, 0] == 1 and not t.dK.any()
    for bad in ("stiffness[4,1]", "mu_m", "speed", "forcing[1,1]", "stiffness[2]"):
        with pytest.raises(ParameterError):
            m.value(bad)
    assert "damping[3,3]" in m.parameter_names() and "omega" not in m.parameter_names()


def test_preset_names_and_equivalence():
    p = Model.luo_xie(2, 5, 0, 1.5, 0.8)
    assert p.preset["name"] == "luo_xie"
    assert p == Model(mass=[1, 2], stiffness=[[1, -1], [-1, 6]], forcing=[1, 0],
                      stop=Stop(mass=1, gap=1.5, restitution=0.8))
    assert p.with_(mu_k=3).value("stiffness[2,2]") == 4.0
    assert p.with_(b=1.2).preset["b"] == 1.2 and p.with_(gap=1.2).preset["b"] == 1.2
    assert p.with_(**{"forcing[2]": 0.1}).preset is None
    assert p.tangent("f2").dP.tolist() == [-1.0, 1.0]
    with pytest.raises(ParameterError):
        Model.luo_xie(-1, 5, 0, 1.5, 0.8)


def test_model_file_round_trip(tmp_path):
    m = Model(**GOOD, stop=STOP)
    f = tmp_path / "m.toml"
    f.write_text(dumps(m))
    assert load_model(f) == m


ISSUE_EXAMPLE = """[model]
mass = [1.0, 1.5, 0.8]
stiffness = [[1.0, -1.0, 0.0], [-1.0, 1.7, -0.7], [0.0, -0.7, 2.7]]
damping = [[0.015, -0.005, 0.0], [-0.005, 0.0235, -0.0035], [0.0, -0.0035, 0.0215]]   # optional
forcing = [1.0, 0.0, 0.0]             # P in P sin(omega t + tau)

[stop]
mass = 1          # 1-based index of the mass that hits the stop
gap = 1.2         # the stop is at x_mass = gap
restitution = 0.8
"""


@pytest.mark.parametrize("edit,key", [
    (lambda s: s.replace("[stop]", "[stop"), ""),
    (lambda s: s.replace("[-1.0, 1.7, -0.7]", "[-1.2, 1.7, -0.7]"), "[model] stiffness"),
    (lambda s: s.replace("mass = [1.0, 1.5, 0.8]", "mass = [1.0, -1.5, 0.8]"), "[model] mass"),
    (lambda s: s.replace("forcing = [1.0, 0.0, 0.0]", "forcing = [1.0, 0.0]"), "[model] forcing"),
    (lambda s: s.replace("forcing = [1.0, 0.0, 0.0]", "forcing = [1.0, nan, 0.0]"),
     "[model] forcing"),
    (lambda s: s.replace("mass = 1 ", "mass = 4 "), "[stop] mass"),
    (lambda s: s.replace("restitution = 0.8", "restitution = 1.8"), "[stop] restitution"),
    (lambda s: s.replace("gap = 1.2", ""), "[stop] gap"),
    (lambda s: s.replace("gap = 1.2", "gapp = 1.2"), "[stop] gapp"),
    (lambda s: s + "\n[extra]\na = 1\n", "extra"),
])
def test_bad_model_file_names_file_and_key(tmp_path, edit, key):
    f = tmp_path / "bad.toml"
    f.write_text(edit(ISSUE_EXAMPLE))
    with pytest.raises(ModelFileError) as e:
        load_model(f)
    msg = str(e.value)
    assert str(f) in msg and key in msg and "\n" not in msg


def test_issue_example_file_loads(tmp_path):
    f = tmp_path / "m.toml"
    f.write_text(ISSUE_EXAMPLE)
    m = load_model(f)
    assert m.n == 3 and m.stop.mass == 1 and m.damped


def test_missing_file(tmp_path):
    with pytest.raises(ModelFileError, match="no such file"):
        load_model(tmp_path / "nope.toml")
