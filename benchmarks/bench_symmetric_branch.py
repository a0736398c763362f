"""A 1000-point branch of a symmetric two-sided orbit (issue 25's target: <= 0.5 s), with
the paper's 1000-point period-1 branch (benchmarks/bench_continue.py) timed in the same run
as the baseline:

    python benchmarks/bench_symmetric_branch.py [--reps 5]

The model: a 1-DOF oscillator (m = k = 1, c = 0.05, P = 1) between rigid stops at
x = +-0.5 (r = 0.9); its symmetric 1-2 orbit (one impact on each stop per forcing period)
continued in omega from 1.0 to 3.0 with multipliers, the half map H of the symmetry and
every test function at each point, the two symmetry-breaking pitchforks located.  Prints
one JSON line: seconds (median of the reps), points, special points, and the ratio to the
baseline."""
import argparse
import json
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_continue import branch_1000  # noqa: E402
from symvi.continuation import continue_branch  # noqa: E402
from symvi.model import Model, Stop  # noqa: E402
from symvi.orbits.periodic import from_simulation  # noqa: E402
from symvi.simulations.simulation import simulate  # noqa: E402

SYM = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
            stops=[Stop(mass=1, gap=0.5, restitution=0.9),
                   Stop(mass=1, gap=-0.5, side="lower", restitution=0.9)])


def symmetric_1000(orbit):
    # h_max chosen so that omega in [1.0, 3.0] takes about 1000 points
    return continue_branch(SYM, "omega", 1.0, 3.0, orbit=orbit, h_max=0.0029,
                           max_points=1000)


def timed(fn, reps):
    out, ts = None, []
    for _ in range(reps):
        t = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts), out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=5)
    a = ap.parse_args()
    orbit = from_simulation(simulate(SYM, 1.0, y0=(-0.1, 0.0), n_impacts=300, transient=3000))
    symmetric_1000(orbit)                       # compile and warm
    branch_1000()
    ts, br = timed(lambda: symmetric_1000(orbit), a.reps)
    tb, base = timed(branch_1000, a.reps)
    print(json.dumps({"symmetric_branch_s": round(ts, 4), "points": len(br),
                      "symmetric": all(pt.orbit.symmetric for pt in br.points),
                      "special": [(sp.kind, round(sp.value, 9)) for sp in br.special],
                      "paper_branch_s": round(tb, 4), "paper_points": len(base),
                      "ratio_to_paper": round(ts / tb, 3)}))


if __name__ == "__main__":
    main()
