"""Orbits through contact phases (elastic stops, issue 25): a run of the walk of
:mod:`symvi.flow.contact` that records every event (rigid impact, entry, exit) as a point of
the shooting system's layout, and the flight times of a guess.

The shooting system (:class:`symvi.orbits.periodic.Problem`) takes an orbit's events as
its points: point i lies on the section of the constraint of event i (x_k = g in the flow's
order, :func:`symvi.flow.compiled.section_index`), and flight i runs in the phase of the
constraints in contact after it.  A run of the walk gives those points directly, so the
period of its last events (:func:`symvi.orbits.periodic.detect_period`) and the guess
follow as for rigid stops.
"""
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError
from ..flow import contact as ct
from ..flow.compiled import section_index
from ..flow.linear import LinearFlow

#: the events of a run that settles on an attractor: dropped, then kept
SETTLE_TRANSIENT, SETTLE_EVENTS = 600, 200


@dataclass(frozen=True)
class EventRun:
    """The events of one walk: ``section[i]`` the point of event i on its constraint's
    section (the shooting layout, tau mod 2 pi), ``t[i]`` its time, ``hits[i]`` its
    constraint, ``active[i]`` the elastic constraints in contact after it, ``stop`` how the
    walk ended ("completed" when it recorded every event asked for)."""

    params: object
    omega: float
    section: np.ndarray
    t: np.ndarray
    hits: np.ndarray
    active: tuple
    stop: str


def section_frames(flow):
    """Per constraint of the flow's model, the flow-order index of each coordinate of its
    section point (:func:`symvi.flow.compiled.section_index`): an event's point is
    ``np.append(flow.to_flow(z)[frames[k]], tau)`` (x_k itself is not a coordinate)."""
    return [section_index(flow.n, flow.position(c)) for c in flow.model.constraints]


def state_of(flow, k, y):
    """The state (mass order) of point y (tau last, not used) of constraint k's section:
    the inverse of the point of :func:`section_frames`, with s_k = g_k."""
    con = flow.model.constraints[k]
    q = flow.position(con)
    zf = np.empty(2 * flow.n)
    zf[q] = con.gap
    zf[section_index(flow.n, q)] = np.asarray(y, dtype=float)[:-1]
    return flow.to_mass(zf)


def default_state(model, omega):
    """The walk's default start: on the first stop's section (s = g), every other mass at
    rest at 0, phase 0, leaving the stop at speed omega max(|g|, 0.1) (as
    :func:`symvi.simulations.simulation.default_start`); nothing in contact."""
    con = model.constraints[0]
    c = np.array(con.normal, dtype=float)
    c = c / (c @ c)                                # c . x = s along c: x = s c / |c|^2
    z = np.zeros(2 * model.n)
    z[:model.n] = c * con.gap
    z[model.n:] = -con.sign * float(omega) * max(abs(con.gap), 0.1) * c
    return z


def event_run(model, omega, z0=None, tau=0.0, *, events=SETTLE_EVENTS,
              transient=SETTLE_TRANSIENT, active=(), start=0):
    """An :class:`EventRun` of ``model`` at ``omega`` from state z0 (mass order; default
    :func:`default_state`) at phase tau, with ``active`` in contact and on the guard of
    ``start`` (leaving it): ``transient`` events dropped, ``events`` kept."""
    flow = LinearFlow.contact(model.linear_part)       # the frames (geometry only)
    frames = section_frames(flow)
    if z0 is None:
        z0 = default_state(model, omega)
    rows, ts, hits, acts = [], [], [], []
    stop, count = "completed", 0
    t_max = 200 * 2 * math.pi / omega
    for ev in ct.walk(model, omega, z0, tau, active=active, start=start, t_max=t_max):
        if ev.kind not in (ct.IMPACT, ct.ENTRY, ct.EXIT):
            stop = ev.kind
            break
        count += 1
        if count <= transient:
            continue
        k = ev.constraint
        rows.append(np.append(flow.to_flow(ev.after)[frames[k]], ev.tau % (2 * math.pi)))
        ts.append(ev.t)
        hits.append(k)
        acts.append(ev.active)
        if count >= transient + events:
            break
    sec = np.array(rows).reshape(-1, 2 * model.n)
    return EventRun(model, float(omega), sec, np.array(ts), np.array(hits, dtype=np.int64),
                    tuple(acts), stop)


def flights(problem, flow, F, pts):
    """(points, flight times) of a guess through contact phases: from each point the walk
    in its flight's phase to the first event, which must meet the constraint the signature
    names; the next point is the given one (``pts`` has p points) or the walk's."""
    model, p = problem.model, problem.p
    Y, T = [np.array(pts[0], dtype=float)], []
    cur = Y[0]
    for i in range(p):
        ka, kb = int(problem.sig[i]), int(problem.sig[(i + 1) % p])
        walk = ct.walk(model, F.omega, state_of(flow, ka, cur), cur[-1],
                       active=problem.phases[i], start=ka,
                       t_max=200 * 2 * math.pi / F.omega)
        ev = next(walk)
        if ev.kind not in (ct.IMPACT, ct.ENTRY, ct.EXIT):
            raise ConvergenceError(f"the guess does not lead to an event ({ev.kind}) at "
                                   f"event {i + 1}", math.inf)
        if ev.constraint != kb:
            raise ConvergenceError(f"the guess meets stop {ev.constraint + 1} at event "
                                   f"{i + 1}, not stop {kb + 1} as the signature says", math.inf)
        T.append(float(ev.t))
        if i + 1 < p:
            if len(pts) == p:
                nxt = np.array(pts[i + 1], dtype=float)
                nxt[-1] = _unwrap(nxt[-1], cur[-1] + F.omega * ev.t)
            else:                                  # the walk's point, tau unwrapped
                za = flow.to_flow(ev.after)
                nxt = np.append(za[problem.frames[kb]], cur[-1] + F.omega * ev.t)
            Y.append(nxt)
            cur = nxt
    return Y, T


def _unwrap(tau, near):
    return tau + 2 * math.pi * round((near - tau) / (2 * math.pi))


