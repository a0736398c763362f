"""Fuzz model files with bad content (issue 23, defects 9 and 13).

Each bad file must give exit 2 and one line on stderr naming the file's key and its
valid range: no traceback, no RecursionError, no allocation by the size of the file
(a 60 KB file's mass list became an N x N diagonal of 3.4 GB), no boolean or
string read as a number.  The runs are in process (tests/fuzz/_cli.py); the memory
and the Model-API cases call symvi.model directly.
"""
import os
import tracemalloc

import numpy as np
import pytest

from symvi.errors import ParameterError
from symvi.model import Model, ModelFileError, Stop, load_model, loads

from ._cli import assert_bad_input, cli

GOOD = """[model]
mass = [1.0, 1.5]
stiffness = [[2.0, -1.0], [-1.0, 2.0]]
forcing = [1.0, 0.0]

[stop]
mass = 1
gap = 0.5
restitution = 0.8
"""
MASS = "mass = [1.0, 1.5]"
STIFF = "stiffness = [[2.0, -1.0], [-1.0, 2.0]]"
FORCE = "forcing = [1.0, 0.0]"


def edit(old, new):
    assert old in GOOD
    return GOOD.replace(old, new, 1)


#: (name, file text, words the one error line must hold: the key, and the range or cause)
CASES = [
    ("huge-n", edit(MASS, "mass = [" + ", ".join(["1.0"] * 4000) + "]"),
     ["[model] mass", "1 <= N <= 8", "4000"]),
    ("n9", edit(MASS, "mass = [" + ", ".join(["1.0"] * 9) + "]"), ["[model] mass", "N <= 8"]),
    ("deep", edit(FORCE, "forcing = " + "[" * 5000 + "]" * 5000),
     ["[model] forcing", "nested more than 8"]),
    ("deep-multiline", edit(STIFF, "stiffness = " + "[\n" * 40 + "1" + "]" * 40),
     ["[model] stiffness", "nested"]),
    ("nested3", edit(MASS, "mass = [[[1.0]], [[1.5]]]"), ["[model] mass", "matrix"]),
    ("bool-entry", edit(MASS, "mass = [true, 1.5]"), ["[model] mass", "not booleans", "true"]),
    ("bool-matrix", edit(STIFF, "stiffness = [[true, -1.0], [-1.0, 2.0]]"),
     ["[model] stiffness", "[1,1]"]),
    ("string-entry", edit(MASS, 'mass = ["1.0", 1.5]'), ["[model] mass", "strings", "'1.0'"]),
    ("string-forcing", edit(FORCE, 'forcing = ["1", 0]'), ["[model] forcing", "[1]"]),
    ("bool-gap", edit("gap = 0.5", "gap = true"), ["[stop] gap", "finite real number"]),
    ("string-gap", edit("gap = 0.5", 'gap = "0.5"'), ["[stop] gap", "finite real number"]),
    ("string-r", edit("restitution = 0.8", 'restitution = "0.8"'), ["[stop] restitution"]),
    ("float-index", edit("mass = 1\n", "mass = 1.0\n"), ["[stop] mass", "integer"]),
    ("bool-index", edit("mass = 1\n", "mass = true\n"), ["[stop] mass", "integer"]),
    ("index-out-of-range", edit("mass = 1\n", "mass = 3\n"), ["[stop] mass", "from 1 to 2"]),
    ("index-zero", edit("mass = 1\n", "mass = 0\n"), ["[stop] mass", "from 1 to"]),
    ("index-5000-digits", edit("mass = 1\n", "mass = " + "9" * 5000 + "\n"),
     ["[stop] mass", "5000 digits"]),
    ("forcing-5000-digits", edit(FORCE, "forcing = [" + "9" * 5000 + ", 0]"),
     ["[model] forcing", "5000 digits"]),
    ("non-square", edit(STIFF, "stiffness = [[2.0, -1.0], [-1.0]]"),
     ["[model] stiffness", "2x2", "row 2"]),
    ("wrong-size", edit(STIFF, "stiffness = [[2.0]]"), ["[model] stiffness", "2x2"]),
    ("ragged-mass", edit(MASS, "mass = [[1.0, 0.0], 1.5]"), ["[model] mass", "row 2"]),
    ("empty-mass", edit(MASS, "mass = []"), ["[model] mass", "1 <= N <= 8"]),
    ("asymmetric", edit(STIFF, "stiffness = [[2.0, -1.0], [-1.1, 2.0]]"),
     ["[model] stiffness", "symmetric"]),
    ("nan", edit(MASS, "mass = [nan, 1.5]"), ["[model] mass", "finite"]),
    ("inf", edit(FORCE, "forcing = [inf, 0.0]"), ["[model] forcing", "finite"]),
    ("inf-gap", edit("gap = 0.5", "gap = -inf"), ["[stop] gap", "finite"]),
    ("huge-entry", edit(STIFF, "stiffness = [[2.0, -1e300], [-1e300, 2.0]]"),
     ["[model] stiffness", "1e+06"]),
    ("negative-mass", edit(MASS, "mass = [-1.0, 1.5]"),
     ["[model] mass", "positive definite", "not positive definite"]),
    ("ill-conditioned-mass", edit(MASS, "mass = [1e-13, 1.5]"),
     ["[model] mass", "ill-conditioned", "condition number", "limit"]),
    ("indefinite-stiffness", edit(STIFF, "stiffness = [[1.0, -1.5], [-1.5, 1.0]]"),
     ["[model] stiffness", "positive semi-definite", "indefinite"]),
    ("nearly-singular-stiffness", edit(STIFF, "stiffness = [[1.0, -1.0], [-1.0, 1.000000000001]]"),
     ["[model] stiffness", "nearly singular", "free mass"]),
    ("negative-damping", edit(FORCE, FORCE + "\ndamping = [[-0.1, 0.0], [0.0, 0.0]]"),
     ["[model] damping", "semi-definite"]),
    ("missing-forcing", edit(FORCE, ""), ["[model] forcing", "missing"]),
    ("missing-stop", GOOD.split("[stop]")[0], ["[stop]", "missing"]),
    ("unknown-key", edit(FORCE, FORCE + "\nspring = 1"), ["[model] spring", "unknown key"]),
    ("unknown-table", GOOD + "\n[extra]\na = 1\n", ["extra", "unknown table"]),
    ("forcing-scalar", edit(FORCE, "forcing = 3"), ["[model] forcing", "list of 2"]),
    ("forcing-table", edit(FORCE, "forcing = {a = 1}"), ["[model] forcing", "list of 2"]),
    ("forcing-date", edit(FORCE, "forcing = [1979-05-27, 0]"), ["[model] forcing", "[1]"]),
    ("model-array-of-tables", GOOD.replace("[model]", "[[model]]"), ["[model]", "table"]),
    ("malformed", "[model\nmass = ", ["malformed TOML"]),
]


@pytest.mark.parametrize("name,text,words", CASES, ids=[c[0] for c in CASES])
def test_bad_model_file_is_one_line_exit_2_naming_the_key(tmp_path, name, text, words):
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    line = assert_bad_input(cli("orbit", "--model", path, "--omega", "1"), *words)
    assert str(path)[-20:] in line and "np.float64" not in line
    assert len(line) < 400


def test_special_files_and_paths(tmp_path):
    fifo = tmp_path / "fifo.toml"
    os.mkfifo(fifo)                          # reading it would block: refused unopened
    assert_bad_input(cli("orbit", "--model", fifo, "--omega", "1"), "not a regular file")
    assert_bad_input(cli("orbit", "--model", tmp_path, "--omega", "1"), "directory")
    assert_bad_input(cli("orbit", "--model", tmp_path / "none.toml", "--omega", "1"),
                     "no such file")
    big = tmp_path / "big.toml"
    big.write_text(GOOD + "#" * (1 << 20))
    assert_bad_input(cli("orbit", "--model", big, "--omega", "1"), "larger than")
    line = assert_bad_input(cli("orbit", "--model", "a" * 5000, "--omega", "1"))
    assert len(line) < 400


def test_a_huge_model_file_is_refused_before_allocating(tmp_path):
    path = tmp_path / "huge.toml"
    # 4000 entries: the diagonal built first would be 128 MB (the 60 KB file: 3.4 GB)
    path.write_text(edit(MASS, "mass = [" + ", ".join(["1.0"] * 4000) + "]"))
    tracemalloc.start()
    try:
        with pytest.raises(ModelFileError, match="1 <= N <= 8"):
            load_model(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50e6                       # the file's own parse, not 4000^2 floats


def test_loads_refuses_deep_nesting_without_recursing():
    with pytest.raises(ModelFileError, match=r"\[model\] forcing: arrays nested"):
        loads(edit(FORCE, "forcing = " + "[" * 100000 + "]" * 100000))
    # brackets in strings and comments are not nesting
    ok = loads(edit(FORCE, FORCE + '  # [[[[[[[[[[[[[[[[[[[[[[[[[[[[\n'))
    assert ok.n == 2


@pytest.mark.parametrize("kw,field,words", [
    ({"mass": np.array([True, False])}, "mass", "not booleans"),
    ({"mass": ["1.0", 1.5]}, "mass", "strings"),
    ({"mass": np.ones(100000)}, "mass", "1 <= N <= 8"),
    ({"mass": np.ones((3, 3, 3))}, "mass", "finite real numbers"),
    ({"forcing": [1.0, True]}, "forcing", "not booleans"),
    ({"forcing": [10 ** 400, 0]}, "forcing", "finite"),
    ({"mass": [1e-13, 1.5]}, "mass", "ill-conditioned"),
])
def test_model_api_refuses_the_same(kw, field, words):
    args = dict(mass=[1.0, 1.5], stiffness=[[2.0, -1.0], [-1.0, 2.0]], forcing=[1.0, 0.0],
                stop=Stop(mass=1, gap=0.5, restitution=0.8))
    args.update(kw)
    with pytest.raises(ParameterError) as e:
        Model(**args)
    msg = str(e.value)
    assert e.value.name == field and words in msg
    assert "\n" not in msg and len(msg) < 400 and "np.float64" not in msg


def test_with_refuses_strings_and_names_the_entry():
    m = loads(GOOD, "m")
    with pytest.raises(ParameterError, match="not a number"):
        m.with_(gap="1")
    with pytest.raises(ParameterError) as e:
        m.with_(**{"stiffness[1,2]": 1e300})
    assert "\n" not in str(e.value) and "entry [1,2]" in str(e.value)
