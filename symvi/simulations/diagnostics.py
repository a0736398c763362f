"""Diagnostics of a simulated attractor of P: Lyapunov exponents, rotation number, class.

* Lyapunov exponents of the section map, per impact, by the QR method
  [Benettin et al. 1980; Eckmann & Ruelle 1985]: Q_{k+1} R_k = DP(y_k) Q_k and
  lambda_i = mean log |R_k[i, i]|.  DP(y_k) is the Jacobian of eqs. (36)–(38)
  at a general section point, compiled by numba: the flight's state transition
  with the flight time eliminated, eq. (30) (:func:`symvi.orbits._shooting.monodromy`;
  :func:`jacobian` gives the same matrix from the generated code in Python).
* The rotation number of an invariant circle: mean turning angle per impact
  around the circle's centre in its principal plane.
* A classification: period-k point, invariant circle, doubled torus, chaos, by the one
  classifier of :mod:`symvi.simulations.classifier` (the plane's).

References
----------
[Benettin et al. 1980] G. Benettin, L. Galgani, A. Giorgilli, J.-M. Strelcyn,
Lyapunov characteristic exponents for smooth dynamical systems, Meccanica 15 (1980).
[Eckmann & Ruelle 1985] J.-P. Eckmann, D. Ruelle, Ergodic theory of chaos and
strange attractors, Rev. Mod. Phys. 57 (1985), Sec. IV.
"""
import math
from dataclasses import dataclass

import numpy as np

import numba as nb

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from ..flow import compiled as cf
#: stored impacts below which a run is not classified: period detection compares
#: points k apart (k <= n/2) and the chaos test needs 10 blocks of exponents
from ..numerics.tolerances import MIN_CLASSIFY
from ..orbits import _shooting
from .classifier import LYAP_MIN

TWO_PI = 2 * math.pi
#: chaos: the largest exponent (per impact) over the last half, less the radial growth,
#: above this floor (and the O(1/n) bias): the classifier's LYAP_MIN
CHAOS_THRESHOLD = LYAP_MIN


def jacobian(params, omega, y, t_e=None):
    """DP at the section point y with flight time t_e, eqs. (36)–(38), tau unwrapped
    (generated code, :func:`symvi.codegen.jets.jacobian_at`; a Params is its preset)."""
    from ..codegen.jets import jacobian_at
    from ..model import Model
    model = Model.of(params)
    if t_e is None:
        t_e = cf.step(cf.constants(model, omega), [float(v) for v in y])[1]
    return jacobian_at(model, omega, y, t_e)


@dataclass(frozen=True)
class Lyapunov:
    """Lyapunov exponents of P per impact (descending) and how they were obtained."""

    exponents: np.ndarray     # (4,) per impact
    n: int                    # Jacobians multiplied
    mean_flight_time: float   # divide exponents by this for per unit time
    stderr: float = math.nan  # standard error of the largest, from 10 consecutive blocks

    @property
    def largest(self):
        return float(self.exponents[0])


def lyapunov(sim, n=None):
    """Lyapunov spectrum of P along the stored section of ``sim`` (QR method).

    Uses the last ``n`` points (default all); each needs its flight time, so
    the last stored point is not used.
    """
    return _spectrum(*_logs(sim, n))


def _spectrum(logs, te):
    # columns of Q stay ordered by growth once converged: column 0 carries lambda_1
    blocks = [b[:, 0].mean() for b in np.array_split(logs, 10) if len(b)]
    err = float(np.std(blocks, ddof=1) / math.sqrt(len(blocks))) if len(blocks) > 1 else math.nan
    return Lyapunov(np.sort(logs.mean(axis=0))[::-1], len(logs), float(np.mean(te)), err)


def classifiable(params):
    """Whether :func:`classify` takes the model of ``params``: any stops, rigid or elastic
    (with several, or an elastic one, the period is that of the events' symbols and the
    points together, the rest is judged on one symbol's section: :func:`event_symbols`)."""
    from ..model import Model
    Model.of(params)
    return True


def event_symbols(model):
    """The symbols the classifier tells events apart by: (constraint, kind) in the model's
    order, "impact" for a rigid stop, "entry" then "exit" for an elastic one (each a section
    of its own: an entry and an exit lie on the same s = g, moving in and out)."""
    out = []
    for k, con in enumerate(model.constraints):
        out += [(k, "entry"), (k, "exit")] if con.kind == "elastic" else [(k, "impact")]
    return tuple(out)


def _symbols_of(events):
    """The symbol (index into :func:`event_symbols`) of each event of an EventRun: an
    elastic event is an entry when its constraint is in contact after it."""
    from ..model import Model
    table = {s: i for i, s in enumerate(event_symbols(Model.of(events.params)))}
    cons = Model.of(events.params).constraints
    return np.array([table[(int(k), "impact" if cons[k].kind != "elastic" else
                            "entry" if k in act else "exit")]
                     for k, act in zip(events.hits, events.active)], dtype=np.int64)


def _logs(sim, n=None):
    """(log |R_k[i, i]| of the QR method over the last ``n`` points, their flight times);
    column 0 is log |DP v| of one tangent vector, the classifier's input.  With several
    stops each DP maps the section of the stop a point lies on to the next one's
    (``sim.hits``): the product over the run is chart-free, so are the exponents."""
    from ..model import Model
    model = Model.of(sim.params)
    if model.elastic:                   # per event, from the shooting system
        return _event_logs(sim.events, n)
    sec, t = np.asarray(sim.section), np.asarray(sim.t)
    if len(sec) < 3:
        raise ValueError("need at least 3 section points")
    k0 = 0 if n is None else max(0, len(sec) - 1 - int(n))
    te = np.diff(t)
    hits = None if model.one_rigid_stop else np.asarray(sim.hits)[k0:]
    if model.nonlinear is not None:     # DP of each flight from its series
        logs = _series_logs(model, sim.omega, sec[k0:-1], te[k0:], hits)
    else:
        logs = _qr_logs_model(model, sim.omega, sec[k0:-1], te[k0:], hits)
    if not np.isfinite(logs).all():
        from ..errors import SingularCaseError
        raise SingularCaseError("grazing", "an impact of the stored section has zero "
                                "velocity (grazing): DP, eq. (30), is undefined there")
    return logs, te[k0:]


def _series_logs(model, omega, sec, te, hits=None):
    """:func:`_qr_logs_model` of a model with nonlinear forces: DP of each flight from its
    first-order series (:func:`symvi.flow.nljet.map_jet`, ~0.2 ms a flight) through the QR
    method of :func:`_qr_mats`; from a flight without approach speed on (grazing) the
    logs are NaN, which :func:`_logs` refuses."""
    from ..errors import SingularCaseError
    from ..flow.nljet import FlowView, map_jet
    view = FlowView.of(model)
    m, d = len(te), sec.shape[1]
    if hits is None:
        hits = np.zeros(m + 1, dtype=np.int64)
    mats = np.full((m, d, d), np.nan)
    for k in range(m):
        try:
            mats[k] = map_jet(view, float(omega), sec[k], float(te[k]), 1, int(hits[k]),
                              int(hits[k + 1]))["J"]
        except SingularCaseError:
            break
    return _qr_mats(mats)


def _qr_logs_model(params, omega, sec, te, hits=None):
    """log |R_k[i, i]| of the QR method (compiled, ~1 us a point for N = 2): flight k from
    sec[k] on stop hits[k] to the section of stop hits[k + 1] (``hits``, one longer than
    ``te``; None: the one stop's section throughout)."""
    from ..flow.compiled import section_index, table
    from ..flow.linear import LinearFlow
    from ..model import Model
    flow = LinearFlow.of(Model.of(params))
    F = flow.forcing(float(omega))
    lam, W, Winv, A, NIL = flow.modal_nil64
    NIL = NIL if flow.free else np.empty((0, 0))
    tab = table(flow)
    idx = np.array([section_index(flow.n, int(row[0])) for row in tab])
    if hits is None:
        hits = np.zeros(len(te) + 1, dtype=np.int64)
    return _qr_logs(lam, W, Winv, A, NIL, F.U, F.V, F.omega, tab, idx,
                    np.ascontiguousarray(sec, dtype=float), np.ascontiguousarray(te, dtype=float),
                    np.ascontiguousarray(hits, dtype=np.int64))


@nb.njit(cache=True)
def _qr_logs(lam, W, Winv, A, NIL, U, V, w, tab, idx, sec, te, hits):
    """Q_{k+1} R_k = DP(y_k) Q_k along the section, DP of flight k from the section of stop
    hits[k] to that of hits[k + 1] by eq. (30) (with several stops the product over the
    run is chart-free, so are the exponents)."""
    m = te.shape[0]
    d = sec.shape[1]
    logs = np.empty((m, d))
    Q = np.eye(d)
    u = np.empty(d + 1)
    sig = np.empty(2, np.int64)
    for k in range(m):
        u[:d] = sec[k]
        u[d] = te[k]
        sig[0], sig[1] = hits[k], hits[k + 1]
        Gu = _shooting.shoot(lam, W, Winv, A, NIL, U, V, U, V, w, tab, idx, sig, 1, u, 1,
                             True, False)[1]
        _, J, ok = _shooting.monodromy(Gu, 1, d)
        if not ok:                       # an impact at zero velocity: DP is undefined
            logs[k, :] = np.nan
            continue
        Q = _qr_update(J, Q, logs, k)
    return logs


@nb.njit(cache=True)
def _qr_update(J, Q, logs, k):
    """One step of the QR method: J Q = Q' R, log |R[i, i]| into logs[k]; returns Q'."""
    d = Q.shape[0]
    Q, R = np.linalg.qr(J @ Q)
    Q = np.ascontiguousarray(Q)
    for i in range(d):
        dg = R[i, i]
        logs[k, i] = math.log(abs(dg))
        if dg < 0.0:                     # keep Q's columns continuous
            Q[:, i] = -Q[:, i]
    return Q


@nb.njit(cache=True)
def _qr_mats(mats):
    """The QR method over given map Jacobians mats[k] (m, d, d); a non-finite one (an
    event at zero speed: no map there) gives NaN logs and is skipped."""
    m, d = mats.shape[0], mats.shape[1]
    logs = np.empty((m, d))
    Q = np.eye(d)
    for k in range(m):
        if not np.all(np.isfinite(mats[k])):
            logs[k, :] = np.nan
            continue
        Q = _qr_update(np.ascontiguousarray(mats[k]), Q, logs, k)
    return logs


def event_jacobians(events, n=None):
    """(DP_i, flight times) of the map from each event's section to the next over the last
    ``n`` events (default all) of ``events`` (:class:`symvi.orbits._phases.EventRun`, every
    impact, entry and exit), eq. (30) with each flight in its contact phase's exact flow.

    The shooting system gives them: the run is cut into chunks at the events of its most
    frequent (constraint, phase before) pair, so that a chunk's events form a
    :class:`symvi.model.Signature` (each elastic stop met an even number of times, ``contact``
    the phase after its first event) whose last flight ends on its first event's constraint
    in the right phase; :meth:`symvi.orbits.periodic.Problem.monodromy` of each chunk gives
    its DP_i, each from its own flight alone (the chunk's wrap-around residual is not
    closed, and need not be).  Events before the first cut and from the last one on are
    not used."""
    from ..errors import SymviError
    from ..model import Signature
    from ..orbits.periodic import Problem
    sec, t = np.asarray(events.section, dtype=float), np.asarray(events.t, dtype=float)
    hits, act = np.asarray(events.hits), events.active
    m, d = len(sec), sec.shape[1] if sec.ndim == 2 else 0
    if m < 3:
        raise ValueError("need at least 3 events")
    k0 = 1 if n is None else max(1, m - 1 - int(n))
    keys = [(int(hits[i]), act[i - 1]) for i in range(k0, m)]
    counts = {}
    for key in keys:
        counts[key] = counts.get(key, 0) + 1
    best = max(counts, key=lambda key: (counts[key], -keys.index(key)))
    cuts = [k0 + j for j, key in enumerate(keys) if key == best]
    mats, te, problems = [], [], {}
    w = float(events.omega)
    for a, b in zip(cuts[:-1], cuts[1:]):
        sig = Signature(tuple(int(h) for h in hits[a:b]), contact=act[a])
        pr = problems.get(sig)
        if pr is None:
            pr = problems[sig] = Problem(events.params, n=1, p=b - a, omega=w, signature=sig)
        Y = sec[a:b].copy()
        T = t[a + 1:b + 1] - t[a:b]
        for i in range(1, b - a):          # tau unwrapped along the chunk
            near = Y[0, -1] + w * (t[a + i] - t[a])
            Y[i, -1] += TWO_PI * round((near - Y[i, -1]) / TWO_PI)
        u = np.concatenate([Y.ravel(), T])
        try:
            Gu = pr.evaluate(u, None)[1]
            mats += pr.monodromy(u, Gu)[0]
        except SymviError:                 # an event at zero speed: no map there
            mats += [np.full((d, d), np.nan)] * (b - a)
        te += list(T)
    return np.array(mats).reshape(-1, d, d), np.array(te)


def _event_logs(events, n=None):
    """:func:`_logs` of an elastic run: the QR method over :func:`event_jacobians`."""
    mats, te = event_jacobians(events, n)
    if len(mats) == 0:
        raise ValueError("no two events of the run repeat a constraint and phase: no map")
    logs = _qr_mats(np.ascontiguousarray(mats))
    if not np.isfinite(logs).all():
        from ..errors import SingularCaseError
        raise SingularCaseError("grazing", "an event of the run has zero speed (grazing): "
                                "DP, eq. (30), is undefined there")
    return logs, te


def _unwrapped(section, center):
    """Section points minus center, tau difference wrapped to (-pi, pi]."""
    X = np.asarray(section, dtype=float) - np.asarray(center, dtype=float)
    X[:, -1] = (X[:, -1] + math.pi) % TWO_PI - math.pi       # tau is the last coordinate
    return X


def circle_center(section):
    """Centroid of the points, tau averaged on the circle."""
    sec = np.asarray(section, dtype=float)
    c = sec.mean(axis=0)
    c[-1] = math.atan2(np.sin(sec[:, -1]).mean(), np.cos(sec[:, -1]).mean()) % TWO_PI
    return c


def _plane(X):
    """Angle of each point in the principal plane of the (standardised) points."""
    s = X.std(axis=0)
    s[s == 0] = 1
    Z = X / s
    _, _, Vt = np.linalg.svd(Z - Z.mean(axis=0), full_matrices=False)
    u = Z @ Vt[:2].T
    return np.arctan2(u[:, 1], u[:, 0]), Z


def rotation_number(section, center=None):
    """Rotation number of points on an invariant circle, in [0, 1/2] (orientation-free).

    Mean turning angle per impact about ``center`` (default the centroid) in
    the principal plane, divided by 2 pi.  Near a Hopf point it tends to
    arg(lambda_1) / (2 pi) of the critical multiplier.
    """
    X = _unwrapped(section, circle_center(section) if center is None else center)
    theta, _ = _plane(X)
    d = (np.diff(theta) + math.pi) % TWO_PI - math.pi
    return float(abs(d.mean()) / TWO_PI)


def branch_count(section, bins=36, min_points=12, separation=6.0):
    """How many sheets the points form over the angle around their centre: 1 for an
    invariant circle, 2 for a doubled torus.

    In each angular bin the points, after removing a linear trend in the
    angle, are split in two by Otsu's criterion; the bin has two sheets when
    the gap between the groups exceeds ``separation`` within-group standard
    deviations.  The answer is the majority over populated bins.
    """
    X = _unwrapped(section, circle_center(section))
    theta, Z = _plane(X)
    edges = np.linspace(-math.pi, math.pi, bins + 1)
    votes = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (theta >= lo) & (theta < hi)
        if sel.sum() < min_points:
            continue
        th, Zb = theta[sel], Z[sel]
        A = np.column_stack([np.ones_like(th), th - th.mean()])
        res = Zb - A @ np.linalg.lstsq(A, Zb, rcond=None)[0]
        _, _, Vt = np.linalg.svd(res, full_matrices=False)
        r = np.sort(res @ Vt[0])
        best = 0.0
        for k in range(3, len(r) - 2):   # Otsu split with at least 3 points a side
            a, b = r[:k], r[k:]
            w = math.sqrt((a.var() * len(a) + b.var() * len(b)) / len(r)) + 1e-300
            best = max(best, (b.mean() - a.mean()) / w)
        votes.append(best > separation)
    if not votes:
        return 0
    return 2 if np.mean(votes) > 0.5 else 1


def period_of(section, max_period=64, tol=1e-7):
    """Smallest q (impacts) after which the points repeat, or None: the one period
    detector of :mod:`symvi.simulations.classifier` (closure ``tol`` relative to
    1 + max|y| over the last points, or a decaying approach)."""
    from .classifier import period_of as _period_of
    return _period_of(section, max_period, tol)


@dataclass(frozen=True)
class Classification:
    """What the stored section of a run looks like (the one classifier,
    :mod:`symvi.simulations.classifier`)."""

    kind: str                 # "period-k" (k forcing periods), "invariant circle",
    #                           "doubled torus", "chaos", "stopped: <reason>",
    #                           "too few impacts to classify ..."
    period: object            # k for a period-k point, else None
    lyapunov: object          # Lyapunov (QR spectrum), or None
    rotation: object          # rotation number on an invariant circle, else None
    branches: object          # 1 for an invariant circle, 2 for a doubled torus, else None
    code: object = None       # attractor code (classifier.ATTRACTORS), None if unclassified
    impacts: object = None    # q impacts per orbit of a period-k point, else None
    #: with several stops, the stops (0-based) of a period-k point's impacts in order
    #: (:func:`symvi.simulations.classifier.signature`); None otherwise
    signature: tuple = None
    #: with an elastic stop, the kind of each event of :attr:`signature` ("impact",
    #: "entry", "exit"); None otherwise
    kinds: tuple = None

    @property
    def signature_names(self):
        """["stop1", "stop2:entry", "stop2:exit", ...] of :attr:`signature` (as
        :meth:`symvi.model.Signature.names` spells an orbit's events), or None."""
        if self.signature is None:
            return None
        kinds = self.kinds or ("impact",) * len(self.signature)
        return [f"stop{g + 1}" + ("" if kind == "impact" else f":{kind}")
                for g, kind in zip(self.signature, kinds)]

    @property
    def label(self):
        """The plane's name of the same attractor ("circle", "period-2", ...), or None."""
        from .classifier import label
        return None if self.code is None else label(self.code, self.period or 0)


def classify(sim, *, max_period=400, tol=1e-7, lyap_points=4000,
             chaos_threshold=CHAOS_THRESHOLD):
    """Classify the attractor sampled by ``sim`` with the one classifier
    (:func:`symvi.simulations.classifier._judge`, as the plane does).

    Its input: the stored points and times, and log |DP v| of the largest exponent over
    the last ``lyap_points`` (column 0 of the QR method, :func:`lyapunov`).  Periodic
    orbits of up to ``max_period`` impacts closing to ``tol``; chaos when the exponent
    over the last half exceeds the radial growth by ``chaos_threshold`` (and the
    O(1/n) bias); else one closed curve (invariant circle) or not (doubled torus).
    A stopped run, or a completed one of fewer than MIN_CLASSIFY impacts, is not
    classified (its kind says so).  With several rigid stops the run's ``hits`` join the
    points (the period of the pairs (stop, point), the signature of a periodic attractor),
    the rest is judged on the stop hit most often.  With an elastic stop the classifier
    judges every event of the run (``sim.events``: impacts, entries and exits), its symbol
    (:func:`event_symbols`: the constraint and the kind) as the hit: a periodic attractor
    has q events in k forcing periods (a k-q orbit of
    :class:`symvi.orbits.periodic.Problem`, the signature's names those of
    :meth:`symvi.model.Signature.names`), the rest is judged on the entries into the stop
    met most often.
    """
    from . import classifier as cl
    if sim.stop != "completed":
        code = cl.code_of_stop(cf.STOP_NAMES.index(sim.stop))
        return Classification(f"stopped: {sim.stop}", None, None, None, None, code)
    if len(sim.section) < MIN_CLASSIFY:
        return Classification(f"too few impacts to classify ({len(sim.section)}; need >= "
                              f"{MIN_CLASSIFY})", None, None, None, None)
    return _judged(sim, max_period, tol, lyap_points, chaos_threshold)[0]


def _judged(sim, max_period, tol, lyap_points, chaos_threshold):
    """(:class:`Classification`, the per-step logs of the largest exponent, the rotation)
    of a completed run: the records of a rigid-only model, the events of an elastic one."""
    from ..errors import SingularCaseError
    from ..model import Model
    from . import classifier as cl
    model = Model.of(sim.params)
    elastic = model.elastic
    several = len(model.constraints) > 1 or elastic
    if elastic:                     # every event, its symbol (stop, kind) the hit
        ev = sim.events
        sec, t, hits = ev.section, ev.t, _symbols_of(ev)
    else:
        sec, t, hits = sim.section, sim.t, np.asarray(sim.hits) if several else None
    try:
        if sim.sticks is not None and len(sim.sticks):
            # a sticking phase between two records: no map P joins them, no exponent
            # (the period detector alone judges; :mod:`symvi.flow.sticking`)
            logs, te, err = np.empty((0, model.dim)), np.empty(0), None
        else:
            logs, te = _logs(sim, lyap_points)
            err = None
    except SingularCaseError as exc:     # a grazing point on the section: DP undefined
        logs, err = np.empty((0, 1)), exc
    except ValueError:                   # a short elastic run: no chunk of events repeats
        logs, te, err = np.empty((0, model.dim)), np.empty(0), None
    code, k, q, rot = cl.classify_section(sec, t, sim.omega, logs[:, 0],
                                          hits=hits, max_period=max_period, tol=tol,
                                          lyap_min=chaos_threshold)
    if code == cl.PERIOD:
        lya = None if err is not None or not len(logs) else _spectrum(logs, te)
        sig, kinds = (cl.signature(hits[len(hits) - q:]) if several else None), None
        if elastic:
            table = event_symbols(model)
            sig, kinds = tuple(table[s][0] for s in sig), tuple(table[s][1] for s in sig)
        return Classification(cl.kind(code, k), k, lya, None, None, code, q, sig,
                              kinds), logs, rot
    if err is not None:
        raise err
    lya = _spectrum(logs, te) if len(logs) else None
    branches = {cl.CIRCLE: 1, cl.DOUBLED: 2}.get(code)
    # the classifier's rotation, over the points it judged (the settled part): over a
    # whole record that still spirals in or out, rotation_number is biased (example 1
    # at 0.738, 5000 impacts from y*: 0.261 against 0.3963 on the circle)
    return Classification(cl.kind(code, k), None, lya, rot if code == cl.CIRCLE else None,
                          branches, code), logs, rot
