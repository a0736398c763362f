"""Benchmark of two-parameter curves (issue 13): the NS curve of the paper's example 1 in
(omega, b), about 500 points with theta and l1 at each, against a baseline in the same run:
the same continuation with finite-difference derivatives where symvi uses the generated
jets, as a tool without exact jets does (MatContM: finite differences of the map):

* the gradient of the bordered test function, by central differences of g over the
  section point and both parameters (each evaluation re-solves the flight time, so it
  differentiates the map P itself), step 1e-6 relative;
* l1 at each point from d2, d3 of P by central differences (steps 1e-4, 1e-3 relative:
  the usual balance of truncation and rounding for second and third differences).

    python benchmarks/bench_curve.py > benchmarks/results_curve.md
"""
import itertools
import statistics
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402

import symvi.curves.curve as curve_mod  # noqa: E402
from bench_jets import md_table  # noqa: E402
from symvi.continuation import continue_branch  # noqa: E402
from symvi.curves import continue_curve  # noqa: E402
from symvi.curves.system import CurveSystem  # noqa: E402
from symvi.errors import NearSingularWarning  # noqa: E402
from symvi.model import Model  # noqa: E402
from symvi.normal_forms.normal_form import kuznetsov_resolved  # noqa: E402

PAPER = Model.luo_xie(2, 5, 0, 1.5, 0.8)
BOUNDS = {"omega": (0.5, 1.0), "b": (0.1, 2.6)}
HALF = 251                         # points each way: 501 in all (the start shared)


def _solve_time(pr, u, a):
    """u with the flight time re-solved (Newton on the impact condition): P, not G."""
    m = pr.size
    u = u.copy()
    for _ in range(30):
        G, Gu, _ = pr.evaluate(u, a, check=False)
        dt = -G[m - 1] / Gu[m - 1, m - 1]
        u[m - 1] += dt
        if abs(dt) <= 1e-15 * (1 + abs(u[m - 1])):
            break
    return u


def _map(pr, y, t0, a):
    """P(y) (tau unwrapped) for a one-impact problem, from a guess t0 of the flight time."""
    u = _solve_time(pr, np.append(y, t0), a)
    G = pr.evaluate(u, a, jac=False, check=False)[0]
    d = pr.d
    out = G[:d] + y
    out[-1] += 2 * np.pi * pr.n_periods
    return out, u[-1]


class FDCurveSystem(CurveSystem):
    """The baseline: dg/dy, dg/da, dg/db by central differences of g on the map."""

    def _grad(self, pr, u, a, K):
        d, m = self.d, self.m

        def g(y, av, bv):
            p = self.problem(bv)
            uu = _solve_time(p, np.append(y, u[d:]), av)
            G, Gu, _ = p.evaluate(uu, av, check=False)
            return self.test(p.monodromy(uu, Gu)[1])[0]
        y, b = u[:d], self._pr[0]
        gu = np.zeros(m)
        for j in range(d):
            h = 1e-6 * max(1.0, abs(y[j]))
            e = np.zeros(d)
            e[j] = h
            gu[j] = (g(y + e, a, b) - g(y - e, a, b)) / (2 * h)
        ha, hb = 1e-6 * max(1.0, abs(a)), 1e-6 * max(1.0, abs(b))
        ga = (g(y, a + ha, b) - g(y, a - ha, b)) / (2 * ha)
        gb = (g(y, a, b + hb) - g(y, a, b - hb)) / (2 * hb)
        self.problem(b)
        return gu, ga, gb


def fd_first_lyapunov(orbit, lam):
    """l1 from d2, d3 of P by central differences (the baseline's normal form)."""
    from symvi.orbits.periodic import Problem
    pr = Problem(orbit.model, orbit.n, orbit.p, omega=orbit.omega)
    y0, t0 = np.array(orbit.u[:pr.d]), float(orbit.times[0])
    d = pr.d

    def P(y):
        return _map(pr, y, t0, None)[0]
    A = np.empty((d, d))
    for j in range(d):
        h = 1e-6 * max(1.0, abs(y0[j]))
        e = np.zeros(d)
        e[j] = h
        A[:, j] = (P(y0 + e) - P(y0 - e)) / (2 * h)
    d2 = np.empty((d, d, d))
    d3 = np.empty((d, d, d, d))
    for order, T, hrel in ((2, d2, 1e-4), (3, d3, 1e-3)):
        for axes in itertools.combinations_with_replacement(range(d), order):
            acc = np.zeros(d)
            hs = [hrel * max(1.0, abs(y0[a])) for a in axes]
            for signs in itertools.product((1, -1), repeat=order):
                z = y0.copy()
                for s, a, h in zip(signs, axes, hs):
                    z[a] += s * h
                acc += np.prod(signs) * P(z)
            v = acc / np.prod([2 * h for h in hs])
            for perm in set(itertools.permutations(axes)):
                T[(slice(None),) + perm] = v
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NearSingularWarning)
            _, l1, noise, _ = kuznetsov_resolved(A, d2, d3)
    except Exception:          # noqa: BLE001 - the baseline reports what it can
        return None, None
    return l1, noise


def run_curve(fd):
    br = continue_branch(PAPER, "omega", 0.70, 0.76)
    ns = next(s for s in br.special if s.kind == "ns")
    old_sys, old_l1 = curve_mod.CurveSystem, curve_mod.first_lyapunov
    if fd:
        curve_mod.CurveSystem, curve_mod.first_lyapunov = FDCurveSystem, fd_first_lyapunov
    try:
        t0 = time.perf_counter()
        c = continue_curve(PAPER, "ns", ("omega", "b"), ns.orbit, bounds=BOUNDS,
                           max_points=HALF, locate=False)
        return time.perf_counter() - t0, c
    finally:
        curve_mod.CurveSystem, curve_mod.first_lyapunov = old_sys, old_l1


def main():
    repeat = 3
    rows, exact, base = [], [], []
    for _ in range(repeat):
        te, ce = run_curve(False)
        tb, cb = run_curve(True)
        exact.append(te)
        base.append(tb)
    n = len(ce)
    assert all(pt.l1 is not None for pt in ce.points if pt.ns)
    # the two agree where both are resolved: how far the baseline's l1 is off
    common = min(len(ce), len(cb))
    err = max(abs(a.l1 - b.l1) / abs(a.l1) for a, b in zip(ce.points[:common], cb.points[:common])
              if a.l1 and b.l1)
    te, tb = statistics.median(exact), statistics.median(base)
    rows.append(("NS curve, (omega, b), theta and l1 at every point", f"{n}",
                 f"{te:.3f} s ({1e3 * te / n:.2f} ms/point)",
                 f"{tb:.3f} s ({1e3 * tb / len(cb):.2f} ms/point)", f"{tb / te:.1f}x"))
    print("# Two-parameter curves (issue 13)\n")
    print("Command: `python benchmarks/bench_curve.py > benchmarks/results_curve.md` "
          f"(median of {repeat}, exact and baseline alternated in one run).\n")
    print("\n".join(md_table(("what", "points", "symvi (generated jets)", "baseline (finite differences)",
                    "baseline / symvi"), rows)))
    print(f"\nTarget: an NS curve of 500 points with l1 along it in <= 2 s. Largest relative "
          f"difference of the baseline's l1 from symvi's along the curve: {err:.1e}.")


if __name__ == "__main__":
    main()
