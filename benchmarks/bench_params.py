"""Parameters as objects (issue 24, item 2): the continuation's speed against a baseline
checkout, on the paths a parameter object touches at every corrector step.

    git worktree add --detach /tmp/base-params main
    python benchmarks/bench_params.py /tmp/base-params 11          # all four cases
    python benchmarks/bench_params.py /tmp/base-params 31 g        # one case (b, c, g, k)

Two long-lived processes, one per checkout, asked in turn (the order alternating), so that
each pair of timings shares the machine's load; medians and the median of the paired
ratios.  Cases: the 1000-point branch in omega (``bench_continue.branch_1000``), the
500-point NS curve in (omega, b) (``bench_curve.run_curve(False)``), a branch in ``gap``
and one in ``stiffness[2,2]`` of a damped two-mass model (every corrector step sets the
parameter: a new model).  Each case's result is compared between the two checkouts
(bit for bit).
"""
import os
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LABELS = {"b": "1000-point branch (omega)", "c": "500-point NS curve (omega, b)",
          "g": "branch in gap (729 points)", "k": "branch in stiffness[2,2] (918 points)"}


def cases():
    import hashlib

    import numpy as np
    import bench_continue as bc
    import bench_curve as bu

    from symvi.continuation import continue_branch
    from symvi.model import Model, Stop
    damped = Model(mass=[1.0, 2.0], stiffness=[[1.0, -1.0], [-1.0, 6.0]],
                   damping=[[0.02, -0.01], [-0.01, 0.03]], forcing=[1.0, 0.0],
                   stop=Stop(mass=1, gap=1.5, restitution=0.8))

    def last(br):              # every state of the branch, bit for bit
        return hashlib.sha256(np.asarray(br.states, dtype=float).tobytes()).hexdigest()
    return {
        "b": (bc.branch_1000, last),
        "c": (lambda: bu.run_curve(False),      # (its own time, the curve)
              lambda out: last(out[1])),
        "g": (lambda: continue_branch(damped, "gap", 1.5, 0.45, omega=1.2, max_points=1000,
                                      h_max=0.002, through=True), last),
        "k": (lambda: continue_branch(damped, "stiffness[2,2]", 6.0, 7.8, omega=1.2,
                                      max_points=1000, h_max=0.002, through=True), last),
    }


def worker(root):
    sys.path.insert(0, root)
    sys.path.insert(0, os.path.join(root, "benchmarks"))
    warnings.simplefilter("ignore")
    import symvi
    assert symvi.__file__.startswith(root), symvi.__file__
    cs = cases()
    for fn, _ in cs.values():
        fn()
    print("ready", flush=True)
    for line in sys.stdin:
        fn, show = cs[line.strip()]
        t = time.perf_counter()
        out = fn()
        dt = out[0] if isinstance(out, tuple) else time.perf_counter() - t
        print(f"{dt} {show(out)}", flush=True)


def paired(base, n, which="bcgk"):
    def start(root):
        p = subprocess.Popen([sys.executable, __file__, "worker", root], stdin=subprocess.PIPE,
                             stdout=subprocess.PIPE, text=True,
                             env=dict(os.environ, PYTHONPATH=root))
        assert p.stdout.readline().strip() == "ready"
        return p

    def ask(p, what):
        p.stdin.write(what + "\n")
        p.stdin.flush()
        t, _, out = p.stdout.readline().partition(" ")
        return float(t), out
    old, new = start(os.path.abspath(base)), start(str(ROOT))
    print("| case | baseline (median) | objects (median) | ratio of medians | "
          "median of paired ratios (quartiles) | same result |")
    print("|---|---|---|---|---|---|")
    for what, label in ((k, LABELS[k]) for k in which):
        tb, tn, ratios, same = [], [], [], True
        for i in range(n):
            order = (old, new) if i % 2 == 0 else (new, old)
            t = {id(p): ask(p, what) for p in order}
            tb.append(t[id(old)][0])
            tn.append(t[id(new)][0])
            ratios.append(tn[-1] / tb[-1])
            same &= t[id(old)][1] == t[id(new)][1]
        q = sorted(ratios)
        print(f"| {label} | {statistics.median(tb):.3f} s | {statistics.median(tn):.3f} s | "
              f"{statistics.median(tn) / statistics.median(tb):.3f} | "
              f"{statistics.median(ratios):.3f} ({q[n // 4]:.2f}-{q[3 * n // 4]:.2f}) | "
              f"{'yes' if same else 'NO'} |", flush=True)
    for p in (old, new):
        p.stdin.close()
        p.wait()


if __name__ == "__main__":
    if sys.argv[1] == "worker":
        worker(sys.argv[2])
    else:
        paired(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 11, *sys.argv[3:4])
