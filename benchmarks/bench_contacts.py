"""Impacts per second of the compiled run loop over several constraints (issue 25's target:
one trajectory of a 1-DOF oscillator between two rigid stops at >= 5e5 impacts/s), with
the paper's one-stop model timed in the same run as the baseline:

    python benchmarks/bench_contacts.py [--impacts 1000000] [--reps 5]

Prints one JSON line: impacts/s of each case (median of the reps) and finder steps per
impact.  The 1-DOF model: m = k = 1, c = 0.05, P = 1.3, stops at x = 0.5 (r = 0.8) and
x = -0.4 (r = 0.7), omega = 1.1 (a run that alternates between the stops)."""
import argparse
import json
import statistics
import time

import numpy as np

from symvi.flow import compiled as cf
from symvi.model import Model, Stop
from symvi.simulations import simulation


def two_sided():
    """The 1-DOF oscillator between two stops."""
    return Model(mass=[[1.0]], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.3],
                 stops=[Stop(mass=1, gap=0.5, restitution=0.8),
                        Stop(mass=1, gap=-0.4, side="lower", restitution=0.7)])


def rate(c, y0, n, reps):
    cf.run(c, y0, 1000)
    out = []
    for _ in range(reps):
        t = time.perf_counter()
        code, sec, *_ = cf.run(c, y0, n)
        out.append(len(sec) / (time.perf_counter() - t))
    steps = cf.run(c, y0, n)[4] / n
    return statistics.median(out), steps, int(code)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--impacts", type=int, default=1_000_000)
    ap.add_argument("--reps", type=int, default=5)
    a = ap.parse_args()
    m = two_sided()
    c = cf.constants(m, 1.1)
    r2, s2, code2 = rate(c, np.array([-0.3, 0.4]), a.impacts, a.reps)
    paper = Model.luo_xie(2, 5, 0, 1.5, 0.8)
    cp = cf.constants(paper, 0.7372)
    y0 = np.array(simulation.start_point(paper, 0.7372)[0])
    r1, s1, code1 = rate(cp, y0, a.impacts, a.reps)
    print(json.dumps({"two_sided_impacts_per_s": round(r2), "two_sided_steps": round(s2, 2),
                      "two_sided_stop": cf.STOP_NAMES[code2],
                      "paper_impacts_per_s": round(r1), "paper_steps": round(s1, 2),
                      "paper_stop": cf.STOP_NAMES[code1]}))


if __name__ == "__main__":
    main()
