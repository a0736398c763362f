"""Benchmark: hopf_points for the paper's example 1 on [0.70, 0.76], every point with its
normal form, warm, against the mpmath chain of the same point measured in the same run.

    python benchmarks/bench_hopf.py [--repeat 15] [--digits 50]

Stages timed separately (medians): the float64 scan + normal form (``hopf_points``),
its parts (order-1 orbit evaluation, order-3 jet, normal form), and the 50-digit chain A
(orbit, jets and normal form on mpmath) and chain B (finite differences of P).
"""
import argparse
import statistics
import time
import warnings

from symvi import Params
from symvi.analysis.hopf import hopf_points
from symvi.paper.jets import jet
from symvi.normal_forms.normal_form import normal_form
from symvi.paper.orbit import period1_orbits
from symvi.studies.mpcheck import chain_a, chain_b

EX1 = Params(2, 5, 0, 1.5, 0.8)


def median_time(fn, repeat):
    ts = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts), min(ts)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--digits", type=int, default=50)
    a = ap.parse_args()
    warnings.simplefilter("ignore")
    res = hopf_points(EX1, 0.70, 0.76)          # warm-up (imports, numba, caches)
    pt = res.points[0]
    rows = []
    med, best = median_time(lambda: hopf_points(EX1, 0.70, 0.76), a.repeat)
    rows.append(("hopf_points(ex1, 0.70, 0.76), float64", med, best))
    base = med
    rows.append(("  one orbit evaluation (both branches, multipliers)",
                 *median_time(lambda: period1_orbits(EX1, 0.7368), 200)))
    j = jet(EX1, pt.omega_c, order=3, orbit=pt.orbit)
    rows.append(("  order-3 jet at v_c", *median_time(
        lambda: jet(EX1, pt.omega_c, order=3, orbit=pt.orbit), 200)))
    rows.append(("  normal_form at v_c (float64)", *median_time(
        lambda: normal_form(j.jacobian, j.d2, j.d3, j.dA), 200)))
    rows.append((f"chain A at {a.digits} digits (v_c, jets, normal form)", *median_time(
        lambda: chain_a(EX1, pt.omega_c, pt.branch, a.digits, pt.multiplier), 1)))
    rows.append((f"chain B at {a.digits}+30 digits (finite differences of P)", *median_time(
        lambda: chain_b(EX1, pt.omega_c, pt.branch, a.digits, pt.multiplier, pt.orbit.y), 1)))
    print(f"{'stage':62} {'median':>10} {'min':>10} {'/ hopf_points':>14}")
    for name, med, best in rows:
        print(f"{name:62} {med * 1e3:8.2f}ms {best * 1e3:8.2f}ms {med / base:13.3g}x")
    print(f"\n{res.samples} orbit evaluations; target <= 50 ms warm: "
          f"{'met' if base <= 0.05 else 'NOT met'}")


if __name__ == "__main__":
    main()
