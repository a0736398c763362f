"""Benchmark of the generated jets (issue 3): regeneration, evaluation, size, import time.

Run:  python benchmarks/bench_jets.py            (writes benchmarks/results_jets.md)

Baseline measured in the same run: central finite differences of the numeric
map P (`symvi.paper.modal_map.fd_jacobian`) for the Jacobian, and the mpmath backend of
the same generated expressions at 50 digits.
"""
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent))

import symvi  # noqa: E402
from symvi.paper import _eval as pe  # noqa: E402
from symvi.paper import jets  # noqa: E402
from symvi.codegen.jets import fixed_point_motion  # noqa: E402
from symvi._io import write_text  # noqa: E402
from symvi.paper.modal_map import fd_jacobian  # noqa: E402


def median_time(fn, n, reps=7):
    out = []
    for _ in range(reps):
        t = time.perf_counter()
        for _ in range(n):
            fn()
        out.append((time.perf_counter() - t) / n)
    return statistics.median(out)


def md_table(header, rows):
    """Markdown table lines."""
    return (["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
            + ["| " + " | ".join(str(c) for c in row) + " |" for row in rows])


def jet_loop(kernel):
    """A numba loop ``loop(inp, n)`` calling ``kernel`` n times and consuming every output
    (so no evaluation is dead code)."""
    import numba as nb
    from numba import literal_unroll

    @nb.njit
    def loop(inp, n):
        s = 0.0
        for i in range(n):
            for v in literal_unroll(kernel((inp[0] + 1e-12 * i,) + inp[1:])):
                s += v
        return s
    return loop


def _in_loop(kernel, inp, n=20000):
    """Per-call time of ``kernel`` inside a compiled loop."""
    loop = jet_loop(kernel)
    loop(inp, 2)
    return median_time(lambda: loop(inp, n), 1) / n


def _paper_jet(p, orb, K):
    """The jet at the orbit as symvi.jet computed it for Params before issue 11 moved it
    to the N = 2 structure: the paper's evaluator, then dy*/domega and F11."""
    v = pe._evaluate(K, pe._orbit_inputs(p, orb), False)
    if K >= 2:
        dy = fixed_point_motion(v["J"], v["dwP"], False)
        v["dA"] = v["dwJ"] + v["d2"] @ dy
    return v


def main():
    p = symvi.Params(2, 5, 0, 1.5, 0.8)
    omega = 0.7369
    orb = [o for o in symvi.period1_orbits(p, omega) if o.admissible][0]
    inp = pe._orbit_inputs(p, orb)
    # regeneration of all orders into a temporary folder
    from symvi._derivations import poincare_jets as pj
    regen = []
    for _ in range(3):
        with tempfile.TemporaryDirectory() as d:
            t = time.perf_counter()
            pj.generate(d, force=True)
            regen.append(time.perf_counter() - t)
    t_regen = statistics.median(regen)
    # evaluation
    res = {}
    for K in (1, 2, 3):
        mod, _ = jets._gen(K)
        res[K] = {
            "gen": median_time(lambda: mod.f64(inp), 2000),
            "arrays": median_time(lambda: pe._evaluate(K, inp, False), 2000),
            "paper_jet": median_time(lambda: _paper_jet(p, orb, K), 1000),
            "jet_at_orbit": median_time(lambda: jets.jet(p, omega, K, orbit=orb), 1000),
            "jet_full": median_time(lambda: jets.jet(p, omega, K), 300),
            "mp50": median_time(lambda: jets.jet(p, omega, K, orbit=None, digits=50), 3, reps=3),
        }
        kern = jets.compiled(K).kernel
        kern(inp)                                             # compile or load from cache
        res[K]["compiled"] = median_time(lambda: kern(inp), 2000)
        res[K]["in_loop"] = _in_loop(kern, inp)
    t_orbit = median_time(lambda: symvi.period1_orbits(p, omega, multipliers=False), 300)
    t_fd = median_time(lambda: fd_jacobian(p, omega, orb.y), 50)
    # size and import time of each order (fresh interpreter, median of 5)
    size, imp = {}, {}
    gen_dir = Path(jets._gen(1)[0].__file__).parent
    for K in (1, 2, 3):
        f = gen_dir / f"order{K}.py"
        size[K] = (f.stat().st_size, len(f.read_text().splitlines()))
        ts = []
        for _ in range(5):
            code = ("import time,importlib,sys;import mpmath,math,symvi;t=time.perf_counter();"
                    f"importlib.import_module('symvi._generated.order{K}');"
                    "print(time.perf_counter()-t)")
            ts.append(float(subprocess.run([sys.executable, "-c", code], capture_output=True,
                                           text=True, check=True).stdout))
        imp[K] = statistics.median(ts)
    us = lambda s: f"{s * 1e6:.1f} µs"
    lines = [
        "# Generated jets: measured figures",
        "",
        f"Command: `python benchmarks/bench_jets.py` (example 1, ω = {omega}; medians of 7 runs).",
        "",
        f"Regenerating all orders (SymPy derivation + CSE + printing, both backends): "
        f"**{t_regen:.1f} s** median of 3 (target ≤ 30 s).",
        "",
    ]
    lines += md_table(
        ["order", "paper's generated f64 call", "+ numpy tensors", "+ F11 (the paper's "
         "evaluator path, before issue 11)", "`jet(orbit=...)` (N = 2 structure, since "
         "issue 11)", "ratio", "`jet()` incl. orbit solve", "mpmath 50 digits", "mp50 / f64"],
        [[K, us(r["gen"]), us(r["arrays"]), us(r["paper_jet"]), us(r["jet_at_orbit"]),
          f"{r['jet_at_orbit'] / r['paper_jet']:.2f}×", us(r["jet_full"]),
          f"{r['mp50'] * 1e3:.1f} ms", f"{r['mp50'] / r['jet_full']:.0f}×"]
         for K, r in res.items()])
    lines += ["", "Compiled evaluators (`symvi.paper.jets.compiled(K)`: the same generated code "
              "compiled by numba):", ""]
    lines += md_table(
        ["order", "Python `f64` call", "compiled kernel called from Python",
         "inside a compiled loop", "Python / compiled loop"],
        [[K, us(r["gen"]), us(r["compiled"]), f"{r['in_loop'] * 1e9:.0f} ns",
          f"{r['gen'] / r['in_loop']:.0f}×"] for K, r in res.items()])
    lines += [
        "",
        f"Targets: order-3 jet ≤ 100 µs, order-1 jet ≤ 20 µs (the generated evaluator with its numpy "
        f"tensors, column 3). The period-1 orbit solve with its admissibility check costs "
        f"{us(t_orbit)} on top (column 5).",
        "",
        f"Baseline, same run: Jacobian by central differences of the numeric map P: {us(t_fd)} "
        f"= **{t_fd / res[1]['arrays']:.0f}×** the generated order-1 evaluator "
        f"(and only ~7 digits).",
        "",
        "| order | file size | lines | import time (fresh interpreter, symvi and mpmath already imported) |",
        "|---|---|---|---|",
    ]
    for K in (1, 2, 3):
        lines.append(f"| {K} | {size[K][0] / 1024:.1f} KiB | {size[K][1]} | {imp[K] * 1e3:.1f} ms |")
    text = "\n".join(lines) + "\n"
    write_text(HERE / "results_jets.md", text)
    print(text)


if __name__ == "__main__":
    main()
