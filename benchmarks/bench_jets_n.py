"""Benchmark of any model (issue 11): regeneration, Python and compiled jets and
`hopf_points` of the damped 3-mass model, and the paper's model through its own
chain (the baseline) and through the any-model chain, in the same run; the
period-1 solver also through its numpy reference (``period1.COMPILED = False``,
the any-model chain before its compiled solver).

    python benchmarks/bench_jets_n.py
"""
import contextlib
import math
import sys
import tempfile
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import numba as nb  # noqa: E402
import numpy as np  # noqa: E402

import symvi  # noqa: E402
from bench_jets import md_table, median_time  # noqa: E402
from symvi._compiled import kernel_of  # noqa: E402
from symvi.codegen.jets import jet_at  # noqa: E402
from symvi.codegen.layout import assemble, module  # noqa: E402
from symvi.flow.linear import LinearFlow  # noqa: E402
from symvi.model import Model, Stop  # noqa: E402
from symvi.orbits import period1, period1_orbits  # noqa: E402

THREE = Model(mass=[1.0, 1.5, 0.8],
              stiffness=[[1.0, -1.0, 0.0], [-1.0, 1.7, -0.7], [0.0, -0.7, 2.7]],
              damping=[[0.015, -0.005, 0.0], [-0.005, 0.0235, -0.0035], [0.0, -0.0035, 0.0215]],
              forcing=[1.0, 0.5, 0.0], stop=Stop(mass=2, gap=0.5, restitution=0.8))


@contextlib.contextmanager
def reference_period1():
    """The numpy reference of the period-1 solver (the any-model chain before the
    compiled one)."""
    old, period1.COMPILED = period1.COMPILED, False
    try:
        yield
    finally:
        period1.COMPILED = old


def compiled_loop(kernel):
    @nb.njit
    def loop(inp, n):
        s = 0.0
        for i in range(n):
            for v in kernel((inp[0] + 1e-12 * i,) + inp[1:]):
                s += v
        return s
    return loop


def main():
    from symvi._derivations import impact_jets as ij
    rows = []
    for n in (3, 4):
        with tempfile.TemporaryDirectory() as d:
            t = time.perf_counter()
            ij.generate(d, ns=(n,), force=True)
            rows.append((f"regenerate N = {n} (orders 1-3)", f"{time.perf_counter() - t:.1f} s",
                         "<= 120 s (N = 4)"))
    warnings.simplefilter("ignore")
    w = 0.95
    o = [x for x in period1_orbits(THREE, w) if x.admissible][0]
    fl, T = LinearFlow.of(THREE), 2 * math.pi / w
    F = fl.forcing(w)
    m3, _ = module(3, 3)
    inp = assemble(fl, F, o.y, T, 3)
    t_f64 = median_time(lambda: m3.f64(inp), 200)
    t_asm = median_time(lambda: assemble(fl, F, o.y, T, 3), 200)
    t_jet = median_time(lambda: jet_at(THREE, w, o.y, T, 3), 100)
    rows.append(("N = 3 damped, order-3 jet in Python (inputs + generated f64)",
                 f"{(t_f64 + t_asm) * 1e6:.0f} µs (f64 {t_f64 * 1e6:.0f}, inputs "
                 f"{t_asm * 1e6:.0f})", "<= 300 µs"))
    rows.append(("N = 3 damped, `jet_at` order 3 (+ tensors, dy*/domega)",
                 f"{t_jet * 1e6:.0f} µs", ""))
    t = time.perf_counter()
    k = kernel_of(m3)
    loop = compiled_loop(k)
    loop(inp, 2)
    t_comp = time.perf_counter() - t
    n = 20000
    t_k = median_time(lambda: loop(inp, n), 1) / n
    rows.append(("N = 3 damped, order-3 kernel compiled, in a numba loop",
                 f"{t_k * 1e6:.2f} µs (first compile {t_comp:.0f} s, then cached)", "<= 5 µs"))
    # the paper: its own modal chain (the oracle since issue 11; symvi's Params path before
    # it) as the baseline, against Params on the N = 2 structure, same run
    from symvi.paper import _eval as pe
    from symvi.codegen.jets import fixed_point_motion
    from symvi.paper import modal_orbit
    p = symvi.Params(2, 5, 0, 1.5, 0.8)
    pm = Model.luo_xie(2, 5, 0, 1.5, 0.8)
    wp = 0.7369
    op = [x for x in symvi.period1_orbits(p, wp) if x.admissible][0]

    def paper_jet():
        v = pe._evaluate(3, pe._orbit_inputs(p, op), False)
        v["dA"] = v["dwJ"] + v["d2"] @ fixed_point_motion(v["J"], v["dwP"], False)
        return v
    # the "order-3 jet 44 µs": the generated evaluator with its tensors, inputs
    # included (modal: closed-form inputs; N = 2 structure: codegen.layout.assemble)
    from symvi.codegen.jets import evaluate
    flp, Fp = LinearFlow.of(pm), LinearFlow.of(pm).forcing(wp)
    yp, Tp = tuple(float(v) for v in op.y), 2 * math.pi / wp
    t_ev_old = median_time(lambda: pe._evaluate(3, pe._orbit_inputs(p, op), False), 200)
    t_ev_new = median_time(lambda: evaluate(flp, Fp, yp, Tp, 3), 200)
    rows.append(("paper model, order-3 generated evaluator + tensors (inputs included): the "
                 "paper's modal evaluator (baseline, the issue's 44 µs)",
                 f"{t_ev_old * 1e6:.0f} µs", ""))
    rows.append(("paper model, order-3 generated evaluator + tensors (inputs included): the "
                 "N = 2 structure", f"{t_ev_new * 1e6:.0f} µs ({t_ev_new / t_ev_old:.2f}x the "
                 "baseline)", "<= 1.2x"))
    t_old = median_time(paper_jet, 100)
    t_new = median_time(lambda: symvi.jet(p, wp, 3, orbit=op), 100)
    rows.append(("paper model, order-3 jet with F11 at the orbit: the paper's modal "
                 "evaluator (baseline, `symvi.jet` before issue 11)", f"{t_old * 1e6:.0f} µs", ""))
    rows.append(("paper model, order-3 jet with F11 at the orbit: `symvi.jet(Params)` on the "
                 "N = 2 structure", f"{t_new * 1e6:.0f} µs ({t_new / t_old:.2f}x the baseline)",
                 ""))
    # period-1 orbits: the compiled any-model solver and its numpy reference (COMPILED =
    # False, the solver before it), per omega over a scan of ex. 1's interval
    ws = [float(x) for x in np.linspace(0.70, 0.76, 50)]

    def scan(f, model):
        return median_time(lambda: [f(model, x) for x in ws], 1, reps=9) / len(ws)

    t_o_old = scan(modal_orbit.period1_orbits, p)
    t_o_new = scan(symvi.period1_orbits, p)
    with reference_period1():
        t_o_ref = scan(period1_orbits, pm)
    rows.append(("paper model, both period-1 orbits with multipliers: the paper's modal closed "
                 "form (baseline, `symvi.period1_orbits(Params)` before issue 11)",
                 f"{t_o_old * 1e6:.0f} µs", ""))
    rows.append(("paper model, both period-1 orbits with multipliers: `symvi.period1_orbits"
                 "(Params)` on the any-model chain",
                 f"{t_o_new * 1e6:.0f} µs ({t_o_new / t_o_old:.2f}x the baseline)", "<= 1x"))
    rows.append(("paper model, both period-1 orbits: any-model chain, numpy reference "
                 "(`period1.COMPILED = False`, before)",
                 f"{t_o_ref * 1e6:.0f} µs ({t_o_ref / t_o_old:.2f}x the baseline)", ""))
    ws = [float(x) for x in np.linspace(0.95, 1.06, 50)]
    t3_new = scan(period1_orbits, THREE)
    with reference_period1():
        t3_ref = scan(period1_orbits, THREE)
    rows.append(("N = 3 damped, both period-1 orbits with multipliers, compiled / numpy "
                 "reference", f"{t3_new * 1e6:.0f} / {t3_ref * 1e6:.0f} µs "
                 f"({t3_ref / t3_new:.2f}x faster)", ""))
    # hopf_points: the N = 3 chain (two NS points), the paper's model both ways
    from symvi import hopf_points
    hopf_points(THREE, 0.99, 1.06)
    t_h3 = median_time(lambda: hopf_points(THREE, 0.99, 1.06), 1, reps=9)
    rows.append(("N = 3 damped, `hopf_points` on [0.99, 1.06] (two NS points, normal forms, "
                 "precision estimates)", f"{t_h3 * 1e3:.0f} ms", "<= 300 ms"))
    t_hp = median_time(lambda: hopf_points(p, 0.70, 0.76), 1, reps=9)
    t_hm = median_time(lambda: hopf_points(pm, 0.70, 0.76), 1, reps=9)
    rows.append(("paper model, `hopf_points` ex. 1 on [0.70, 0.76]: `Params` (the any-model "
                 "chain since issue 11; against the commit before, see bench_hopf_client.py)",
                 f"{t_hp * 1e3:.1f} ms", ""))
    rows.append(("paper model, `hopf_points` ex. 1 on [0.70, 0.76]: `Model.luo_xie`",
                 f"{t_hm * 1e3:.1f} ms ({t_hm / t_hp:.2f}x `Params`)", ""))
    print("\n".join(md_table(["what", "median", "target"], rows)))


if __name__ == "__main__":
    main()
