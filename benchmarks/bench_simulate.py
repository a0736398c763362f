"""Benchmark of the impact simulation (issue 5): impacts/s and one-step error.

Run:  python benchmarks/bench_simulate.py      (writes benchmarks/results_simulate.md)

Measured in the same run, on the same trajectories (points on the attractors of
the paper's examples):

* symvi: the compiled finder and map (``symvi.flow.compiled``, on which
  ``simulate`` runs ``Params`` as ``Model.luo_xie``), one trajectory and a
  parallel batch over many omegas (numba threads);
* the pure-Python reference map ``symvi.paper.modal_map.poincare_map`` (float64);
* baseline: ``scipy.integrate.solve_ivp`` on eq. (3) with a terminal event at
  x1 = b, as a user would write it, at the default and at tight tolerances.

One-step error: time of flight and state at the next impact against the same
map at 40 digits (``poincare_map(..., digits=40)``).
"""
import math
import statistics
import sys
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent))

import numba  # noqa: E402

from symvi import Model, Params  # noqa: E402
from symvi._io import write_text  # noqa: E402
from symvi.flow import compiled as cf  # noqa: E402

from bench_jets import median_time  # noqa: E402  median_time(fn, calls, reps): per call
from symvi.paper.modal_map import poincare_map  # noqa: E402
from symvi.simulations.simulation import simulate  # noqa: E402

CASES = [(Params(2, 5, 0, 1.5, 0.8), 0.7372, "ex1 circle"),
         (Params(2, 5, 0, 1.5, 0.8), 0.7440, "ex1 doubled torus"),
         (Params(2, 5, 0, 1.5, 0.8), 0.7555, "ex1 0.7555"),
         (Params(4, 2, 0, 1.8, 0.8), 0.4944, "ex2 chaos")]
N_ERR = 40          # one-step error sample per case
N_IVP = 40          # solve_ivp impacts timed per case


def ivp_step(params, omega, y, rtol, atol):
    """Next impact from section point y with solve_ivp (RK45) and an x1 = b event."""
    M = np.diag([1.0, params.mu_m])
    K = np.array([[1.0, -1.0], [-1.0, 1.0 + params.mu_k]])
    Minv = np.linalg.inv(M)
    P = np.array([1 - params.f2, params.f2])
    v1, x2, v2, tau = y

    def rhs(t, s):
        x, v = s[:2], s[2:]
        return np.concatenate([v, Minv @ (P * math.sin(omega * t + tau) - K @ x)])

    def hit(t, s):
        return s[0] - params.b
    hit.terminal, hit.direction = True, 1
    sol = solve_ivp(rhs, (0, 2000 * math.pi / omega), [params.b, x2, v1, v2], events=hit,
                    rtol=rtol, atol=atol)
    te = sol.t_events[0][0]
    s = sol.y_events[0][0]
    return te, np.array([-params.r * s[2], s[1], s[3], (tau + omega * te) % (2 * math.pi)])


def one_step_errors(params, omega, pts):
    c = cf.constants(Model.of(params), omega)
    rows = {"symvi": [], "ivp default": [], "ivp tight": []}
    for y in pts:
        ref = poincare_map(params, omega, y, digits=40)
        tr = float(ref.t)
        yr = np.array([float(v) for v in ref.y])
        st, te, yn, *_ = cf.step(c, y)
        got = {"symvi": (te, yn),
               "ivp default": ivp_step(params, omega, y, 1e-3, 1e-6),
               "ivp tight": ivp_step(params, omega, y, 1e-10, 1e-12)}
        for k, (t, z) in got.items():
            dz = np.abs(z - yr)
            dz[3] = min(dz[3], 2 * math.pi - dz[3])
            rows[k].append(max(abs(t - tr), dz.max()))
    return {k: (statistics.median(v), max(v)) for k, v in rows.items()}


def _lyapunov_python(sim):
    """Baseline: the same QR method with the Python evaluator and numpy, point by point."""
    from symvi.simulations.diagnostics import jacobian
    sec, te = np.asarray(sim.section), np.diff(sim.t)
    Q, logs = np.eye(4), np.empty((len(te), 4))
    for k in range(len(te)):
        Q, R = np.linalg.qr(jacobian(sim.params, sim.omega, sec[k], te[k]) @ Q)
        d = np.diag(R)
        Q = Q * np.sign(d)
        logs[k] = np.log(np.abs(d))
    return np.sort(logs.mean(axis=0))[::-1]


def lyapunov_section(n=4000):
    """symvi.diagnostics.lyapunov (compiled generated Jacobian + QR) against the baseline."""
    from symvi.simulations.diagnostics import lyapunov
    out = ["## Lyapunov exponents (QR method), 4000 section points", "",
           "| case | ω | compiled (`diagnostics.lyapunov`) | Python evaluator + numpy QR | ratio "
           "| max difference of the exponents |", "|---|---|---|---|---|---|"]
    for params, omega, name in CASES:
        sim = simulate(params, omega, n_impacts=n + 1, transient=20000)
        lyapunov(sim)
        tc = median_time(lambda: lyapunov(sim), 1, reps=5)
        tp = median_time(lambda: _lyapunov_python(sim), 1, reps=3)
        diff = np.max(np.abs(lyapunov(sim).exponents - _lyapunov_python(sim)))
        out.append(f"| {name} | {omega} | {tc * 1e3:.3g} ms | {tp * 1e3:.3g} ms | "
                   f"{tp / tc:.3g}× | {diff:.1e} |")
    return out + [""]


def rates(params, omega, y0, n=200_000, n_ivp=N_IVP):
    """Impacts/s from y0: symvi's compiled map (with its finder steps per impact), and
    solve_ivp with an x1 = b event at default and tight tolerances, same trajectory."""
    c = cf.constants(Model.of(params), omega)
    cf.run(c, y0, 10)
    out = {"symvi": n / median_time(lambda: cf.run(c, y0, n), 1, reps=5),
           "steps": cf.run(c, y0, n)[4] / n}
    for label, rtol, atol in (("default", 1e-3, 1e-6), ("tight", 1e-10, 1e-12)):
        def ivp_run():
            z = y0
            for _ in range(n_ivp):
                z = tuple(ivp_step(params, omega, z, rtol, atol)[1])
        out[label] = n_ivp / median_time(ivp_run, 1, reps=3)
    return out


def main():
    nthreads = numba.get_num_threads()
    lines = ["# Impact simulation: measured figures", "",
             "Command: `python benchmarks/bench_simulate.py` (medians of 5 runs; "
             f"{nthreads} numba threads; start points on each attractor after 20000 impacts).", ""]
    single, ref_rate, ivp = [], [], {}
    errs = {}
    for params, omega, name in CASES:
        s = simulate(params, omega, n_impacts=N_ERR, transient=20000)
        y0 = tuple(s.section[-1])
        r = rates(params, omega, y0)
        single.append((name, omega, r["symvi"], r["steps"]))
        for label in ("default", "tight"):
            ivp.setdefault(label, []).append(r[label])
        # pure-Python reference map, same start
        m = 200
        y = y0

        def ref():
            z = y
            for _ in range(m):
                z = poincare_map(params, omega, z).y
        ref_rate.append(m / median_time(ref, 1, reps=3))
        errs[name] = one_step_errors(params, omega, [tuple(v) for v in s.section])

    lines += ["## One trajectory (200 000 impacts)", "",
              "| case | ω | symvi impacts/s | finder steps/impact | reference map (Python) "
              "impacts/s | solve_ivp default | solve_ivp tight | symvi / ivp tight |",
              "|---|---|---|---|---|---|---|---|"]
    for i, (name, omega, rate, steps) in enumerate(single):
        lines.append(f"| {name} | {omega} | {rate:,.0f} | {steps:.2f} | {ref_rate[i]:,.0f} | "
                     f"{ivp['default'][i]:,.0f} | {ivp['tight'][i]:,.0f} | "
                     f"{rate / ivp['tight'][i]:,.0f}× |")
    med_single = statistics.median(r for _, _, r, _ in single)
    med_ivp = statistics.median(ivp["tight"])
    lines += ["", f"Median single-trajectory rate: **{med_single:,.0f} impacts/s** "
              f"(target ≥ 100 000); median ratio to solve_ivp (tight): "
              f"**{statistics.median(r / v for (_, _, r, _), v in zip(single, ivp['tight'])):,.0f}×**"
              f", to solve_ivp (default tolerances): "
              f"**{statistics.median(r / v for (_, _, r, _), v in zip(single, ivp['default'])):,.0f}×**.",
              f"(solve_ivp tight median {med_ivp:,.0f} impacts/s.)", ""]

    # batch: many omegas of example 1 in parallel
    p = Params(2, 5, 0, 1.5, 0.8)
    oms = np.linspace(0.7300, 0.7560, 256)
    from symvi.simulations.simulation import sweep_starts
    starts = sweep_starts(p, oms)
    model = Model.of(p)
    C = np.array([cf.constants(model, w) for w in oms])
    nb_imp = 4000
    cf.run_batch(C[:2], starts[:2], 10)
    dt = median_time(lambda: cf.run_batch(C, starts, nb_imp), 1, reps=5)
    agg = len(oms) * nb_imp / dt
    dt1 = median_time(lambda: [cf.run(C[i], starts[i], nb_imp) for i in range(len(oms))], 1,
                      reps=5)
    lines += ["## Batch: 256 values of ω in [0.7300, 0.7560] (example 1), 4000 impacts each", "",
              "| mode | impacts/s |", "|---|---|",
              f"| parallel batch (`run_batch`, {nthreads} threads) | **{agg:,.0f}** |",
              f"| same runs one after another | {len(oms) * nb_imp / dt1:,.0f} |", "",
              f"Aggregate {agg:,.0f} impacts/s (target ≥ 1 000 000); speed-up over serial "
              f"{dt1 / dt:.2f}× on {nthreads} threads.", ""]

    lines += ["## One-step error against the same map at 40 digits", "",
              f"Max over time of flight and the four section coordinates; median (max) of "
              f"{N_ERR} points per case.", "",
              "| case | symvi | solve_ivp default (rtol 1e-3) | solve_ivp tight (rtol 1e-10, atol 1e-12) |",
              "|---|---|---|---|"]
    for name, e in errs.items():
        lines.append(f"| {name} | {e['symvi'][0]:.1e} ({e['symvi'][1]:.1e}) | "
                     f"{e['ivp default'][0]:.1e} ({e['ivp default'][1]:.1e}) | "
                     f"{e['ivp tight'][0]:.1e} ({e['ivp tight'][1]:.1e}) |")
    lines += lyapunov_section()
    text = "\n".join(lines) + "\n"
    write_text(HERE / "results_simulate.md", text)
    print(text)


if __name__ == "__main__":
    main()
