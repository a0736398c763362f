"""One set of command-line conventions (issue 26, item 3): one range form ``NAME=LO:HI[:N]``,
``--json`` on every command, the old spellings working for one release with one notice."""
import json

import numpy as np
import pytest

from symvi.cli import COMMANDS, Range, build_parser, parse_range
from symvi.errors import ParameterError

from ..fuzz._cli import assert_bad_input, cli

PRESET = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]


def _notices(err):
    return [ln for ln in err.splitlines() if ln.startswith("symvi: warning:")]


@pytest.mark.parametrize("text, kw, expected", [
    ("omega=0.7:0.76", {}, Range("omega", 0.7, 0.76, None)),
    ("stop[2].gap=-0.6:-0.4", {}, Range("stop[2].gap", -0.6, -0.4, None)),
    ("stiffness[1,2]=1e-3:2E1", {}, Range("stiffness[1,2]", 1e-3, 20.0, None)),
    ("b=1.6:1.4", {"ordered": False}, Range("b", 1.6, 1.4, None)),
    ("omega=0.7:0.76:50", {"steps": True}, Range("omega", 0.7, 0.76, 50)),
])
def test_a_range_is_name_equals_lo_colon_hi(text, kw, expected):
    r = parse_range(text, "--range", **kw)
    assert r == expected and (r.name, r.lo, r.hi, r.n) == tuple(expected)


@pytest.mark.parametrize("text, kw, words", [
    ("0.7:0.76", {}, ["NAME=LO:HI"]),
    ("omega:0.7:0.76", {}, ["NAME=LO:HI"]),
    ("omega=0.76:0.7", {}, ["LO < HI"]),
    ("b=1.5:1.5", {"ordered": False}, ["LO != HI"]),
    ("omega=nan:1", {}, ["finite"]),
    ("omega=0.7:inf", {}, ["finite"]),
    ("omega=a:1", {}, ["NAME=LO:HI"]),
    ("omega=0.7:0.76:5", {}, ["no :N here"]),
    ("omega=0.7:0.76", {"steps": True}, ["NAME=LO:HI:N", ":N is missing"]),
    ("omega=0.7:0.76:1", {"steps": True}, ["N >= 2"]),
    ("omega=0.7:0.76:2.5", {"steps": True}, ["integer N"]),
    ("omega=0.7:0.76:9", {"steps": True, "most": 8}, ["2 .. 8"]),
    ("b=0.7:0.76", {"names": ("omega",)}, ["omega=LO:HI"]),
    ("=0.7:0.76", {}, ["NAME=LO:HI"]),
])
def test_a_bad_range_is_one_message_naming_the_flag_and_the_form(text, kw, words):
    with pytest.raises(ParameterError) as e:
        parse_range(text, "--range", **kw)
    assert e.value.name == "--range"
    for w in words:
        assert w in str(e.value), (w, str(e.value))


def test_every_command_takes_json_and_no_help_teaches_an_old_spelling():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    assert set(sub.choices) == {"continue" if c == "continuation" else c for c in COMMANDS}
    for name, p in sub.choices.items():
        flags = {s for a in p._actions for s in a.option_strings}
        assert "--json" in flags, name
        text = p.format_help()
        for old in ("--omega-min", "--omega-max", "--steps", "--param ", "--from ", "--to ",
                    "NAME:LO"):
            assert old not in text, (name, old)


HOPF = ["hopf", *PRESET, "--json"]


def test_hopf_old_and_new_ranges_give_the_same_json_and_the_old_one_notice():
    rc, new, err = cli(*HOPF, "--range", "omega=0.70:0.76")
    assert rc == 0 and _notices(err) == [], err
    rc, old, err = cli(*HOPF, "--omega-min", "0.70", "--omega-max", "0.76")
    assert rc == 0 and json.loads(old) == json.loads(new)
    [line] = _notices(err)
    assert "--omega-min --omega-max are deprecated" in line and "--range omega=LO:HI" in line
    # every run says it (not once per process, as Python's warning registry would)
    assert _notices(cli(*HOPF, "--omega-min", "0.70", "--omega-max", "0.76")[2]) == [line]


def test_continue_old_and_new_ranges_give_the_same_branches():
    argv = ["continue", *PRESET, "--max-points", "40", "--json"]
    rc, new, err = cli(*argv, "--range", "omega=1.3:1.1")
    assert rc == 0 and _notices(err) == [], err
    rc, old, err = cli(*argv, "--param", "omega", "--from", "1.3", "--to", "1.1")
    assert rc == 0 and json.loads(old) == json.loads(new)
    assert json.loads(new)["points"][0]["value"] == 1.3          # A is the start
    [line] = _notices(err)
    assert "--param --from --to are deprecated" in line and "--range NAME=LO:HI" in line


def test_sweep_old_and_new_ranges_store_the_same_diagram(tmp_path):
    argv = ["sweep", *PRESET, "--impacts", "20", "--transient", "50", "--json"]
    rc, out, err = cli(*argv, "--range", "omega=0.73:0.745:3", "--out", tmp_path / "a.npz")
    assert rc == 0 and _notices(err) == [], err
    assert json.loads(out)["steps"] == 3 and json.loads(out)["omega_max"] == 0.745
    rc, _, err = cli(*argv, "--omega-min", "0.73", "--omega-max", "0.745", "--steps", "3",
                     "--out", tmp_path / "b.npz")
    assert rc == 0 and len(_notices(err)) == 1 and "--steps" in err
    a, b = np.load(tmp_path / "a.npz"), np.load(tmp_path / "b.npz")
    assert np.array_equal(a["omegas"], b["omegas"]) and np.array_equal(a["section"],
                                                                       b["section"])


def test_plane_axes_old_and_new_forms_are_the_same_axis():
    from symvi.plane import parse_axis
    assert parse_axis("stop[2].gap=-0.6:-0.4:3", "--x") == parse_axis("stop[2].gap:-0.6:-0.4:3",
                                                                      "--x")
    assert_bad_input(cli("plane", *PRESET, "--x", "omega=0.7:0.8", "--y", "b=1.4:1.6:2",
                         "--impacts", "10", "--transient", "10", "--out", "p.zarr"),
                     "--x", "NAME=LO:HI:N")


@pytest.mark.parametrize("argv, words", [
    (["hopf", *PRESET, "--range", "omega=0.7:0.76", "--omega-min", "0.7"],
     ["--omega-min", "not with --range"]),
    (["hopf", *PRESET], ["--range", "omega=LO:HI"]),
    (["hopf", *PRESET, "--omega-min", "0.7"], ["--omega-max", "--omega-min"]),
    (["hopf", *PRESET, "--range", "b=0.7:0.76"], ["--range", "omega=LO:HI"]),
    (["curve", *PRESET, "--range", "omega=0.7:0.76:3", "--params", "omega,b"],
     ["--range", "no :N"]),
    (["continue", *PRESET, "--range", "zeta=1:2"], ["--range", "zeta"]),
    (["continue", *PRESET, "--range", "omega=0:1"], ["--range", "0.0001"]),
    (["sweep", *PRESET, "--range", "omega=0.7:0.76", "--out", "x.npz"],
     ["--range", ":N is missing"]),
    (["sweep", *PRESET, "--range", "omega=0.7:0.76:3", "--steps", "3", "--out", "x.npz"],
     ["--steps", "not with --range"]),
])
def test_range_mistakes_are_one_line(argv, words, tmp_path):
    assert_bad_input(cli(*argv, cwd=tmp_path), *words)
    assert list(tmp_path.iterdir()) == []


class _Terminal:
    """A stdout that says it is a terminal."""

    def __init__(self, buf):
        self.buf = buf

    def write(self, s):
        return self.buf.write(s)

    def flush(self):
        pass

    def isatty(self):
        return True


def _on_terminal(*argv):
    import contextlib
    import io

    from symvi.cli import main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(_Terminal(out)), contextlib.redirect_stderr(err):
        rc = main([str(a) for a in argv])
    return rc, out.getvalue(), err.getvalue()


def test_simulate_prints_text_on_a_terminal_json_with_json_and_for_scripts(tmp_path):
    argv = ["simulate", *PRESET, "--omega", "0.75", "--impacts", "300", "--classify"]
    rc, text, err = _on_terminal(*argv, "--out", tmp_path / "a.npz")
    assert rc == 0 and err == "", err
    assert text.startswith("model: mu_m=2") and "attractor: " in text
    assert "Lyapunov exponents (per impact): " in text and "{" not in text
    rc, js, err = _on_terminal(*argv, "--out", tmp_path / "b.npz", "--json")
    assert rc == 0 and err == "" and json.loads(js)["class"]
    # a script (not a terminal) without --json: JSON for one release, and a notice
    rc, js2, err = cli(*argv, "--out", tmp_path / "c.npz")
    assert json.loads(js2)["lyapunov"] == json.loads(js)["lyapunov"]
    [line] = _notices(err)
    assert "add --json to keep JSON" in line


def test_sweep_prints_text_on_a_terminal(tmp_path):
    rc, text, err = _on_terminal("sweep", *PRESET, "--range", "omega=0.73:0.745:3",
                                 "--impacts", "20", "--transient", "50", "--branches",
                                 "--out", tmp_path / "a.npz")
    assert rc == 0 and err == "", err
    assert "3 omega values in [0.73, 0.745]" in text and "runs ended: completed 3" in text
    assert "ns       omega = 0.736876922" in text and "{" not in text


def test_a_long_continuation_shows_a_counting_bar_and_a_short_one_nothing(monkeypatch):
    """Issue 26: a bar once a wait exceeds ~2 s (progress.DELAY), counting the engine's
    points; nothing before that, and nothing outside a counting block."""
    import io

    import symvi.progress as progress
    from symvi import Model
    from symvi.continuation import continue_orbits
    model = Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    for delay, shows in ((0.0, True), (60.0, False)):
        monkeypatch.setattr(progress, "DELAY", delay)
        err = io.StringIO()
        with progress.counting("continuing in omega", stream=err, enabled=True) as bar:
            branches = continue_orbits(model, "omega", 1.3, 1.2, max_points=30)
            counted = bar.n
        # every accepted point after each branch's start
        assert counted == sum(len(br) - 1 for br in branches) > 0
        assert ("continuing in omega" in err.getvalue()) == shows, err.getvalue()
    progress.tick()                                # no bar: nothing happens
