"""Benchmark of parameter planes on Dask (issue 14).

Targets (the issue): a 256 x 256 plane of the paper model with 3000 impacts per point
(1000 transient + 2000 kept; about 2e8 impacts) on this 2-core machine with the local
cluster in <= 5 min; two workers >= 1.8 x one worker; Dask's overhead against the bare
compiled batch <= 15 % at this size.

Measured in one run, as ratios against baselines of the same run:

* ``dask-2``: ``symvi plane`` 256 x 256 on a local cluster of 2 worker processes, from
  start to the last row written (cluster start-up, zarr writes included);
* ``bare-2``: the same blocks (``compute_block``: inputs + the compiled batch) in a
  plain ``multiprocessing`` pool of 2 processes, results kept in memory: no Dask, no store;
  overhead = dask-2 / bare-2 - 1;
* ``dask-1`` and ``dask-2`` on a 128 x 128 plane: the speed-up of the second worker.

    python benchmarks/bench_plane.py > benchmarks/results_plane.md
"""
import argparse
import json
import multiprocessing as mp
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from symvi.model import Model  # noqa: E402
from symvi.plane import PlaneSpec, parse_axis, run_plane  # noqa: E402
from symvi.plane.engine import compute_block  # noqa: E402

PAPER = Model.luo_xie(2, 5, 0, 1.5, 0.8)


def spec(n, impacts=2000, transient=1000):
    # example 1 over its NS point, flips and chaos: omega 0.65..0.80, b 1.0..2.0
    return PlaneSpec(model=PAPER, x=parse_axis(f"omega:0.65:0.80:{n}", "x"),
                     y=parse_axis(f"b:1.0:2.0:{n}", "y"), impacts=impacts,
                     transient=transient)


def _block(args):
    return compute_block(*args)


def bare(sp, procs):
    text = json.dumps(sp.as_dict(), sort_keys=True)
    t = time.perf_counter()
    ctx = mp.get_context("spawn")            # as Dask's nannies start their workers
    with ctx.Pool(procs) as pool:
        res = pool.map(_block, [(text, r0, r1) for r0, r1 in sp.blocks()], chunksize=1)
    dt = time.perf_counter() - t
    return dt, np.concatenate([r["attractor"] for r in res])


def dask(sp, workers, folder):
    out = os.path.join(folder, f"plane-{sp.x.n}-{workers}.zarr")
    t = time.perf_counter()
    run = run_plane(sp, out, workers=workers, progress=False)
    dt = time.perf_counter() - t
    from symvi.plane import PlaneStore
    lab = np.asarray(PlaneStore.read(out).dataset()["attractor"])
    shutil.rmtree(out)
    return dt, lab, run


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--n-scale", type=int, default=128)
    args = ap.parse_args()
    folder = tempfile.mkdtemp(prefix="bench-plane-")
    try:
        # warm the numba cache (compiled once, loaded by every process)
        run_plane(spec(8, 20, 20), os.path.join(folder, "warm.zarr"), workers=0,
                  progress=False)
        big = spec(args.n)
        t_d2, lab_d2, run = dask(big, 2, folder)
        t_b2, lab_b2 = bare(big, 2)
        assert np.array_equal(lab_d2, lab_b2), "Dask and the bare batch disagree"
        small = spec(args.n_scale)
        t_s1, lab1, _ = dask(small, 1, folder)
        t_s2, lab2, _ = dask(small, 2, folder)
        assert np.array_equal(lab1, lab2)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    n_imp = big.x.n * big.y.n * (big.impacts + big.transient)
    print("# Parameter plane on Dask (issue 14)\n")
    print(f"Command: `python benchmarks/bench_plane.py` ({time.strftime('%Y-%m-%d %H:%M')}, "
          f"{os.cpu_count()} cores). Plane: the paper's example 1, omega 0.65..0.80 x "
          f"b 1.0..2.0, {big.transient} transient + {big.impacts} kept impacts per point.\n")
    print("| run | points | impacts (requested) | seconds | impacts/s |")
    print("|---|---|---|---|---|")
    print(f"| dask, 2 workers (local cluster, zarr) | {args.n}x{args.n} | {n_imp:.3g} | "
          f"{t_d2:.1f} | {n_imp / t_d2:.3g} |")
    print(f"| bare batch, 2 processes (no Dask) | {args.n}x{args.n} | {n_imp:.3g} | "
          f"{t_b2:.1f} | {n_imp / t_b2:.3g} |")
    n_s = small.x.n * small.y.n * (small.impacts + small.transient)
    print(f"| dask, 1 worker | {args.n_scale}x{args.n_scale} | {n_s:.3g} | {t_s1:.1f} | "
          f"{n_s / t_s1:.3g} |")
    print(f"| dask, 2 workers | {args.n_scale}x{args.n_scale} | {n_s:.3g} | {t_s2:.1f} | "
          f"{n_s / t_s2:.3g} |")
    print()
    print(f"- 256 x 256 in {t_d2:.0f} s (target <= 300 s): "
          f"{'met' if t_d2 <= 300 else 'NOT met'}.")
    print(f"- Dask overhead against the bare batch: {100 * (t_d2 / t_b2 - 1):+.1f} % "
          f"(target <= 15 %).")
    print(f"- Two workers against one: {t_s1 / t_s2:.2f} x (target >= 1.8).")
    cnt = {str(k): int(v) for k, v in zip(*np.unique(lab_d2, return_counts=True))}
    print(f"- Attractors of the 256 x 256 plane: {cnt}.")


if __name__ == "__main__":
    main()
