"""Argument parsing shared by every subcommand (issue 23, defect 11 and items of 13):
flags given twice, negative numbers with exponents, names with commas in brackets, one-line
errors naming the flag, numbers rendered without numpy reprs."""
import numpy as np
import pytest

from symvi.cli import build_parser
from symvi.curves import parse_params
from symvi.errors import ParameterError

from ..fuzz._cli import assert_bad_input, cli

PRESET = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]


def parse(*argv):
    return build_parser().parse_args(list(argv))


@pytest.mark.parametrize("text, value", [("-1e-3", -1e-3), ("-.5", -0.5), ("-1.", -1.0),
                                         ("-2E+3", -2000.0), ("-7", -7.0)])
def test_negative_numbers_are_values_not_flags(text, value):
    a = parse("simulate", *PRESET, "--omega", "0.7", "--out", "x.npz",
              "--y0", text, "0", "-1e-3", "0")
    assert a.y0 == [value, 0.0, -1e-3, 0.0]
    assert parse("continue", *PRESET, "--param", "b", "--from", text, "--to", "1").start \
        == value
    assert np.isneginf(parse("orbit", *PRESET, "--omega", "-inf").omega)


def test_a_flag_given_twice_is_refused_naming_it():
    line = assert_bad_input(cli("orbit", *PRESET, "--omega", "0.7", "--omega", "0.8"),
                            "--omega")
    assert "once" in line
    assert_bad_input(cli("orbit", *PRESET, "--omega", "0.7", "--om", "0.8"), "--omega")
    assert_bad_input(cli("orbit", *PRESET, "--omega=0.7", "--omega=0.8"), "--omega")
    assert_bad_input(cli("orbit", *PRESET, "--json", "--omega", "0.7", "--json"), "--json")


def test_repeatable_flags_repeat():
    a = parse("continue", *PRESET, "--range", "b=1:2",
              "--set", "omega=1.2", "--set", "mass[1,2]=0.1")
    assert a.sets == ["omega=1.2", "mass[1,2]=0.1"]
    a = parse("curve", *PRESET, "--range", "omega=0.7:0.76", "--params",
              "omega,b", "--bounds", "b=1:2", "--bounds", "omega=0.5:1")
    assert a.bounds == ["b=1:2", "omega=0.5:1"]


def test_curve_params_split_outside_brackets():
    """Defect 11: stiffness[1,2] was split at its comma."""
    assert parse_params("omega,stiffness[1,2]") == ("omega", "stiffness[1,2]")
    assert parse_params(" damping[1,2] , mass[2,2]") == ("damping[1,2]", "mass[2,2]")
    for bad in ("omega,stiffness[1,2", "omega,b,r", "omega", "omega,stiffness[1,2]]"):
        with pytest.raises(ParameterError, match="--params"):
            parse_params(bad)
    # the names reach the model: the next error is about --bounds, not --params
    base = ["curve", *PRESET, "--range", "omega=0.7:0.76"]
    assert_bad_input(cli(*base, "--params", "omega,stiffness[1,2]", "--bounds",
                         "stiffness[1,2]=nan:1"), "--bounds")
    assert_bad_input(cli(*base, "--params", "omega,stiffness[1,3]"), "--params",
                     "stiffness[1,3]")
    assert_bad_input(cli(*base, "--params", "b,gap"), "--params", "one parameter")


def test_continue_from_equal_to_is_an_error():
    """Was exit 0 with no branch."""
    assert_bad_input(cli("continue", *PRESET, "--range", "omega=1.2:1.2"), "--range",
                     "LO != HI")


@pytest.mark.parametrize("args, words", [
    (["--range", "omega=1.2:nan"], ["--range", "finite"]),
    (["--range", "r=0.8:1.5", "--set", "omega=1.2"],
     ["--range", "0 < r <= 1"]),
    (["--range", "mu_m=2:-1", "--set", "omega=1.2"],
     ["--range", "mu_m > 0"]),
    (["--range", "mass[1,2]=0:5", "--set", "omega=1.2"],
     ["--range", "positive definite"]),
    (["--range", "b=1.5:1.6", "--set", "omega=0.8804857344718374"],
     ["--set omega", "natural frequency"]),
])
def test_continue_range_checks_name_the_flag(args, words):
    assert_bad_input(cli("continue", *PRESET, *args), *words)


@pytest.mark.parametrize("bounds, words", [
    ("r=0.5:1.5", ["--bounds", "0 < r <= 1"]), ("r=nan:1", ["--bounds", "finite"]),
    ("omega=0:1", ["--bounds", "omega"]), ("omega=0.5:0.6", ["--bounds", "start value"]),
])
def test_curve_bounds_are_range_checked(bounds, words):
    assert_bad_input(cli("curve", *PRESET, "--range", "omega=0.7:0.76",
                         "--params", "omega,r", "--bounds", bounds, "--max-points", "20"),
                     *words)


def test_parameter_error_renders_numpy_values_plainly():
    """np.float64(...) reprs and multi-line arrays never reach a message."""
    assert str(ParameterError("x", np.float64(0.5), "y")) == \
        "x = 0.5 is invalid; valid range: y"
    msg = str(ParameterError("bounds", (np.float64(1.0), np.float64(2.0)), "y"))
    assert "np." not in msg and "(1.0, 2.0)" in msg
    msg = str(ParameterError("stiffness", np.array([[1.0, 1e300], [1e300, 6.0]]), "y"))
    assert "\n" not in msg and "array" not in msg


def test_version_and_defaults_in_help():
    """symvi --version prints the package's version; each option with a default shows it
    in --help, once (issue 26: one set of CLI conventions)."""
    import argparse

    import symvi
    rc, out, err = cli("--version")
    assert rc == 0 and out.strip() == f"symvi {symvi.__version__}"
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    assert "(default: 5000)" in " ".join(sub.choices["continue"].format_help().split())
    for name, p in sub.choices.items():
        fmt = p._get_formatter()
        for action in p._actions:
            if action.help:
                assert fmt._expand_help(action).lower().count("default") <= 1, \
                    (name, action.dest)


def test_json_on_the_report_and_regenerate_commands(tmp_path):
    """--json on run and regenerate (issue 26: --json on every command): one JSON object
    naming what was written, or for --check whether generated/ is fresh."""
    import json
    rc, out, err = cli("regenerate", "--check", "--json")
    d = json.loads(out)
    assert rc == (0 if d["fresh"] else 1) and d["folders"] and isinstance(d["stale"], list)
    from pathlib import Path
    scene = sorted((Path(__file__).resolve().parents[2] / "symvi" / "scenes").glob("*.toml"))[0]
    rc, out, err = cli("run", str(scene), "--out", str(tmp_path / "r"), "--quick", "--json")
    assert rc == 0, err
    d = json.loads(out)
    assert d["report"].endswith("report.md") and Path(d["report"]).exists()
    assert d["parts"] >= 1 and all(Path(f).exists() for f in d["figures"])


def test_one_figure_flag_old_spellings_warn(tmp_path):
    """--plot is the figure flag of every command: a figure given to sweep as --out still
    works for one release, and says it is deprecated (after the work, so that a refusal
    stays one line)."""
    ex1 = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]
    fig = tmp_path / "bif.png"
    rc, out, err = cli("sweep", *ex1, "--range", "omega=0.73:0.74:3", "--impacts", "5", "--transient", "10", "--out", fig)
    assert rc == 0 and fig.exists() and "deprecated" in err and "--plot" in err
    rc, out, err = cli("sweep", *ex1, "--range", "omega=0.73:0.74:3", "--impacts", "5", "--transient", "10", "--out", tmp_path / "b.npz",
                       "--plot", tmp_path / "b2.png")
    assert rc == 0 and "deprecated" not in err and (tmp_path / "b2.png").exists()
