"""`symvi hopf`: table, JSON contract, bad input."""
import json
import subprocess
import sys

import pytest

BASE = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]


def run(*args):
    return subprocess.run([sys.executable, "-m", "symvi", "hopf", *args], capture_output=True,
                          text=True)


@pytest.mark.slow
def test_json_contract():
    r = run(*BASE, "--range", "omega=0.70:0.76", "--json")
    assert r.returncode == 0, r.stderr
    obj = json.loads(r.stdout)
    assert {"params", "points", "events"} <= set(obj)
    (pt,) = obj["points"]
    assert {"omega_c", "multiplier", "theta_over_2pi", "dmod_domega", "dmod_domega_branch", "l1",
            "f1_paper", "f1_wan", "kind", "h1", "h2", "nearest_resonance", "orbit",
            "circle"} <= set(pt)
    assert pt["kind"] == "supercritical" and abs(pt["omega_c"] - 0.736876922090593) < 1e-12


def test_table(capsys):
    from symvi.cli import main
    assert main(["hopf", *BASE, "--range", "omega=0.70:0.76"]) == 0
    out = capsys.readouterr().out
    assert "omega_c = 0.73687692209059" in out and "supercritical" in out
    assert "multiplier-1" in out


@pytest.mark.parametrize("args,word", [
    (["--range", "omega=0.76:0.70"], "--range"),
    (["--range", "omega=nan:0.70"], "--range"),
    (["--range", "omega=1e-300:0.70"], "--range"),
    (["--omega-min", "0.76", "--omega-max", "0.70"], "--omega-max"),   # the deprecated form
    (["--omega-min", "1e-300", "--omega-max", "0.70"], "--omega-min"),
    (["--range", "omega=0.7:0.76", "--digits", "5"], "--digits"),
    # an end at a natural frequency (inside the interval it is cut: test_hopf_conservative_resonance)
    (["--range", "omega=0.7:0.8804857344718374"], "omega_1"),
])
def test_bad_input(args, word, capsys):
    from symvi.cli import main
    assert main(["hopf", *BASE, *args]) == 2
    err = capsys.readouterr().err
    assert word in err and "Traceback" not in err


def test_table_cautions_when_hypotheses_fail(capsys):
    """At b = 2.8016416356 the ex. 1 Hopf point has lambda1^3 ~ 1 (stress.py, m = 3) and a
    multiplier outside the unit circle: the table must say the normal form does not apply."""
    from symvi.cli import main
    assert main(["hopf", "--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "2.8016416356",
                 "--r", "0.8", "--range", "omega=0.66:0.69"]) == 0
    out = capsys.readouterr().out
    assert "(H2) NO" in out and "strong resonance 1:3" in out
    assert "(H1) NO" in out and "caution: (H1) fails" in out
    # the circle of the normal form is no prediction when its hypotheses fail (issue 23, 14)
    assert "circle (stable" not in out and "circle (unstable" not in out
    assert "circle: not predicted ((H1) fails" in out and "(H2) fails" in out


def test_table_prints_the_circle_when_its_hypotheses_hold(capsys):
    from symvi.cli import main
    assert main(["hopf", *BASE, "--range", "omega=0.70:0.76"]) == 0
    out = capsys.readouterr().out
    assert "circle (stable, omega > omega_c): radius 4.92278 sqrt|mu|" in out
    assert "not predicted" not in out and "NOT certified" not in out


def test_table_has_no_caution_when_hypotheses_hold(capsys):
    from symvi.cli import main
    assert main(["hopf", *BASE, "--range", "omega=0.70:0.76"]) == 0
    assert "caution" not in capsys.readouterr().out
