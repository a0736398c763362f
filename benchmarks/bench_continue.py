"""Benchmark of continuation (issue 12): a 1000-point period-1 branch of the paper's model
with multipliers and every test function, and n-p Newton solves (p = 1, 2, 4), each against
a baseline in the same run: the same code with finite-difference Jacobians (forward
differences of the shooting residual, step sqrt(eps) relative), which is how a user without
exact derivatives would do it.  A second reference, also in the same run: the same exact
system evaluated by the numpy reference (``Problem.compiled = False``), i.e. without the
compiled shooting kernel of symvi.orbits._shooting.

    python benchmarks/bench_continue.py > benchmarks/results_continue.md
"""
import statistics
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402

import symvi  # noqa: E402
import symvi.continuation.branch as branch_mod  # noqa: E402
import symvi.orbits.periodic as periodic_mod  # noqa: E402
from bench_jets import md_table  # noqa: E402
from symvi.continuation import continue_branch, switch_at_flip  # noqa: E402
from symvi.model import Model, Stop  # noqa: E402
from symvi.orbits.periodic import Problem, periodic_orbit  # noqa: E402

PAPER = Model.luo_xie(2, 5, 0, 1.5, 0.8)
ONE_DAMPED = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                   stop=Stop(mass=1, gap=0.0, restitution=0.8))


class FDProblem(Problem):
    """The baseline: G_u and G_lam by forward differences of G (m + 1 residuals)."""

    def evaluate(self, u, lam, jac=True, dparam=False, check=True):
        G = Problem.evaluate(self, u, lam, jac=False, check=check)[0]
        Gu = Gl = None
        if jac:
            Gu = np.empty((len(G), len(u)))
            for j in range(len(u)):
                h = 1.5e-8 * max(1.0, abs(u[j]))
                v = u.copy()
                v[j] += h
                Gu[:, j] = (Problem.evaluate(self, v, lam, jac=False, check=False)[0] - G) / h
        if dparam:
            h = 1.5e-8 * max(1.0, abs(lam))
            Gl = (Problem.evaluate(self, u, lam + h, jac=False, check=False)[0] - G) / h
        return G, Gu, Gl


class NumpyProblem(Problem):
    """The numpy reference of the same exact system (no compiled kernel)."""

    compiled = False


def with_problem(cls, fn):
    old = branch_mod.Problem, periodic_mod.Problem
    branch_mod.Problem = periodic_mod.Problem = cls
    try:
        return fn()
    finally:
        branch_mod.Problem, periodic_mod.Problem = old


def branch_1000():
    # h_max chosen so that omega in [1.0, 1.3] takes about 1000 points
    return continue_branch(PAPER, "omega", 1.3, 1.0, h_max=0.0021, max_points=1000,
                           through=True)


def timed(fn, reps):
    ts = []
    out = None
    for _ in range(reps):
        t = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts), out


def main():
    warnings.simplefilter("ignore")
    branch_1000()                                    # warm-up (imports, caches)
    t_exact, br = timed(branch_1000, 5)
    t_fd, br_fd = timed(lambda: with_problem(FDProblem, branch_1000), 3)
    t_np, br_np = timed(lambda: with_problem(NumpyProblem, branch_1000), 3)
    hopf = symvi.hopf_points(PAPER, 1.0, 1.3)
    ns = [s.value for s in br.special if s.kind == "ns"]
    ns_fd = [s.value for s in br_fd.special if s.kind == "ns"]
    err = abs(ns[0] - hopf.points[0].omega_c) if ns else float("nan")
    err_fd = abs(ns_fd[0] - hopf.points[0].omega_c) if ns_fd else float("nan")
    l1 = [s.coefficients["l1"] for s in br.special if s.kind == "ns"]
    l1_fd = [s.coefficients["l1"] for s in br_fd.special if s.kind == "ns"]
    # n-p Newton solves from a guess 1e-4 off, p = 1, 2, 4 (the 4-4 orbit by two switches)
    b1 = continue_branch(ONE_DAMPED, "omega", 2.0, 3.0)
    b2 = switch_at_flip(b1, [s for s in b1.special if s.kind == "flip"][0])
    b4 = switch_at_flip(b2, [s for s in b2.special if s.kind == "flip"][0])
    rows_np = []
    for b in (b1, b2, b4):
        pt = b.points[len(b) // 3]
        g = np.array(pt.orbit.points) + 1e-4
        solve = (lambda pt=pt, g=g, b=b: periodic_orbit(ONE_DAMPED, n=b.n, p=b.p, guess=g,
                                                         omega=pt.value))
        solve()
        te, o = timed(solve, 31)
        tf, of = timed(lambda: with_problem(FDProblem, solve), 11)
        tn, _ = timed(lambda: with_problem(NumpyProblem, solve), 11)
        rows_np.append((f"{b.n}-{b.p} at omega = {pt.value:.6f}", f"{te * 1e3:.2f} ms",
                        f"{tf * 1e3:.2f} ms", f"{tf / te:.1f}x", f"{tn * 1e3:.2f} ms",
                        f"{tn / te:.1f}x", f"{o.residual:.1e} / {of.residual:.1e}"))
    print("# Continuation (issue 12)\n")
    print(f"Command: `python benchmarks/bench_continue.py`; {time.strftime('%Y-%m-%d')}; "
          "medians; baselines in the same run: the same code with forward-difference "
          "Jacobians, and the numpy reference of the exact system (Problem.compiled = False)."
          "\n")
    print("## Period-1 branch of the paper's model, omega from 1.3 to 1.0, with multipliers, "
          "admissibility and every test function (fold, flip, NS, grazing), special points "
          "located\n")
    rows = [("exact (symvi)", len(br), f"{t_exact:.3f} s", f"{t_exact / len(br) * 1e3:.3f} ms",
             f"{1000 * t_exact / len(br):.3f} s", f"{err:.1e}", f"{l1[0]:.12g}" if l1 else "-"),
            ("finite differences", len(br_fd), f"{t_fd:.3f} s",
             f"{t_fd / len(br_fd) * 1e3:.3f} ms", f"{1000 * t_fd / len(br_fd):.3f} s",
             f"{err_fd:.1e}", f"{l1_fd[0]:.12g}" if l1_fd else "-"),
            ("exact, numpy reference", len(br_np), f"{t_np:.3f} s",
             f"{t_np / len(br_np) * 1e3:.3f} ms", f"{1000 * t_np / len(br_np):.3f} s", "", "")]
    print("\n".join(md_table(("derivatives", "points", "time", "per point", "per 1000 points",
                              "|omega_NS - hopf_points|", "l1 at NS"), rows)))
    per = t_exact / len(br)
    print(f"\nRatio per point, FD baseline / exact: {t_fd / len(br_fd) / per:.2f}x;"
          f" numpy reference / compiled: {t_np / len(br_np) / per:.2f}x."
          " Target: 1000 points <= 1 s.\n")
    print("## n-p Newton solves (ONE_DAMPED: m = k = 1, c = 0.05, gap 0, r = 0.8), from a guess "
          "1e-4 off; target <= 2 ms for p <= 4\n")
    print("\n".join(md_table(("orbit", "exact", "finite differences", "ratio FD / exact",
                              "exact, numpy reference", "ratio numpy / compiled",
                              "residual exact / FD"), rows_np)))


if __name__ == "__main__":
    main()
