"""``symvi continue``: the JSON contract, plots, starts from a simulation, one-line errors."""
import json
from types import SimpleNamespace

import numpy as np

import symvi

from symvi.cli import main
from symvi.model import dumps

from tests.zoo import ONE_DAMPED_GAP0
from ..fuzz._cli import cli

PRESET = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]


def _run(*args):
    """``symvi ARGS`` in this process (tests/fuzz/_cli.py), as (returncode, stdout, stderr)."""
    rc, out, err = cli(*args)
    return SimpleNamespace(returncode=rc, stdout=out, stderr=err)


def test_json_contract_and_plot(tmp_path, capsys):
    png = tmp_path / "b.png"
    assert main(["continue", *PRESET, "--range", "omega=1.3:1.1",
                 "--json", "--plot", str(png)]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["param"] == "omega"
    pt = d["points"][0]
    assert set(pt) >= {"value", "y", "multipliers", "stable", "admissible"}
    assert len(pt["y"]) == 4 and len(pt["multipliers"]) == 4
    kinds = {s["kind"] for s in d["special"]}
    assert {"flip", "ns"} <= kinds
    for s in d["special"]:
        assert set(s) >= {"kind", "value", "y", "multipliers", "coefficients", "detail"}
    ns = [s for s in d["special"] if s["kind"] == "ns"][0]
    assert abs(ns["value"] - 1.12405893783818) < 1e-9 and ns["coefficients"]["l1"] < 0
    assert png.stat().st_size > 10000


def test_model_file_other_parameter_and_switch(tmp_path, capsys):
    f = tmp_path / "one.toml"
    f.write_text(dumps(ONE_DAMPED_GAP0))
    assert main(["continue", "--model", str(f), "--range", "omega=2.0:3.0", "--switch", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    orbits = [b["orbit"] for b in d["branches"]]
    assert orbits[0] == "1-1" and "2-2" in orbits
    assert main(["continue", "--model", str(f), "--range", "restitution=0.8:0.6", "--set", "omega=2.5", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["param"] == "restitution" and d["points"][-1]["value"] <= 0.8


def test_from_section_starts_on_the_simulated_orbit(tmp_path, capsys):
    f = tmp_path / "one.toml"
    f.write_text(dumps(ONE_DAMPED_GAP0))
    npz = tmp_path / "s.npz"
    assert main(["simulate", "--model", str(f), "--omega", "2.69", "--impacts", "200",
                 "--transient", "3000", "--out", str(npz)]) == 0
    capsys.readouterr()
    assert main(["continue", "--model", str(f), "--range", "omega=2.66:2.72", "--from-section", str(npz), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert all(b["orbit"] == "2-2" for b in d["branches"])
    sec = np.load(npz)["section"]
    start = [p for p in d["points"] if abs(p["value"] - 2.69) < 1e-12][0]
    assert min(np.max(np.abs(np.array(start["y"]) - s)) for s in sec[-2:]) < 1e-8


def test_errors_are_one_line_exit_2(tmp_path):
    bad = [["--range", "nonsense=1:2", "--set", "omega=1"],
           ["--range", "omega=1.3:1.1", "--orbit", "x-1"],
           ["--range", "b=1.4:1.6"],
           ["--range", "omega=1.3:1.1", "--set", "b"],
           ["--range", "omega=1.3:1.1", "--from-section",
            str(tmp_path / "missing.npz")]]
    for args in bad:
        r = _run("continue", *PRESET, *args)
        assert r.returncode == 2, (args, r.stderr)
        assert r.stderr.count("\n") == 1 and r.stderr.startswith("symvi: error:"), r.stderr
        assert "Traceback" not in r.stderr


def test_sweep_overlays_the_branches(tmp_path, capsys):
    png = tmp_path / "bif.png"
    assert main(["sweep", *PRESET, "--range", "omega=0.70:0.76:12",
                 "--impacts", "20", "--transient", "200", "--out", str(png), "--branches",
                 "--progress", "never"]) == 0
    d = json.loads(capsys.readouterr().out)
    got = {(s["kind"], s["orbit"]): s["value"] for s in d["special"]}
    res = symvi.hopf_points(symvi.Model.luo_xie(2, 5, 0, 1.5, 0.8), 0.70, 0.76)
    flip = [e.omega for e in res.events if e.kind == "multiplier-1"]
    assert abs(got[("flip", "1-1")] - flip[0]) < 1e-10
    assert abs(got[("ns", "1-1")] - res.points[0].omega_c) < 1e-10
    assert ("flip", "2-2") in got or ("grazing", "2-2") in got     # the doubled branch
    assert png.stat().st_size > 10000


def test_no_start_orbit_names_the_reason():
    """A start where no period-1 orbit exists (the stop mass's anti-resonance): one line
    naming --range, with the reason."""
    from tests.fuzz._cli import assert_bad_input, cli
    line = assert_bad_input(cli("continue", "--mu-m", "0.3333333333333333", "--mu-k",
                                "0.3333333333333333", "--f2", "0", "--b", "1.5", "--r", "0.8",
                                "--range", "omega=2:2.1"), "--range")
    assert "anti-resonance" in line


def test_from_section_of_a_run_that_sticks_continues_the_sticking_orbit(tmp_path, capsys):
    """symvi simulate --out keeps the sticking phases (sticks, hits); symvi continue
    --from-section then solves and continues the orbit with a sticking phase, whose release
    phase is pi - asin(k gap / P) for one mass, to the held phase's end."""
    model = symvi.Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
                        stop=symvi.Stop(mass=1, gap=0.2, restitution=0.5))
    f = tmp_path / "held.toml"
    f.write_text(dumps(model))
    npz = tmp_path / "held.npz"
    assert main(["simulate", "--model", str(f), "--omega", "0.5", "--y0", "-0.5", "0",
                 "--impacts", "2000", "--out", str(npz), "--json"]) == 0
    capsys.readouterr()
    saved = np.load(npz)
    assert saved["sticks"].shape[1] == 3 and len(saved["hits"]) == len(saved["t"])
    assert main(["continue", "--model", str(f), "--range", "omega=0.5:0.7",
                 "--from-section", str(npz), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    (br,) = d["branches"]
    assert "held phase vanishes" in br["end"]
    first = min(d["points"], key=lambda p: abs(p["value"] - 0.5))
    assert abs(first["value"] - 0.5) < 1e-12
    assert first["signature"] == "1-0+stick"
    assert abs(first["y"][-1] - (np.pi - np.arcsin(0.2))) < 1e-9


def test_a_model_with_nonlinear_forces_continues(tmp_path, capsys):
    """[model] nonlinear and [model.parameters]: the branch of a Duffing impact oscillator
    in omega and in its named parameter, with its flip (issue 28)."""
    from symvi import Model, Stop
    m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.0, restitution=0.8), nonlinear=["beta*x1**3"],
              parameters={"beta": 0.2})
    f = tmp_path / "duffing.toml"
    f.write_text(dumps(m))
    assert main(["continue", "--model", str(f), "--range", "omega=2.6:2.8", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    flips = [s for s in d["special"] if s["kind"] == "flip"]
    assert len(flips) == 1 and abs(flips[0]["value"] - 2.74735426190) < 1e-9
    assert main(["continue", "--model", str(f), "--range", "beta=0.2:0.1", "--set",
                 "omega=2.7", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["param"] == "beta" and len(d["points"]) > 5
