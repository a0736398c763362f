"""The run loop and the classifier (issue 24, item 5), timed in whatever checkout is on
PYTHONPATH, for ratios against a baseline measured in the same session:

    PYTHONPATH=/tmp/base python benchmarks/bench_runloop.py   # baseline checkout
    python benchmarks/bench_runloop.py                       # this one

Prints one JSON line of median seconds: ``simulate`` (one trajectory, 2e5 impacts on the
circle of example 1 at omega = 0.7372, as bench_simulate.py), ``batch`` (run_batch of 16
omegas x 2e4 impacts, as a sweep) and ``plane`` (the compiled classifier over 64 points of
example 1, 2000 kept after 2000, as one plane task)."""
import json
import statistics
import time

import numpy as np

import symvi
from symvi.flow import compiled as cf
from symvi.simulations import simulation

try:
    from symvi.simulations.classifier import classify_runs as classify
except ImportError:                                   # a checkout before issue 24, item 5
    from symvi.plane.kernel import classify

REPS = 7


def _median(f):
    f()
    out = []
    for _ in range(REPS):
        t = time.perf_counter()
        f()
        out.append(time.perf_counter() - t)
    return statistics.median(out)


def main():
    model = symvi.Model.luo_xie(2, 5, 0, 1.5, 0.8)
    c = cf.constants(model, 0.7372)
    y0 = np.array(simulation.start_point(model, 0.7372)[0])
    oms = np.linspace(0.70, 0.76, 16)
    C = np.array([cf.constants(model, w) for w in oms])
    Y0 = simulation.sweep_starts(model, oms)
    pl = np.linspace(0.72, 0.76, 64)
    CP = np.array([cf.constants(model, w) for w in pl])
    YP = simulation.sweep_starts(model, pl)
    print(json.dumps({
        "simulate": _median(lambda: cf.run(c, y0, 200_000)),
        "batch": _median(lambda: cf.run_batch(C, Y0, 20_000)),
        "plane": _median(lambda: classify(CP, YP, 2000, 2000)),
    }))


if __name__ == "__main__":
    main()
