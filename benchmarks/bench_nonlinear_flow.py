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
  beta = 0; the Taylor method with its tape interpreted, as a short run takes it, and with
  the tape's own kernel, :mod:`symvi.flow.taylor_kernel`, as a long run or a sweep takes
  it), the baseline -- the exact linear flow's compiled run
  (``symvi.flow.compiled.run``) on the same model with beta = 0 -- and ``solve_ivp`` with
  events, as a user would write it (times: the thread's CPU time, :func:`rate`);
* where a Taylor step's time goes (beta = 0.5): each kernel of a step timed alone in a
  compiled loop -- the series (interpreted, :func:`symvi.flow.taylor._coefficients`, and
  by the tape's own kernel), the step rule,
  the guard's polynomial and its exclusion bound, the step's end --, and what an impact
  adds (the hull, the bracket and Newton on the polynomial, the reset) as the rest of the
  run's time.
"""
import math
import statistics
import sys
import time
from pathlib import Path

import mpmath
import numba as nb
import numpy as np
from scipy.integrate import solve_ivp

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent))

from symvi import Model, Stop  # noqa: E402
from symvi._io import write_text  # noqa: E402
from symvi.flow import compiled as cf  # noqa: E402
from symvi.flow import taylor, taylor_kernel  # noqa: E402
from symvi.flow.nonlinear import NonlinearFlow  # noqa: E402

LIN = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
OMEGA, BETA, GAP, Y0 = 1.3, 0.5, 0.5, (-0.3, 0.1)
N_ACC = 10            # flights checked against mpmath
N_RUN = 50000         # impacts of a timed run of the nonlinear flow
N_LIN = 200000        # impacts of a timed run of the exact linear flow
N_IVP = 40            # impacts of solve_ivp timed
N_PART = 20000        # calls of each kernel of a Taylor step timed
METHODS = {"taylor": "nonlinear flow, Taylor (tape interpreted)",
           "dop853": "nonlinear flow, DOP853"}
KERNEL = "nonlinear flow, Taylor (the tape's own kernel)"
INTERPRETED = "the tape interpreted"


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
    """n / the median time of fn(): the calling thread's CPU time (every timed run is one
    thread; on a shared machine wall time also counts the other processes' slices)."""
    ts = []
    for _ in range(reps):
        t0 = time.thread_time()
        fn()
        ts.append(time.thread_time() - t0)
    return n / statistics.median(ts)


def speeds():
    """impacts/s of each trajectory (module docstring) and the Taylor runs' steps an
    impact.  The Taylor method twice: the tape interpreted (a short run, the process
    having run fewer than KERNEL_IMPACTS on it), then the tape's own kernel (compiled
    here, as a long run or a sweep compiles it)."""
    m = Model(**LIN, nonlinear=["beta*x1**3"], parameters={"beta": BETA})
    m0 = m.with_(beta=0.0)
    c = cf.constants(Model(**LIN), OMEGA)
    cf.run(c, Y0, 10)                                  # compile (or load the cache)
    out = {"exact linear flow (baseline), beta = 0": rate(lambda: cf.run(c, Y0, N_LIN),
                                                           N_LIN)}
    steps = {}
    taylor_kernel.KERNEL_IMPACTS = 10 ** 18            # the interpreted rows first
    for method, name in list(METHODS.items()) + [("taylor", KERNEL)]:
        f, f0 = NonlinearFlow(m, method=method), NonlinearFlow(m0, method=method)
        if name == KERNEL:
            taylor_kernel.kernel(f.tape[0], f.tape[2], 2)     # beta = 0: the same tape
        f.run(OMEGA, Y0, 10)
        f0.run(OMEGA, Y0, 10)
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


@nb.njit
def _loop_series(sy, tj, y, X, n):
    for i in range(n):
        taylor._coefficients(sy, tj, 1e-9 * i, y, X)


@nb.njit
def _loop_own(sy, tj, y, X, n):
    kern, ad, w, tau = tj[18], tj[19], sy[8][0], sy[9][0]
    for i in range(n):
        taylor._series_of(kern, ad, w, tau, sy, tj, 1e-9 * i, y, X)


@nb.njit
def _loop_rule(X, n):
    s = 0.0
    for i in range(n):
        s += taylor._jorba_zou_h(X, 10.0 + 1e-9 * i)
    return s


@nb.njit
def _loop_guard(X, normals, cons, g, h, n):
    s = 0.0
    for i in range(n):
        taylor._guard_coeffs(X, normals, 0, cons[0, 1], cons[0, 2], h + 1e-12 * i, g)
        ub = g[0]
        for k in range(1, g.shape[0]):
            ub += max(g[k], 0.0)
        s += ub
    return s


@nb.njit
def _loop_end(X, h, y, n):
    for i in range(n):
        taylor._at(X, h + 1e-12 * i, y, None)


def breakdown(run_rate, steps):
    """ns of each kernel of a Taylor step (beta = 0.5, at a state of the run), the series
    both ways, and the rest of an impact's time with the tape's own kernel: 1e9 /
    run_rate - steps (sum of its step's kernels)."""
    m = Model(**LIN, nonlinear=["beta*x1**3"], parameters={"beta": BETA})
    f = NonlinearFlow(m)
    _, sec, *_ = f.run(OMEGA, Y0, 2)
    sy, tj = f._system(OMEGA, sec[0, 1]), f._taylor_work()
    X, g, y = tj[8], tj[9], np.empty(2)
    z = np.array([GAP, sec[0, 0]])
    taylor._prepare(sy, tj)
    taylor._coefficients(sy, tj, 0.0, z, X)
    h = taylor._jorba_zou_h(X, f._cap(OMEGA))
    own = taylor.work(*f.tape, 2, kernel=taylor_kernel.kernel(f.tape[0], f.tape[2], 2))
    taylor._prepare(sy, own)
    parts = {f"series, {INTERPRETED} (and the linear part, orders 0..p)":
             lambda n: _loop_series(sy, tj, z, X, n),
             "series, the tape's own kernel": lambda n: _loop_own(sy, own, z, own[8], n),
             "step rule": lambda n: _loop_rule(X, n),
             "guard polynomial and exclusion bound":
             lambda n: _loop_guard(X, f.normals, f._table, g, h, n),
             "step end (Horner)": lambda n: _loop_end(X, h, y, n)}
    out = {}
    for name, fn in parts.items():
        fn(10)
        out[name] = 1e9 / rate(lambda: fn(N_PART), N_PART, reps=5)
    step = sum(v for k, v in out.items() if INTERPRETED not in k)   # the kernel's step
    rest = "an impact's rest per impact (hull, bracket, Newton, reset, run loop)"
    out[rest] = 1e9 / run_rate - steps * step
    return out, step


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
        f"{k.split(', ', 1)[1]} {v:.1f}" for k, v in steps.items()), ""]
    name = KERNEL
    parts, step = breakdown(rates[f"{name}, beta = 0.5"], steps[name])
    lines += [f"| a Taylor step with the tape's own kernel (order {taylor.FLOW_ORDER}, beta "
              "= 0.5) | ns | share of an impact |", "|---|---|---|"]
    per = 1e9 / rates[f"{name}, beta = 0.5"]
    for k, v in parts.items():
        n = 1.0 if k.startswith("an impact") else steps[name]
        share = "(not in it)" if INTERPRETED in k else f"{n * v / per:.2f}"
        lines.append(f"| {k} | {v:.0f} | {share} |")
    lines += [f"| one step | {step:.0f} | {steps[name] * step / per:.2f} |", ""]
    text = "\n".join(lines)
    print(text)
    write_text(HERE / "results_nonlinear_flow.md", text)


if __name__ == "__main__":
    main()
