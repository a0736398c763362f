"""``--model FILE`` on the command line: orbits of any model, one-line errors, exit 2."""
import json
import subprocess
import sys

import pytest

from symvi.cli import main
from symvi.model import dumps

from ..nmodel.models import PAPER, THREE


def _run(*args):
    return subprocess.run([sys.executable, "-m", "symvi", *args], capture_output=True, text=True)


def test_orbit_json_for_a_model_file(tmp_path, capsys):
    f = tmp_path / "m.toml"
    f.write_text(dumps(THREE))
    assert main(["orbit", "--model", str(f), "--omega", "0.95", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    o = [x for x in d["orbits"] if x["admissible"]][0]
    assert o["names"] == ["v2+", "x1", "x3", "v1", "v3", "tau"] and len(o["y"]) == 6
    assert o["y"][0] < 0 and len(o["multipliers"]) == 6


def test_preset_through_a_model_file_gives_the_preset_numbers(tmp_path, capsys):
    f = tmp_path / "p.toml"
    f.write_text(dumps(PAPER))
    main(["orbit", "--model", str(f), "--omega", "0.7369", "--json"])
    new = json.loads(capsys.readouterr().out)["orbits"]
    main(["orbit", "--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8",
          "--omega", "0.7369", "--json"])
    old = json.loads(capsys.readouterr().out)["orbits"]
    for a, b in zip(new, old):
        assert a["branch"] == b["branch"]
        assert max(abs(x - y) for x, y in zip(a["y"], b["y"])) < 1e-12
        assert b["names"] == ["x1dot+", "x20", "x20dot", "tau0"]


@pytest.mark.parametrize("text,key", [("[model]\nmass = [1.0\n", "malformed TOML"),
                                      ("[model]\nmass=[1.0]\nstiffness=[[1.0]]\n"
                                       "forcing=[1.0]\n[stop]\nmass=2\ngap=1\nrestitution=0.5\n",
                                       "[stop] mass")])
def test_bad_model_file_is_one_line_exit_2(tmp_path, text, key):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    r = _run("orbit", "--model", str(f), "--omega", "1.0")
    assert r.returncode == 2 and r.stdout == ""
    assert len(r.stderr.strip().splitlines()) == 1 and key in r.stderr and str(f) in r.stderr


def test_model_and_preset_flags_are_exclusive(tmp_path):
    f = tmp_path / "m.toml"
    f.write_text(dumps(THREE))
    r = _run("orbit", "--model", str(f), "--b", "2", "--omega", "1.0")
    assert r.returncode == 2 and "--model" in r.stderr
    r = _run("orbit", "--omega", "1.0")
    assert r.returncode == 2 and "--mu-m" in r.stderr
