"""The branches through the orbits at a start: starting orbits found, each continued both
ways, duplicates dropped and, on request, the period-doubled branch of each flip followed.

:func:`continue_orbits` is what ``symvi continue`` runs.  Where
:func:`~symvi.continuation.continue_branch` continues one orbit, it finds the orbits
to start from: every admissible period-1 orbit at the start (the closed form), or the
n-p orbit a run of the map settles on there, or the one a given simulation settled on.
"""
import dataclasses
import math
import os
import warnings
from numbers import Integral

import numpy as np

from ..errors import NearSingularWarning, ParameterError, SingularCaseError, SymviError
from ..flow import check_value
from .branch import continue_branch, same_branch, switch_at_branch_point, switch_at_flip

#: what each argument is called in error messages, by default its own name; a front end
#: passes its own spelling (the command line its flags: ``symvi.cli.continuation``)
NAMES = {"start": "start", "stop": "stop", "param": "param", "orbit": "orbit",
         "start_omega": "start_omega", "simulation": "simulation",
         "max_points": "max_points", "fixed": "fixed", "omega": "omega"}
#: a run of the map that finds the n-p orbit to start from: impacts kept, transient dropped
SETTLE_IMPACTS, SETTLE_TRANSIENT = 400, 4000
#: values of [start, stop] tried for an admissible period-1 orbit where the start has none
SEARCH_SAMPLES = 200
#: values of [start, stop] where a run of the map is tried when none settles at the start
SEARCH_RUNS = 20
#: the branch each kind of special point starts with ``switch``
_SWITCHES = {"flip": switch_at_flip, "symmetry-breaking": switch_at_branch_point,
             "branch-point": switch_at_branch_point}


def continue_orbits(model, param, start, stop, /, *, orbit=(1, 1), start_omega=None,
                    simulation=None, switch=False, through=False, max_points=5000,
                    names=None, **fixed):
    """The branches of n-p orbits of ``model`` in a named parameter, from every orbit at a start.

    In the named parameter ``param``, started at ``start`` and kept between ``start``
    and ``stop``: a list of :class:`Branch`.  What ``symvi continue`` runs.  Each
    starting orbit is continued by :func:`continue_branch`; a branch that retraces
    another (:func:`same_branch`) is dropped.

    The orbits to start from:

    * ``orbit`` 1-1 (the default): every admissible period-1 orbit at ``start`` (the
      closed form; two of them joined by a fold give one branch);
    * another ``orbit`` (``(n, p)`` or ``"n-p"``): the n-p orbit a run of the map from
      the period-1 orbit settles on at ``start``;
    * ``simulation`` (a :class:`symvi.simulations.Simulation` of ``model``, or the path
      of an ``.npz`` written by ``symvi simulate --out``): the orbit it settled on, its
      n-p found (``orbit``, when not 1-1, must match); with ``param`` omega the branch
      starts at the simulation's omega, goes both ways and stays in [start, stop];
      otherwise the simulation's omega is the fixed one unless ``omega`` is given.

    ``start_omega`` (with ``param`` omega) starts at that omega inside [start, stop] and
    continues both ways.  ``fixed`` sets the other parameters: ``omega`` (required when
    ``param`` is not omega, unless a simulation gives it) and any named parameter of
    the model (``gap=0.4``, ``**{"stiffness[1,2]": -1.0}``).  ``switch`` adds the
    period-doubled branch born at each flip point and the other branch through each branch
    point (at a symmetry-breaking pitchfork, an asymmetric one; a failed switch is a
    warning),
    ``through`` follows branches on where their orbits are inadmissible,
    ``max_points`` bounds each branch.  Errors are :class:`ParameterError` naming the
    argument, as ``names`` spells it (:data:`NAMES`; the command line passes its flags).
    Where the start has no admissible period-1 orbit, the first of 200 values towards
    ``stop`` with one is taken (refined to the edge of existence by bisection); where no
    run settles on a periodic orbit at the start of a model with no period-1 closed
    form (several stops, a lower one), the first of 20 values towards ``stop`` where
    one does.  A branch then says so in its ``notes``.

    Parameters
    ----------
    model : Model
        The model (positional only; the paper's Params as ``Model.of(params)``).
    param : str
        The continued parameter (positional only): ``"omega"`` or a named parameter of
        the model (:meth:`symvi.Model.parameter`).
    start : float
        Where the branches start (positional only); a valid value of ``param`` for the
        model (omega: 1e-4 to 1e4, not at an undamped natural frequency).
    stop : float
        The other end of the interval (positional only), != ``start``.
    orbit : tuple of int or str, optional
        The orbit's n-p, ``(n, p)`` or ``"n-p"``, 1 <= n, p <= 64 (default ``(1, 1)``).
    start_omega : float, optional
        With ``param`` omega only: start there, inside [start, stop], and continue both
        ways.  Not with ``simulation``.
    simulation : Simulation or str or os.PathLike, optional
        A :func:`symvi.simulate` run of ``model`` that settled on a periodic orbit, or
        the path of an ``.npz`` written by ``symvi simulate --out``: start from its
        orbit.  A run that settled on a sticking orbit (its ``sticks``: two complete
        sticking phases, the last in its second half) gives the branch of that orbit
        (:func:`symvi.continuation.sticking.continue_sticking`; ``orbit`` and
        ``switch`` do not apply).
    switch : bool, optional
        Also follow the branch born at each flip point and at each branch point
        (default False).
    through : bool, optional
        Follow branches on where their orbits are inadmissible (default False).
    max_points : int, optional
        Most points on each branch, 2 to 1000000 (default 5000).
    names : dict, optional
        How errors name the arguments: keys of :data:`NAMES` (``"start"``, ``"stop"``,
        ``"param"``, ...) to the caller's spelling (default: the argument names).
    **fixed : float
        The other parameters' values: ``omega=...`` (required when ``param`` is not
        omega, unless ``simulation`` gives it) and any named parameter of the model
        (``gap=0.4``, ``**{"stiffness[1,2]": -1.0}``).

    Returns
    -------
    list of Branch
        The branches from each starting orbit (each direction from ``start_omega`` or a
        simulation's omega), then, with ``switch``, the branches switched to.

    Raises
    ------
    ParameterError
        An argument out of range, naming it: ``model`` not a Model, an unknown
        ``param`` or fixed name, ``param`` also fixed, a bad ``orbit`` or
        ``max_points``, no ``omega`` when it is needed, ``start == stop``,
        ``start_omega`` outside the interval, a simulation that settled on no periodic
        orbit (or on another n-p), no start found anywhere in the interval.
    SingularCaseError
        ``"forcing-resonance"``: ``start``, ``start_omega`` or the fixed omega at an
        undamped natural frequency.
    SymviError
        Newton does not converge from a starting orbit (a ConvergenceError).

    Warns
    -----
    UserWarning
        With ``switch``: a branch switch that failed, with the reason.

    Examples
    --------
    >>> from symvi import Model
    >>> from symvi.continuation import continue_orbits
    >>> m = Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    >>> branches = continue_orbits(m, "omega", 0.72, 0.75)
    >>> [(br.n, br.p, br.end) for br in branches]
    [(1, 1, 'reached omega = 0.75')]
    >>> [(sp.kind, round(sp.value, 6)) for sp in branches[0].special]
    [('ns', 0.736877)]
    """
    from ..model import Model
    from ..orbits.periodic import detect_period
    N = _names(names)
    if not isinstance(model, Model):
        raise ParameterError("model", model, "a symvi.Model (Model.of(params) for the "
                                             "paper's Params)")
    n, p = _orbit(orbit, N)
    if not isinstance(param, str):
        raise ParameterError(N["param"], param, "a parameter name (omega, gap, ...)")
    # the names parsed once, here at the entry: lenses on (model, omega) from now on
    par = _known(model, param, N["param"])
    pars = {name: _known(model, name, N["fixed"]) for name in fixed}
    if param in fixed:
        raise ParameterError(N["fixed"], param, f"a parameter other than {N['param']}")
    if (isinstance(max_points, bool) or not isinstance(max_points, Integral)
            or not 2 <= max_points <= 10 ** 6):
        raise ParameterError(N["max_points"], max_points, "an integer from 2 to 1000000")
    fixed = {k: _real(v, N["omega"] if pars[k].is_forcing_frequency else k)
             for k, v in fixed.items()}
    # the model with the fixed values: the ranges of start and stop are those of this model
    others = {k: v for k, v in fixed.items() if not pars[k].is_forcing_frequency}
    at = model.with_(**others) if others else model
    base, moved = at, None
    if not par.is_forcing_frequency and "omega" not in fixed and simulation is None:
        raise ParameterError(N["omega"], None, f"a fixed forcing frequency: give "
                             f"{N['omega']}=VALUE when {N['param']} is not omega")
    if "omega" in fixed:
        check_value(at, "omega", fixed["omega"], N["omega"])
    start, stop = _real(start, N["start"], False), _real(stop, N["stop"], False)
    starts_here = start_omega is None and simulation is None
    check_value(at, par, start, N["start"], resonance=starts_here)
    check_value(at, par, stop, N["stop"], resonance=False)
    if start == stop:
        raise ParameterError(N["stop"], stop, f"a value != {N['start']} = {start:g} (the "
                             "branch lies between them)")
    lo, hi = sorted((start, stop))
    if start_omega is not None:
        if not par.is_forcing_frequency:
            raise ParameterError(N["start_omega"], start_omega, f"only with {N['param']} "
                                 f"omega (fix omega with {N['omega']}=W otherwise)")
        start_omega = _real(start_omega, N["start_omega"], finite=False)
        if not lo <= start_omega <= hi:
            raise ParameterError(N["start_omega"], start_omega, f"a value in [{lo}, {hi}]")
        check_value(at, "omega", start_omega, N["start_omega"])
        if simulation is not None:
            raise ParameterError(N["start_omega"], start_omega, f"not with "
                                 f"{N['simulation']} (which gives the start)")
        a, stops = start_omega, (lo, hi)
    else:
        a, stops = start, (stop,)
    sim = shown = None
    if simulation is not None:
        sim, shown = _simulation(simulation, N, at)
    if sim is not None and _sticks(sim):
        # a run that settled on a sticking orbit: its branch on the release section
        from .sticking import continue_sticking
        if par.is_forcing_frequency:
            a = float(sim.omega)
            if not lo <= a <= hi:
                raise ParameterError(N["simulation"], shown,
                                     f"a simulation at omega in [{lo}, {hi}]")
            return [continue_sticking(at, param, a, b, guess=sim,
                                      max_points=max_points) for b in (lo, hi) if b != a]
        return [continue_sticking(at, param, start, stop, guess=sim,
                                  max_points=max_points,
                                  omega=fixed.get("omega", sim.omega))]
    if sim is not None:
        if par.is_forcing_frequency:
            a, stops = sim.omega, (lo, hi)
            if not lo <= a <= hi:
                raise ParameterError(N["simulation"], shown, f"a simulation at omega in "
                                     f"[{lo}, {hi}] (it has {a})")
        else:
            fixed.setdefault("omega", sim.omega)
        found = detect_period(sim)
        if found is None:
            raise ParameterError(N["simulation"], shown, "a simulation settled on a "
                                 "periodic orbit (none of at most 16 impacts found)")
        if (n, p) != (1, 1) and found != (n, p):
            raise ParameterError(N["orbit"], _shown_orbit(orbit), f"the simulated orbit's "
                                 f"{found[0]}-{found[1]}")
        n, p = found
        guesses = [sim]
    else:
        # the model and omega at the start, with the fixed values
        if not par.is_forcing_frequency:
            at = at.parameter(par).apply(at, a)
        w = a if par.is_forcing_frequency else fixed["omega"]
        guesses = []
        if (n, p) == (1, 1) and at.one_rigid_stop and at.nonlinear is not None:
            # nonlinear forces: the period-1 orbits the homotopy from the linear part's
            # closed form reaches (the attractor among them), admissible ones
            guesses = [o.y for o in nonlinear_period1(at, w).orbits if o.admissible]
            moved = (f"started from the {len(guesses)} admissible period-1 orbit(s) at "
                     f"{param} = {a:.12g} continued from the linear part's closed form in "
                     "the forces' scale, and the attractor of a run (symvi.continuation."
                     "homotopy; an orbit on an isola may be missed)")
        if guesses:
            pass                        # the homotopy's orbits
        elif (n, p) == (1, 1) and (not at.one_rigid_stop or at.nonlinear is not None):
            # no closed form to start from (several stops, a lower one): the periodic
            # attractor a run of the map settles on at the start, or else at the first of
            # SEARCH_RUNS values towards the stop where a run settles on one
            a0 = a
            a, sim, why = _attractor(base, par, a0, stop, fixed.get("omega"))
            if sim is None:
                raise ParameterError(N["start_omega"] if a0 != start else N["start"], a0,
                                     "a value where a run of the map settles on a periodic "
                                     "orbit", f"none at {param} = {a0:g} ({why}), nor at "
                                     f"{SEARCH_RUNS} values towards {stop:g}")
            n, p = detect_period(sim)
            guesses = [sim]
            sig = ", ".join(_signature_names(at, sim, p))
            moved = (f"started on the {n}-{p} orbit (signature {sig}) a simulation at "
                     f"{param} = {a:.12g} settled on ({SETTLE_TRANSIENT} impacts dropped from "
                     "a default start on stop 1)")
            if a != a0:
                moved = (f"no periodic attractor at {param} = {a0:.12g} ({why}); " + moved
                         + f", the first of {SEARCH_RUNS} values towards {stop:g} with one")
        elif (n, p) != (1, 1):
            sim = _settle(at, w)
            found = detect_period(sim)
            if found != (n, p):
                got = (f"none of at most 16 impacts (the run ended: {sim.stop})"
                       if found is None else f"a {found[0]}-{found[1]} orbit")
                raise ParameterError(N["orbit"], _shown_orbit(orbit), f"an orbit the "
                                     f"simulation at {param} = {a} settles on (give "
                                     f"{N['simulation']})", f"it settles on {got}")
            guesses = [sim]
        else:
            from ..orbits.period1 import admissible_orbits
            guesses = [o.y for o in admissible_orbits(at, w, multipliers=False)]
            if not guesses:
                from ..orbits.period1 import no_orbit_reason
                why = no_orbit_reason(at, w) or "every period-1 orbit there is inadmissible"
                found = first_admissible(base, par, a, stop, fixed.get("omega"))
                if found is None:
                    raise ParameterError(N["start"], a, "a value where an admissible "
                                         "period-1 orbit exists", f"none at {param} = {a} "
                                         f"({why}), nor at {SEARCH_SAMPLES} values of "
                                         f"[{lo:g}, {hi:g}]")
                a, guesses = found
                moved = (f"no admissible period-1 orbit at {param} = {start:.12g} ({why}); "
                         f"the branch starts at {param} = {a:.12g}, the first of "
                         f"{SEARCH_SAMPLES} values towards {stop:g} with one, refined to "
                         f"the edge of existence by bisection (a window narrower than "
                         f"{abs(stop - start) / SEARCH_SAMPLES:.3g} may be missed)")
    branches = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        for guess in guesses:
            for s in stops:
                if s == a:
                    continue
                br = continue_branch(model, param, a, s, guess=guess, n=n, p=p,
                                     max_points=max_points, through=through, **fixed)
                if moved:
                    br = dataclasses.replace(br, notes=br.notes + (moved,))
                if not any(same_branch(br, other) for other in branches):
                    branches.append(br)
        if switch:
            for br in list(branches):
                for sp in br.special:
                    switch = _SWITCHES.get(sp.kind)
                    if switch is not None:
                        try:
                            new = switch(br, sp, max_points=max_points, through=through)
                        except Exception as exc:  # noqa: BLE001 - reported, not hidden
                            warnings.warn(f"branch switching at the {sp.kind} at "
                                          f"{sp.value:.12g} failed: {exc}", stacklevel=2)
                            continue
                        if not any(same_branch(new, other) for other in branches):
                            branches.append(new)
    return branches


def first_admissible(model, par, start, stop, omega=None, samples=SEARCH_SAMPLES):
    """(value, section points) of the first parameter value from ``start`` towards
    ``stop`` where ``model`` has an admissible period-1 orbit, or None: ``samples`` equal
    steps, then bisection between the last value without one and the first with one
    (to 1e-12 relative), the value returned being on the side with one.  ``par`` is the
    parameter (a lens of :meth:`symvi.model.Model.parameter`), ``omega`` the fixed
    forcing frequency when ``par`` is not omega.  A value where the model is invalid or
    singular counts as one without."""
    from ..orbits.period1 import admissible_orbits

    def orbits(v):
        try:
            m = model if par.is_forcing_frequency else par.apply(model, v)
            w = v if par.is_forcing_frequency else omega
            return [o.y for o in admissible_orbits(m, w, multipliers=False)]
        except SymviError:
            return []
    prev = start
    for j in range(1, samples + 1):
        v = start + (stop - start) * j / samples
        ys = orbits(v)
        if ys:
            lo, hi, best = prev, v, (v, ys)
            for _ in range(80):
                if abs(hi - lo) <= 1e-12 * max(1.0, abs(hi)):
                    break
                mid = 0.5 * (lo + hi)
                ys = orbits(mid)
                if ys:
                    hi, best = mid, (mid, ys)
                else:
                    lo = mid
            return best
        prev = v
    return None


# --------------------------------------------------------------------------- checks
# --------------------------------------------------------------------------- simulations
class _Run:
    """What :func:`symvi.orbits.periodic.detect_period` reads of a simulation, and with its
    sticking phases (``sticks``) what :func:`symvi.orbits.sticking.release_point` reads
    (``params``: the run's model; an .npz keeps arrays, not the model)."""

    def __init__(self, section, t, omega, hits=None, sticks=None, params=None):
        self.section, self.t, self.omega, self.hits = section, t, omega, hits
        self.sticks, self.params = sticks, params


def _names(names):
    """:data:`NAMES` with the caller's spellings."""
    if names is None:
        return NAMES
    if not isinstance(names, dict) or not set(names) <= set(NAMES) or not all(
            isinstance(v, str) for v in names.values()):
        raise ParameterError("names", names, "a dict from argument names ("
                             + ", ".join(NAMES) + ") to strings")
    return {**NAMES, **names}


def _orbit(orbit, N):
    """(n, p) of ``orbit``: a pair of integers or the text "n-p", 1 <= n, p <= 64."""
    try:
        if isinstance(orbit, str):
            n, p = (int(v) for v in orbit.split("-"))
        else:
            n, p = orbit
        ok = all(isinstance(v, Integral) and not isinstance(v, bool) and 1 <= v <= 64
                 for v in (n, p))
    except (ValueError, TypeError):
        ok = False
    if not ok:
        raise ParameterError(N["orbit"], orbit, "n-p with integers 1 <= n, p <= 64, e.g. "
                                                "1-1, 2-2")
    return int(n), int(p)


def _shown_orbit(orbit):
    return orbit if isinstance(orbit, str) else f"{orbit[0]}-{orbit[1]}"


def _known(model, name, shown):
    """The :class:`symvi.model.parameters.Parameter` called ``name`` (omega included);
    refuse a name that is not a parameter of ``model``, calling it ``shown``."""
    try:
        return model.parameter(name)
    except ParameterError as exc:
        raise ParameterError(shown, name, exc.valid) from None
    except (SymviError, TypeError):
        raise ParameterError(shown, name, "a parameter of the model: "
                             + ", ".join(model.parameter_names())) from None


def _real(value, shown, finite=True):
    """``value`` as a float (a bool or a non-number refused, naming ``shown``)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = None
    if v is None or isinstance(value, bool) or (finite and not math.isfinite(v)):
        raise ParameterError(shown, value, "a finite real number" if finite else "a real number")
    return v


def _sticks(simulation):
    """Whether a run settled on sticking: two complete sticking phases or more, the last one
    in the second half of the run."""
    import numpy as np
    st = getattr(simulation, "sticks", None)
    if st is None or len(st) < 2 or len(simulation.t) == 0:
        return False
    done = st[np.isfinite(st[:, 1])]
    return len(done) >= 2 and done[-1, 0] > simulation.t[len(simulation.t) // 2]


def _simulation(simulation, N, model):
    """(a simulation-like object, how errors show it) of a Simulation or an .npz path; an
    .npz's run is taken as one of ``model`` (the command's), with its sticking phases when
    ``symvi simulate --out`` saved them (the arrays sticks and hits)."""
    import numpy as np
    if isinstance(simulation, (str, os.PathLike)):
        shown = os.fspath(simulation)
        try:
            with np.load(shown) as f:
                section, t, omega = f["section"], f["t"], float(f["omega"])
                hits = f["hits"] if "hits" in f.files else None
                sticks = (np.array(f["sticks"], dtype=float).reshape(-1, 3)
                          if "sticks" in f.files else None)
        except (OSError, KeyError, ValueError, TypeError) as exc:
            raise ParameterError(N["simulation"], shown, "an .npz written by symvi simulate "
                                 "--out (arrays section, t, omega)", str(exc)) from None
        if sticks is not None and (
                hits is None or section.ndim != 2 or section.shape[1] != model.dim
                or len(t) != len(section) or len(hits) != len(section)):
            raise ParameterError(N["simulation"], shown, f"a run of this model: section of "
                                 f"{model.dim} columns, t and hits one per row")
        return _Run(section, t, omega, hits, sticks, model), shown
    try:
        hits = getattr(simulation, "hits", None)
        sim = _Run(np.asarray(simulation.section, dtype=float),
                   np.asarray(simulation.t, dtype=float), float(simulation.omega),
                   None if hits is None else np.asarray(hits, dtype=np.int64),
                   getattr(simulation, "sticks", None), getattr(simulation, "params", model))
    except (AttributeError, TypeError, ValueError):
        raise ParameterError(N["simulation"], type(simulation).__name__, "a Simulation "
                             "(symvi.simulate) or the path of an .npz of one") from None
    return sim, f"the simulation at omega = {sim.omega:g}"


def _settle(model, omega):
    """A run of the map at ``omega`` from symvi.simulate's default start (the admissible
    period-1 orbit plus 1e-4 in each component) or, with no period-1 closed form (several
    stops, a lower one), from :func:`default_start`: SETTLE_TRANSIENT impacts dropped,
    SETTLE_IMPACTS kept."""
    from ..simulations.simulation import default_start, simulate
    if model.elastic:        # every event (impacts, entries, exits) in the shooting layout
        from ..orbits._phases import event_run
        return event_run(model, omega, events=SETTLE_IMPACTS, transient=SETTLE_TRANSIENT)
    y0 = None if model.one_rigid_stop else default_start(model, omega)
    try:
        return simulate(model, omega, y0, n_impacts=SETTLE_IMPACTS, transient=SETTLE_TRANSIENT)
    except SingularCaseError as exc:
        if exc.kind != "no-orbit":
            raise
        # simulate's own hint (pass y0) names an argument continuation does not take
        raise SingularCaseError("no-orbit", str(exc).split(": ", 1)[1].replace(
            "to start from (pass y0 explicitly)", "to run the map from (start from a run of "
            "your own: simulation=, or --from-section on the command line)")) from None


def _attractor(model, par, start, stop, omega):
    """(value, the run that settled on a periodic orbit there, why none at the start): the
    start itself, else the first of SEARCH_RUNS values towards ``stop``; (start, None,
    why) when no run settles."""
    from ..orbits.periodic import detect_period
    why = ""
    for k in range(SEARCH_RUNS + 1):
        v = start + (stop - start) * k / SEARCH_RUNS
        at, w = (model, v) if par.is_forcing_frequency else (par.apply(model, v), omega)
        try:
            sim = _settle(at, w)
        except SymviError as exc:             # a resonance, a start inside a stop
            got = str(exc)
        else:
            if detect_period(sim) is not None:
                return v, sim, why
            got = _unsettled(sim)
        if k == 0:
            why = got
    return start, None, why


def attractor_orbit(model, omega):
    """The periodic orbit a run of the map settles on at ``omega``, refined by Newton.

    From :func:`default_start` (SETTLE_TRANSIENT impacts dropped), refined by Newton on
    its signature: what ``symvi orbit`` gives for a model with no period-1 closed form
    (several stops, a lower one).  SingularCaseError ("no-orbit") with the reason when
    the run settles on none.  The default start lies on the first stop's section: every
    other mass at rest at 0, phase 0, the stop's mass leaving at speed
    omega * max(abs(gap), 0.1); 4000 impacts are dropped and the period is read from
    the next 400 (at most 16 impacts).

    Parameters
    ----------
    model : Model
        Any model (several stops, lower, elastic and between-masses stops included).
    omega : float
        Forcing frequency, 1e-4 <= omega <= 1e4, not at the natural frequency of an
        undamped mode.

    Returns
    -------
    PeriodicOrbit
        The n-p orbit (``n``, ``p``, ``points``, ``times``, ``multipliers``,
        ``stable``, ``admissible``, ``signature``).

    Raises
    ------
    ParameterError
        ``omega`` out of range.
    SingularCaseError
        ``"forcing-resonance"`` (omega at an undamped natural frequency), or
        ``"no-orbit"``: the run settles on no periodic orbit of at most 16 impacts
        (or ends early: grazing, chatter, ...).
    SymviError
        Newton does not converge from the run (a ConvergenceError).

    Examples
    --------
    >>> from symvi import Model, Stop
    >>> from symvi.continuation import attractor_orbit
    >>> m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
    ...           stop=Stop(mass=1, gap=0.0, restitution=0.8))
    >>> o = attractor_orbit(m, 2.69)          # past the flip at omega = 2.656
    >>> o.n, o.p, o.admissible, o.stable
    (2, 2, True, True)
    """
    from ..flow import check_omega
    from ..orbits.periodic import detect_period, from_simulation
    omega = check_omega(model, omega)             # the free flight's (LinearFlow.free)
    sim = _settle(model, omega)
    if detect_period(sim) is None:
        raise SingularCaseError("no-orbit", f"a run of the map from a default start on stop "
                                f"1 at omega = {omega:g} settles on no periodic orbit "
                                f"({_unsettled(sim)})")
    return from_simulation(sim)


def _signature_names(model, sim, p):
    """The names of the last p events of a run (:meth:`symvi.model.Signature.names`)."""
    from ..model import Signature
    act = getattr(sim, "active", None)
    sig = Signature(tuple(int(k) for k in sim.hits[-p:]), () if act is None else act[-p])
    return sig.names(model) if model.elastic else [f"stop{k + 1}" for k in sig.hits]


def _unsettled(sim):
    """Why a run settled on no periodic orbit, in a phrase."""
    return (f"the run ended: {sim.stop}" if sim.stop != "completed" else
            "it settles on no periodic orbit of at most 16 impacts")




#: frequencies of [omega_min, omega_max] whose attractors start :func:`ns_scan`'s branches
SCAN_SAMPLES = 8
#: why :func:`ns_scan` certifies nothing, said with every result
SCAN_UNCERTIFIED = ("no period-1 closed form for this model: the NS points are those of "
                    "the branches continued from the periodic attractors that runs of the "
                    "map settle on at {samples} frequencies; an orbit no run settles on, "
                    "and a branch that does not reach one, are not searched")


@dataclasses.dataclass(frozen=True)
class BranchScan:
    """The Neimark-Sacker points of a model with no period-1 closed form over
    [omega_min, omega_max] (:func:`ns_scan`): ``points`` the located NS points (each a
    :class:`SpecialPoint` with l1, ||q||_2 = 1, <p,q> = 1), ``branches`` the continued
    branches they lie on, ``starts`` the (omega, n, p, signature) of each attractor a
    branch started from.  Never certified (:data:`SCAN_UNCERTIFIED`)."""

    model: object
    omega_min: float
    omega_max: float
    points: tuple
    branches: tuple
    starts: tuple
    samples: int
    complete: bool = False

    @property
    def reason(self):
        extra = ("; with nonlinear forces also the period-1 orbits at both ends continued "
                 "from the linear part's closed form in the forces' scale"
                 if self.model.nonlinear is not None and self.model.one_rigid_stop else "")
        return SCAN_UNCERTIFIED.format(samples=self.samples) + extra

    def as_dict(self):
        index = {id(br): k + 1 for k, br in enumerate(self.branches)}
        return {"model": self.model.as_dict(), "omega_min": self.omega_min,
                "omega_max": self.omega_max, "complete": False,
                "uncertified": [[self.omega_min, self.omega_max]],
                "uncertified_reasons": [self.reason],
                "points": [{**sp.as_dict(), "branch": index[id(br)]}
                           for sp, br in self.points],
                "branches": [{"orbit": f"{br.n}-{br.p}",
                              "signature": br.points[0].orbit.signature_names,
                              "omega": [float(br.values.min()), float(br.values.max())],
                              "end": br.end} for br in self.branches],
                "starts": [{"omega": w, "orbit": f"{n}-{p}", "signature": sig}
                           for w, n, p, sig in self.starts]}


def ns_scan(model, omega_min, omega_max, samples=SCAN_SAMPLES, max_points=5000):
    """The Neimark–Sacker points of a model with no period-1 closed form, uncertified.

    The NS points of ``model`` (one with no period-1 closed form: several stops, a
    lower one, an elastic stop, nonlinear forces) in [omega_min, omega_max], as ``symvi
    hopf`` reports them there: at ``samples`` frequencies a run of the map from the
    default start settles on a periodic attractor; each new one is continued in omega
    over the interval both ways (:func:`continue_orbits`), and the NS points located on
    the branches are kept, each once.  With nonlinear forces on one rigid stop the
    period-1 orbits at both ends that :mod:`.homotopy` reaches are continued too.  A
    :class:`BranchScan`, which says it is not certified: an orbit no run settles on, and a
    branch that does not reach one, are not searched (the certified scan of closed-form
    branches is :func:`symvi.hopf_points`).

    Parameters
    ----------
    model : Model
        Any model.
    omega_min : float
        Lower end of the interval, 1e-4 <= omega_min < omega_max.
    omega_max : float
        Upper end, at most 1e4.
    samples : int, optional
        Frequencies (the midpoints of equal sub-intervals) where a run looks for an
        attractor (default 8).
    max_points : int, optional
        Most points on each branch (default 5000).

    Returns
    -------
    BranchScan
        ``points``: (SpecialPoint, Branch) pairs of kind "ns", sorted by omega, each
        with its normal-form coefficients (``l1``); ``branches``, ``starts`` (omega,
        n, p, signature of each attractor started from), ``complete`` False and
        ``reason``.

    Raises
    ------
    ParameterError
        ``model`` not a Model, an end not a real number or out of range, or
        ``omega_max <= omega_min``.
    """
    from ..model import Model
    from ..orbits.periodic import detect_period, from_simulation
    if not isinstance(model, Model):
        raise ParameterError("model", model, "a symvi.Model")
    lo = check_value(model, "omega", _real(omega_min, "omega_min"), "omega_min",
                     resonance=False)
    hi = check_value(model, "omega", _real(omega_max, "omega_max"), "omega_max",
                     resonance=False)
    if not lo < hi:
        raise ParameterError("omega_max", hi, f"a value > omega_min = {lo:g}")
    from ..progress import Progress
    branches, starts = [], []

    def follow(w, orbit):
        if not orbit.admissible or any(_on(br, orbit) for br in branches):
            return
        starts.append((w, orbit.n, orbit.p, orbit.signature_names))
        for stop in (lo, hi):
            if stop == w:
                continue
            try:
                br = continue_branch(model, "omega", w, stop, orbit=orbit,
                                     max_points=max_points)
            except SymviError:
                continue
            if not any(same_branch(br, other) for other in branches):
                branches.append(br)
    with warnings.catch_warnings(), Progress(samples, "NS scan (attractors)") as bar:
        warnings.simplefilter("ignore", NearSingularWarning)
        if model.nonlinear is not None and model.one_rigid_stop:
            # nonlinear forces: also the period-1 orbits at both ends that the homotopy
            # from the linear part's closed form reaches (unstable ones included)
            from .homotopy import period1_orbits
            for w in (lo, hi):
                for orbit in period1_orbits(model, w).orbits:
                    follow(w, orbit)
        for k in range(samples):
            bar.update()
            w = lo + (hi - lo) * (k + 0.5) / samples
            try:
                sim = _settle(model, w)
                found = detect_period(sim)
                if found is None:
                    continue
                orbit = from_simulation(sim)
            except SymviError:
                continue
            follow(w, orbit)
    seen, points = [], []
    for br in branches:
        for sp in br.special:
            key = (_rotation_key(sp.orbit.signature_names), sp.value)
            if sp.kind == "ns" and not any(k[0] == key[0] and abs(k[1] - key[1]) <= 1e-9 *
                                           (1 + abs(key[1])) for k in seen):
                seen.append(key)
                points.append((sp, br))
    points.sort(key=lambda t: t[0].value)
    return BranchScan(model, lo, hi, tuple(points), tuple(branches), tuple(starts), samples)


def _on(branch, orbit):
    """Whether ``orbit`` lies on ``branch``: the same n-p and signature up to where the
    orbit starts (a rotation), and the orbit's point of the branch's first event within
    1e-3 of the branch's points interpolated at its omega (a start found again is not
    continued twice)."""
    if (branch.n, branch.p) != (orbit.n, orbit.p) or not branch.points:
        return False
    sig, mine = branch.points[0].orbit.signature_names, orbit.signature_names
    shifts = [r for r in range(orbit.p) if mine[r:] + mine[:r] == sig]
    for a, b in zip(branch.points[:-1], branch.points[1:]):
        wa, wb = a.orbit.omega, b.orbit.omega
        if not (min(wa, wb) <= orbit.omega <= max(wa, wb) and wa != wb):
            continue
        s = (orbit.omega - wa) / (wb - wa)
        ya, yb = np.array(a.orbit.y), np.array(b.orbit.y)
        for r in shifts:
            y = np.array(orbit.points[r])
            d = ya + s * (yb - ya) - y
            d[-1] = (d[-1] + math.pi) % (2 * math.pi) - math.pi
            if np.max(np.abs(d)) <= 1e-3 * (1 + np.max(np.abs(y))):
                return True
    return False


def _rotation_key(names):
    """The signature's smallest rotation: one key for an orbit whichever event it starts at."""
    return min(tuple(names[r:] + names[:r]) for r in range(len(names)))


def period1_branches(model, omega_min, omega_max, *, switch=True, max_points=5000):
    """The period-1 branches over [omega_min, omega_max], and the period-doubled ones.

    Started from the admissible period-1 orbits at both ends (duplicates dropped), and
    with ``switch`` the period-doubled branch of each flip: what a bifurcation diagram
    overlays.  An end where the orbits are singular (a resonance, not isolated) starts
    nothing; a branch or switch that fails is left out, silently.

    Parameters
    ----------
    model : Model or Params
        A model with one rigid upper stop on one mass (the paper's Params as its
        ``Model.luo_xie``); with nonlinear forces its period-1 orbits at the ends are
        those :func:`nonlinear_period1` finds (the closed form's otherwise).
    omega_min : float
        Lower end of the interval, at least 1e-4; branches start at both ends.
    omega_max : float
        Upper end, at most 1e4.
    switch : bool, optional
        Add the 2-2 branch born at each admissible flip point (default True).
    max_points : int, optional
        Most points on each branch (default 5000).

    Returns
    -------
    list of Branch
        The 1-1 branches continued in omega from each end, then the doubled ones.

    Raises
    ------
    ParameterError
        ``model`` neither a Model nor Params, an end out of range, or a model with
        several stops or a lower, elastic or between-masses stop.

    Examples
    --------
    >>> from symvi import Model, Stop
    >>> from symvi.continuation import period1_branches
    >>> m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
    ...           stop=Stop(mass=1, gap=0.0, restitution=0.8))
    >>> [(br.n, br.p) for br in period1_branches(m, 2.5, 2.8)]
    [(1, 1), (2, 2)]
    """
    from ..model import Model
    model = Model.of(model)      # the paper's Params too (it found no branch: silently none)
    out = []
    for a, b in ((omega_max, omega_min), (omega_min, omega_max)):
        try:
            orbits = _period1_starts(model, a)
        except SingularCaseError:      # a singular end (resonance, not isolated): none there
            continue
        for y in orbits:
            try:
                br = continue_branch(model, "omega", a, b, guess=y, max_points=max_points)
            except SymviError:
                continue
            if not any(same_branch(br, x) or same_branch(x, br) for x in out):
                out.append(br)
    if switch:
        for br in list(out):
            for sp in br.special:
                if sp.kind == "flip" and sp.orbit.admissible:
                    try:
                        out.append(switch_at_flip(br, sp, max_points=max_points))
                    except SymviError:
                        pass
    return out


def _period1_starts(model, omega):
    """The section points of the admissible period-1 orbits at omega: the closed form's,
    or with nonlinear forces those :func:`nonlinear_period1` finds."""
    if model.nonlinear is None:
        from ..orbits.period1 import admissible_orbits
        return [o.y for o in admissible_orbits(model, omega, multipliers=False)]
    return [o.y for o in nonlinear_period1(model, omega).orbits if o.admissible]


def diagram_branches(system, omega_min, omega_max, component=0):
    """What a bifurcation diagram over omega overlays, for a Model or the paper's Params.

    (curves of :meth:`Branch.curve`, special points as dicts with the orbit's n-p), of
    the branches of :func:`period1_branches` (doubled branches included).

    Parameters
    ----------
    system : Model or Params
        A model with one rigid upper stop on one mass, or the paper's parameters.
    omega_min : float
        Lower end of the interval, at least 1e-4.
    omega_max : float
        Upper end, at most 1e4.
    component : int, optional
        The section coordinate drawn (0-based index into the orbit's section point;
        default 0, the stop mass's velocity after the impact).

    Returns
    -------
    curves : list of dict
        One :meth:`Branch.curve` per branch.
    special : list of dict
        Every special point (:meth:`SpecialPoint.as_dict`), with ``"orbit"`` its
        branch's ``"n-p"``.

    Raises
    ------
    ParameterError
        As :func:`period1_branches`.

    Examples
    --------
    >>> from symvi import Model, Stop
    >>> from symvi.continuation import diagram_branches
    >>> m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
    ...           stop=Stop(mass=1, gap=0.0, restitution=0.8))
    >>> curves, special = diagram_branches(m, 2.5, 2.8)
    >>> len(curves), [(s["kind"], s["orbit"]) for s in special]
    (2, [('flip', '1-1'), ('flip', '2-2')])
    """
    from ..model import Model
    brs = period1_branches(Model.of(system), omega_min, omega_max)
    return ([b.curve(component) for b in brs],
            [dict(sp.as_dict(), orbit=f"{b.n}-{b.p}") for b in brs for sp in b.special])


def nonlinear_period1(model, omega):
    """The period-1 orbits of a model with nonlinear forces at omega: those the homotopy
    from its linear part reaches (:func:`symvi.continuation.homotopy.period1_orbits`) and
    the attractor of a run (:func:`attractor_orbit`) where it is 1-1 and not among them;
    a :class:`symvi.continuation.homotopy.NonlinearPeriod1`."""
    from .homotopy import period1_orbits
    try:
        also, notes = [(attractor_orbit(model, omega), "attractor")], ()
    except SymviError as exc:
        also, notes = [], (f"attractor: none of period 1 found ({exc})",)
    return period1_orbits(model, omega, also=also, notes=notes)
