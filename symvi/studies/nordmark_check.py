"""Nordmark's map against simulation just past grazing (issue 27, item 3).

At distances mu past a grazing point (:mod:`symvi.orbits.nordmark`) the run starts on the
smooth orbit (the orbit that ignores the grazing contact, solved on the section Pi), where
it comes back out of the stop, so that the first contact near the grazing point is the
new impact.  Measured against predicted:

* the first new impact's velocity v1 against c_first sqrt(mu), c_first =
  sqrt(2 |a| |delta'|) (the flight's apex at depth delta = |delta'| mu);
* over a long run (``transient`` impacts dropped), the attractor's kind (the one classifier,
  :func:`symvi.simulations.diagnostics.classify`) against the predicted scenario, the
  number of forcing periods per new impact, and the largest new-impact velocity against
  the 1-D reduction's bound c_attractor sqrt(mu) (where that reduction applies), and the
  impacting period-1 orbit's velocity sqrt(2 |a|) s (:func:`period1_speed`) for a run that
  settles on one.

A new impact is one slower than half the slowest impact of the grazing orbit (every impact
when the grazing orbit has no other).
"""
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..maps.section import Section
from ..orbits.nordmark import descent_point, discontinuity_map, other_speeds, smooth_orbit
from ..simulations.diagnostics import classify
from ..simulations.simulation import simulate

#: the smooth orbit's depths delta = |delta'| mu past grazing of the report's check (mu
#: follows from the map's rate delta', which differs by orders of magnitude between models)
DEFAULT_DEPTHS = (1e-3, 1e-4, 1e-5)


@dataclass(frozen=True)
class NordmarkCheck:
    """The map and one row per mu (:meth:`as_dict`)."""

    map: object
    rows: tuple

    def as_dict(self):
        return {"map": self.map.as_dict(), "rows": [dict(r) for r in self.rows]}


def check(nm, mus=None, *, depths=DEFAULT_DEPTHS, n_impacts=400, transient=3000):
    """Simulation just past the grazing point of ``nm`` (a
    :class:`symvi.orbits.nordmark.DiscontinuityMap`) at each mu of ``mus``.

    Parameters
    ----------
    nm : DiscontinuityMap
        With a parameter (``delta_rate`` finite), touching the model's first stop.
    mus : sequence of float, optional
        Distances past grazing, > 0, in units of the branch parameter; default: those of
        ``depths``.
    depths : sequence of float
        The smooth orbit's depths delta past the stop, mu = delta / |delta'| (used when
        ``mus`` is None).
    n_impacts, transient : int
        The long run's stored and dropped impacts.

    Returns
    -------
    NordmarkCheck
        Per mu: the parameter value, delta (the smooth orbit's depth), predicted and
        measured v1 and their ratio, the attractor's kind, forcing periods per new
        impact, the largest new-impact velocity and its ratio to c_attractor sqrt(mu).
    """
    if nm.past_direction is None:
        raise ParameterError("map", nm.param, "a grazing point with a nonzero rate delta'")
    if nm.stop != 0 or nm.names[0] != "h" or Section.of(nm.model).perm[0] != \
            _stop_mass(nm.model):
        raise ParameterError("map", f"stop {nm.stop + 1}", "a touch of the model's first stop")
    if mus is None:
        mus = [float(d) / abs(nm.delta_rate) for d in depths]
    v_regular = other_speeds(nm)
    cut = 0.5 * min(v_regular) if v_regular else math.inf
    rows = []
    for mu in mus:
        mu = float(mu)
        if not mu > 0:
            raise ParameterError("mus", mus, "distances past grazing > 0")
        xi, model, omega = smooth_orbit(nm, mu)
        z, phi = descent_point(nm, xi, model, omega)
        y0 = Section.of(model).point(z, phi % (2 * math.pi))
        k = len(nm.legs) - 1                    # the grazing orbit's other impacts come first
        first = simulate(model, omega, y0, n_impacts=k + 1)
        v1 = float(first.impact_velocity[k]) if len(first.impact_velocity) > k else math.nan
        pred = nm.c_first * math.sqrt(mu)
        sim = simulate(model, omega, y0, n_impacts=n_impacts, transient=transient)
        cls = classify(sim)
        v = np.asarray(sim.impact_velocity)
        idx = np.flatnonzero(v < cut)
        new = v[idx]
        periods = (float(sim.t[idx[-1]] - sim.t[idx[0]]) * omega / (2 * math.pi) /
                   (len(idx) - 1) if len(idx) > 1 and sim.stop == "completed" else math.nan)
        vmax = float(new.max()) if len(new) else math.nan
        bound = None if nm.c_attractor is None else nm.c_attractor * math.sqrt(mu)
        rows.append({"mu": mu, "value": nm.value + nm.past_direction * mu,
                     "delta": float(xi[0]), "v1_predicted": pred, "v1_measured": v1,
                     "v1_ratio": v1 / pred, "attractor": cls.kind, "stop": sim.stop,
                     "new_impacts": int(len(new)), "periods_per_new_impact": periods,
                     "v_new_max": vmax,
                     "v_new_bound": bound,
                     "v_new_ratio": None if bound is None else vmax / bound,
                     "v_period1_predicted": period1_speed(nm, float(xi[0]))})
    return NordmarkCheck(nm, tuple(rows))


def period1_speed(nm, delta):
    """The new impact's velocity of the impacting period-1 orbit of Nordmark's map at
    depth ``delta`` of the smooth orbit: sqrt(2 |a|) s, s^2 - c s - delta = 0 with
    c = e_h . (I - N)^-1 E (:mod:`symvi.orbits.nordmark`); None where no root s > 0."""
    c = nm.c_fixed
    disc = c * c + 4 * delta
    if not (math.isfinite(c) and disc >= 0):
        return None
    s = 0.5 * (c + math.sqrt(disc))
    return math.sqrt(2 * abs(nm.acceleration)) * s if s > 0 else None


def check_branch(model, param, start, stop, mus=None, *, depths=DEFAULT_DEPTHS,
                 n_impacts=400, transient=3000, **fixed):
    """:func:`check` at the first grazing point of the 1-1 branch of ``model`` continued in
    ``param`` over [start, stop] (:func:`symvi.continuation.continue_orbits`; ``fixed``
    its other parameters, e.g. ``omega``)."""
    from ..continuation import continue_orbits
    for br in continue_orbits(model, param, start, stop, **fixed):
        for s in br.special:
            if s.kind == "grazing":
                nm = discontinuity_map(s.orbit, s, param=param)
                return check(nm, mus, depths=depths, n_impacts=n_impacts,
                             transient=transient)
    raise ParameterError("range", (start, stop), f"a range of {param} with a grazing point "
                         "on a branch")


def _stop_mass(model):
    return model.constraints[0].coordinate


def study(params, spec, quick):
    """The report's part: :func:`check_branch` over the scene's [omega_min, omega_max]."""
    from ..model import Model
    model = Model.of(params)
    n, tr = (200, 1000) if quick else (400, 3000)
    res = check_branch(model, "omega", spec["omega_min"], spec["omega_max"],
                       depths=spec.get("depths") or DEFAULT_DEPTHS, n_impacts=n, transient=tr)
    return res.as_dict()


__all__ = ["DEFAULT_DEPTHS", "NordmarkCheck", "check", "check_branch", "period1_speed",
           "study"]
