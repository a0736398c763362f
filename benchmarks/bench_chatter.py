"""Runs through complete chatter and sticking (issue 27, item 4): 10^4 chatter sequences,
each summed from its accumulation point, held and released, against the compiled run of
the same number of ordinary impacts, in one process:

    python benchmarks/bench_chatter.py [--reps 5]

The case: x'' + 0.1 x' + x = sin(0.5 t), a rigid stop at x = 0 with r = 0.5: every
forcing period the mass returns, chatters (about 20 exact impacts down to the finder's
grazing speed, then the closed-form remainder), sticks while sin > 0 and is released at
phase pi (:func:`symvi.flow.sticking.run_through`).  Baseline: ``cf.run`` of 10^4
impacts of example 1 on its circle (omega = 0.7372), no chatter.  Prints one JSON line:
median seconds of each, their ratio, the exact impacts per chatter and the cost of one
chatter sequence in microseconds (target: 10^4 sequences <= 1 s)."""
import argparse
import json
import statistics
import time

import numpy as np

import symvi
from symvi.flow import compiled as cf
from symvi.flow.sticking import run_through
from symvi.model import Model, Stop
from symvi.simulations import simulation

SEQUENCES = 10_000


def _median(f, reps):
    f()
    out = []
    for _ in range(reps):
        t = time.perf_counter()
        f()
        out.append(time.perf_counter() - t)
    return statistics.median(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=5)
    reps = ap.parse_args().reps
    one = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
                stop=Stop(mass=1, gap=0.0, restitution=0.5))
    c = cf.constants(one, 0.5)
    # settle on the sticking orbit, then count the stored impacts of 10^4 periods
    code, sec, _, _, hits, st, _ = run_through(one, c, (-0.5, 0.0), 2000)
    y0 = sec[-1]
    probe = run_through(one, c, y0, 2000, k=int(hits[-1]))
    per = 2000 / len(probe[5])                       # impacts stored per chatter sequence
    n_keep = int(round(per * SEQUENCES))
    res = {}

    def chatter():
        res["out"] = run_through(one, c, y0, n_keep, k=int(hits[-1]))

    t_chatter = _median(chatter, reps)
    code, _, _, _, _, sticks, _ = res["out"]
    ex1 = symvi.Model.luo_xie(2, 5, 0, 1.5, 0.8)
    ce = cf.constants(ex1, 0.7372)
    ye = np.array(simulation.start_point(ex1, 0.7372)[0])
    t_base = _median(lambda: cf.run(ce, ye, SEQUENCES), reps)
    print(json.dumps({
        "sequences": int(len(sticks)), "stop": cf.STOP_NAMES[code],
        "exact_impacts_per_sequence": round(per, 2),
        "chatter_s": t_chatter, "baseline_s": t_base, "ratio": t_chatter / t_base,
        "us_per_sequence": 1e6 * t_chatter / len(sticks),
    }))


if __name__ == "__main__":
    main()
