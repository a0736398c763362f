"""Benchmark of the nonlinear jets and branches (issue 28): the order-3 jet of a 1-DOF
Duffing impact oscillator's map (target <= 1 ms) and a 1000-point branch (target <= 5 s),
with the exact linear flow's generated jet and branch as baselines in the same run.

Run:  python benchmarks/bench_nonlinear_jets.py    (writes benchmarks/results_nonlinear_jets.md)

The model: x'' + 0.05 x' + x + 0.2 x^3 = sin(omega t + tau), a rigid stop at x = 0 with
r = 0.8 (the model of tests/continuation/test_nonlinear_branch.py).  Measured:

* the order-3 and order-5 jets of P at the period-1 point at omega = 2.6
  (:meth:`symvi.orbits.periodic.PeriodicOrbit.jet`: the series flight of
  :mod:`symvi.flow.nljet`, the Taylor method on series of :mod:`symvi.flow.jet_taylor`),
  median of N_JET calls; the baseline: the same call on the linear model (beta absent:
  the generated jets of the exact flow);
* the same at omega = 1.3, a flight twice as long (t_e = 4.83), on the model of
  tests/flow/test_nljet.py (x'' + 0.1 x' + x + 0.5 x^3 = sin(omega t + tau), stop at
  0.5, r = 0.8; the bench model has no period-1 orbit there), against its linear part;
* a branch of 1000 points: :func:`symvi.continuation.branch.continue_branch` in omega from
  2.2 with max_points = 1000 (special points located, admissibility checked), steps capped
  so that it takes 1000 points; the baseline: the same on the linear model.
"""
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent))

import symvi  # noqa: E402
from symvi import Model, Stop  # noqa: E402
from symvi._io import write_text  # noqa: E402
from symvi.continuation.branch import continue_branch  # noqa: E402
from symvi.orbits.period1 import admissible_orbits  # noqa: E402
from symvi.orbits.periodic import periodic_orbit  # noqa: E402

KW = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
          stop=Stop(mass=1, gap=0.0, restitution=0.8))
#: the omega = 1.3 model and its period-1 orbit's guess (tests/flow/test_nljet.py)
KW13 = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
            stop=Stop(mass=1, gap=0.5, restitution=0.8))
GUESS13 = (-1.2407, 1.6538)
N_JET = 200
POINTS = 1000


def _orbit(model, omega):
    sim = symvi.simulate(model, omega, n_impacts=50, transient=3000)
    return periodic_orbit(model, n=1, p=1, guess=sim, omega=omega)


def _jet_time(orbit, order):
    orbit.jet(order)                               # compiled, cached
    ts = []
    for _ in range(N_JET):
        t0 = time.perf_counter()
        orbit.jet(order)
        ts.append(time.perf_counter() - t0)
    return statistics.median(ts)


def _branch_time(model, orbit):
    continue_branch(model, "omega", 2.2, 2.3, orbit=orbit, max_points=20)
    t0 = time.perf_counter()
    br = continue_branch(model, "omega", 2.2, 40.0, orbit=orbit, max_points=POINTS,
                         h_max=0.004)
    return time.perf_counter() - t0, len(br.points), [s.kind for s in br.special]


def main():
    nl = Model(**KW, nonlinear=["beta*x1**3"], parameters={"beta": 0.2})
    lin = Model(**KW)
    rows = []
    o_nl, o_lin = _orbit(nl, 2.6), _orbit(lin, 2.6)
    o13_nl = periodic_orbit(Model(**KW13, nonlinear=["beta*x1**3"], parameters={"beta": 0.5}),
                            n=1, p=1, guess=GUESS13, omega=1.3)
    lin13 = Model(**KW13)
    o13_lin = periodic_orbit(lin13, n=1, p=1, guess=admissible_orbits(lin13, 1.3)[0].y,
                             omega=1.3)
    for label, (p, q) in (("omega = 2.6", (o_nl, o_lin)), ("omega = 1.3", (o13_nl, o13_lin))):
        for order in (3, 5):
            a, b = _jet_time(p, order), _jet_time(q, order)
            rows.append(f"| order-{order} jet of P (1-DOF), {label} | {a * 1e3:.3f} ms "
                        f"| {b * 1e3:.3f} ms | {a / b:.1f} |")
    o_nl, o_lin = _orbit(nl, 2.2), _orbit(lin, 2.2)
    (tn, nn, kn), (tl, nlin, kl) = _branch_time(nl, o_nl), _branch_time(lin, o_lin)
    rows.append(f"| branch in omega from 2.2, {nn} / {nlin} points | {tn:.2f} s "
                f"({tn / nn * 1e3:.2f} ms/pt) | {tl:.2f} s ({tl / nlin * 1e3:.2f} ms/pt) "
                f"| {tn / nn / (tl / nlin):.1f} per point |")
    text = "\n".join([
        "# Nonlinear jets and branches (issue 28)", "",
        f"`python benchmarks/bench_nonlinear_jets.py`, {time.strftime('%Y-%m-%d %H:%M')}.",
        "Duffing impact oscillator beta = 0.2 against the same model without the spring's "
        "cubic term (the exact linear flow's generated jets and compiled shooting); at "
        "omega = 1.3 the model of tests/flow/test_nljet.py (c = 0.1, beta = 0.5, stop at "
        "0.5) against its linear part.  The series flights: the Taylor method on series "
        "(symvi/flow/jet_taylor.py).", "",
        "| what | nonlinear (series) | linear baseline | ratio |", "|---|---|---|---|",
        *rows, "",
        f"special points: nonlinear {kn}; linear {kl}", ""])
    write_text(HERE / "results_nonlinear_jets.md", text)
    print(text)


if __name__ == "__main__":
    main()
