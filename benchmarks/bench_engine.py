"""The one continuation engine (issue 24, item 4): its speed against a baseline checkout, and
the evidence for its one turning-angle limit MIN_COS.

    git worktree add /tmp/base-engine <baseline commit>
    python benchmarks/bench_engine.py paired /tmp/base-engine 15
    python benchmarks/bench_engine.py turns

``paired``: the 1000-point branch of ``bench_continue.branch_1000`` and the 500-point NS curve
of ``bench_curve.run_curve(False)`` in two long-lived processes, one per checkout, asked in
turn (the order alternating), so that each pair of timings shares the machine's load; medians
and the median of the paired ratios.  ``turns``: on branches and curves, the smallest cosine
between consecutive tangents the engine meets and how many trial steps turn more than
0.95 and 0.97 allow (refused with either value when both counts agree),
then two runs with steps large enough that the limit binds, at 0.95 and at 0.97.
"""
import os
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def worker(root):
    sys.path.insert(0, root)
    sys.path.insert(0, os.path.join(root, "benchmarks"))
    warnings.simplefilter("ignore")
    import bench_continue as bc
    import bench_curve as bu
    import symvi
    assert symvi.__file__.startswith(root), symvi.__file__
    bc.branch_1000()
    bu.run_curve(False)
    print("ready", flush=True)
    for line in sys.stdin:
        if line.strip() == "b":
            t = time.perf_counter()
            bc.branch_1000()
            print(time.perf_counter() - t, flush=True)
        elif line.strip() == "c":
            print(bu.run_curve(False)[0], flush=True)


def paired(base, n):
    def start(root):
        p = subprocess.Popen([sys.executable, __file__, "worker", root], stdin=subprocess.PIPE,
                             stdout=subprocess.PIPE, text=True,
                             env=dict(os.environ, PYTHONPATH=root))
        assert p.stdout.readline().strip() == "ready"
        return p

    def ask(p, what):
        p.stdin.write(what + "\n")
        p.stdin.flush()
        return float(p.stdout.readline())
    old, new = start(os.path.abspath(base)), start(str(ROOT))
    for what, label in (("b", "1000-point branch"), ("c", "500-point NS curve")):
        tb, tn, ratios = [], [], []
        for i in range(n):
            order = (old, new) if i % 2 == 0 else (new, old)
            t = {id(p): ask(p, what) for p in order}
            tb.append(t[id(old)])
            tn.append(t[id(new)])
            ratios.append(t[id(new)] / t[id(old)])
        q = sorted(ratios)
        print(f"| {label} | {statistics.median(tb):.3f} s | {statistics.median(tn):.3f} s | "
              f"{statistics.median(tn) / statistics.median(tb):.3f} | "
              f"{statistics.median(ratios):.3f} ({q[n // 4]:.2f}-{q[3 * n // 4]:.2f}) |",
              flush=True)
    for p in (old, new):
        p.stdin.close()
        p.wait()


def turns():
    import numpy as np
    sys.path.insert(0, str(ROOT))
    warnings.simplefilter("ignore")
    import symvi.continuation.engine as E
    from symvi.continuation import continue_branch, switch_at_flip
    from symvi.curves import continue_curve, curve_from_interval
    from tests.zoo import ONE_DAMPED_GAP0, PAPER_EX1
    seen = []
    tangent = E.tangent

    def recording(Gu, Gl, t_prev):
        t = tangent(Gu, Gl, t_prev)
        seen.append(float(np.dot(t, t_prev)))
        return t
    E.tangent = recording
    b2 = continue_branch(PAPER_EX1, "omega", 0.70, 0.76)
    ns = next(s for s in b2.special if s.kind == "ns")
    fl = next(s for s in b2.special if s.kind == "flip")
    one = continue_branch(ONE_DAMPED_GAP0, "omega", 2.0, 3.0)
    box = {"omega": (0.5, 1.0), "b": (0.1, 2.6)}
    cases = {
        "branch, 1000-point benchmark": lambda: continue_branch(
            PAPER_EX1, "omega", 1.3, 1.0, h_max=0.0021, max_points=1000, through=True),
        "branch, omega 0.70-0.76": lambda: continue_branch(PAPER_EX1, "omega", 0.70, 0.76),
        "branch through the fold, 1.45-1.7": lambda: continue_branch(
            PAPER_EX1, "omega", 1.45, 1.7, through=True),
        "the same, h_max 0.2": lambda: continue_branch(PAPER_EX1, "omega", 1.45, 1.7,
                                                       through=True, h_max=0.2, h=0.05),
        "branch 1.3-0.6, h_max 0.3": lambda: continue_branch(PAPER_EX1, "omega", 1.3, 0.6,
                                                             through=True, h_max=0.3, h=0.1),
        "doubled branch (switch at a flip)": lambda: switch_at_flip(
            one, next(s for s in one.special if s.kind == "flip")),
        "branch in b": lambda: continue_branch(PAPER_EX1, "b", 1.5, 0.5, omega=0.73),
        "NS curve (omega, b), 500-point benchmark": lambda: continue_curve(
            PAPER_EX1, "ns", ("omega", "b"), ns.orbit, bounds=box, max_points=251,
            locate=False),
        "NS curve (omega, r), codim-2 points": lambda: continue_curve(
            PAPER_EX1, "ns", ("omega", "r"), ns.orbit,
            bounds={"omega": (0.5, 1.0), "r": (0.05, 1.0)}, max_points=3000),
        "NS curve (omega, b), h_max 0.3": lambda: continue_curve(
            PAPER_EX1, "ns", ("omega", "b"), ns.orbit, bounds=box, h_max=0.3, max_points=600),
        "fold curve, h_max 0.3": lambda: curve_from_interval(
            PAPER_EX1, 1.4, 1.6, ("omega", "b"), kind="fold",
            bounds={"omega": (0.5, 3.0), "b": (0.5, 3.0)}, h_max=0.3)[0],
        "flip curve": lambda: continue_curve(PAPER_EX1, "flip", ("omega", "b"), fl.orbit,
                                             bounds={"omega": (0.5, 1.0), "b": (0.5, 3.0)},
                                             max_points=1500),
    }
    print("| run | smallest cos(turn) of a trial step | trial steps with cos < 0.95 "
          "| with cos < 0.97 |")
    print("|---|---|---|---|")
    for name, fn in cases.items():
        seen.clear()
        fn()
        # every tangent the engine takes (trial steps, and points inside a bracket)
        c = np.array(seen)
        print(f"| {name} | {c.min():.5f} | {int(np.sum(c < 0.95))} | {int(np.sum(c < 0.97))} |",
              flush=True)
    E.tangent = tangent
    print("\nSteps large enough that the limit binds:\n")
    for mc in (0.95, 0.97):
        E.MIN_COS = mc
        b = continue_branch(PAPER_EX1, "omega", 1.45, 1.7, through=True, h_max=1.0, h=0.3)
        c = curve_from_interval(PAPER_EX1, 1.4, 1.6, ("omega", "b"), kind="fold",
                                bounds={"omega": (0.5, 3.0), "b": (0.5, 3.0)}, h_max=2.0,
                                h=0.5)[0]
        print(f"MIN_COS = {mc}: branch 1.45-1.7 (h_max 1): {len(b)} points, "
              f"{[(s.kind, repr(s.value)) for s in b.special]}; fold curve (h_max 2): "
              f"{len(c)} points, ends {[e[:22] for e in c.ends]}", flush=True)


if __name__ == "__main__":
    if sys.argv[1] == "worker":
        worker(sys.argv[2])
    elif sys.argv[1] == "paired":
        paired(sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else 15)
    else:
        turns()
