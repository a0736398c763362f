"""Benchmark of the compiled simulator of any model (symvi.flow.compiled): impacts/s.

Run:  python benchmarks/bench_simulate_n.py      (prints markdown tables; writes nothing)

Measured in the same run, one trajectory each (start points on the attractor
after 20000 impacts), medians of 7 runs:

* the damped N = 3 model (stop on mass 2, forcing on two masses; gap 1.2, r = 0.8)
  at omega = 0.4 (a non-periodic attractor) and 0.8 (the stable period-1 orbit);
* the paper's model through ``Model.luo_xie`` (symvi.flow.compiled) against the
  same runs through ``Params`` (symvi._fastflow, the paper-only kernels): the
  Params run is the baseline, the two alternate rep by rep so load on the
  machine hits both alike.

Targets: N = 3 damped >= 3e5 impacts/s; the Model path of the paper's model no
more than 20 % slower than the Params path.
"""
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent))

import numba  # noqa: E402

from symvi import Params  # noqa: E402
from symvi import _fastflow as ff  # noqa: E402
from symvi.flow import compiled as cf  # noqa: E402
from symvi.model import Model, Stop  # noqa: E402
from symvi.simulation import simulate  # noqa: E402

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


def paper_rows():
    rows = []
    for p, omega, name in PAPER_CASES:
        params, model = Params(*p), Model.luo_xie(*p)
        y0 = simulate(params, omega, n_impacts=1, transient=20000).section[-1]
        c0, c1 = ff.constants(params, omega), cf.constants(model, omega)
        s0, s1 = ff.run(c0, y0, N)[4], cf.run(c1, y0, N)[4]
        t0, t1 = [], []
        for _ in range(REPS):             # alternate: a load spike hits both paths
            t0.append(_time(lambda: ff.run(c0, y0, N)))
            t1.append(_time(lambda: cf.run(c1, y0, N)))
        r0, r1 = N / statistics.median(t0), N / statistics.median(t1)
        rows.append((name, omega, r0, r1, s0 / N, s1 / N))
    return rows


def main():
    three, paper = three_rows(), paper_rows()
    lines = [f"Command: `python benchmarks/bench_simulate_n.py` (one trajectory of {N:,} "
             f"impacts, medians of {REPS} runs, {numba.get_num_threads()} numba threads)", "",
             "### Damped N = 3 model (symvi.flow.compiled)", ""]
    lines += md_table(["case", "ω", "impacts/s", "finder steps/impact"],
                      [(n, w, f"{r:,.0f}", f"{s:.2f}") for n, w, r, s in three])
    lines += ["", f"Median {statistics.median(r for *_, r, _ in three):,.0f} impacts/s "
              "(target ≥ 300,000).", "",
              "### Paper's model: `Model.luo_xie` (symvi.flow.compiled) vs `Params` "
              "(symvi._fastflow)", ""]
    lines += md_table(["case", "ω", "Params impacts/s", "Model impacts/s", "Model / Params",
                       "steps/impact (Params, Model)"],
                      [(n, w, f"{a:,.0f}", f"{b:,.0f}", f"{b / a:.2f}", f"{s0:.2f}, {s1:.2f}")
                       for n, w, a, b, s0, s1 in paper])
    ratio = statistics.median(b / a for _, _, a, b, _, _ in paper)
    lines += ["", f"Median ratio Model / Params: **{ratio:.2f}** (target ≥ 0.80).", ""]
    print("\n".join(lines))
    return np.array([r for *_, r, _ in three]), ratio


if __name__ == "__main__":
    main()
