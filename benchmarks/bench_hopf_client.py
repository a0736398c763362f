"""symvi.hopf_points on example 1 over [0.70, 0.76] for Params (with the paper's f1 of
eq. (60)) and Model.luo_xie: prints "median min median min" (ms, Params then Model).  Run it beside a worktree of another
commit, alternating processes, for a same-run baseline:

    for i in 1 2 3; do PYTHONPATH=<worktree> python benchmarks/bench_hopf_client.py; \
                       python benchmarks/bench_hopf_client.py; done
"""
import sys, time, warnings, statistics
warnings.simplefilter("ignore")
from symvi import Model, Params, hopf_points   # public names: the same in every commit
P = Params(2, 5, 0, 1.5, 0.8); M = Model.luo_xie(2, 5, 0, 1.5, 0.8)
out = []
for x in (P, M):
    for _ in range(3): hopf_points(x, 0.70, 0.76)
    ts = []
    for _ in range(21):
        t = time.perf_counter(); hopf_points(x, 0.70, 0.76); ts.append(time.perf_counter() - t)
    out.append((statistics.median(ts) * 1e3, min(ts) * 1e3))
print(" ".join(f"{a:.2f} {b:.2f}" for a, b in out))
