"""Benchmark of the compiled simulator of any model (symvi.flow.compiled): impacts/s.

Run:  python benchmarks/bench_simulate_n.py [--baseline DIR]   (prints markdown; writes nothing)

Measured in the same run, one trajectory each (start points on the attractor
after 20000 impacts), medians of 7 runs:

* the damped N = 3 model (stop on mass 2, forcing on two masses; gap 1.2, r = 0.8)
  at omega = 0.4 (a non-periodic attractor) and 0.8 (the stable period-1 orbit);
* the paper's model, ``simulate(Params(...), ...)`` (since issue 11 on
  symvi.flow.compiled, as ``Model.luo_xie``); with ``--baseline DIR`` (a checkout
  of another commit, e.g. ``git worktree add DIR <commit>``) the same calls in
  DIR are the baseline: each rep runs one process in DIR and one in this
  checkout, alternately, so load on the machine hits both alike.

Targets: N = 3 damped >= 3e5 impacts/s; the paper's model no more than 20 %
slower than before issue 11 (its own kernels, ``symvi._fastflow``).
"""
import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))

import numba  # noqa: E402

from symvi import Params  # noqa: E402
from symvi.flow import compiled as cf  # noqa: E402
from symvi.model import Model, Stop  # noqa: E402
from symvi.simulations.simulation import simulate  # noqa: E402

from bench_jets import md_table  # noqa: E402

THREE = Model(mass=[1.0, 1.5, 0.8],
              stiffness=[[1.0, -1.0, 0.0], [-1.0, 1.7, -0.7], [0.0, -0.7, 2.7]],
              damping=[[0.015, -0.005, 0.0], [-0.005, 0.0235, -0.0035],
                       [0.0, -0.0035, 0.0215]],
              forcing=[1.0, 0.5, 0.0], stop=Stop(mass=2, gap=1.2, restitution=0.8))
THREE_CASES = [(0.4, "N = 3 damped, attractor"), (0.8, "N = 3 damped, period-1")]
PAPER_CASES = [((2, 5, 0, 1.5, 0.8), 0.7372, "ex1 circle"),
               ((2, 5, 0, 1.5, 0.8), 0.7440, "ex1 doubled torus"),
               ((2, 5, 0, 1.5, 0.8), 0.7555, "ex1 0.7555"),
               ((4, 2, 0, 1.8, 0.8), 0.4944, "ex2 chaos")]
N = 200_000
REPS = 7

#: run in a fresh process in a checkout (``python -c`` imports the symvi of its cwd):
#: seconds of ``simulate(Params(*p), omega, y0=y0, n_impacts=N)`` per case, warm
_PAPER_TIMER = """
import json, sys, time
from symvi import Params
from symvi.simulations.simulation import simulate
cases, n = json.loads(sys.argv[1]), int(sys.argv[2])
out = []
for p, omega, y0 in cases:
    simulate(Params(*p), omega, y0=y0, n_impacts=10)
    t = time.perf_counter()
    s = simulate(Params(*p), omega, y0=y0, n_impacts=n)
    out.append(time.perf_counter() - t)
    assert s.stop == "completed", s.stop
print(json.dumps(out))
"""


def _time(fn):
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def three_rows():
    rows = []
    for omega, name in THREE_CASES:
        s = simulate(THREE, omega, y0=(-0.5, 0, 0, 0, 0, 1.0), n_impacts=1, transient=20000)
        assert s.stop == "completed", s.stop
        c, y0 = cf.constants(THREE, omega), s.section[-1]
        code, _, _, _, steps = cf.run(c, y0, N)
        assert cf.STOP_NAMES[code] == "completed"
        dt = statistics.median(_time(lambda: cf.run(c, y0, N)) for _ in range(REPS))
        rows.append((name, omega, N / dt, steps / N))
    return rows


def _paper_times(cwd, cases):
    out = subprocess.run([sys.executable, "-c", _PAPER_TIMER, json.dumps(cases), str(N)],
                         cwd=cwd, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.splitlines()[-1])


def paper_rows(baseline=None):
    """Per case (name, omega, impacts/s here, impacts/s in ``baseline`` or None, steps/impact)."""
    cases, steps = [], []
    for p, omega, _ in PAPER_CASES:
        y0 = simulate(Params(*p), omega, n_impacts=1, transient=20000).section[-1]
        cases.append((p, omega, [float(v) for v in y0]))
        steps.append(cf.run(cf.constants(Model.luo_xie(*p), omega), y0, N)[4] / N)
    here, base = [], []
    for _ in range(REPS):             # alternate: a load spike hits both checkouts
        if baseline is not None:
            base.append(_paper_times(baseline, cases))
        here.append(_paper_times(ROOT, cases))
    rows = []
    for i, (_, omega, name) in enumerate(PAPER_CASES):
        r1 = N / statistics.median(t[i] for t in here)
        r0 = N / statistics.median(t[i] for t in base) if base else None
        rows.append((name, omega, r1, r0, steps[i]))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", help="a checkout of the baseline commit (git worktree)")
    args = ap.parse_args()
    three, paper = three_rows(), paper_rows(args.baseline)
    lines = [f"Command: `python benchmarks/bench_simulate_n.py"
             f"{' --baseline DIR' if args.baseline else ''}` (one trajectory of {N:,} "
             f"impacts, medians of {REPS} runs, {numba.get_num_threads()} numba threads)", "",
             "### Damped N = 3 model (symvi.flow.compiled)", ""]
    lines += md_table(["case", "ω", "impacts/s", "finder steps/impact"],
                      [(n, w, f"{r:,.0f}", f"{s:.2f}") for n, w, r, s in three])
    lines += ["", f"Median {statistics.median(r for *_, r, _ in three):,.0f} impacts/s "
              "(target ≥ 300,000).", "",
              "### Paper's model: `simulate(Params(...))` (symvi.flow.compiled)", ""]
    if args.baseline:
        lines += md_table(["case", "ω", "baseline impacts/s", "impacts/s", "ratio",
                           "steps/impact"],
                          [(n, w, f"{b:,.0f}", f"{a:,.0f}", f"{a / b:.2f}", f"{s:.2f}")
                           for n, w, a, b, s in paper])
        ratio = statistics.median(a / b for _, _, a, b, _ in paper)
        lines += ["", f"Median ratio to the baseline (`{args.baseline}`): **{ratio:.2f}** "
                  "(target ≥ 0.80).", ""]
    else:
        lines += md_table(["case", "ω", "impacts/s", "steps/impact"],
                          [(n, w, f"{a:,.0f}", f"{s:.2f}") for n, w, a, _, s in paper])
        lines += [""]
    print("\n".join(lines))
    return np.array([r for *_, r, _ in three]), paper


if __name__ == "__main__":
    main()
