"""No missed contact over 1e7 impacts between two close stops (issue 25's target), checked
on a sample of flights against an independent finder:

    python benchmarks/stress_contacts.py [--impacts 10000000] [--sample 300]

The case: one mass (m = k = 1, c = 0.02, P = 2) between rigid stops at x = +-0.1
(r = 0.95), omega = 1.3: about 8 impacts a forcing period, alternating between the
stops, flights down to a few hundredths of a period.  The compiled run loop
(:func:`symvi.flow.compiled.run`) makes the impacts; for ``--sample`` flights drawn
uniformly, DOP853 with one terminal event per guard (rtol = atol = 1e-12) integrates the
same flight from the same section point.  A missed contact would show as the reference
meeting a contact earlier than the compiled finder, or another stop.  Prints one JSON
line: impacts, impacts/s, the stop reason, and for the sample the number checked, the
number where the constraint or time disagree (0 expected), and the largest time and
state differences.
"""
import argparse
import json
import math
import time

import numpy as np
from scipy.integrate import solve_ivp

from symvi.flow import compiled as cf
from symvi.model import Model, Stop

GAP, P, R, OMEGA, DAMPING = 0.1, 2.0, 0.95, 1.3, 0.02


def model():
    return Model(mass=[[1.0]], stiffness=[[1.0]], damping=[[DAMPING]], forcing=[P],
                 stops=[Stop(mass=1, gap=GAP, restitution=R),
                        Stop(mass=1, gap=-GAP, side="lower", restitution=R)])


def reference(y, k, t_cap):
    """(time, constraint, x, v at contact) of the first contact from section point y on
    constraint k, by DOP853 and events."""
    x0 = GAP if k == 0 else -GAP
    tau = y[-1]

    def rhs(t, z):
        return [z[1], P * math.sin(OMEGA * t + tau) - z[0] - DAMPING * z[1]]

    def up(t, z):
        return z[0] - GAP
    up.terminal, up.direction = True, 1.0

    def lo(t, z):
        return -GAP - z[0]
    lo.terminal, lo.direction = True, 1.0
    sol = solve_ivp(rhs, (0.0, t_cap), [x0, y[0]], method="DOP853", rtol=1e-12,
                    atol=1e-12, events=[up, lo], first_step=1e-7)
    hits = [(sol.t_events[g][0], g) for g in (0, 1)
            if len(sol.t_events[g]) and sol.t_events[g][0] > 1e-9]
    if not hits:
        return None
    t, g = min(hits)
    z = sol.y_events[g][0]
    return t, g, z[0], z[1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--impacts", type=int, default=10_000_000)
    ap.add_argument("--sample", type=int, default=300)
    a = ap.parse_args()
    c = cf.constants(model(), OMEGA)
    y0 = np.array([-0.5, 0.1])
    cf.run(c, y0, 1000)
    t0 = time.perf_counter()
    code, sec, times, vimp, steps, hits = cf.run(c, y0, a.impacts, hits=True)
    dt = time.perf_counter() - t0
    rng = np.random.default_rng(0)
    picks = np.sort(rng.choice(np.arange(1, len(sec)), size=min(a.sample, len(sec) - 1),
                               replace=False))
    bad, dtime, dstate = 0, 0.0, 0.0
    for i in picks:
        y, k = sec[i - 1], hits[i - 1]
        te = times[i] - times[i - 1]
        ref = reference(y, k, 4 * te + 1.0)
        if ref is None or ref[1] != hits[i] or abs(ref[0] - te) > 1e-7 * (1 + te):
            bad += 1
            continue
        dtime = max(dtime, abs(ref[0] - te))
        # the section point after the impact holds v+ = -r v-: compare v- = -v+ / r
        dstate = max(dstate, abs(-sec[i][0] / R - ref[3]))
    print(json.dumps({"impacts": int(len(sec)), "impacts_per_s": round(len(sec) / dt),
                      "finder_steps_per_impact": round(steps / len(sec), 2),
                      "stop": cf.STOP_NAMES[code], "per_stop": np.bincount(hits).tolist(),
                      "sample": int(len(picks)), "disagree": bad,
                      "max_time_diff": dtime, "max_velocity_diff": dstate}))


if __name__ == "__main__":
    main()
