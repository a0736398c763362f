"""Diagnostics of a simulated attractor of P: Lyapunov exponents, rotation number, class.

* Lyapunov exponents of the section map, per impact, by the QR method
  [Benettin et al. 1980; Eckmann & Ruelle 1985]: Q_{k+1} R_k = DP(y_k) Q_k and
  lambda_i = mean log |R_k[i, i]|.  DP(y_k) is the Jacobian of eqs. (36)–(38)
  at a general section point, compiled by numba: the flight's state transition
  with the flight time eliminated, eq. (30) (:func:`symvi.orbits._shooting.monodromy`;
  :func:`jacobian` gives the same matrix from the generated code in Python).
* The rotation number of an invariant circle: mean turning angle per impact
  around the circle's centre in its principal plane.
* A classification: period-k point, invariant circle, doubled torus, chaos.

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

from ..flow import compiled as cf
#: stored impacts below which a run is not classified: period detection compares
#: points k apart (k <= n/2) and the chaos test needs 10 blocks of exponents
from ..numerics.tolerances import MIN_CLASSIFY
from ..orbits import _shooting

TWO_PI = 2 * math.pi
#: a bounded attractor is chaotic when its largest exponent (per impact) exceeds
#: this floor and CHAOS_SIGMAS block standard errors
CHAOS_THRESHOLD = 1e-3
CHAOS_SIGMAS = 4.0


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
    sec, t = np.asarray(sim.section), np.asarray(sim.t)
    if len(sec) < 3:
        raise ValueError("need at least 3 section points")
    k0 = 0 if n is None else max(0, len(sec) - 1 - int(n))
    te = np.diff(t)
    m = len(sec) - 1 - k0
    logs = _qr_logs_model(sim.params, sim.omega, sec[k0:-1], te[k0:])
    if not np.isfinite(logs).all():
        from ..errors import SingularCaseError
        raise SingularCaseError("grazing", "an impact of the stored section has zero "
                                "velocity (grazing): DP, eq. (30), is undefined there")
    # columns of Q stay ordered by growth once converged: column 0 carries lambda_1
    blocks = [b[:, 0].mean() for b in np.array_split(logs, 10) if len(b)]
    err = float(np.std(blocks, ddof=1) / math.sqrt(len(blocks))) if len(blocks) > 1 else math.nan
    return Lyapunov(np.sort(logs.mean(axis=0))[::-1], m, float(np.mean(te[k0:])), err)


def _qr_logs_model(params, omega, sec, te):
    """log |R_k[i, i]| of the QR method (compiled, ~1 µs a point for N = 2)."""
    from ..flow.linear import LinearFlow
    from ..model import Model
    flow = LinearFlow.of(Model.of(params))
    F = flow.forcing(float(omega))
    lam, W, Winv, A = flow.modal64
    return _qr_logs(lam, W, Winv, A, F.U, F.V, F.omega, flow.constraint64,
                    np.ascontiguousarray(sec, dtype=float),
                    np.ascontiguousarray(te, dtype=float))


@nb.njit(cache=True)
def _qr_logs(lam, W, Winv, A, U, V, w, con, sec, te):
    """Q_{k+1} R_k = DP(y_k) Q_k along the section, DP of one flight by eq. (30)."""
    m, d = sec.shape
    logs = np.empty((m, d))
    Q = np.eye(d)
    u = np.empty(d + 1)
    for k in range(m):
        u[:d] = sec[k]
        u[d] = te[k]
        Gu = _shooting.shoot(lam, W, Winv, A, U, V, U, V, w, con, 1, u, 1, True, False)[1]
        _, J, ok = _shooting.monodromy(Gu, 1, d)
        if not ok:                       # an impact at zero velocity: DP is undefined
            logs[k, :] = np.nan
            continue
        Q, R = np.linalg.qr(J @ Q)
        Q = np.ascontiguousarray(Q)
        for i in range(d):
            dg = R[i, i]
            logs[k, i] = math.log(abs(dg))
            if dg < 0.0:                 # keep Q's columns continuous
                Q[:, i] = -Q[:, i]
    return logs


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
    """Smallest k with |y_{n+k} - y_n| <= tol * scale over the points, or None."""
    sec = np.asarray(section, dtype=float)
    scale = max(1.0, float(np.abs(sec[:, :-1]).max()))
    for k in range(1, min(max_period, len(sec) // 2) + 1):
        D = _unwrapped(sec[k:], 0) - _unwrapped(sec[:-k], 0)
        D[:, -1] = (D[:, -1] + math.pi) % TWO_PI - math.pi
        if np.abs(D).max() <= tol * scale:
            return k
    return None


@dataclass(frozen=True)
class Classification:
    """What the stored section of a run looks like."""

    kind: str                 # "period-k", "invariant circle", "doubled torus", "chaos",
    #                           "periodic (period > max)", "quasi-periodic", "stopped: <reason>"
    period: object            # k for a period-k point, else None
    lyapunov: object          # Lyapunov, or None
    rotation: object          # rotation number on an invariant circle, else None
    branches: object          # branch_count for quasi-periodic sets, else None


def classify(sim, *, max_period=400, tol=1e-7, lyap_points=4000,
             chaos_threshold=CHAOS_THRESHOLD):
    """Classify the attractor sampled by ``sim`` (use a run past its transient).

    Period-k when the points repeat (to ``tol``), with the exponents of the orbit
    (log |multipliers of P^k| / k); else chaos when the largest Lyapunov exponent is
    positive beyond ``chaos_threshold`` and CHAOS_SIGMAS block standard errors; else an
    invariant circle (one sheet) or a doubled torus (two sheets, :func:`branch_count`).
    A completed run of fewer than MIN_CLASSIFY impacts is not classified (its kind says
    so).
    """
    if sim.stop != "completed":
        return Classification(f"stopped: {sim.stop}", None, None, None, None)
    if len(sim.section) < MIN_CLASSIFY:
        return Classification(f"too few impacts to classify ({len(sim.section)}; need >= "
                              f"{MIN_CLASSIFY})", None, None, None, None)
    k = period_of(sim.section, max_period, tol)
    if k is not None:
        from ..errors import SingularCaseError
        try:
            lya = lyapunov(sim, n=lyap_points)
        except SingularCaseError:        # a grazing point on the orbit: DP undefined there
            lya = None
        return Classification(f"period-{k}", k, lya, None, None)
    lya = lyapunov(sim, n=lyap_points)
    if lya.largest > max(chaos_threshold, CHAOS_SIGMAS * lya.stderr):
        return Classification("chaos", None, lya, None, None)
    if lya.largest < -max(chaos_threshold, CHAOS_SIGMAS * lya.stderr):
        # contracting in every direction but not repeating yet: a long period
        return Classification(f"periodic (period > {max_period})", None, lya, None, None)
    nb = branch_count(sim.section)
    if nb == 1:
        return Classification("invariant circle", None, lya, rotation_number(sim.section), 1)
    if nb == 2:
        return Classification("doubled torus", None, lya, None, 2)
    return Classification("quasi-periodic", None, lya, None, nb)
