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
    rc = main(["sweep", *EX1, "--range", "omega=0.73:0.745:12",
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
    ["sweep", *EX1, "--range", "omega=0.75:0.74:5", "--out", "x.npz"],
    ["sweep", *EX1, "--range", "omega=0.73:0.74:1", "--out", "x.npz"],
    ["sweep", *EX1, "--range", "omega=0.73:0.74:5", "--out", "x.txt"],
])
def test_bad_input_one_line_exit_2(argv, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        raise SystemExit(main(argv))
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("symvi: error:") and err.count("\n") == 1
    assert not list(tmp_path.iterdir())


# ------------------------------------------------------------------ issue 23 (items 8, 13, 14)
from tests.fuzz._cli import assert_bad_input, cli, snapshot  # noqa: E402


def test_classify_needs_enough_impacts(tmp_path):
    from symvi.cli.simulate import MIN_CLASSIFY
    from symvi.simulations import diagnostics
    assert MIN_CLASSIFY == diagnostics.MIN_CLASSIFY
    line = assert_bad_input(cli("simulate", *EX1, "--omega", "0.7372", "--impacts", "3",
                                "--classify", "--out", tmp_path / "c.npz"),
                            "--impacts", "too few impacts to classify", str(MIN_CLASSIFY))
    assert "3" in line and not list(tmp_path.iterdir())


def test_classify_of_a_short_run_says_so():
    from symvi.simulations.diagnostics import MIN_CLASSIFY, classify
    from symvi.simulations.simulation import simulate
    sim = simulate(symvi_params(), 0.73, n_impacts=MIN_CLASSIFY - 1, transient=100)
    cl = classify(sim)
    assert cl.kind.startswith("too few impacts") and cl.lyapunov is None


def symvi_params():
    import symvi
    return symvi.Params(2, 5, 0, 1.5, 0.8)


def test_classify_json_has_lyapunov_for_a_periodic_orbit(tmp_path):
    rc, out, err = cli("simulate", *EX1, "--omega", "0.73", "--impacts", "200",
                       "--transient", "3000", "--classify", "--out", tmp_path / "p.npz")
    assert rc == 0, err
    got = json.loads(out)
    assert got["class"] == "period-1"
    assert got["attractor"] == "period-1" and got["impacts_per_orbit"] == 1
    # the exponents of a period-1 orbit are log |multipliers|: their sum converges at
    # once (log |det DP| along the orbit), each one more slowly
    from symvi.paper.orbit import period1_orbits
    orb = [o for o in period1_orbits(symvi_params(), 0.73) if o.admissible][0]
    logs = np.sort(np.log(np.abs(np.array(orb.multipliers, dtype=complex))))[::-1]
    lya = np.array(got["lyapunov"])
    assert len(lya) == 4 and lya.max() < 0
    assert abs(lya.sum() - logs.sum()) < 1e-6 * abs(logs.sum())
    assert np.abs(lya - logs).max() < 0.03        # ~ 1/n over n = 200 impacts


def test_out_names_a_figure_or_another_extension(tmp_path):
    before = snapshot(tmp_path)
    assert_bad_input(cli("simulate", *EX1, "--omega", "0.7372", "--impacts", "20",
                         "--out", tmp_path / "s.png"), "--out", ".npz", "--plot")
    assert snapshot(tmp_path) == before
    rc, out, err = cli("simulate", *EX1, "--omega", "0.7372", "--impacts", "20",
                       "--out", tmp_path / "legacy-name.dat")
    assert rc == 0 and "deprecated" in err and "legacy-name.dat" in err
    assert np.load(tmp_path / "legacy-name.dat")["section"].shape == (20, 4)


def test_full_disk_while_saving_is_one_line_and_keeps_the_old_file(tmp_path, monkeypatch):
    import errno
    import os
    out = tmp_path / "s.npz"
    out.write_bytes(b"an older result")

    def full(*a, **k):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(np, "savez", full)
    assert_bad_input(cli("simulate", *EX1, "--omega", "0.7372", "--impacts", "20",
                         "--out", out), "No space left", "s.npz")
    assert out.read_bytes() == b"an older result" and os.listdir(tmp_path) == ["s.npz"]


@pytest.mark.parametrize("argv,flag", [
    (["--range", "omega=0.73:0.74:100001"], "--range"),
    (["--range", "omega=0.73:0.74:100000", "--impacts", "200"], "--impacts"),
    (["--range", "omega=0.73:0.74:10", "--impacts", "0"], "--impacts"),
    (["--range", "omega=0.73:0.74:10", "--transient", "-1"], "--transient"),
    (["--omega-min", "0.73", "--omega-max", "0.74", "--steps", "100001"], "--steps"),
])
def test_sweep_sizes_bounded_before_allocating(tmp_path, argv, flag):
    assert_bad_input(cli("sweep", *EX1, *argv,
                         "--out", tmp_path / "s.npz"), flag)
    assert not list(tmp_path.iterdir())


def test_huge_start_is_refused_naming_the_flag(tmp_path):
    """--y0 -1e300 0 0 0 ran and stopped with 'grazing' (the finder's scale overflowed);
    now one line naming --y0 and the range."""
    from tests.fuzz._cli import assert_bad_input, cli
    line = assert_bad_input(cli("simulate", "--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b",
                                "1.5", "--r", "0.8", "--omega", "0.7372", "--impacts", "100",
                                "--y0", "-1e300", "0", "0", "0", "--out", tmp_path / "x.npz"), "--y0")
    assert "1e+06" in line and not (tmp_path / "x.npz").exists()
