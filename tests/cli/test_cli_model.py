"""``--model FILE`` on the command line: orbits of any model, one-line errors, exit 2."""
import json
from types import SimpleNamespace

import pytest

from symvi.cli import main
from symvi.model import dumps

from ..fuzz._cli import cli
from tests.zoo import PAPER_EX1, THREE_STOP2_GAP05


def _run(*args):
    """``symvi ARGS`` in this process (tests/fuzz/_cli.py), as (returncode, stdout, stderr)."""
    rc, out, err = cli(*args)
    return SimpleNamespace(returncode=rc, stdout=out, stderr=err)


def test_orbit_json_for_a_model_file(tmp_path, capsys):
    f = tmp_path / "m.toml"
    f.write_text(dumps(THREE_STOP2_GAP05))
    assert main(["orbit", "--model", str(f), "--omega", "0.95", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    o = [x for x in d["orbits"] if x["admissible"]][0]
    assert o["names"] == ["v2+", "x1", "x3", "v1", "v3", "tau"] and len(o["y"]) == 6
    assert o["y"][0] < 0 and len(o["multipliers"]) == 6


def test_preset_through_a_model_file_gives_the_preset_numbers(tmp_path, capsys):
    f = tmp_path / "p.toml"
    f.write_text(dumps(PAPER_EX1))
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
    f.write_text(dumps(THREE_STOP2_GAP05))
    r = _run("orbit", "--model", str(f), "--b", "2", "--omega", "1.0")
    assert r.returncode == 2 and "--model" in r.stderr
    r = _run("orbit", "--omega", "1.0")
    assert r.returncode == 2 and "--mu-m" in r.stderr


def test_hopf_json_for_a_model_file(tmp_path, capsys):
    f = tmp_path / "m.toml"
    f.write_text(dumps(THREE_STOP2_GAP05))
    assert main(["hopf", "--model", str(f), "--range", "omega=0.99:1.02",
                 "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["model"]["stop"]["mass"] == 2 and len(d["points"]) == 1
    pt = d["points"][0]
    assert abs(pt["omega_c"] - 0.99971142245776) < 1e-9 and pt["l1"] < 0
    assert pt["orbit"]["names"][0] == "v2+"


def test_simulate_and_sweep_with_a_model_file(tmp_path, capsys):
    import numpy as np
    f = tmp_path / "m.toml"
    f.write_text(dumps(THREE_STOP2_GAP05))
    out = tmp_path / "s.npz"
    assert main(["simulate", "--model", str(f), "--omega", "0.95", "--impacts", "50",
                 "--transient", "3000", "--out", str(out)]) == 0
    d = json.loads(capsys.readouterr().out)
    z = np.load(out)
    assert z["section"].shape == (50, 6) and list(z["names"])[0] == "v2+"
    assert "[stop]" in str(z["model"]) and d["stop"] == "completed"
    # the stable period-1 orbit at 0.95 (|lambda| = 0.966): the run converges onto it
    from symvi.orbits import admissible_orbits
    y = np.array(admissible_orbits(THREE_STOP2_GAP05, 0.95)[0].y)
    assert np.abs(z["section"][-1] - y).max() < 1e-6
    sw = tmp_path / "sw.npz"
    assert main(["sweep", "--model", str(f), "--range", "omega=0.9:0.95:3", "--impacts", "10", "--transient", "100", "--out", str(sw),
                 "--progress", "never"]) == 0
    assert np.load(sw)["section"].shape == (3, 10, 6)


@pytest.mark.parametrize("args,name", [(["--y0", "1", "2", "3"], "--y0"),
                                       (["--component", "7"], "--component")])
def test_model_shaped_arguments_are_checked(tmp_path, args, name):
    f = tmp_path / "m.toml"
    f.write_text(dumps(THREE_STOP2_GAP05))
    cmd = ("simulate", "--omega", "0.95", "--out", str(tmp_path / "x.npz")) \
        if name == "--y0" else ("sweep", "--range", "omega=0.9:0.95:3", "--out", str(tmp_path / "x.npz"))
    r = _run(*cmd, "--model", str(f), *args)
    assert r.returncode == 2 and name in r.stderr and len(r.stderr.strip().splitlines()) == 1


TWO_STOPS = """[model]
mass = [1.0, 2.0]
stiffness = [[1.0, -1.0], [-1.0, 6.0]]
forcing = [1.0, 0.3]

[[stop]]
mass = 1
gap = 0.5
restitution = 0.8

[[stop]]
mass = 1
gap = -0.5
side = "lower"
restitution = 0.8
"""


def test_hopf_of_several_stops_says_it_is_not_certified(tmp_path):
    """A two-stop file: symvi hopf has no period-1 closed form to certify its scan with,
    so it scans the branches from the attractors it finds and says so; --digits (the
    mpmath chains of period-1 orbits of one stop) is refused in one line, exit 2."""
    f = tmp_path / "two.toml"
    f.write_text(TWO_STOPS)
    r = _run("hopf", "--model", str(f), "--range", "omega=0.9:1.1")
    assert r.returncode == 0 and "NOT CERTIFIED" in r.stdout
    r = _run("hopf", "--model", str(f), "--range", "omega=0.9:1.1",
             "--digits", "40")
    assert r.returncode == 2 and r.stdout == ""
    assert len(r.stderr.strip().splitlines()) == 1 and "Traceback" not in r.stderr
    assert "--digits" in r.stderr


def test_simulate_runs_several_stops(tmp_path):
    """simulate takes a two-stop file: a start is asked for (no period-1 orbit to start
    from), --classify judges the run (tests/simulations/test_classify_stops.py), and a run
    names the impacts on each stop (JSON) and the stop of each impact (the .npz's
    "hits")."""
    import numpy as np
    f = tmp_path / "two.toml"
    f.write_text(TWO_STOPS)
    out = tmp_path / "s.npz"
    base = ("simulate", "--model", str(f), "--omega", "1.1", "--impacts", "400",
            "--out", str(out))
    r = _run(*base)
    assert r.returncode == 2 and "--y0" in r.stderr and "closed form" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and not out.exists()
    r = _run(*base[:-1], str(tmp_path / "c.npz"), "--y0", "-0.3", "0.0", "0.0", "0.4",
             "--classify")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["class"] and not out.exists()
    r = _run(*base, "--y0", "-0.3", "0.0", "0.0", "0.4", "--plot", str(tmp_path / "s.png"))
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["stop"] == "completed" and d["n"] == 400
    per = d["impacts_per_stop"]
    assert len(per) == 2 and sum(per) == 400 and min(per) > 0
    z = np.load(out)
    assert np.array_equal(np.bincount(z["hits"], minlength=2), per)
    assert (tmp_path / "s.png").stat().st_size > 0
