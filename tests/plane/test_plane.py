"""Parameter planes (issue 14): Dask results equal the serial computation bit for bit;
interrupted, restarted and killed runs lose nothing; bad input is refused with the store
intact."""
import hashlib
import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import symvi
from symvi.cli import main
from symvi.plane import PlaneSpec, PlaneStore, compute_serial, parse_axis, run_plane

EX1 = dict(mu_m=2.0, mu_k=5.0, f2=0.0, b=1.5, r=0.8)
FLAGS = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]
VARS = ("attractor", "stop", "period", "impacts_per_orbit", "lyapunov", "rotation",
        "impacts_per_period", "max_velocity", "own_start")


def _spec(n=16, impacts=300, transient=300, **kw):
    # example 1 across its NS (omega ~ 0.737) and the period-1 region below it
    return PlaneSpec(model=symvi.Model.luo_xie(**EX1), x=parse_axis(f"omega:0.70:0.78:{n}", "x"),
                     y=parse_axis(f"b:1.3:1.7:{n}", "y"), impacts=impacts,
                     transient=transient, **kw)


def _same(ds, ref):
    for v in VARS:
        a, b = np.asarray(ds[v]), np.asarray(ref[v])
        if a.dtype.kind == "f":
            assert np.array_equal(a, b, equal_nan=True), v
            assert np.array_equal(a.view(np.int64), b.view(np.int64)), v      # bit for bit
        else:
            assert np.array_equal(a, b), v


def _files(path, skip=(".zattrs", ".zmetadata")):
    """sha256 of every file of a store (the root attrs, which hold the command, skipped)."""
    out = {}
    for root, _, files in os.walk(path):
        for f in files:
            rel = os.path.relpath(os.path.join(root, f), path)
            if rel in skip:
                continue
            with open(os.path.join(root, f), "rb") as fh:
                out[rel] = hashlib.sha256(fh.read()).hexdigest()
    return out


def test_dask_plane_equals_serial_bit_for_bit(tmp_path, cluster):
    _, client = cluster
    spec = _spec()
    run = run_plane(spec, tmp_path / "p.zarr", client=client, progress=False)
    assert run.computed == run.blocks == len(spec.blocks()) >= 8 and run.workers == 2
    ds = PlaneStore.read(tmp_path / "p.zarr").dataset()
    _same(ds, compute_serial(spec))
    assert ds["done"].all()
    # the plane is not trivial: it holds period-1 points and quasi-periodic ones
    labels = set(np.asarray(ds["attractor"]).ravel())
    assert "period-1" in labels and labels & {"circle", "doubled-torus", "chaos"}
    assert list(ds.coords) == ["b", "omega"] or set(ds.coords) == {"b", "omega"}
    assert np.allclose(ds["omega"], np.linspace(0.70, 0.78, 16))
    assert ds.attrs["x"] == "omega" and ds.attrs["y"] == "b"
    assert ds.attrs["symvi_version"] == symvi.__version__ and "mu_m" in ds.attrs["preset"]
    # a second run finds everything done and computes nothing
    again = run_plane(spec, tmp_path / "p.zarr", client=client, progress=False)
    assert again.computed == 0


def test_follow_rows_start_from_the_previous_attractor(tmp_path):
    spec = _spec(n=8, follow=True)
    run_plane(spec, tmp_path / "f.zarr", workers=0, progress=False)
    ds = PlaneStore.read(tmp_path / "f.zarr").dataset()
    _same(ds, compute_serial(spec))
    own = np.asarray(ds["own_start"])
    lab = np.asarray(ds["attractor"])
    bounded = np.isin(lab[:, :-1], ["circle", "doubled-torus", "chaos"]) | \
        np.char.startswith(lab[:, :-1].astype(str), "period-")
    assert not own[:, 1:][bounded].any()          # followed points did not start afresh


def test_killed_worker_loses_nothing(tmp_path):
    import logging

    from distributed import Client, LocalCluster
    spec = _spec(impacts=1500, transient=500, chunk_rows=1)
    out = tmp_path / "k.zarr"
    cl = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None, silence_logs=logging.CRITICAL)
    client = Client(cl, set_as_default=False)
    try:
        result = {}
        t = threading.Thread(target=lambda: result.update(
            run=run_plane(spec, out, client=client, progress=False)))
        t.start()
        deadline = time.time() + 60
        while time.time() < deadline and not (out.exists() and PlaneStore(out, spec).done().any()):
            time.sleep(0.02)
        nanny = next(iter(cl.workers.values()))
        os.kill(nanny.process.process.pid, signal.SIGKILL)       # a worker dies mid-run
        t.join(120)
        assert not t.is_alive() and "run" in result
    finally:
        client.close()
        cl.close()
    assert PlaneStore(out, spec).done().all()
    _same(PlaneStore.read(out).dataset(), compute_serial(spec))


def _cli_plane(out, *extra):
    return ["plane", *FLAGS, "--x", "omega:0.70:0.78:12", "--y", "b:1.3:1.7:12",
            "--impacts", "8000", "--transient", "500", "--chunk-rows", "1",
            "--out", str(out), *extra]


def _interrupt(args, out, sig):
    """Start ``symvi`` with args, send ``sig`` once a row is written; its exit code."""
    # a shell's background job (as CI may be) ignores SIGINT, and a child inherits that:
    # restore the default so that Python turns SIGINT into KeyboardInterrupt, as at a terminal
    p = subprocess.Popen([sys.executable, "-m", "symvi", *args], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.time() + 90
    while time.time() < deadline and p.poll() is None:
        try:
            if PlaneStore.read(out).done().any():
                break
        except Exception:   # noqa: BLE001 -- not created yet
            pass
        time.sleep(0.02)
    p.send_signal(sig)
    p.communicate(timeout=60)
    return p.returncode


@pytest.mark.slow
@pytest.mark.parametrize("sig,workers", [(signal.SIGINT, "1"), (signal.SIGKILL, "0")])
def test_interrupted_run_restarts_to_the_identical_store(tmp_path, capsys, sig, workers):
    out, ref = tmp_path / "i.zarr", tmp_path / "ref.zarr"
    rc = _interrupt(_cli_plane(out, "--workers", workers), out, sig)
    assert rc != 0
    spec = PlaneStore.read(out).spec
    done = PlaneStore(out, spec).done()
    assert done.any() and not done.all()                     # stopped part way
    assert main(_cli_plane(out, "--workers", workers, "--json")) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["resumed_blocks"] == int(done.sum()) and summary["computed_blocks"] > 0
    assert main(_cli_plane(ref, "--workers", "0", "--json")) == 0
    capsys.readouterr()
    assert _files(out) == _files(ref)                         # every chunk, byte for byte
    a, b = PlaneStore.read(out).dataset(), PlaneStore.read(ref).dataset()
    _same(a, b)
    assert {k: v for k, v in a.attrs.items() if k != "command"} == \
        {k: v for k, v in b.attrs.items() if k != "command"}


def test_real_scheduler_on_localhost(tmp_path, capsys):
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    addr = f"tcp://127.0.0.1:{port}"
    sched = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host",
                              "127.0.0.1", "--port", str(port), "--no-dashboard"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    work = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", addr,
                             "--nthreads", "1", "--nworkers", "1", "--no-dashboard"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        out = tmp_path / "s.zarr"
        args = ["plane", *FLAGS, "--x", "omega:0.70:0.78:8", "--y", "b:1.3:1.7:8",
                "--impacts", "300", "--transient", "300", "--out", str(out),
                "--scheduler", addr, "--json"]
        from distributed import Client
        with Client(addr, timeout=30, set_as_default=False) as c:
            c.wait_for_workers(1, timeout=60)          # the worker has registered
        rc = main(args)
        got = json.loads(capsys.readouterr().out)
        assert rc == 0 and got["workers"] == 1 and got["points"] == 64
        st = PlaneStore.read(out)
        _same(st.dataset(), compute_serial(st.spec))
    finally:
        for p in (work, sched):
            p.terminate()
            p.wait(30)


def _tree(path):
    return _files(path, skip=())


@pytest.mark.parametrize("args,key", [
    (["--x", "omega:0.8:0.7:8", "--y", "b:1.3:1.7:8"], "--x"),
    (["--x", "omega:0.7:0.8:0", "--y", "b:1.3:1.7:8"], "--x"),
    (["--x", "omega:0.7:0.8", "--y", "b:1.3:1.7:8"], "--x"),
    (["--x", "omega:0.7:0.8:8", "--y", "bb:1.3:1.7:8"], "--y"),
    (["--x", "omega:0.7:0.8:8", "--y", "omega:0.5:0.6:8"], "--y"),
    (["--x", "omega:0.7:0.8:8", "--y", "r:0.5:1.5:8"], "--y"),
    (["--x", "omega:0.7:0.8:8", "--y", "mu_m:-1:2:8"], "--y"),
    (["--x", "b:1:2:8", "--y", "r:0.5:0.9:8"], "--omega"),
    (["--x", "omega:0.7:0.8:8", "--y", "b:1.3:1.7:8", "--impacts", "0"], "--impacts"),
    (["--x", "omega:0.7:0.8:8", "--y", "b:1.3:1.7:8", "--impacts", "3"], "--impacts"),
    (["--x", "omega:0.7:0.8:8", "--y", "b:1.3:1.7:8", "--workers", "-1"], "--workers"),
])
def test_bad_input_one_line_exit_2_store_intact(tmp_path, capsys, args, key):
    out = tmp_path / "keep.zarr"
    good = ["plane", *FLAGS, "--x", "omega:0.7:0.8:4", "--y", "b:1.3:1.7:4", "--impacts",
            "20", "--transient", "20", "--workers", "0", "--out", str(out)]
    assert main(good) == 0
    before = _tree(out)
    capsys.readouterr()
    counts = [] if "--impacts" in args else ["--impacts", "20"]
    cmd = ["plane", *FLAGS, *counts, "--transient", "20", "--out", str(out), *args]
    assert main(cmd) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and key in err and "Traceback" not in err
    assert _tree(out) == before


def test_other_run_or_foreign_path_refused_intact(tmp_path, capsys):
    out = tmp_path / "p.zarr"
    base = ["plane", *FLAGS, "--x", "omega:0.7:0.8:4", "--y", "b:1.3:1.7:4", "--transient",
            "20", "--workers", "0", "--out", str(out)]
    assert main([*base, "--impacts", "20"]) == 0
    before = _tree(out)
    capsys.readouterr()
    assert main([*base, "--impacts", "30"]) == 2
    err = capsys.readouterr().err
    assert "--out" in err and "impacts" in err and _tree(out) == before
    f = tmp_path / "notes.txt"
    f.write_text("mine")
    assert main([*base[:-1], str(f), "--impacts", "20"]) == 2
    assert f.read_text() == "mine" and "not a folder" in capsys.readouterr().err
    d = tmp_path / "mine"
    d.mkdir()
    (d / "notes.txt").write_text("mine")
    assert main([*base[:-1], str(d), "--impacts", "20"]) == 2
    assert "not a symvi plane store" in capsys.readouterr().err
    assert os.listdir(d) == ["notes.txt"]
    assert sorted(os.listdir(tmp_path)) == ["mine", "notes.txt", "p.zarr"]   # no lock left


def test_unreachable_scheduler(tmp_path, capsys, monkeypatch):
    import symvi.plane.engine as eng
    monkeypatch.setattr(eng, "CONNECT_TIMEOUT", 2)
    out = tmp_path / "u.zarr"
    args = ["plane", *FLAGS, "--x", "omega:0.7:0.8:4", "--y", "b:1.3:1.7:4", "--impacts", "20",
            "--transient", "20", "--out", str(out), "--scheduler", "tcp://127.0.0.1:9"]
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--scheduler" in err
    assert not out.exists()                       # nothing half-made is left behind


def test_plot_draws_both_maps(tmp_path, capsys):
    out = tmp_path / "p.zarr"
    assert main(["plane", *FLAGS, "--x", "omega:0.70:0.78:8", "--y", "b:1.3:1.7:6",
                 "--impacts", "200", "--transient", "200", "--workers", "0",
                 "--out", str(out)]) == 0
    fig = tmp_path / "p.png"
    # --out is the old spelling of --plot: it works for a release, with a notice
    assert main(["plot", str(out), "--out", str(fig), "--no-curves", "--json"]) == 0
    cap = capsys.readouterr()
    got = json.loads(cap.out.strip().splitlines()[-1])
    assert fig.stat().st_size > 10_000 and got["rows_done"] == 6 and "--plot" in cap.err
    assert main(["plot", str(out), "--plot", str(fig), "--no-curves", "--json"]) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out.strip().splitlines()[-1])["plot"] == str(fig)
    assert "deprecated" not in cap.err
    assert main(["plot", str(tmp_path / "none.zarr"), "--plot", str(fig)]) == 2
    assert main(["plot", str(out), "--plot", str(tmp_path / "x.txt")]) == 2


def test_sweep_on_the_engine_equals_one_sweep(cluster):
    from symvi.plane.engine import run_sweep
    from symvi.simulations.simulation import sweep
    _, client = cluster
    p = symvi.Params(**EX1)
    om = np.linspace(0.70, 0.76, 24)
    ref = sweep(p, om, n_impacts=40, transient=200)
    for res in (run_sweep(p, om, n_impacts=40, transient=200, client=client, chunk=5),
                run_sweep(p, om, n_impacts=40, transient=200, workers=0)):
        assert np.array_equal(res.section, ref.section, equal_nan=True)
        assert res.stops == ref.stops and np.array_equal(res.counts, ref.counts)
