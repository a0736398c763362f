"""Period-1 one-impact orbits of a model with nonlinear forces (issue 28): continued from
the linear part's, in the forces' scale.

The homotopy M x'' + C x' + K x + s f(x, v) = P sin(omega t + tau), s from 0 to 1: at
s = 0 the period-1 orbits are the closed form's (eqs. (10)-(18), both branches); each one
that arrives at the stop (v_k- > 0) is continued in s by the branch engine (pseudo-
arclength, through inadmissible stretches) to s = 1, then refined by Newton on the model
itself.  :func:`symvi.continuation.start.nonlinear_period1` adds the orbit a run of the
map settles on where it is 1-1.  The paths are followed over s in [-REACH, REACH], so an
orbit reached by a path only after a fold in s beyond that is found: every crossing of
s = 1 counts.  No closed form counts the orbits of a nonlinear flow: one on an isola
(joined to no linear orbit and not an attractor) is missed, and a path cut short is named
in ``notes``; the list is never called complete.
"""
import math
from dataclasses import dataclass

from ..errors import SingularCaseError, SymviError

#: the scale's name in the homotopy's model (suffixed where the model already has it)
SCALE = "homotopy_s"
#: the paths in the forces' scale are followed over s in [-REACH, REACH]
REACH = 4.0
#: the largest arclength step of those paths, and the most points on each
H_MAX = 1.0
MAX_POINTS = 300
#: two orbits are one where their section points agree to this (tau mod 2 pi)
SAME = 1e-7


@dataclass(frozen=True)
class NonlinearPeriod1:
    """What :func:`period1_orbits` found: ``orbits`` (:class:`PeriodicOrbit`, n = p = 1,
    admissible or not), ``origins`` (where each came from: ``"linear branch +"``,
    ``"attractor"``) and ``notes`` (each path that found nothing, and why)."""

    orbits: tuple
    origins: tuple
    notes: tuple


def _scaled(model):
    """The homotopy's model: every force times a new parameter, set to 0."""
    from ..model import Model
    names = set(model.parameter_names())
    s = SCALE
    while s in names:
        s += "_"
    nl = model._nl
    new = Model(mass=model.mass, stiffness=model.stiffness, damping=model.damping,
                forcing=model.forcing, stops=model.stops,
                nonlinear=[f"{s}*({t})" for t in nl.texts],
                parameters={**dict(nl.parameters), s: 0.0})
    return new, s


def _same(a, b):
    ya, yb = a.y, b.y
    d = max(abs(p - q) for p, q in zip(ya[:-1], yb[:-1]))
    dt = abs((ya[-1] - yb[-1] + math.pi) % (2 * math.pi) - math.pi)
    return max(d, dt) <= SAME * (1 + max(abs(v) for v in ya[:-1]))


def period1_orbits(model, omega, *, also=(), notes=()):
    """The period-1 one-impact orbits of a model with nonlinear forces at ``omega`` that
    the homotopy from its linear part reaches (module docstring), then the orbits of
    ``also`` ((PeriodicOrbit, origin) pairs: the attractor of a run, added by
    :func:`symvi.continuation.start.nonlinear_period1`) that are not among them; a
    :class:`NonlinearPeriod1` (``notes`` first in its notes).

    Only for one rigid stop (the closed form at s = 0).  A linear part whose period-1
    conditions are singular at omega (an undamped mode's resonance) starts no path: said
    in ``notes``.
    """
    from ..orbits.period1 import period1_orbits as closed_form
    from ..orbits.periodic import periodic_orbit
    from .branch import continue_branch
    model.require_one_rigid_stop()
    found, origins, notes = [], [], list(notes)

    def add(orbit, origin):
        if orbit.n == 1 and orbit.p == 1 and not any(_same(orbit, o) for o in found):
            found.append(orbit)
            origins.append(origin)

    try:
        starts = closed_form(model.linear_part, omega, multipliers=False)
    except SingularCaseError as exc:
        starts = []
        notes.append(f"the linear part's period-1 conditions are singular here ({exc}): "
                     "no path starts")
    hm, s = _scaled(model) if starts else (None, None)
    for o in starts:
        what = f"linear branch {o.branch}"
        if not o.impact_velocity > 0:
            notes.append(f"{what}: not followed (it arrives moving away from the stop, "
                         f"v- = {float(o.impact_velocity):.6g})")
            continue
        for stop in (REACH, -REACH):
            try:
                br = continue_branch(hm, s, 0.0, stop, guess=o.y, omega=omega,
                                     through=True, locate=False, h_max=H_MAX,
                                     max_points=MAX_POINTS)
            except SymviError as exc:
                notes.append(f"{what}, s towards {stop:g}: the path failed ({exc})")
                continue
            pts = br.points
            if not br.end.startswith("reached"):
                notes.append(f"{what}, s towards {stop:g}: the path ends at s = "
                             f"{pts[-1].value:.6g} ({br.end})")
            for a, b in zip(pts, pts[1:]):
                if (a.value - 1) * (b.value - 1) <= 0 and a.value != b.value:
                    near = a if abs(a.value - 1) <= abs(b.value - 1) else b
                    try:
                        add(periodic_orbit(model, n=1, p=1, guess=near.orbit.y,
                                           omega=omega), what)
                    except SymviError as exc:
                        notes.append(f"{what}: Newton on the model failed from s = "
                                     f"{near.value:.6g} ({exc})")
    for orbit, origin in also:
        add(orbit, origin)
    return NonlinearPeriod1(tuple(found), tuple(origins), tuple(notes))
