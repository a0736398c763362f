"""Branches of periodic orbits with a sticking phase (issue 27, item 4): a client of the
one engine (:func:`symvi.continuation.engine.run`).

The system is the release map's fixed-point condition F(xi; lam) = R(xi; lam) - xi -
2 pi n e_tau of :mod:`symvi.orbits.sticking` (:class:`symvi.orbits.sticking.ReleaseMap`,
derivatives by central differences: its ``corr_tol`` is the engine's step tolerance),
continued in omega or any named parameter of the model.  A branch ends, with its reason,
where its orbit stops being a sticking orbit of its signature:

* the held phase vanishes: the chatter's accumulation point lands at a release, or where
  the contact force pulls (the accumulation is no longer pushed into the stop);
* the free flight grazes a stop it is not pushed into (the finder's grazing contact with
  the guard's acceleration pulling away: R is not a sticking trip there);
* another stop is met while the mass is held, or the run leaves the flight bound.

Where the count of impacts before the chatter changes (an impact's speed overtakes its
predecessor's, so it joins or leaves the chatter's tail of :mod:`symvi.orbits.sticking`),
R stays smooth: the branch goes on, each point with its own signature, and its ``notes``
say where the signature changed.

Where R itself cannot be evaluated past such a point the corrector fails and the step
halves down to the engine's smallest step; the end then names R's reason.
"""
import math

import numpy as np

from ..errors import ParameterError
from ..model import Model
from ..orbits.sticking import (
    ReleaseMap,
    StickingOrbit,
    StickingSignature,
    newton,
    orbit_at,
    release_point,
)
from . import engine
from .engine import Client, tangent
from .points import Branch, BranchPoint

__all__ = ["continue_sticking"]


#: the held phase is called vanished where the linear extrapolation of its length along
#: the branch reaches 0 within this relative distance of the parameter (the corrector
#: cannot pass that point: past it the accumulation lies where the contact force pulls)
HOLD_END = 1e-6


class _StickingRun(Client):
    """A branch of sticking orbits as a client of the engine."""

    def __init__(self, system, signature):
        self.system, self.signature = system, signature
        self.names = (system.param,)
        self.prev = None
        self.changes = []

    def point(self, X, prev, Gu):
        m = self.system.size
        return BranchPoint(float(X[m]), orbit_at(self.system, X[:m], X[m], Gu))

    def stop(self, X, pt):
        o, lam = pt.orbit, pt.value
        if not o.admissible:
            return (f"the orbit stops being a sticking orbit near {self.where(X)}: "
                    f"{o.reason}")
        prev, self.prev = self.prev, (lam, o.hold, o.signature)
        if prev is None:
            return ""
        if prev[2] != o.signature:
            self.changes.append(f"the signature changes from {prev[2]} to {o.signature} "
                                f"between {self.names[0]} = {prev[0]:.12g} and {lam:.12g} "
                                "(an impact of the flight joins or leaves the chatter)")
        if o.hold < prev[1] and lam != prev[0]:
            lam0 = lam + (lam - prev[0]) * o.hold / (prev[1] - o.hold)
            if abs(lam0 - lam) <= HOLD_END * (1.0 + abs(lam)):
                return (f"the held phase vanishes near {self.names[0]} = {lam0:.9g} (hold "
                        f"{o.hold:.3g} and falling: the chatter's accumulation point "
                        "reaches the release)")
        return ""

    def finish(self, end, X):
        if end.startswith("step below"):
            return (f"the orbit stops being a sticking orbit near {self.where(X)} "
                    f"({end})")
        return end


def continue_sticking(model, param, start, stop, *, guess, signature=None, h=None,
                      h_max=None, max_points=500, **fixed):
    """Continue a periodic orbit with a sticking phase in ``param`` from ``start`` towards
    ``stop`` (pseudo-arclength, :mod:`symvi.continuation.engine`).

    Parameters
    ----------
    model : Model
    param : str
        ``"omega"`` or a named parameter of the model (``"gap"``, ``"forcing[1]"``, ...).
    start, stop : float
        The branch starts at ``start`` and stays between the two.
    guess : Simulation or StickingOrbit or sequence of float
        A :func:`symvi.simulate` run at ``start`` that sticks (its ``sticks``), a solved
        :class:`symvi.orbits.sticking.StickingOrbit`, or a release point xi.
    signature : StickingSignature, optional
        Default: the simulation's stop and periods, the count of impacts of the first
        orbit (or the orbit's own signature).
    h, h_max : float, optional
        First and largest step (defaults as :func:`continue_branch`).
    max_points : int, optional
        Most points (default 500).
    **fixed : float
        ``omega=...`` when ``param`` is not omega (default: the simulation's), other
        named parameters.

    Returns
    -------
    Branch
        ``points`` (each a :class:`BranchPoint` whose ``orbit`` is a StickingOrbit), no
        special points, ``end`` why it ended (module docstring), ``n`` the periods and
        ``p`` the impacts before the chatter.
    """
    model = Model.of(model)
    par = model.parameter(param)
    start, stop = float(start), float(stop)
    if not (math.isfinite(start) and math.isfinite(stop)) or start == stop:
        raise ParameterError("stop", stop, f"a finite value != start = {start!r}")
    omega = fixed.pop("omega", None)
    for name, v in fixed.items():
        model = model.parameter(name).apply(model, v)
    if hasattr(guess, "sticks"):
        xi, periods, g = release_point(guess)
        sig = signature or StickingSignature(g, 0, periods)
        if omega is None and not par.is_forcing_frequency:
            omega = guess.omega
        given = signature is not None
    elif isinstance(guess, StickingOrbit):
        xi, sig, given = np.asarray(guess.xi, float), signature or guess.signature, True
    else:
        xi, sig = np.asarray(guess, float), signature or StickingSignature()
        given = signature is not None
    if par.is_forcing_frequency and omega is not None:
        raise ParameterError("omega", omega, "not fixed when the parameter is omega")
    system = ReleaseMap(model, sig.stop, sig.periods, omega, param)
    if xi.shape != (system.size,):
        raise ParameterError("guess", tuple(xi), f"{system.size} numbers "
                             f"({', '.join(system.names)})")
    xi, J = newton(system, xi, start)
    first = orbit_at(system, xi, start, J, sig if given else None)
    if not given:
        sig = first.signature
    if not first.admissible:
        return Branch(system.param, sig.periods, sig.impacts, (BranchPoint(start, first),),
                      (), f"the first orbit is no sticking orbit: {first.reason}", (),
                      system, (np.append(xi, start),), tuple(sorted((start, stop))))
    lo, hi = sorted((start, stop))
    span = hi - lo
    h_max = span / 25 + 0.05 if h_max is None else float(h_max)
    h = min(h_max, span / 100) if h is None else float(h)
    X = np.append(xi, start)
    _, Gu, Gl = system.evaluate(xi, start, dparam=True)
    e = np.zeros(len(X))
    e[-1] = 1.0 if stop > start else -1.0
    t = tangent(Gu, Gl, e)
    client = _StickingRun(system, sig)
    points, states, end = engine.run(system, client, X, t, [lo], [hi], h=h, h_max=h_max,
                                     max_points=max_points,
                                     first=BranchPoint(start, first))
    return Branch(system.param, sig.periods, sig.impacts, tuple(points), (), end,
                  tuple(client.changes), system, tuple(states), (lo, hi))
