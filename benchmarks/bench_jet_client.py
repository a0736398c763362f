"""symvi.jet(Params, orbit=...) at example 1's orbit (omega = 0.7369), orders 1, 2, 3:
prints the three medians in µs (7 runs of 1000 calls each).  Run it beside a worktree of
another commit, alternating processes, for a same-run baseline:

    for i in 1 2 3; do PYTHONPATH=<worktree> python benchmarks/bench_jet_client.py; \
                       python benchmarks/bench_jet_client.py; done
"""
import statistics
import time
import warnings

import symvi

warnings.simplefilter("ignore")
P, W = symvi.Params(2, 5, 0, 1.5, 0.8), 0.7369
ORB = [o for o in symvi.period1_orbits(P, W) if o.admissible][0]
out = []
for K in (1, 2, 3):
    for _ in range(200):
        symvi.jet(P, W, K, orbit=ORB)
    ts = []
    for _ in range(7):
        t = time.perf_counter()
        for _ in range(1000):
            symvi.jet(P, W, K, orbit=ORB)
        ts.append((time.perf_counter() - t) / 1000)
    out.append(statistics.median(ts) * 1e6)
print(" ".join(f"{x:.1f}" for x in out))
