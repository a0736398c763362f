"""Long runs of the Poincaré map P, eqs. (26) and (31): impact sections and sweeps.

The float64 path runs the compiled exact flow and first-impact finder of
:mod:`symvi.flow.compiled` for any :class:`symvi.model.Model`, whose section
points have the 2N components of :mod:`symvi.maps.section`.  A
:class:`symvi.Params` (the paper's model) runs there as
:meth:`symvi.model.Model.luo_xie` (:meth:`Model.of`), whose section layout is the
paper's (x1dot+, x2, x2dot, tau) of eq. (9).  :func:`simulate_mp` runs the same map
through :func:`symvi.maps.impact.step` on mpmath, as an independent reference.  A model
with an elastic stop runs the exact walk of :mod:`symvi.flow.contact` through free flights,
contact phases and rigid impacts instead, in Python (:func:`_simulate_contacts`: its
records are rigid impacts and contact entries, with each contact's exit).

A rigid run goes on through complete chatter and sticking (:mod:`symvi.flow.sticking`:
the accumulation point of a converging impact sequence, the motion held on the stop, the
release where the contact force changes sign; ``Simulation.sticks``).  It ends early,
with a stop reason, on

* ``grazing``  -- a contact with x1dot- below the grazing speed and x1'' < 0,
* ``sticking`` -- a sticking that cannot be continued (``Simulation.stop_reason`` says
  why: r >= 1, a second stop met while held, held past the flight bound, ...),
* ``chatter``  -- CHATTER_COUNT flights in a row shorter than CHATTER_FLIGHT
  forcing periods that do not converge to an accumulation point,
* ``no-impact`` -- no return to the stop within 1000 forcing periods,

never with a hang or a section point past an unresolved contact.
"""
import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, SingularCaseError
from ..flow import check_omega
from ..flow import compiled as cf
from ..flow.sticking import run_through
from ..model import Model
from ..numerics.tolerances import ABS_MAX

#: default start: the admissible period-1 orbit y* plus this vector (x1dot+, x2, x2dot, tau)
DEFAULT_PERTURBATION = (1e-4, 1e-4, 1e-4, 1e-4)

STOP_NAMES = cf.STOP_NAMES


@dataclass(frozen=True)
class Simulation:
    """A finished run: section points after the transient, in the order of eq. (9)."""

    params: object
    omega: float
    y0: tuple                 # start point used (x1dot+, x2, x2dot, tau); 2N for a Model
    section: np.ndarray       # (n, 4): x1dot+, x2, x2dot, tau in [0, 2 pi); (n, 2N) for a Model
    t: np.ndarray             # (n,) impact times since the start, transient included
    impact_velocity: np.ndarray   # (n,) x1dot- just before each stored impact
    stop: str                 # "completed", "grazing", "chatter", "sticking", "no-impact"
    transient: int            # images dropped before the first stored one
    fixed_point: tuple = None     # the period-1 orbit y* at omega, when it exists
    hits: np.ndarray = None   # (n,) the constraint (0-based index) each stored impact hit;
                              # its section point lies on that constraint's section
    #: with an elastic stop (:func:`_simulate_contacts`): the time each stored contact ends
    #: and its approach speed then (guard . v < 0, leaving); NaN for a rigid impact, and
    #: for a contact still open when the run stopped.  None for a rigid-only model.
    exit_t: np.ndarray = None
    exit_velocity: np.ndarray = None
    #: with an elastic stop: every event from the first stored record on (rigid impacts,
    #: entries and exits, :class:`symvi.orbits._phases.EventRun`: each point on its
    #: constraint's section in the shooting layout, the constraints in contact after it),
    #: what the Lyapunov exponents and the classifier read.  None for a rigid-only model.
    events: object = None
    #: every sticking phase of a rigid run (:mod:`symvi.flow.sticking`): rows (t_stick,
    #: t_release, constraint), t_stick the accumulation point of the chatter before it (or
    #: the zero-speed contact), t_release where the contact force changed sign (NaN: still
    #: held when the run stopped); times since the start as ``t``.  Empty: never stuck.
    sticks: np.ndarray = None
    #: why a stopped run could not go on ("" for a completed one, or a stop the run loop
    #: names itself: grazing, no impact, non-finite)
    stop_reason: str = ""

    @property
    def n(self):
        return len(self.section)

    @property
    def flight_times(self):
        """t_e of eq. (26) from each stored point to the next impact (n - 1 values)."""
        return np.diff(self.t)

    @property
    def stops(self):
        """Number of stops of the model run."""
        return len(Model.of(self.params).constraints)

    def impacts_per_stop(self):
        """Stored impacts on each stop, in the model's order."""
        return [int(v) for v in np.bincount(self.hits, minlength=self.stops)]

    def on_stop(self, k):
        """The stored section points of impacts on stop k (0-based): the points of one
        section (with several stops, each point lies on the section of its stop)."""
        return self.section[np.asarray(self.hits) == k]


def _frozen(a):
    a = np.ascontiguousarray(a, dtype=np.float64)
    a.flags.writeable = False
    return a


#: stored impacts are 32 bytes each: 5e7 of them is 1.6 GB
MAX_STORED = 50_000_000
MAX_TRANSIENT = 1_000_000_000


def _positive_int(name, value, minimum=1, maximum=MAX_STORED):
    if (isinstance(value, bool) or not isinstance(value, (int, np.integer))
            or not minimum <= value <= maximum):
        raise ParameterError(name, value, f"an integer from {minimum} to {maximum}")
    return int(value)


def fixed_point(params, omega):
    """y* of the admissible period-1 orbit at omega, or None (eqs. (10)–(18))."""
    from ..orbits import admissible_orbits
    try:
        ok = admissible_orbits(Model.of(params), omega, multipliers=False)
    except SingularCaseError:
        return None
    return tuple(float(v) for v in ok[0].y) if ok else None


def _no_orbit_reason(params, omega):
    """Why no period-1 orbit exists at omega ("" if one exists but is inadmissible)."""
    from ..orbits.period1 import no_orbit_reason
    try:
        return no_orbit_reason(Model.of(params), omega)
    except SingularCaseError as exc:
        return str(exc)


def _check_size(y, y0, name):
    # a state beyond ABS_MAX over- or underflows in the flow (the finder's scale L = sum of
    # the amplitudes): refused, not simulated into a wrong stop reason
    if any(abs(v) > ABS_MAX for v in y[:-1]):
        raise ParameterError(name, y0, f"displacements and velocities with |value| <= "
                             f"{ABS_MAX:g}")


def _check_system_start(params, y0, name="y0"):
    """y0 checked for the system (a Model, or the paper's Params as its Model): 2N numbers."""
    return _check_model_start(Model.of(params), y0, name)


def _check_model_start(model, y0, name="y0"):
    """A 2N section point (:mod:`symvi.maps.section`) of the first constraint that leaves
    it, outside every other constraint, tau mod 2 pi."""
    from ..maps import Section
    sec = Section.of(model)
    y = tuple(float(v) for v in sec.check(y0, name))
    names = sec.names
    first = model.constraints[0]
    if not first.sign * y[0] < 0:
        side = "< 0" if first.sign > 0 else "> 0"
        raise ParameterError(name, y0, f"{names[0]} {side}: the mass must leave the stop")
    _check_size(y, y0, name)
    if len(model.constraints) > 1:
        z, _ = sec.state(np.array(y), first.gap)
        x = np.empty(model.n)
        if sec.labels is None:
            x[list(sec.perm)] = z[:model.n]
        else:                                  # the flow's frame q = T x (a stop between masses)
            from ..flow.linear import frame_of
            x = np.linalg.inv(frame_of(model)[1]) @ z[:model.n]
        for i, con in enumerate(model.constraints[1:], start=2):
            if not con.guard(x) < 0:
                raise ParameterError(name, y0, f"a start outside every other stop "
                                     f"(stop {i}: s = {con.s(x):.10g} is at or past its gap "
                                     f"{con.gap:g})")
    return y[:-1] + (y[-1] % (2 * math.pi),)


def _perturbation(params, perturbation):
    """The start offset for params: 2N numbers (N = 2 for the paper's Params), the default
    1e-4 each."""
    dim = Model.of(params).dim
    if perturbation is DEFAULT_PERTURBATION:
        return (DEFAULT_PERTURBATION[0],) * dim
    try:
        d = tuple(float(v) for v in perturbation)
    except (TypeError, ValueError):
        d = ()
    if len(d) != dim or not all(math.isfinite(v) for v in d):
        raise ParameterError("perturbation", perturbation, f"{dim} finite numbers")
    return d


def start_point(params, omega, perturbation=DEFAULT_PERTURBATION):
    """Default start y* + perturbation, and y*; raises if no admissible orbit exists."""
    perturbation = _perturbation(params, perturbation)
    ys = fixed_point(params, omega)
    if ys is None:
        why = _no_orbit_reason(params, omega)
        raise SingularCaseError(
            "no-orbit", f"no admissible period-1 orbit at omega = {omega!r} to start from "
            "(pass y0 explicitly)" + (f": {why}" if why else ""))
    return tuple(a + d for a, d in zip(ys, perturbation)), ys


def simulate(params, omega, y0=None, n_impacts=5000, transient=0, *,
             perturbation=DEFAULT_PERTURBATION):
    """Iterate the Poincaré map P of eq. (31) on float64 with the exact flow.

    ``y0`` defaults to the admissible period-1 orbit y* plus ``perturbation``
    (the paper starts from the "theoretical fixed point"; an exact fixed point
    would stay there).  The first ``transient`` images are dropped and the next
    ``n_impacts`` stored.  ``params`` is a :class:`symvi.Params` or any
    :class:`symvi.model.Model` (then y0 and ``perturbation`` have 2N components).  A
    model with an elastic stop needs ``y0`` and runs :func:`_simulate_contacts` (records:
    rigid impacts and contact entries; ``exit_t``, ``exit_velocity``; with nonlinear forces
    too, each contact phase on the Taylor flow); a rigid-only model
    runs the compiled loop of :mod:`symvi.flow.compiled`.  A model with nonlinear forces
    (:attr:`symvi.Model.nonlinear`, issue 28) needs ``y0`` and runs the numerical flow of
    :mod:`symvi.flow.nonlinear` (every rigid constraint), with the same records, through
    chatter and sticking as well (:mod:`symvi.flow.nlsticking`).

    A rigid run goes on through complete chatter and sticking (``sticks``: when each
    sticking phase began and ended).  A run ends early, with its reason in ``stop``, on a
    grazing contact, on a sticking that cannot be continued, on chatter that does not
    converge (16 flights in a row shorter than 1e-3 forcing periods), or when no impact
    follows within 1000 forcing periods (``stop_reason`` says why where the stop name
    does not); never with a hang or a section point past an unresolved contact.

    Parameters
    ----------
    params : Params or Model
        The paper's parameters, or any :class:`symvi.Model` (several stops, lower stops,
        stops between masses and elastic stops included).
    omega : float
        Forcing frequency, 1e-4 <= omega <= 1e4, not at the natural frequency of an
        undamped mode.
    y0 : sequence of float, optional
        The start: a section point of the first stop, 2N numbers in the order of
        :class:`symvi.Orbit`'s ``names`` (v_k+, x_j, v_j for j != k, tau), leaving the
        stop (entering it, for an elastic stop) and outside every other stop;
        ``abs(value) <= 1e6``.  Default None: y* + ``perturbation``, which needs a
        model with one rigid upper stop on one mass and an admissible period-1 orbit at
        omega; required for any other model.
    n_impacts : int, optional
        Impacts stored, 1 to 5e7 (default 5000).
    transient : int, optional
        Impacts dropped before the first stored one, 0 to 1e9 (default 0).
    perturbation : sequence of float, optional
        Added to y* for the default start: 2N finite numbers (default 1e-4 each).

    Returns
    -------
    Simulation
        ``section`` (n, 2N): the stored section points, tau in [0, 2 pi); ``t`` the
        impact times since the start (transient included); ``impact_velocity`` the
        approach speed before each stored impact; ``hits`` the stop (0-based) each
        impact hit; ``stop`` why the run ended ("completed", "grazing", "chatter",
        "sticking", "no-impact", "non-finite"); ``y0`` the start used; ``fixed_point``
        y* when it exists (else None); ``params``, ``omega``, ``transient``; with an
        elastic stop also ``exit_t``, ``exit_velocity`` and ``events``; with rigid stops
        ``sticks`` (m, 3): (t_stick, t_release, stop) of each sticking phase, and
        ``stop_reason``.  The arrays are read-only.

    Raises
    ------
    ParameterError
        ``omega`` out of range, ``n_impacts`` or ``transient`` not an integer in range,
        ``perturbation`` not 2N finite numbers, a ``y0`` that is not 2N finite numbers,
        does not leave the stop or lies past another stop, or no ``y0`` for a model
        with no period-1 closed form (several stops, a lower, elastic or between-masses
        stop).
    SingularCaseError
        ``"forcing-resonance"`` (omega at an undamped natural frequency), or
        ``"no-orbit"``: no ``y0`` and no admissible period-1 orbit at omega to start
        from.

    Examples
    --------
    >>> import symvi
    >>> p = symvi.Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    >>> sim = symvi.simulate(p, 0.72, n_impacts=50, transient=500)
    >>> sim.stop, sim.section.shape
    ('completed', (50, 4))
    >>> print(abs(sim.section - sim.fixed_point).max() < 1e-6)     # a stable orbit
    True
    """
    model = Model.of(params)
    if model.elastic:                 # contact phases: the walk of symvi.flow.contact
        return _simulate_contacts(model, omega, y0, n_impacts, transient)
    if model.nonlinear is not None:   # the numerical flow of symvi.flow.nonlinear
        return _simulate_nonlinear(model, omega, y0, n_impacts, transient)
    omega = check_omega(params, omega)
    n_impacts = _positive_int("n_impacts", n_impacts)
    transient = _positive_int("transient", transient, minimum=0, maximum=MAX_TRANSIENT)
    perturbation = _perturbation(params, perturbation)
    if not model.one_rigid_stop:
        # several stops, or a lower one: no period-1 closed form to start from
        if y0 is None:
            from ..maps import Section
            raise ParameterError("y0", None, f"a start on the first stop's section "
                                 f"({', '.join(Section.of(model).names)}): no period-1 "
                                 "orbit in closed form to start from with several stops or "
                                 "a lower one (symvi orbit finds the attractor)")
        ys = None
    else:
        ys = fixed_point(params, omega)
    if y0 is None:
        y0, ys = start_point(params, omega, perturbation)
    y0 = _check_system_start(params, y0)
    c = cf.constants(model, omega)
    # the run loop, continued through complete chatter and sticking
    code, sec, t, vimp, hits, sticks, reason = run_through(model, c, y0, n_impacts, transient)
    hits = np.ascontiguousarray(hits, dtype=np.int64)
    hits.flags.writeable = False
    return Simulation(params, omega, y0, _frozen(sec), _frozen(t), _frozen(vimp),
                      STOP_NAMES[code], transient, ys, hits, sticks=_frozen(sticks),
                      stop_reason=reason)


def _simulate_nonlinear(model, omega, y0, n_impacts, transient):
    """:func:`simulate` of a model with nonlinear forces (issue 28): the run of
    :class:`symvi.flow.nonlinear.NonlinearFlow` (the Taylor method, every contact located
    on the solution's polynomial) through complete chatter and sticking
    (:func:`symvi.flow.nlsticking.run_through`), the same records, ``sticks`` and stop
    reasons as the compiled run.
    Without ``y0`` it starts from :func:`default_start` (no period-1 orbit in closed form to
    start near)."""
    from ..flow.linear import check_range
    from ..flow.nlsticking import run_through as run_through_nonlinear
    from ..flow.nonlinear import NonlinearFlow
    if isinstance(omega, (bool, str)):
        raise ParameterError("omega", omega, "a finite real number > 0")
    omega = check_range(omega)
    n_impacts = _positive_int("n_impacts", n_impacts)
    transient = _positive_int("transient", transient, minimum=0, maximum=MAX_TRANSIENT)
    flow = NonlinearFlow(model)                   # refuses what it cannot run yet
    # no period-1 orbit in closed form to start near: the default start off the stop
    y0 = _check_model_start(model, default_start(model, omega) if y0 is None else y0)
    # the run loop, continued through complete chatter and sticking
    code, sec, t, vimp, hits, sticks, reason = run_through_nonlinear(flow, float(omega), y0,
                                                                     n_impacts, transient)
    hits = np.ascontiguousarray(hits, dtype=np.int64)
    hits.flags.writeable = False
    return Simulation(model, float(omega), y0, _frozen(sec), _frozen(t), _frozen(vimp),
                      STOP_NAMES[code], transient, None, hits, sticks=_frozen(sticks),
                      stop_reason=reason)


def _simulate_contacts(model, omega, y0, n_impacts, transient):
    """:func:`simulate` for a model with an elastic stop (and any rigid ones, each stop on
    one mass): the exact walk of :mod:`symvi.flow.contact` through free flights, contact
    phases and rigid impacts, in Python (float64; about 1 ms an event).

    A record is a rigid impact, as the compiled run stores it, or the *entry* into an
    elastic contact: its section point lies on s = g (the layout of
    :mod:`symvi.maps.section` for the stop's mass) with the velocities at the entry (no
    jump: y[0] = v_k there, moving into the stop), ``t`` the entry time,
    ``impact_velocity`` the approach speed guard . v > 0 at the entry, and ``exit_t``,
    ``exit_velocity`` the end of that contact.  ``y0`` is such a point of the first stop:
    leaving it for a rigid stop, entering it for an elastic one.  The stop reasons are the
    compiled run's; a contact that does not end within 1000 forcing periods is
    ``sticking``, and chatter counts records closer than CHATTER_FLIGHT periods.  With
    nonlinear forces each phase runs on the Taylor flow (:mod:`symvi.flow.nlcontact`), the
    same walk and records."""
    from ..flow.linear import LinearFlow
    from ..maps import Section
    # the frame: q = T x (stops between masses), the linear part's (geometry only)
    flow = LinearFlow.contact(model.linear_part)
    omega = check_omega(model, omega)
    n_impacts = _positive_int("n_impacts", n_impacts)
    transient = _positive_int("transient", transient, minimum=0, maximum=MAX_TRANSIENT)
    sec = Section.of(model)
    if y0 is None:
        raise ParameterError("y0", None, f"a start on the first stop's section "
                             f"({', '.join(sec.names)}): no period-1 orbit in closed form to "
                             "start from with an elastic stop (symvi orbit finds the "
                             "attractor)")
    y0, z0 = _check_walk_start(model, sec, y0, flow)
    active = (0,) if model.constraints[0].kind == "elastic" else ()
    return _walk_records(model, omega, z0, y0[-1], active, 0, n_impacts, transient, y0)


def contact_run(model, omega, n_impacts, transient, start=None):
    """:func:`_simulate_contacts` of a checked (model, omega) from ``start`` = (state z0 in
    mass order, phase tau, the elastic constraints in contact, the constraint whose guard z0
    lies on), by default :func:`symvi.orbits._phases.default_state` (the first stop's
    section, leaving it, nothing in contact): the runs of a sweep or a plane."""
    if start is None:
        from ..orbits._phases import default_state
        start = (default_state(model, omega), 0.0, (), 0)
    z0, tau, active, k = start
    return _walk_records(model, float(omega), np.asarray(z0, dtype=float), float(tau),
                         tuple(active), int(k), int(n_impacts), int(transient))


def _walk_records(model, omega, z0, tau, active, start, n_impacts, transient, y0=None):
    """The records of :func:`_simulate_contacts` from state z0 (mass order) at phase tau with
    ``active`` in contact, on the guard of ``start``; ``Simulation.events`` every event from
    the first record kept on (:class:`symvi.orbits._phases.EventRun`: the exits too, each
    point on its constraint's section, and the constraints in contact after it)."""
    from ..flow import contact as ct
    from ..flow.linear import LinearFlow
    from ..orbits._phases import EventRun, section_frames
    flow = LinearFlow.contact(model.linear_part)      # the frames (geometry only)
    frames = section_frames(flow)
    if y0 is None:                    # the start as a section point of its constraint
        zf = flow.to_flow(z0)
        y0 = tuple(float(v) for v in zf[frames[start]]) + (tau % (2 * math.pi),)
    n = model.n
    rows, t, vin, hits, t_out, v_out = [], [], [], [], [], []
    ev_rows, ev_t, ev_hits, ev_act = [], [], [], []
    total = transient + n_impacts
    count, short, last, stop = 0, 0, 0.0, "completed"
    t_chat = cf.CHATTER_FLIGHT * 2 * math.pi / omega
    open_ = {}                        # elastic constraint in contact -> its record (-1: dropped)
    for ev in ct.walk(model, omega, z0, tau, active=active, start=start):
        done = count >= total
        point = None                      # the event's point on its constraint's section
        if ev.kind in (ct.IMPACT, ct.ENTRY, ct.EXIT) and np.all(np.isfinite(ev.after)):
            point = tuple(flow.to_flow(ev.after)[frames[ev.constraint]]) + (ev.tau,)
        if point is not None and (
                count > transient or (count == transient and ev.kind != ct.EXIT)):
            g = ev.constraint             # every event from the first kept record on
            ev_rows.append(point)
            ev_t.append(ev.t)
            ev_hits.append(g)
            ev_act.append(ev.active)
        if ev.kind == ct.EXIT:
            j = open_.pop(ev.constraint, -1)
            if j >= 0:
                con = model.constraints[ev.constraint]
                t_out[j], v_out[j] = ev.t, con.approach(ev.before[n:])
        elif ev.kind in (ct.IMPACT, ct.ENTRY):
            if done:
                continue
            if not np.all(np.isfinite(ev.after)):
                stop = "non-finite"
                break
            kept = count - transient
            count += 1
            short = short + 1 if ev.t - last < t_chat else 0
            last = ev.t
            g = ev.constraint
            if ev.kind == ct.ENTRY:
                open_[g] = kept
            if kept >= 0:
                con = model.constraints[g]
                rows.append(point)
                t.append(ev.t)
                vin.append(con.approach(ev.before[n:]))
                hits.append(g)
                t_out.append(math.nan)
                v_out.append(math.nan)
            if short >= cf.CHATTER_COUNT:
                stop = "chatter"
                break
        else:                          # the walk ended
            if not done:
                stop = {ct.GRAZING: "grazing", ct.STICKING: "sticking",
                        ct.NO_EVENT: "no-impact", ct.NONFINITE: "non-finite"}[ev.kind]
            break
        if count >= total and not any(j >= 0 for j in open_.values()):
            break
    hits = np.array(hits, dtype=np.int64)
    hits.flags.writeable = False
    ev_hits = np.array(ev_hits, dtype=np.int64)
    ev_hits.flags.writeable = False
    events = EventRun(model, omega, _frozen(np.array(ev_rows).reshape(-1, model.dim)),
                      _frozen(ev_t), ev_hits, tuple(ev_act), stop)
    return Simulation(model, omega, y0, _frozen(np.array(rows).reshape(-1, model.dim)),
                      _frozen(t), _frozen(vin), stop, transient, None, hits,
                      _frozen(t_out), _frozen(v_out), events)


def _check_walk_start(model, sec, y0, flow, name="y0"):
    """(y0 as a tuple with tau mod 2 pi, the state z0 in mass order): a point of the first
    stop's section, leaving a rigid stop or entering an elastic one, outside every other."""
    y = tuple(float(v) for v in sec.check(y0, name))
    first = model.constraints[0]
    names = sec.names
    if first.kind == "elastic" and not first.sign * y[0] > 0:
        side = "> 0" if first.sign > 0 else "< 0"
        raise ParameterError(name, y0, f"{names[0]} {side}: the section of an elastic stop "
                             "is the entry into contact")
    if first.kind == "rigid" and not first.sign * y[0] < 0:
        side = "< 0" if first.sign > 0 else "> 0"
        raise ParameterError(name, y0, f"{names[0]} {side}: the mass must leave the stop")
    _check_size(y, y0, name)
    zf, _ = sec.state(np.array(y), first.gap)
    n = model.n
    z = flow.to_mass(zf)
    for i, con in enumerate(model.constraints[1:], start=2):
        if not con.guard(z[:n]) < 0:
            raise ParameterError(name, y0, f"a start outside every other stop "
                                 f"(stop {i}: s = {con.s(z[:n]):.10g} is at or past its gap "
                                 f"{con.gap:g})")
    return y[:-1] + (y[-1] % (2 * math.pi),), z


def simulate_mp(params, omega, y0, n_impacts, *, digits=40):
    """Reference run of the same map on mpmath at ``digits`` (slow: about 1 ms per impact).

    Uses :func:`symvi.maps.impact.step` on the mpmath flow, so it shares no code with the
    compiled kernels.  Values are rounded to float64 only on output.
    """
    # the reference map (symvi.maps.impact) runs one stop: refused before any work
    model = Model.of(params).require_one_rigid_stop()
    return _simulate_model_mp(model, omega, y0, n_impacts, digits)


def _simulate_model_mp(model, omega, y0, n_impacts, digits):
    """:func:`simulate_mp` for a Model: :func:`symvi.maps.impact.step` on mpmath."""
    import mpmath

    from ..flow.linear import LinearFlow
    from ..maps.impact import step
    omega = LinearFlow.of(model).check_omega(omega)
    n_impacts = _positive_int("n_impacts", n_impacts)
    y0 = _check_model_start(model, y0)
    out, times, vimp = [], [], []
    stop = "completed"
    flow = LinearFlow.of(model, digits)
    with mpmath.mp.workdps(digits):
        F = flow.forcing(mpmath.mpf(omega))
        y = np.array([mpmath.mpf(v) for v in y0], dtype=object)
        T = mpmath.mpf(0)
        for _ in range(n_impacts):
            s = step(flow, F, y)
            if s.status != "impact":
                stop = s.status
                break
            y, T = np.array(s.y, dtype=object), T + s.t
            out.append([float(v) for v in y])
            times.append(float(T))
            vimp.append(float(s.impact_velocity))
    return Simulation(model, omega, y0, _frozen(np.array(out).reshape(-1, model.dim)),
                      _frozen(times), _frozen(vimp), stop, 0, fixed_point(model, omega))


@dataclass(frozen=True)
class Sweep:
    """Section points of many runs over a grid of omega (a bifurcation diagram)."""

    params: object
    omegas: np.ndarray        # (m,)
    section: np.ndarray       # (m, n, 4), (m, n, 2N) for a Model; rows past counts[i] are NaN
    counts: np.ndarray        # (m,) points stored per omega
    stops: tuple              # stop reason per omega
    starts: np.ndarray        # (m, 4) start points used; (m, 2N) for a Model
    transient: int
    impacts_total: int        # map iterations requested (runs that stop early do fewer)
    #: the attractor of each run (:class:`symvi.simulations.classifier.Classified`, one
    #: row per omega) when asked for (``sweep(..., classify=True)``), else None
    classes: object = None

    def labels(self):
        """The class of each omega in the one vocabulary (:func:`classifier.label`:
        "period-1", "circle", ...); None when the sweep was not classified."""
        return None if self.classes is None else self.classes.labels()

    def signatures(self):
        """With several stops, per omega the stops of a periodic attractor's impacts
        (["stop1", "stop2"], :func:`classifier.signature`), None where it is not periodic;
        None when the sweep was not classified or the model has one stop."""
        if self.classes is None or self.classes.signature is None:
            return None
        return self.classes.signature_names()

    def class_counts(self):
        """{class: number of omegas}, the classes sorted by name; None when the sweep was
        not classified."""
        labels = self.labels()
        if labels is None:
            return None
        return {c: int(n) for c, n in zip(*np.unique(labels, return_counts=True))}


#: how :func:`omega_grid` names its arguments in an error (the command line passes its flags)
GRID_NAMES = {"omega_min": "omega_min", "omega_max": "omega_max", "steps": "steps"}


def omega_grid(params, omega_min, omega_max, steps, *, names=None):
    """``steps`` evenly spaced forcing frequencies from ``omega_min`` to ``omega_max`` (the
    grid of a sweep, ``symvi sweep``), each valid for ``params``: the ends in range, in
    order, and no point at a natural frequency.  Errors name the arguments as ``names``
    spells them (:data:`GRID_NAMES`)."""
    from ..errors import SymviError
    N = {**GRID_NAMES, **(names or {})}
    check_omega(params, omega_min, N["omega_min"], warn=False)
    check_omega(params, omega_max, N["omega_max"], warn=False)
    if not omega_min < omega_max:
        raise ParameterError(N["omega_max"], omega_max,
                             f"greater than {N['omega_min']} = {omega_min!r}")
    omegas = np.linspace(omega_min, omega_max, steps)
    for k, w in enumerate(omegas[1:-1], start=1):
        try:
            check_omega(params, float(w), "omega", warn=False)
        except SymviError as exc:
            raise ParameterError(N["steps"], len(omegas), f"a grid ({N['omega_min']}, "
                                 f"{N['omega_max']}, {N['steps']}) with no point at a "
                                 "natural frequency", f"grid point {k} is omega = "
                                 f"{float(w)!r}: {str(exc).split(':', 1)[0]}") from None
    return omegas


def default_start(model, omega):
    """A start on the first stop's section: every other mass at rest at 0, the phase 0,
    and the stop's mass leaving it at speed omega max(|gap|, 0.1) (a flight of the size of
    the clearance, not a chatter at the stop)."""
    con = model.constraints[0]
    y = [0.0] * (2 * model.n)
    y[0] = -con.sign * float(omega) * max(abs(con.gap), 0.1)
    return tuple(y)


def sweep_starts(params, omegas, perturbation=DEFAULT_PERTURBATION):
    """Start points for a sweep: y* + perturbation at each omega.

    Where no admissible orbit exists the nearest omega's start is reused; if
    none exists anywhere, raise.  A model with no period-1 closed form (several stops, a
    lower one) starts each omega from :func:`default_start`.
    """
    model = Model.of(params)
    if model.elastic:                 # the walk's default start, as a section point
        return np.array([contact_start(model, w)[1] for w in omegas])
    if not model.one_rigid_stop or model.nonlinear is not None:
        return np.array([default_start(model.require_rigid_stops(), w) for w in omegas])
    perturbation = _perturbation(params, perturbation)
    ys = [fixed_point(params, w) for w in omegas]
    have = [i for i, y in enumerate(ys) if y is not None]
    if not have:
        why = {_no_orbit_reason(params, float(w)) for w in omegas} - {""}
        raise SingularCaseError("no-orbit", "no admissible period-1 orbit anywhere on the "
                                "omega grid to start from"
                                + (f": {why.pop()}" if len(why) == 1 else ""))
    starts = np.empty((len(omegas), Model.of(params).dim))
    for i in range(len(omegas)):
        j = min(have, key=lambda k: abs(k - i))
        starts[i] = np.add(ys[j], perturbation)
    return starts


def sweep(params, omegas, n_impacts=200, transient=2000, *, starts=None,
          perturbation=DEFAULT_PERTURBATION, chunk=None, progress=None, classify=False):
    """Independent runs at each omega in parallel (numba threads).

    ``progress(done, total)`` is called after each chunk of omegas.  ``params``
    is a :class:`symvi.Params` or any :class:`symvi.model.Model`.  ``classify``: also
    label each omega's attractor (:func:`classify_sweep`; ``n_impacts`` >= 4), in
    ``Sweep.classes``.  A model with an elastic stop or nonlinear forces runs each omega
    in Python (:func:`_sweep_walked`; ``starts`` are points of the first stop's section
    leaving it, nothing in contact, by default :func:`contact_start`, or
    :func:`default_start` with nonlinear forces on rigid stops; ``n_impacts`` >= 4 per symbol of
    :func:`symbol_count` to classify).
    """
    omegas = np.array([check_omega(params, w, warn=False) for w in np.ravel(omegas)])
    n_impacts = _positive_int("n_impacts", n_impacts, maximum=max(1, MAX_STORED // len(omegas)))
    if classify:
        _check_classifiable(n_impacts, params=params)
    transient = _positive_int("transient", transient, minimum=0, maximum=MAX_TRANSIENT)
    if _walked(Model.of(params)):     # contact phases or nonlinear forces: omega by omega
        return _sweep_walked(params, omegas, n_impacts, transient, starts, progress,
                             classify)
    if starts is None:
        starts = sweep_starts(params, omegas, perturbation)
    try:
        rows = list(starts)
    except TypeError:
        raise ParameterError("starts", starts, f"{len(omegas)} start points") from None
    if len(rows) != len(omegas):
        raise ParameterError("starts", starts, f"{len(omegas)} start points, one per omega")
    starts = np.array([_check_system_start(params, y, "starts") for y in rows])
    m = len(omegas)
    model = Model.of(params)
    C = np.array([cf.constants(model, w) for w in omegas])
    sec = np.full((m, n_impacts, starts.shape[1]), np.nan)
    counts = np.zeros(m, dtype=np.int64)
    codes = np.zeros(m, dtype=np.int64)
    chunk = chunk or max(1, m // 50)
    for lo in range(0, m, chunk):
        hi = min(m, lo + chunk)
        cd, ct, s, _, _, _ = cf.run_batch(C[lo:hi], starts[lo:hi], n_impacts, transient)
        sec[lo:hi], counts[lo:hi], codes[lo:hi] = s, ct, cd
        for i in lo + np.flatnonzero(cd == cf.STOP_STICKING):
            # the same run again, on through its sticking phases (in Python)
            codes[i], s_i = run_through(model, C[i], starts[i], n_impacts, transient)[:2]
            counts[i] = len(s_i)
            sec[i] = np.nan
            sec[i, :len(s_i)] = s_i
        if progress is not None:
            progress(hi, m)
    res = Sweep(params, _frozen(omegas), _frozen(sec), counts, tuple(STOP_NAMES[k] for k in codes),
                _frozen(starts), transient, int(m * (n_impacts + transient)))
    return dataclasses.replace(res, classes=classify_sweep(res)) if classify else res


def _check_classifiable(n_impacts, name="n_impacts", params=None):
    """Refuse a classification the classifier does not take: too few kept impacts
    (:func:`~symvi.simulations.classifier.min_kept`: 4, or 4 per symbol of
    :func:`symbol_count`)."""
    from .classifier import MIN_KEPT, min_kept
    least = MIN_KEPT
    if params is not None:
        least = min_kept(symbol_count(Model.of(params)))
    if n_impacts < least:
        raise ParameterError(name, n_impacts, f"an integer >= {least} to classify"
                             + (f" ({MIN_KEPT} per stop)" if least > MIN_KEPT else ""))


def classify_sweep(res):
    """The attractor of each run of the sweep ``res`` by the one classifier
    (:func:`symvi.simulations.classifier.classify_runs`: the shared run loop with its
    tangent map, then :func:`~symvi.simulations.classifier._judge`, as the plane and
    ``symvi simulate --classify`` judge): the same runs again (the sweep's start points,
    kept impacts and transient), one row per omega.  A
    :class:`~symvi.simulations.classifier.Classified`; ``.labels()`` names the classes."""
    from .classifier import classify_runs
    n_keep = res.section.shape[1]
    _check_classifiable(n_keep, params=res.params)
    model = Model.of(res.params)
    if _walked(model):                # the same walks (runs of the numerical flow) again
        return classify_walked([(model, float(w)) for w in res.omegas], n_keep,
                               res.transient,
                               starts=[_walk_start(model, y) for y in res.starts])
    C = np.array([cf.constants(model, float(w)) for w in res.omegas])
    return classify_runs(C, res.starts, n_keep, res.transient, models=model)


def symbol_count(model):
    """How many kinds of record the classifier tells apart: one per rigid stop, two per
    elastic one (its entries and exits, :func:`symvi.simulations.diagnostics.event_symbols`);
    a classified run keeps at least :func:`~symvi.simulations.classifier.min_kept` of it."""
    return sum(2 if con.kind == "elastic" else 1 for con in model.constraints)


def contact_start(model, omega):
    """(the walk's start of :func:`contact_run`, the same as a section point of the first
    stop): :func:`symvi.orbits._phases.default_state`, leaving the first stop, nothing in
    contact, phase 0."""
    from ..flow.linear import LinearFlow
    from ..orbits._phases import default_state, section_frames
    z = default_state(model, omega)
    flow = LinearFlow.contact(model.linear_part)
    frame = section_frames(flow)[0]
    return (z, 0.0, (), 0), tuple(float(v) for v in flow.to_flow(z)[frame]) + (0.0,)


def _leaving(model, y, name="starts"):
    """The walk's start from a section point y of the first stop leaving it (a sweep's
    start, :func:`contact_start`), nothing in contact; checked as :func:`_check_model_start`."""
    from ..flow.linear import LinearFlow
    from ..maps import Section
    y = _check_model_start(model, y, name)
    zf, _ = Section.of(model).state(np.array(y), model.constraints[0].gap)
    return LinearFlow.contact(model.linear_part).to_mass(zf), y[-1], (), 0


def _walked(model):
    """Whether a sweep runs ``model`` omega by omega in Python: an elastic stop's walk, or
    the numerical flow of nonlinear forces (no compiled batch for either)."""
    return model.elastic or model.nonlinear is not None


def _walk(model, omega, n_keep, transient, start):
    """One run of a walked model (:func:`_walked`) from ``start`` (None: its default):
    an elastic stop's walk (:func:`contact_run`) or the numerical flow of nonlinear forces
    (:func:`_simulate_nonlinear`, a section point of the first stop); with elastic stops
    and nonlinear forces the walk, its phases on the Taylor flow."""
    if model.nonlinear is not None and not model.elastic:
        return _simulate_nonlinear(model, omega, start, n_keep, transient)
    return contact_run(model, omega, n_keep, transient, start)


def _walk_start(model, y):
    """The start :func:`_walk` takes for a sweep's section point y of the first stop."""
    return tuple(y) if not model.elastic else _leaving(model, y)


def _sweep_walked(model, omegas, n_impacts, transient, starts, progress, classify):
    """:func:`sweep` of a model run omega by omega (:func:`_walked`): an elastic stop's walk
    (:func:`contact_run`, from ``starts``, default :func:`contact_start`) or the numerical
    flow of nonlinear forces (:func:`_simulate_nonlinear`, default :func:`default_start`),
    its records as the section; ``classify`` judges those same runs."""
    model = Model.of(model)
    m = len(omegas)
    if starts is None:
        starts = sweep_starts(model, omegas)
    try:
        rows = list(starts)
    except TypeError:
        raise ParameterError("starts", starts, f"{m} start points") from None
    if len(rows) != m:
        raise ParameterError("starts", starts, f"{m} start points, one per omega")
    begin = [_walk_start(model, y) for y in rows]
    sims = []
    for i, w in enumerate(omegas):
        sims.append(_walk(model, float(w), n_impacts, transient, begin[i]))
        if progress is not None:
            progress(i + 1, m)
    sec = np.full((m, n_impacts, model.dim), np.nan)
    counts = np.zeros(m, dtype=np.int64)
    for i, sim in enumerate(sims):
        counts[i] = sim.n
        sec[i, :sim.n] = sim.section
    res = Sweep(model, _frozen(omegas), _frozen(sec), counts, tuple(s.stop for s in sims),
                _frozen(np.array([s.y0 for s in sims])), transient,
                int(m * (n_impacts + transient)))
    return (dataclasses.replace(res, classes=_classified([_judge_run(s) for s in sims]))
            if classify else res)


#: the codes after which a followed point starts from the previous one's end (a bounded
#: attractor: period, circle, doubled torus, chaos)
_BOUNDED = (0, 1, 2, 3)


def classify_walked(points, n_keep, transient, *, follow=False, row_len=None, starts=None):
    """:func:`symvi.simulations.classifier.classify_runs` for models run point by point in
    Python (:func:`_walked`): per point (model, omega) one run, ``n_keep`` records after
    ``transient`` -- an elastic stop's walk (:func:`contact_run`, from ``starts``, default
    :func:`contact_start`) or the numerical flow of nonlinear forces
    (:func:`_simulate_nonlinear`, default :func:`default_start`) -- judged by
    :func:`symvi.simulations.diagnostics.classify`'s judge on every event of the run.
    ``follow``: in each row of ``row_len`` points a point after the first starts from the
    previous point's last event (its state, phase and contacts) when that run reached a
    bounded attractor.  About 0.2-1 ms an event for a walk, 0.1-2 ms with nonlinear forces
    (Lyapunov exponents from each flight's series)."""
    points = list(points)
    row_len = len(points) if row_len is None else int(row_len)
    rows, followed, prev = [], [], None
    for p, (model, omega) in enumerate(points):
        start = None if starts is None else starts[p]
        own = True
        if follow and p % row_len and prev is not None and prev[1][0] in _BOUNDED:
            start, own = _end_state(model, prev[0]), False
        sim = _walk(model, omega, n_keep, transient, start)
        prev = (sim, _judge_run(sim))
        rows.append(prev[1])
        followed.append(not own)
    return _classified(rows, followed)


def _end_state(model, sim):
    """The walk's start at the last event of ``sim`` (state, phase, contacts, constraint),
    its section point put on ``model``'s constraint (the next point of a row); with
    nonlinear forces the last stored point on the first stop's section."""
    if not model.elastic:
        first = np.flatnonzero(np.asarray(sim.hits) == 0)
        return tuple(float(v) for v in sim.section[first[-1]]) if len(first) else None
    from ..flow.linear import LinearFlow
    from ..orbits._phases import state_of
    ev = sim.events
    k = int(ev.hits[-1])
    return (state_of(LinearFlow.contact(model.linear_part), k, ev.section[-1]),
            float(ev.section[-1][-1]), tuple(ev.active[-1]), k)


def _judge_run(sim):
    """One walked run's (:func:`_walked`) row of
    :class:`~symvi.simulations.classifier.Classified`: (code, period, events per orbit,
    lyapunov, rotation, records per period, max velocity, stop, last event's point, its
    constraint, signature, kinds)."""
    from . import classifier as cl
    from .diagnostics import _judged
    stop = STOP_NAMES.index(sim.stop)
    ev = sim if sim.events is None else sim.events      # the nonlinear flow: its impacts
    dim = Model.of(sim.params).dim
    y_end, k_end = (ev.section[-1], int(ev.hits[-1])) if len(ev.t) else (np.full(dim, np.nan), 0)
    vmax = float(np.max(np.abs(sim.impact_velocity))) if sim.n else math.nan
    if sim.stop != "completed":
        return (cl.code_of_stop(stop), 0, 0, math.nan, math.nan, math.nan, vmax, stop, y_end,
                k_end, (), ())
    c, glog, rot = _judged(sim, cl.Q_MAX, cl.TOL_CLOSED, None, cl.LYAP_MIN)
    per = math.nan
    if sim.n > 1:
        per = (sim.n - 1) / ((sim.t[-1] - sim.t[0]) * sim.omega / (2 * math.pi))
    return (c.code, c.period or 0, c.impacts or 0,
            float(glog[:, 0].mean()) if len(glog) else math.nan, rot, per, vmax, stop, y_end,
            k_end, c.signature or (), c.kinds or ())


def _classified(rows, followed=None):
    """The :class:`~symvi.simulations.classifier.Classified` of rows of :func:`_judge_run`."""
    from . import classifier as cl
    m = len(rows)
    col = list(zip(*rows)) if m else [()] * 12
    followed = np.zeros(m, dtype=np.bool_) if followed is None else np.array(followed, bool)
    return cl.Classified(np.array(col[0], dtype=np.int8), np.array(col[1], dtype=np.int32),
                         np.array(col[2], dtype=np.int32), np.array(col[3], dtype=float),
                         np.array(col[4], dtype=float), np.array(col[5], dtype=float),
                         np.array(col[6], dtype=float), np.array(col[7], dtype=np.int8),
                         np.array(col[8], dtype=float).reshape(m, -1), followed,
                         np.array(col[9], dtype=np.int64), tuple(col[10]), tuple(col[11]))


def quick_counts(spec, quick, default_impacts=2000, default_transient=5000):
    """(impacts, transient, note): the counts a simulation uses, reduced in quick mode."""
    n, tr = spec["impacts"], spec.get("transient", 0)
    if not quick:
        return n, tr, ""
    qn = spec.get("quick_impacts") or min(n, default_impacts)
    qt = spec.get("quick_transient")
    qt = min(tr, default_transient) if qt is None else qt
    if (qn, qt) == (n, tr):
        return n, tr, ""
    return qn, qt, (f"quick mode: {qn} impacts after a transient of {qt} "
                    f"(full run: {n} after {tr})")
