"""Benchmark of the nonlinear flow (issue 28): its two integrators, accuracy and impacts/s.

Run:  python benchmarks/bench_nonlinear_flow.py      (writes benchmarks/results_nonlinear_flow.md)

The model: the 1-DOF impact Duffing oscillator x'' + 0.1 x' + x + beta x^3 = sin(omega t +
tau), a rigid stop at x = 0.5 with r = 0.8, omega = 1.3, beta = 0.5.  Measured in the same
run:

* accuracy of :class:`symvi.flow.nonlinear.NonlinearFlow` with each of its integrators
  -- the Taylor method (:mod:`symvi.flow.taylor`, events on the solution's polynomial) and
  DOP853 (events on the dense output) --: the first impact of N_ACC flights from points of
  a run, against mpmath's Taylor integrator (``mpmath.odefun``) at 30 digits, its event
  located by ``findroot``; and against ``solve_ivp`` (DOP853, rtol = atol = 1e-13, an
  event);
* impacts/s of one trajectory: the nonlinear flow with each integrator (beta = 0.5 and
  beta = 0), the baseline -- the exact linear flow's compiled run
  (``symvi.flow.compiled.run``) on the same model with beta = 0 -- and ``solve_ivp`` with
  events, as a user would write it.
"""
import math
import statistics
import sys
import time
from pathlib import Path

import mpmath
import numpy as np
from scipy.integrate import solve_ivp

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent))

from symvi import Model, Stop  # noqa: E402
from symvi._io import write_text  # noqa: E402
from symvi.flow import compiled as cf  # noqa: E402
from symvi.flow.nonlinear import NonlinearFlow  # noqa: E402

LIN = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
OMEGA, BETA, GAP, Y0 = 1.3, 0.5, 0.5, (-0.3, 0.1)
N_ACC = 10            # flights checked against mpmath
N_RUN = 20000         # impacts of a timed run of the nonlinear flow
N_LIN = 200000        # impacts of a timed run of the exact linear flow
N_IVP = 40            # impacts of solve_ivp timed
METHODS = {"taylor": "nonlinear flow, Taylor", "dop853": "nonlinear flow, DOP853"}


def rhs(beta, omega, tau):
    def f(t, y):
        return [y[1], math.sin(omega * t + tau) - 0.1 * y[1] - y[0] - beta * y[0] ** 3]
    return f


def mp_impact(z0, tau, t_guess):
    """(t_e, v_e-) of the first impact from z0 at 30 digits (mpmath.odefun, findroot)."""
    with mpmath.workdps(30):
        b, c = mpmath.mpf(BETA), mpmath.mpf("0.1")
        F = mpmath.odefun(lambda t, y: [y[1], mpmath.sin(OMEGA * t + tau) - c * y[1] - y[0]
                                        - b * y[0] ** 3], 0, [mpmath.mpf(v) for v in z0])
        te = mpmath.findroot(lambda t: F(t)[0] - GAP, mpmath.mpf(t_guess))
        return float(te), float(F(te)[1])


def ivp_impact(z0, tau, beta=BETA):
    ev = lambda t, y: y[0] - GAP                                   # noqa: E731
    ev.terminal, ev.direction = True, 1
    s = solve_ivp(rhs(beta, OMEGA, tau), (0, 1000), z0, method="DOP853", rtol=1e-13,
                  atol=1e-13, events=ev)
    return s.t_events[0][0], s.y_events[0][0][1]


def accuracy(method):
    m = Model(**LIN, nonlinear=["beta*x1**3"], parameters={"beta": BETA})
    flow = NonlinearFlow(m, method=method)
    _, sec, *_ = NonlinearFlow(m).run(OMEGA, Y0, N_ACC)
    starts = [Y0] + [tuple(p) for p in sec[:N_ACC - 1]]
    e_mp, e_ivp = [], []
    for y in starts:
        z0 = (GAP, y[0])
        st, te, _, ze = flow.first_impact(OMEGA, z0, y[1], just_hit=0)
        tm, vm = mp_impact(z0, y[1], te)
        ti, vi = ivp_impact(z0, y[1])
        e_mp.append(max(abs(te - tm) / tm, abs(ze[1] - vm) / max(1.0, abs(vm))))
        e_ivp.append(max(abs(te - ti) / ti, abs(ze[1] - vi) / max(1.0, abs(vi))))
    return max(e_mp), max(e_ivp)


def rate(fn, n, reps=3):
    ts = []
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return n / statistics.median(ts)


def speeds():
    m = Model(**LIN, nonlinear=["beta*x1**3"], parameters={"beta": BETA})
    m0 = m.with_(beta=0.0)
    c = cf.constants(Model(**LIN), OMEGA)
    cf.run(c, Y0, 10)                                  # compile (or load the cache)
    out = {"exact linear flow (baseline), beta = 0": rate(lambda: cf.run(c, Y0, N_LIN),
                                                           N_LIN)}
    steps = {}
    for method, name in METHODS.items():
        f, f0 = NonlinearFlow(m, method=method), NonlinearFlow(m0, method=method)
        f.run(OMEGA, Y0, 10)
        out[f"{name}, beta = 0.5"] = rate(lambda: f.run(OMEGA, Y0, N_RUN), N_RUN)
        out[f"{name}, beta = 0"] = rate(lambda: f0.run(OMEGA, Y0, N_RUN), N_RUN)
        steps[name] = f.run(OMEGA, Y0, N_RUN)[5] / N_RUN

    def ivp():
        z, tau = (GAP, Y0[0]), Y0[1]
        for _ in range(N_IVP):
            te, ve = ivp_impact(z, tau)
            z, tau = (GAP, -0.8 * ve), (tau + OMEGA * te) % (2 * math.pi)
    out["solve_ivp DOP853 + events, beta = 0.5"] = rate(ivp, N_IVP, reps=1)
    return out, steps


def main():
    acc = {name: accuracy(method) for method, name in METHODS.items()}
    rates, steps = speeds()
    base = rates["exact linear flow (baseline), beta = 0"]
    lines = ["# Nonlinear flow (issue 28)", "",
             "`python benchmarks/bench_nonlinear_flow.py`: the 1-DOF impact Duffing oscillator "
             f"(omega = {OMEGA}, beta = {BETA}, gap {GAP}, r = 0.8).", "",
             "| accuracy of the first impact (t_e, v_e-), max relative over "
             f"{N_ACC} flights | against mpmath.odefun at 30 digits | against solve_ivp "
             "DOP853 rtol 1e-13 |", "|---|---|---|"]
    for name, (e_mp, e_ivp) in acc.items():
        lines.append(f"| {name} | {e_mp:.1e} | {e_ivp:.1e} |")
    lines += ["", "| one trajectory | impacts/s | / baseline |", "|---|---|---|"]
    for k, v in rates.items():
        lines.append(f"| {k} | {v:.3g} | {v / base:.3g} |")
    lines += ["", "steps per impact (beta = 0.5): " + ", ".join(
        f"{k.split(', ')[1]} {v:.1f}" for k, v in steps.items()), ""]
    text = "\n".join(lines)
    print(text)
    write_text(HERE / "results_nonlinear_flow.md", text)


if __name__ == "__main__":
    main()
