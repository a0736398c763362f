"""``symvi curve``: the JSON contract (issue 13), the plot, one-line errors with exit 2."""
import json
from types import SimpleNamespace

import pytest

from symvi.cli import main

from ..fuzz._cli import cli

PRESET = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]
BASE = ["curve", *PRESET, "--range", "omega=0.70:0.76"]


def _run(*args):
    """``symvi ARGS`` in this process (tests/fuzz/_cli.py), as (returncode, stdout, stderr)."""
    rc, out, err = cli(*args)
    return SimpleNamespace(returncode=rc, stdout=out, stderr=err)


def test_json_contract_and_plot(tmp_path, capsys):
    png = tmp_path / "c.png"
    assert main([*BASE, "--params", "omega,r", "--bounds", "r=0.05:1", "--bounds",
                 "omega=0.5:1", "--max-points", "600", "--json", "--plot", str(png)]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["params"] == ["omega", "r"]
    pt = d["points"][0]
    assert set(pt) >= {"params", "theta", "l1", "admissible"}
    assert set(pt["params"]) == {"omega", "r"}
    kinds = [s["kind"] for s in d["special"]]
    assert kinds.count("CH") == 2 and {"R3", "R4"} <= set(kinds)
    for s in d["special"]:
        assert set(s) >= {"kind", "params", "coefficients", "detail"}
        if s["kind"] == "CH":
            assert "l2" in s["coefficients"] and s["coefficients"]["l2"] < 0
            assert abs(s["coefficients"]["l1"]) < 1e-12
    assert png.stat().st_size > 10000


def test_flip_curve_meets_the_ns_curve_at_the_same_pdns_point(capsys):
    assert main([*BASE, "--params", "omega,b", "--kind", "flip", "--bounds", "b=1.5:2.5",
                 "--bounds", "omega=0.5:1", "--json"]) == 0
    flip = json.loads(capsys.readouterr().out)
    assert flip["start"]["orbit"] == "1-1"
    assert main([*BASE, "--params", "omega,b", "--bounds", "b=1.5:2.5", "--bounds",
                 "omega=0.5:1", "--json"]) == 0
    ns = json.loads(capsys.readouterr().out)
    a = next(s for s in flip["special"] if s["kind"] == "PDNS")["params"]
    b = next(s for s in ns["special"] if s["kind"] == "PDNS")["params"]
    assert a["omega"] == pytest.approx(b["omega"], abs=1e-9)
    assert a["b"] == pytest.approx(b["b"], abs=1e-9)


@pytest.mark.parametrize("args, key", [
    (["--params", "omega"], "--params"),
    (["--params", "omega,omega"], "--params"),
    (["--params", "omega,zeta"], "zeta"),
    (["--params", "omega,b", "--bounds", "b=2:1"], "--bounds"),
    (["--params", "omega,b", "--bounds", "r=0:1"], "--bounds"),
    (["--params", "omega,b", "--plot", "x.txt"], "--plot"),
])
def test_bad_input_is_one_line_and_exit_2(args, key):
    r = _run(*BASE, *args)
    assert r.returncode == 2
    assert key in r.stderr and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_no_start_point_is_a_clear_error():
    r = _run("curve", *PRESET, "--range", "omega=1.3:1.31", "--params",
             "omega,b", "--kind", "fold")
    assert r.returncode == 2 and "no admissible fold point" in r.stderr
