"""Random chains with several rigid stops (issue 25): the compiled run against DOP853 with
one event per guard, flight by flight.

Each example draws a chain of 1-3 masses, 2-3 rigid stops on random masses and sides (at
most one upper and one lower stop a mass, with room between them), light damping, a
forcing and a start on the first stop's section inside every other stop.  For each of
the first impacts of the compiled run, DOP853 (rtol = atol = 1e-12) integrates the same
flight from the same section point: it must meet the same stop at the same time, and
never an earlier contact (a contact the finder stepped over).  Comparisons end at the
first near-grazing impact (approach speed below 1e-3 of the motion's scale), where the
reference's sign test may itself miss a double crossing."""
import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from symvi.flow import compiled as cf
from symvi.flow.linear import LinearFlow
from symvi.model import Model, Stop
from tests.flow.test_compiled_constraints import first_contact, state


def _f(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


@st.composite
def chains(draw):
    n = draw(st.integers(1, 3))
    mass = [draw(_f(0.5, 2.0)) for _ in range(n)]
    springs = [draw(_f(0.5, 3.0)) for _ in range(n)]       # ground spring of mass 1, then
    K = np.zeros((n, n))                                    # the couplings i-1 -- i
    K[0, 0] += springs[0]
    for i in range(1, n):
        K[i - 1, i - 1] += springs[i]
        K[i, i] += springs[i]
        K[i - 1, i] -= springs[i]
        K[i, i - 1] -= springs[i]
    K[n - 1, n - 1] += draw(_f(0.2, 1.0))                   # the last mass grounded too
    c = draw(_f(0.0, 0.08))
    forcing = [draw(_f(0.3, 2.5)) * draw(st.sampled_from([-1, 1])) for _ in range(n)]
    # stops: each mass gets none, an upper, a lower or both, at least two in all
    stops = []
    for k in range(1, n + 1):
        kind = draw(st.sampled_from(["none", "upper", "lower", "both"]))
        up, lo = draw(_f(0.15, 1.0)), -draw(_f(0.15, 1.0))
        if kind in ("upper", "both"):
            stops.append(Stop(mass=k, gap=up, restitution=draw(_f(0.5, 0.95))))
        if kind in ("lower", "both"):
            stops.append(Stop(mass=k, gap=lo, side="lower", restitution=draw(_f(0.5, 0.95))))
    if len(stops) < 2:
        k = draw(st.integers(1, n))
        have = {(s.mass, s.side) for s in stops}
        for side, gap in (("upper", 0.4), ("lower", -0.4)):
            if (k, side) not in have and len(stops) < 2:
                stops.append(Stop(mass=k, gap=gap, side=side, restitution=0.8))
    model = Model(mass=np.diag(mass).tolist(), stiffness=K.tolist(),
                  damping=(c * np.eye(n)).tolist(), forcing=forcing, stops=stops)
    omega = draw(_f(0.4, 2.5))
    # the start: on the first stop, leaving it; every other coordinate inside its stops
    first = stops[0]
    x = np.empty(n)
    for i in range(n):
        hi = min([s.gap for s in stops if s.mass == i + 1 and s.side == "upper"], default=1.0)
        lo = max([s.gap for s in stops if s.mass == i + 1 and s.side == "lower"], default=-1.0)
        x[i] = lo + draw(_f(0.2, 0.8)) * (hi - lo)
    x[first.mass - 1] = first.gap
    v = np.array([draw(_f(-1.0, 1.0)) for _ in range(n)])
    speed = draw(_f(0.1, 1.5))
    v[first.mass - 1] = -speed if first.side == "upper" else speed
    tau = draw(_f(0.0, 2 * math.pi))
    return model, omega, x, v, tau


def _section_point(model, x, v, tau):
    """(x, v) on the first stop's section as the compiled run takes it (flow order)."""
    flow = LinearFlow.of(model)
    perm = list(flow.perm)
    n = model.n
    xs, vs = x[perm], v[perm]
    return np.array([vs[0], *xs[1:], *vs[1:], tau])


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(chains())
def test_compiled_run_meets_each_contact_of_the_reference(case):
    model, omega, x, v, tau = case
    c = cf.constants(model, omega)
    y0 = _section_point(model, x, v, tau)
    code, sec, times, vimp, _, hits = cf.run(c, y0, 8, hits=True)
    scale = 1.0 + float(np.max(np.abs(sec[:, :-1]))) if len(sec) else 1.0
    y, k, t_prev = y0, 0, 0.0
    for i in range(len(sec)):
        te = times[i] - t_prev
        ref = first_contact(model, omega, y[-1], state(model, c, y, k), 0.0, 4 * te + 10.0,
                            k, tol=1e-12, first_step=1e-7)
        assert ref is not None, f"impact {i}: the reference meets no contact"
        t_ref, g_ref, _ = ref
        # never a contact stepped over: the reference meets none earlier
        assert t_ref >= te - 1e-7 * (1 + te), (i, t_ref, te)
        assert g_ref == hits[i] and abs(t_ref - te) <= 1e-7 * (1 + te), (i, ref, te, hits[i])
        if vimp[i] < 1e-3 * scale:
            break                                  # near grazing: the reference may miss
        y, k, t_prev = sec[i], hits[i], times[i]
