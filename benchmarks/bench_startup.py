"""Start-up of one whole `symvi hopf ... --json` process (issue 24, item 10), against a
baseline checkout in the same run.

    git worktree add --detach /tmp/base-startup main
    python benchmarks/bench_startup.py --base /tmp/base-startup [--warm 9] [--cold 2]

Warm: numba's cache already filled (each checkout keeps its own, beside its sources); the
two trees alternate, one untimed run each first.  Cold: NUMBA_CACHE_DIR set to a new empty
directory for every run, so everything compiles (the real cache is not touched).  Wall
time and CPU time (user + sys of the process and the processes it waited for: the cold
run's compiling workers) are medians; ratios are new / base.  The floor rows time bare
imports, to show what a process pays before symvi does anything.
"""
import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ARGS = ["hopf", "--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8",
        "--omega-min", "0.70", "--omega-max", "0.76", "--json"]
FLOOR = [("python -c pass", "pass"),
         ("import numpy", "import numpy"),
         ("import numpy, numba", "import numpy, numba"),
         ("import numpy, numba, scipy.linalg", "import numpy, numba, scipy.linalg"),
         ("import numpy, numba, scipy.optimize", "import numpy, numba, scipy.optimize"),
         ("import symvi.cli (this tree)", "import symvi.cli")]

#: the floor of any process that runs a numba kernel: a one-loop kernel, cached on disk,
#: imported and called once (numba's import, its first-use set-up, one cached load)
KERNEL = """import numba
@numba.njit(cache=True)
def f(a):
    s = 0.0
    for i in range(a.shape[0]):
        s += a[i]
    return s
"""


def timed(cmd, env):
    """(wall s, cpu s, stdout) of one process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    r = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{r.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, r.stdout


PHASES = r"""
import time
clock, marks = time.process_time, []
def mark(label):
    marks.append((label, clock()))
mark("start")
import numpy
mark("import numpy")
import numba
mark("import numba")
import scipy.linalg
mark("import scipy.linalg (numba imports it at its first load: its BLAS check)")
import scipy.optimize
mark("import scipy.optimize beyond scipy.linalg (the scan's linear_sum_assignment)")
import symvi.cli.hopf, symvi.analysis.hopf
mark("import symvi's modules (the CLI, the scan and what they import)")
from symvi.params import Params
p = Params(2, 5, 0, 1.5, 0.8)
symvi.analysis.hopf.hopf_points(p, 0.70, 0.76)
mark("first scan: numba's first-use set-up, 8 kernels loaded from the cache, the scan")
symvi.analysis.hopf.hopf_points(p, 0.70, 0.76)
mark("second scan in the same process: the scan's own work")
for (_, a), (label, b) in zip(marks, marks[1:]):
    print(f"{label}\t{b - a:.4f}")
"""


def phases(tree, runs):
    """Median CPU seconds of each step of one process, in order (process_time)."""
    rows = {}
    for _ in range(runs):
        r = subprocess.run([sys.executable, "-c", PHASES], env=env_for(tree),
                           capture_output=True, text=True, check=True)
        for line in r.stdout.splitlines():
            label, secs = line.split("\t")
            rows.setdefault(label, []).append(float(secs))
    return [(label, med(v)) for label, v in rows.items()]


def env_for(tree, **extra):
    env = dict(os.environ, PYTHONPATH=tree, **extra)
    env.pop("SYMVI_PROGRESS", None)
    return env


def med(xs):
    return statistics.median(xs)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base", required=True, help="baseline checkout (e.g. of main)")
    ap.add_argument("--warm", type=int, default=9, help="warm pairs (9)")
    ap.add_argument("--cold", type=int, default=2, help="cold pairs (2; each compiles)")
    ap.add_argument("--floor", type=int, default=7, help="runs of each floor row (7)")
    a = ap.parse_args()
    trees = {"base": os.path.abspath(a.base), "new": HERE}
    cmd = [sys.executable, "-m", "symvi", *ARGS]
    out = {}
    for name, tree in trees.items():          # fill each tree's cache; results must agree
        out[name] = timed(cmd, env_for(tree))[2]
    same = out["base"] == out["new"]
    res = {(k, n): [] for k in ("warm", "cold") for n in trees}
    for _ in range(a.warm):
        for name, tree in trees.items():
            res["warm", name].append(timed(cmd, env_for(tree))[:2])
    for _ in range(a.cold):
        for name, tree in trees.items():
            with tempfile.TemporaryDirectory() as cache:
                res["cold", name].append(timed(cmd, env_for(tree, NUMBA_CACHE_DIR=cache))[:2])
    floor = []
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "floor_kernel.py"), "w") as fh:
            fh.write(KERNEL)
        call = (f"import sys; sys.path.insert(0, {d!r}); import numpy, floor_kernel; "
                "floor_kernel.f(numpy.ones(3))")
        timed([sys.executable, "-c", call], env_for(HERE))          # fills its cache
        rows = FLOOR + [("one cached numba kernel, imported and called", call)]
        for label, code in rows:
            runs = [timed([sys.executable, "-c", code], env_for(HERE))[:2]
                    for _ in range(a.floor)]
            floor.append((label, med([w for w, _ in runs]), med([c for _, c in runs])))

    print(f"`symvi {' '.join(ARGS)}`, whole process; {os.cpu_count()} CPUs, load average "
          f"{os.getloadavg()[0]:.1f} at the end; stdout identical to the baseline's: {same}\n")
    print("| cache | runs | base wall s | new wall s | ratio | base CPU s | new CPU s | ratio |")
    print("|---|---|---|---|---|---|---|---|")
    for kind in ("warm", "cold"):
        b, n = res[kind, "base"], res[kind, "new"]
        bw, nw = med([w for w, _ in b]), med([w for w, _ in n])
        bc, nc = med([c for _, c in b]), med([c for _, c in n])
        print(f"| {kind} | {len(b)} pairs | {bw:.3f} | {nw:.3f} | {nw / bw:.2f}x | {bc:.3f} | "
              f"{nc:.3f} | {nc / bc:.2f}x |")
    print("\n| floor (medians) | wall s | CPU s |\n|---|---|---|")
    for label, w, c in floor:
        print(f"| {label} | {w:.3f} | {c:.3f} |")
    print("\n| where a warm process's time goes, step by step (this tree, medians) | CPU s |")
    print("|---|---|")
    for label, c in phases(HERE, a.floor):
        print(f"| {label} | {c:.3f} |")


if __name__ == "__main__":
    main()
