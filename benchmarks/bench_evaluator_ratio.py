"""The paper's order-3 jet as the generated evaluator with its tensors, inputs included
(the issue-11 "44 µs" row): the paper's modal evaluator against the N = 2 structure,
interleaved in one process (31 rounds of 300 calls each), so the host's noise hits
both alike.  Prints the medians, minima and the median of the per-round ratios.

    python benchmarks/bench_evaluator_ratio.py
"""
import time, statistics, math
import symvi
from symvi.paper import _eval as pe
from symvi.codegen.jets import evaluate
from symvi.flow.linear import LinearFlow
from symvi.model import Model
p = symvi.Params(2,5,0,1.5,0.8); pm=Model.of(p); w=0.7369
op=[o for o in symvi.period1_orbits(p,w) if o.admissible][0]
fl=LinearFlow.of(pm); F=fl.forcing(w); y=tuple(float(v) for v in op.y); T=2*math.pi/w
a=lambda: pe._evaluate(3, pe._orbit_inputs(p, op), False)
b=lambda: evaluate(fl, F, y, T, 3)
ra, rb, rat = [], [], []
for r in range(31):
    s=time.perf_counter()
    for _ in range(300): a()
    ta=(time.perf_counter()-s)/300
    s=time.perf_counter()
    for _ in range(300): b()
    tb=(time.perf_counter()-s)/300
    ra.append(ta); rb.append(tb); rat.append(tb/ta)
print(f"modal {statistics.median(ra)*1e6:.1f} (min {min(ra)*1e6:.1f}) N=2 {statistics.median(rb)*1e6:.1f} (min {min(rb)*1e6:.1f}) ratio median {statistics.median(rat):.3f} min-ratio {min(rb)/min(ra):.3f}")
