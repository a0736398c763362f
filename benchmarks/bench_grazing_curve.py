"""Grazing curves (issue 27; target: 500 points <= 2 s), with the NS curve of the same
engine timed in the same run as the baseline:

    python benchmarks/bench_grazing_curve.py [--reps 3]

* impact: COCO's Example 15.2 oscillator (k = 1, c = 0.1, d = 1, e = 0.8), its impacting
  orbit's grazing curve in (omega, forcing[1]) over omega in [0.3, 3];
* touch: the paper's example 1, its period-1 orbit touching the stop, in (omega, b);
* baseline: example 1's NS curve in (omega, r) (multipliers, l1 and the codimension-two
  test functions at each point).

Prints one JSON line: points, seconds per 500 points (median of the reps) of each, and
their ratios to the baseline per point."""
import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_symmetric_branch import timed  # noqa: E402
from symvi import Model, Stop  # noqa: E402
from symvi.continuation import continue_orbits  # noqa: E402
from symvi.curves import continue_grazing, curve_from_interval  # noqa: E402

COCO = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[2.0],
             stops=[Stop(mass=1, gap=1.0, restitution=0.8)])
EX1 = Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)


def grazing_point(model, param, a, b, omega):
    brs = continue_orbits(model, param, a, b, omega=omega)
    return [s for br in brs for s in br.special if s.kind == "grazing"][0]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=3)
    a = ap.parse_args()
    g1 = grazing_point(COCO, "forcing[1]", 2.0, 0.2, 1.5)
    g2 = grazing_point(EX1, "b", 1.5, 0.1, 0.75)
    runs = {
        "impact": lambda: continue_grazing(COCO, ("omega", "forcing[1]"), g1,
                                           bounds={"omega": (0.3, 3.0),
                                                   "forcing[1]": (0.05, 10.0)},
                                           max_points=500),
        "touch": lambda: continue_grazing(EX1, ("omega", "b"), g2,
                                          bounds={"omega": (0.6, 0.9), "b": (0.05, 1.5)},
                                          max_points=500),
        "ns_baseline": lambda: curve_from_interval(EX1, 0.70, 0.76, ("omega", "r"),
                                                   bounds={"omega": (0.5, 1.0),
                                                           "r": (0.05, 1.0)})[0],
    }
    out = {}
    for name, run in runs.items():
        run()                                     # compile and warm
        t, cv = timed(run, a.reps)
        out[name] = {"points": len(cv.points), "s_per_500": round(500 * t / len(cv.points), 3)}
    base = out["ns_baseline"]["s_per_500"]
    for name in ("impact", "touch"):
        out[name]["ratio_to_ns"] = round(out[name]["s_per_500"] / base, 3)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
