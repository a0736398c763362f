"""Benchmark: l2 at the Chenciner points of the paper's example 1 in (omega, r), float64
(generated order-5 jets) against the 50-digit finite-difference chain of
:mod:`symvi.codim2_check`, measured in the same run (issue 13, performance target
"l2 to >= 8 digits against 50-digit mpmath").

    python benchmarks/bench_l2.py [--repeat 21] [--digits 50] [--verify]

Per CH point: the float64 cost of l2 at the located point (the order-5 jet of the orbit,
``PeriodicOrbit.jet(5)``, then ``codim2.chenciner``; median of ``repeat``) and the chain's
(location at 105 digits, order-5 jets at 135 digits, codim2 on the mpmath backend; one
run), the digits of agreement of the location and of c1, c2, l1 (relative to |c1|), l2,
and inside the chain of codim2's c1 and l1 with ``kuznetsov_l1``.  ``--verify`` adds the
chain's coefficients recomputed with a step 10^-3 smaller at 20 more digits.
"""
import argparse
import statistics
import time
import warnings

import mpmath

import symvi
from symvi.curves import curve_from_interval
from symvi.normal_forms import codim2
from symvi.studies.codim2_check import check_codim2

MODEL = symvi.Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)


def median_time(fn, repeat):
    ts = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts), min(ts)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=21)
    ap.add_argument("--digits", type=int, default=50)
    ap.add_argument("--verify", action="store_true")
    a = ap.parse_args()
    warnings.simplefilter("ignore")
    t = time.perf_counter()
    curve, _ = curve_from_interval(MODEL, 0.70, 0.76, ("omega", "r"),
                                   bounds={"omega": (0.5, 1.0), "r": (0.05, 1.0)})
    t_curve = time.perf_counter() - t
    print(f"NS curve of example 1 in (omega, r): {len(curve)} points, {t_curve:.2f} s "
          f"(float64, with every codim-2 point located)\n")
    chs = [s for s in curve.special if s.kind == "CH"]
    agree = []
    for pt in chs:
        orbit = pt.orbit

        def float_l2():
            return codim2.chenciner(*orbit.jet(5)).l2
        float_l2()                                       # warm (imports, loaded modules)
        med_jet, _ = median_time(lambda: orbit.jet(5), a.repeat)
        med_f, best_f = median_time(float_l2, a.repeat)
        res = check_codim2(curve, pt, digits=a.digits, verify=a.verify)
        co = res.coefficients
        agree.append(res.agreement["l2"])
        print(f"CH at omega = {pt.params['omega']:.12g}, r = {pt.params['r']:.12g}")
        print(f"  l2 float64 = {pt.coefficients['l2']:.16e}")
        print(f"  l2 chain   = {mp_str(co['l2'])}")
        print(f"  chain's point: omega = {mp_str(res.params['omega'])}, "
              f"r = {mp_str(res.params['r'])}")
        print("  digits of agreement float64 vs chain: "
              + ", ".join(f"{k} {v}" for k, v in {**res.location, **res.agreement}.items()))
        print("  inside the chain: " + ", ".join(f"{k} {v}" for k, v in res.internal.items()))
        print(f"  {'stage':52} {'median':>10} {'min':>10} {'/ float64 l2':>13}")
        rows = [("float64 l2: orbit.jet(5) + codim2.chenciner", med_f, best_f),
                ("  of which orbit.jet(5) (generated order-5 jets)", med_jet, None),
                (f"chain at {a.digits} digits, total (1 run)", res.times["total"], None),
                (f"  location (order-3 FD jets, {res.dps['locate']} digits, "
                 f"{res.iterations} steps)", res.times["locate"], None),
                (f"  coefficients (order-5 FD jets, {res.dps['coefficients']} digits)",
                 res.times["coefficients"], None)]
        if a.verify:
            rows.append((f"  verify (step / 1000, {res.dps['verify']} digits)",
                         res.times["verify"], None))
        for name, med, best in rows:
            b = f"{best * 1e3:8.2f}ms" if best is not None else f"{'':10}"
            print(f"  {name:52} {med * 1e3:8.1f}ms {b} {med / med_f:12.4g}x")
        print(f"  map evaluations of the chain: {res.evaluations}\n")
    worst = min(agree)
    print(f"l2 float64 vs {a.digits}-digit chain, worst over {len(agree)} CH points: "
          f"{worst} digits; target >= 8: {'met' if worst >= 8 else 'NOT met'}")


def mp_str(x, n=25):
    return mpmath.nstr(x, n)


if __name__ == "__main__":
    main()
