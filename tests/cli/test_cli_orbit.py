"""`symvi orbit` and bad input on the command line."""
import json
import subprocess
import sys
from types import SimpleNamespace

import pytest

from ..fuzz._cli import cli

BASE = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]


def run(*args):
    """``symvi ARGS`` in this process (tests/fuzz/_cli.py), as (returncode, stdout, stderr)."""
    rc, out, err = cli(*args)
    return SimpleNamespace(returncode=rc, stdout=out, stderr=err)


def run_process(*args):
    """``python -m symvi ARGS``: the entry point itself."""
    return subprocess.run([sys.executable, "-m", "symvi", *args], capture_output=True, text=True)


def test_orbit_json_contract():
    r = run_process("orbit", *BASE, "--omega", "0.7369", "--json")
    assert r.returncode == 0, r.stderr
    obj = json.loads(r.stdout)
    assert set(obj) == {"params", "omega", "orbits"}
    keys = {"branch", "v1_plus", "x20", "x20_dot", "tau0", "impact_velocity", "admissible",
            "reason", "multipliers", "stable"}
    assert {o["branch"] for o in obj["orbits"]} == {"+", "-"}
    for o in obj["orbits"]:
        assert set(o) == keys | {"precision", "y", "names"}   # issue 11 adds y, names
        assert o["precision"]["y"]["trusted"] and o["precision"]["y"]["digits"] >= 8
        assert len(o["multipliers"]) == 4 and all(len(z) == 2 for z in o["multipliers"])


def test_orbit_table():
    r = run("orbit", *BASE, "--omega", "0.7369")
    assert r.returncode == 0
    assert "INADMISSIBLE" in r.stdout and "multipliers" in r.stdout


@pytest.mark.parametrize("args,word", [
    (["--mu-m", "-2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8", "--omega", "0.7"], "mu_m"),
    (BASE + ["--omega", "nan"], "omega"),
    (BASE + ["--omega", "abc"], "omega"),
    (BASE + ["--omega", "0"], "omega"),
    (["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "1.5", "--omega", "0.7"], "r"),
    (["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "inf", "--r", "0.8", "--omega", "0.7"], "b"),
    (BASE + ["--omega", "0.8804857344718374"], "resonance"),
    (BASE, "omega"),
])
def test_bad_input_exits_2_with_one_line(args, word):
    r = run("orbit", *args)
    assert r.returncode == 2
    assert r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and word in lines[0]


def test_precision_line_prints_complex_multipliers(capsys):
    """Issue 23 (14): the precision line printed only the real parts of the multipliers."""
    import re

    from symvi.cli import main
    assert main(["orbit", *BASE, "--omega", "0.73"]) == 0
    lines = capsys.readouterr().out.splitlines()
    mult = [ln for ln in lines if ln.strip().startswith("multipliers:")]
    prec = [ln for ln in lines if ln.strip().startswith("precision:")]
    assert len(mult) == len(prec) == 2
    for m, p in zip(mult, prec):
        shown = [complex(s.replace("i", "j")) for s in m.split(":", 1)[1].split(", ")]
        text = re.search(r"multipliers = (.*?)  \(", p).group(1)
        estimated = [complex(s.replace("i", "j")) if s.endswith("i") else complex(float(s))
                     for s in text.split(", ")]
        assert len(estimated) == len(shown) == 4
        for a, b in zip(estimated, shown):
            assert abs(a - b) < 1e-7, (a, b)       # imaginary parts included
        assert any(z.imag != 0 for z in estimated)


def test_no_orbit_names_the_reason():
    """At the stop mass's anti-resonance the answer is 'no orbit', with the reason (was
    ZeroDivisionError; before that, 'discriminant of eq. (16) negative')."""
    from tests.fuzz._cli import cli
    pre = ["--mu-m", "0.3333333333333333", "--mu-k", "0.3333333333333333", "--f2", "0",
           "--b", "1.5", "--r", "0.8", "--omega", "2"]
    rc, out, err = cli("orbit", *pre)
    assert rc == 0 and err == "", err
    assert "anti-resonance" in out and "discriminant" not in out
    rc, out, _ = cli("orbit", *pre, "--json")
    import json
    d = json.loads(out)
    assert rc == 0 and d["orbits"] == [] and "anti-resonance" in d["reason"]


def test_orbit_of_a_nonlinear_model(tmp_path):
    """Issue 28: the period-1 orbits the homotopy from the linear part reaches, each with
    its origin; the list is said not to be complete; JSON carries the same."""
    f = tmp_path / "duffing.toml"
    f.write_text('[model]\nmass = [1.0]\nstiffness = [[1.0]]\ndamping = [[0.05]]\n'
                 'forcing = [1.0]\nnonlinear = ["beta*x1**3"]\n[model.parameters]\n'
                 'beta = 0.2\n[stop]\nmass = 1\ngap = 0.0\nrestitution = 0.8\n')
    r = run("orbit", "--model", str(f), "--omega", "2.6")
    assert r.returncode == 0, r.stderr
    assert "3 period-1 one-impact orbit(s)" in r.stdout and "not complete" in r.stdout
    assert r.stdout.count("from the linear branch +") == 3
    assert "note: linear branch -: not followed" in r.stdout
    j = run("orbit", "--model", str(f), "--omega", "2.6", "--json")
    obj = json.loads(j.stdout)
    assert len(obj["orbits"]) == 3 and [o["stable"] for o in obj["orbits"]].count(True) == 2
    assert all(o["origin"] == "linear branch +" for o in obj["orbits"]) and obj["notes"]
