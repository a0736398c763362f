"""``symvi simulate`` and ``symvi sweep`` end to end (in-process)."""
import json

import numpy as np
import pytest

from symvi.cli import main

EX1 = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]


def test_simulate_writes_npz_and_plot(tmp_path, capsys):
    out, png = tmp_path / "sec.npz", tmp_path / "sec.png"
    rc = main(["simulate", *EX1, "--omega", "0.7372", "--impacts", "2000", "--transient", "500",
               "--out", str(out), "--plot", str(png)])
    assert rc == 0
    res = json.loads(capsys.readouterr().out)
    assert res["stop"] == "completed" and res["n"] == 2000
    with np.load(out) as z:
        assert z["section"].shape == (2000, 4) and z["t"].shape == (2000,)
        assert (np.diff(z["t"]) > 0).all()
    assert png.stat().st_size > 1000
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".tmp-")]


def test_sweep_writes_diagram_and_data(tmp_path, capsys):
    npz, pdf = tmp_path / "sw.npz", tmp_path / "sw.pdf"
    rc = main(["sweep", *EX1, "--omega-min", "0.73", "--omega-max", "0.745", "--steps", "12",
               "--impacts", "50", "--transient", "500", "--out", str(npz), "--plot", str(pdf),
               "--progress", "always"])
    assert rc == 0
    cap = capsys.readouterr()
    assert "12/12" in cap.err                      # the progress bar went to stderr
    assert json.loads(cap.out)["stops"] == {"completed": 12}
    with np.load(npz) as z:
        assert z["section"].shape == (12, 50, 4)
    assert pdf.read_bytes()[:4] == b"%PDF"


@pytest.mark.parametrize("argv", [
    ["simulate", *EX1, "--omega", "-0.7", "--out", "x.npz"],
    ["simulate", *EX1, "--omega", "0.74", "--impacts", "0", "--out", "x.npz"],
    ["simulate", *EX1, "--omega", "0.74", "--out", "x.npz", "--plot", "x.gif"],
    ["simulate", *EX1, "--omega", "abc", "--out", "x.npz"],
    ["simulate", "--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "1.5",
     "--omega", "0.74", "--out", "x.npz"],
    ["sweep", *EX1, "--omega-min", "0.75", "--omega-max", "0.74", "--steps", "5", "--out", "x.npz"],
    ["sweep", *EX1, "--omega-min", "0.73", "--omega-max", "0.74", "--steps", "1", "--out", "x.npz"],
    ["sweep", *EX1, "--omega-min", "0.73", "--omega-max", "0.74", "--steps", "5", "--out", "x.txt"],
])
def test_bad_input_one_line_exit_2(argv, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        raise SystemExit(main(argv))
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("symvi: error:") and err.count("\n") == 1
    assert not list(tmp_path.iterdir())
