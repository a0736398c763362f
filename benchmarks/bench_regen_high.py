"""Benchmark of issue 13: regenerating orders 4-5 of the N = 2 structure (the
paper's model) against the baseline, orders 1-3 of N = 2, in the same run; the
stages of order 5 (series, composition, CSE and printing); the shipped sizes;
and the evaluation of ``high_jet`` against ``jet_at`` order 3.

Each regeneration runs in a fresh interpreter (SymPy's cache would otherwise
favour the later runs) through ``impact_jets.generate``, the function that
``symvi regenerate`` calls, into a temporary folder.

    python benchmarks/bench_regen_high.py [--reps 3] [--n3]

``--n3`` adds one on-demand regeneration of N = 3 orders 4-5 (about a minute).
"""
import argparse
import math
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_jets import md_table, median_time  # noqa: E402

CHILD_GENERATE = """
import sys, tempfile, time
from symvi._derivations import impact_jets as ij
n, orders = int(sys.argv[1]), tuple(int(k) for k in sys.argv[2].split(","))
with tempfile.TemporaryDirectory() as d:
    t = time.perf_counter()
    ij.generate(d, ns=(n,), orders=orders, force=True)
    print(time.perf_counter() - t)
"""

CHILD_STAGES = """
import sys, time
from symvi._derivations import impact_jets as ij
n, K = int(sys.argv[1]), int(sys.argv[2])
t0 = time.perf_counter()
ij.model(n, K)
t1 = time.perf_counter()
V_, defs, names, exprs = ij.build(n, K)      # model() again, then the composition
t2 = time.perf_counter()
ij.emit_body(ij.inputs(n, K), defs, exprs)
t3 = time.perf_counter()
print(t1 - t0, (t2 - t1) - (t1 - t0), t3 - t2)
"""


def child(code, *args):
    r = subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True,
                       text=True, check=True)
    return [float(v) for v in r.stdout.split()]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--n3", action="store_true")
    a = ap.parse_args()
    base, high = [], []
    for _ in range(a.reps):          # interleaved, so a slow spell of the host hits both
        base.append(child(CHILD_GENERATE, 2, "1,2,3")[0])
        high.append(child(CHILD_GENERATE, 2, "4,5")[0])
    tb, th = statistics.median(base), statistics.median(high)
    rows = [("regenerate N = 2, orders 1-3 (baseline)", f"{tb:.1f} s", ""),
            ("regenerate N = 2, orders 4-5", f"{th:.1f} s ({th / tb:.1f}x the baseline)",
             "<= 120 s")]
    for K in (4, 5):
        s = child(CHILD_STAGES, 2, K)
        rows.append((f"N = 2, order {K} stages: series / composition / CSE + printing",
                     f"{s[0]:.1f} / {s[1]:.1f} / {s[2]:.1f} s", ""))
    if a.n3:
        t3 = child(CHILD_GENERATE, 3, "4,5")[0]
        rows.append(("regenerate N = 3, orders 4-5 (on demand, per-user cache)",
                     f"{t3:.0f} s ({t3 / tb:.0f}x the baseline)", ""))
    gen = ROOT / "generated"
    sizes = {f"n{n}_order{K}": (gen / f"impact_n{n}_order{K}.py").stat().st_size
             for n in (1, 2) for K in (4, 5)}
    rows.append(("shipped sizes (KB): " + ", ".join(f"{k} {v / 1e3:.0f}" for k, v in sizes.items()),
                 f"{sum(sizes.values()) / 1e3:.0f} KB in all", "< 2 MB"))
    # evaluation: high_jet against jet_at order 3 at the paper's orbit next to its NS point
    import warnings
    warnings.simplefilter("ignore")
    import symvi
    from symvi.codegen.high import high_jet
    from symvi.codegen.jets import jet_at
    from symvi.orbits import admissible_orbits
    m, w = symvi.Model.luo_xie(2, 5, 0, 1.5, 0.8), 0.7369
    y, te = admissible_orbits(m, w)[0].y, 2 * math.pi / w
    t = time.perf_counter()
    high_jet(m, w, y, te)
    t_load = time.perf_counter() - t
    t_j3 = median_time(lambda: jet_at(m, w, y, te, 3), 50)
    t_h5 = median_time(lambda: high_jet(m, w, y, te), 50)
    t_h5m = median_time(lambda: high_jet(m, w, y, te, digits=60), 3)
    rows.append(("paper model, `jet_at` order 3, float64 (baseline)", f"{t_j3 * 1e6:.0f} µs", ""))
    rows.append(("paper model, `high_jet` order 5, float64",
                 f"{t_h5 * 1e6:.0f} µs ({t_h5 / t_j3:.1f}x the baseline; first call with "
                 f"import {t_load * 1e3:.0f} ms)", ""))
    rows.append(("paper model, `high_jet` order 5, 60 digits", f"{t_h5m * 1e3:.0f} ms", ""))
    print("\n".join(md_table(["what", "median", "target"], rows)))


if __name__ == "__main__":
    main()
