"""Elastic stops: the contact phases, each an exact linear flow, and the hybrid walk through
free flights, contact phases and rigid impacts (issue 25).

Contact law (:mod:`symvi.model._constraint`).  While the elastic constraint i (normal c_i,
gap g_i, side sign_i, stiffness k_i, damping c_si) is penetrated, h_i = sign_i (c_i^T x - g_i)
> 0, the force f_i = -sign_i (k_i h_i + c_si h_i') c_i acts.  As sign_i^2 = 1 this is

    f_i = -(k_i (c_i^T x - g_i) + c_si c_i^T x') c_i

on either side: it points out of the stop (along -c_i for an upper stop, c_i^T x > g_i;
along +c_i for a lower one, c_i^T x < g_i).  With the set S of constraints in contact::

    M x'' + C_S x' + K_S x = P sin(omega t + tau) + f_S,
    K_S = K + sum_{i in S} k_i c_i c_i^T,   C_S = C + sum_{i in S} c_si c_i c_i^T,
    f_S = sum_{i in S} k_i g_i c_i,

a linear flow with a constant force, exact in modal form like the free flight (S empty)::

    z(t) = Phi_S(t) (z0 - zp(0) - zs) + zp(t) + zs,   zs = (K_S^-1 f_S, 0),

zp the steady response of (M, C_S, K_S) to P (:mod:`symvi.flow.linear`, the same modal form:
undamped modes in closed form, damped ones from the eigenvectors of A_S, refused when
ill-conditioned).  K_S is positive definite and C_S semi-definite, so Re lambda <= 0 in every
phase.  There is no jump: entry (h_i = 0, h_i' > 0) and exit (h_i = 0, h_i' < 0) switch S.

Events.  In phase S the walk watches every constraint: the guard h_i of each i outside S
(a rigid impact or an elastic entry) and -h_i of each i in S (the exit), each as
h = G . x - level < 0.  Every step is safe for every guard by the bound of
:meth:`symvi.flow.linear.Motion.first_impact`: with M2 = sum_j |d_j| |lambda_j|^2 +
|G . X| omega^2 >= |h''| for t >= 0 (the constant zs has no derivative),
h(t + s) <= h + h' s + M2 s^2 / 2, so no crossing occurs before the first root of that
quadratic; the grazing thresholds (eps_h, v_graze) are the reference's.  A rigid impact
applies its reset v+ = R v- (:meth:`symvi.model.Constraint.reset_matrix`) and keeps S.

Determinants (the elastic counterpart of det DP = prod r_i^2 exp(-tr(M^-1 C) T) for rigid
contacts).  No jump: the state's monodromy over [0, T] is the product of the phases' flow
matrices Phi_S and the saltation matrices of the switches (:func:`saltation`), each of
determinant 1, so det Phi_total = exp(int tr A dt) with

    int_0^T tr A dt = -tr(M^-1 C) T - sum_contacts c_s c^T M^-1 c (time in contact).

The map from one entry section (s = g dropped, tau kept) to the p-th next carries the flux
through the sections: det DP^p = exp(int tr A dt) h'(start) / h'(end), h' = sign c^T v.  On
a periodic orbit the speeds cancel; a contact of one mass (zeta = c_s / (2 sqrt(k_s m)),
time pi / omega_d as k_s grows) contributes exp(-2 zeta pi / sqrt(1 - zeta^2)) = r_eff^2,
r_eff = exp(-zeta pi / sqrt(1 - zeta^2)) its effective restitution: the rigid r^2.
(tests/flow/test_contact_flow.py checks both against finite differences.)

float64 and numpy only (the compiled run, :mod:`symvi.flow.compiled`, takes rigid stops).
With nonlinear forces each phase is the Taylor flow of the same law
(:mod:`symvi.flow.nlcontact`: K_S, C_S and f_S added to the forces' program) and the walk
is this one.

References: [di Bernardo, Budd, Champneys & Kowalczyk, Piecewise-smooth Dynamical Systems:
Theory and Applications, Springer 2008] (saltation matrices).
"""
import functools
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, SingularCaseError
from ..numerics.backend import FLOAT64
from ..numerics.tolerances import CONTACT_TIME_ULPS, CONTACT_ULPS, GRAZING_SPEED_FACTOR
from ..numerics.tolerances import EPS64 as _EPS
from ..numerics.tolerances import FORCING_RESONANCE_REFUSE
from ._events import (ENTRY, EXIT, GRAZING, IMPACT, NO_EVENT, NONFINITE, STICKING,  # noqa: F401
                      TIME, Hit)
from ._steady import steady_state
from .linear import contact_matrices, modal_form




class Phase:
    """The linear flow of one set S of elastic constraints in contact (module docstring),
    in mass order, float64: M, K_S, C_S, f_S, the static offset zs, A_S and the modes."""

    def __init__(self, model, active):
        self.active = tuple(sorted(active))
        n = self.n = model.n
        M = np.array(model.mass, dtype=float)
        if any(model.constraints[i].kind != "elastic" for i in self.active):
            raise ParameterError("active", self.active, "indices of elastic constraints")
        # the contact law's matrices, one owner (the shooting's LinearFlow.contact reads it)
        K, C, f = (np.array(a, dtype=float) if a is not None else np.zeros(n)
                   for a in contact_matrices(model, self.active))
        self.M, self.K, self.C, self.f = M, K, C, f
        self.P = np.array(model.forcing, dtype=float)
        Minv = self.Minv = np.linalg.inv(M)
        self.A = np.block([[np.zeros((n, n)), np.eye(n)], [-(Minv @ K), -(Minv @ C)]])
        # the one modal form (symvi.flow.linear.modal_form): closed form undamped, the
        # eigenvectors damped (refused when ill-conditioned), a mass on no spring's drift
        self.omegas, self.lam, self.W, self.Winv, nil = modal_form(
            FLOAT64, M, K, C, self.A, bool(C.any()))
        self.NIL = nil
        # the static offset of the constant force f_S: K_S xs = f_S
        xs = np.zeros(n)
        if self.active:
            if nil is not None:
                raise SingularCaseError(
                    "free-mass", f"the contact phase {list(self.active)} leaves a mass on no "
                    "spring: its contact force has no static offset (the contact must act "
                    "on every free mode)")
            xs = np.linalg.solve(K, f)
        self.zs = np.concatenate([xs, np.zeros(n)])
        # Re lambda <= 0 up to rounding; a rounding-sized Re lambda > 0 enters the bound
        self.growth_rate = max(0.0, float(np.max(self.lam.real)))
        self._forcing = {}

    def forcing(self, omega):
        """(U, V): the steady response x_p = U sin(phi) + V cos(phi) of this phase at omega;
        SingularCaseError at a forcing resonance of the phase (relative distance as
        :meth:`LinearFlow.check_omega` measures it)."""
        hit = self._forcing.get(omega)
        if hit is None:
            L = np.linalg.cholesky(self.M)
            Li = np.linalg.inv(L)
            Kt, Ct = Li @ self.K @ Li.T, Li @ self.C @ Li.T
            w = float(omega)
            smin = np.linalg.svd(Kt - w * w * np.eye(self.n) + 1j * w * Ct, compute_uv=False)[-1]
            if smin / (2 * w * w) < FORCING_RESONANCE_REFUSE:
                raise SingularCaseError(
                    "forcing-resonance", f"omega = {w!r} is at a natural frequency of the "
                    f"contact phase {list(self.active)} (relative distance "
                    f"{smin / (2 * w * w):.1e}): its steady-state response is infinite")
            U, V, _, _ = steady_state(self.K, self.M, self.C, self.P, w)
            if len(self._forcing) > 256:       # bounded: a sweep in omega stays small
                self._forcing.clear()
            hit = self._forcing[omega] = (U, V)
        return hit

    def motion(self, omega, z0, tau):
        """The motion of this phase from state z0 (mass order) at phase tau."""
        return PhaseMotion(self, omega, np.asarray(z0, dtype=float), float(tau))

    def field(self, z, t, omega, tau):
        """z' = A_S z + (0, M^-1 (P sin(omega t + tau) + f_S)): the vector field."""
        n = self.n
        rhs = self.Minv @ (self.P * math.sin(omega * t + tau) + self.f)
        return self.A @ z + np.concatenate([np.zeros(n), rhs])

    def phi(self, t):
        """Phi_S(t) = e^{A_S t} (real 2N x 2N): Re(W e^{Lambda t} W^-1) + t NIL."""
        out = np.real((self.W * np.exp(self.lam * t)) @ self.Winv)
        return out if self.NIL is None else out + t * self.NIL


@functools.lru_cache(maxsize=64)
def phase(model, active=()):
    """The :class:`Phase` of ``model`` with the elastic constraints ``active`` in contact."""
    return Phase(model, tuple(sorted(active)))


def phases_of(model):
    """The phases of ``model``'s walk: :func:`phase` (the exact linear flow), or with
    nonlinear forces :func:`symvi.flow.nlcontact.phase` (the Taylor flow, the same law)."""
    if model.nonlinear is None:
        return phase
    from .nlcontact import phase as nonlinear_phase
    return nonlinear_phase


class PhaseMotion:
    """z(t) = Re(W (a e^{lambda t})) + t NIL w + zp(t) + zs of one phase, w = z0 - zp(0) - zs,
    a = W^-1 w (the drift t NIL w of a mass on no spring moves positions only)."""

    def __init__(self, ph, omega, z0, tau):
        self.phase, self.omega, self.tau = ph, omega, tau
        self.U, self.V = ph.forcing(omega)
        w = z0 - self._zp(tau) - ph.zs
        self.a = ph.Winv @ w
        self.nw = None if ph.NIL is None else ph.NIL @ w

    def _zp(self, phase):
        s, c = math.sin(phase), math.cos(phase)
        U, V, w = self.U, self.V, self.omega
        return np.concatenate([U * s + V * c, w * (U * c - V * s)])

    def state(self, t):
        """z(t), mass order."""
        ph = self.phase
        z = (np.real(ph.W @ (self.a * np.exp(ph.lam * t))) + self._zp(self.omega * t + self.tau)
             + ph.zs)
        return z if self.nw is None else z + t * self.nw

    def first_event(self, G, level, start=None, t_max=None, max_steps=1_000_000):
        """First t > 0 with h_g(t) = G[g] . x(t) - level[g] = 0 for some guard g, from a start
        on guard ``start`` (h = 0 there, leaving: h' < 0) or off every guard (None).

        The step is the reference's (:meth:`symvi.flow.linear.Motion.first_impact`) taken
        for every guard, the smallest of them: safe for each.  A start at or past another
        guard (a corner) is a GRAZING at t = 0."""
        ph, om = self.phase, self.omega
        n = ph.n
        if t_max is None:
            t_max = 2000 * math.pi / om
        G = np.asarray(G, dtype=float)
        level = np.asarray(level, dtype=float) - G @ ph.zs[:n]    # the offset as a level
        D = (G @ ph.W[:n]) * self.a                 # h(t) = Re D e^{lambda t} + G.x_p - level
        Dv = (G @ ph.W[n:]) * self.a
        D2 = Dv * ph.lam
        GU, GV = G @ self.U, G @ self.V
        # the free modes' drift: a rate of each guard, no part of h'' (it is linear in t)
        drift = np.zeros(len(G)) if self.nw is None else G @ self.nw[:n]
        X = np.hypot(GU, GV)
        al = np.abs(ph.lam)
        grow = math.exp(ph.growth_rate * 4 * t_max)
        M2 = np.maximum((np.abs(D) @ (al * al)) * grow + X * om * om, 1e-300)
        L = np.abs(D).sum(axis=1) + X + np.abs(level)
        eps_h = CONTACT_ULPS * _EPS * L
        v_graze = GRAZING_SPEED_FACTOR * np.sqrt(2 * M2 * eps_h)
        lam, tau = ph.lam, self.tau

        def h(t):
            e = np.exp(lam * t)
            p = om * t + tau
            s, c = math.sin(p), math.cos(p)
            return ((D @ e).real + t * drift + GU * s + GV * c - level,
                    (Dv @ e).real + om * (GU * c - GV * s))

        def h2(t, g):
            p = om * t + tau
            return float((D2[g] @ np.exp(lam * t)).real
                         - om * om * (GU[g] * math.sin(p) + GV[g] * math.cos(p)))

        hh, hd = h(0.0)
        steps = np.empty(len(G))
        for g in range(len(G)):
            if g == start:
                if not hd[g] < 0:
                    return Hit(GRAZING, 0.0, g, h2(0.0, g), 0)
                steps[g] = -hd[g] / M2[g]   # the vertex of the bound: h < 0 up to here
            elif hh[g] >= -eps_h[g]:
                return Hit(GRAZING, 0.0, g, h2(0.0, g), 0)
            else:
                steps[g] = _safe(hh[g], hd[g], M2[g])
        t = float(steps.min())
        for it in range(1, max_steps + 1):
            hh, hd = h(t)
            near = np.nonzero(hh >= -eps_h)[0]
            if len(near):
                g = int(near[np.argmax(hh[near])])
                if hd[g] <= v_graze[g]:
                    return Hit(GRAZING, t, g, h2(t, g), it)
                for _ in range(3):            # Newton polish of a transversal root
                    dt = -hh[g] / hd[g]
                    t += dt
                    hh, hd = h(t)
                    if abs(dt) <= CONTACT_TIME_ULPS * _EPS * t:
                        break
                return Hit("event", t, g, h2(t, g), it)
            if t > t_max or not np.all(np.isfinite(hh)):
                return Hit(NO_EVENT, t, 0, 0.0, it)
            t += min(_safe(hh[g], hd[g], M2[g]) for g in range(len(G)))
        return Hit(NO_EVENT, t, 0, 0.0, max_steps)


def _safe(h, hd, M2):
    """First positive root of h + hd s + M2 s^2 / 2 (h < 0, M2 > 0), in the stable form."""
    return -2 * h / (hd + math.sqrt(hd * hd - 2 * M2 * h))


@dataclass(frozen=True)
class Event:
    """One event of a walk (:func:`walk`): ``kind`` IMPACT, ENTRY or EXIT, or how the walk
    ended (GRAZING, STICKING, NO_EVENT, NONFINITE, TIME); the constraint (index into
    ``model.constraints``; -1 for NO_EVENT and TIME), the time t since the start, the phase
    tau = tau0 + omega t mod 2 pi, the state z = (x, v) (mass order) before the event and
    after it (after the reset of a rigid impact; the same for an elastic switch or an end),
    and the constraints in contact after it."""

    kind: str
    constraint: int
    t: float
    tau: float
    before: np.ndarray
    after: np.ndarray
    active: tuple


def guards(model, active):
    """(G, level) of every constraint in phase ``active``: h_i = sign_i (c_i^T x - g_i) for
    a constraint not in contact, -h_i (its exit) for one in contact; each h < 0 off it."""
    G, lv = [], []
    for i, con in enumerate(model.constraints):
        s = -con.sign if i in active else con.sign
        G.append(s * np.array(con.normal))
        lv.append(s * con.gap)
    return np.array(G), np.array(lv)


def walk(model, omega, z0, tau, *, active=(), start=None, t_end=None, t_max=None):
    """Yield the events of the motion of ``model`` from state z0 (mass order) at phase tau,
    with the elastic constraints ``active`` in contact, until an end (GRAZING, STICKING,
    NO_EVENT or, with ``t_end``, TIME: the state at t_end), which is yielded last.

    ``start``: the constraint whose guard z0 lies on, leaving it (just after a rigid impact,
    or at an elastic entry with it in ``active``, or at an exit without it); None when z0 is
    off every guard.  ``t_max`` bounds one phase (default 1000 forcing periods; a contact
    phase that lasts longer ends the walk as STICKING, a free one as NO_EVENT).  A rigid
    impact's state is put on its section (c = e_k: x_k = g exactly, as the compiled run's
    section points do).
    """
    omega = float(omega)
    cons = model.constraints
    phase_of = phases_of(model)
    S = frozenset(active)
    z = np.array(z0, dtype=float)
    tau = float(tau) % (2 * math.pi)
    T = 0.0
    Minv = None
    while True:
        ph = phase_of(model, tuple(sorted(S)))
        mo = ph.motion(omega, z, tau)
        G, lv = guards(model, S)
        tm = t_max if t_max is not None else 2000 * math.pi / omega
        if t_end is not None:
            tm = min(tm, t_end - T)
        hit = mo.first_event(G, lv, start, tm)
        if t_end is not None and (hit.status == NO_EVENT or hit.t > t_end - T):
            zt = mo.state(t_end - T)
            ta = (tau + omega * (t_end - T)) % (2 * math.pi)
            yield Event(TIME, -1, t_end, ta, zt, zt, tuple(sorted(S)))
            return
        zb = mo.state(hit.t)
        ta = (tau + omega * hit.t) % (2 * math.pi)
        g = hit.guard
        if hit.status != "event":
            kind = NONFINITE if hit.status == NONFINITE else \
                NO_EVENT if hit.status == NO_EVENT and not S else \
                STICKING if hit.status == NO_EVENT or hit.h2 > 0 else GRAZING
            yield Event(kind, -1 if kind in (NO_EVENT, NONFINITE) else g, T + hit.t, ta, zb, zb,
                        tuple(sorted(S)))
            return
        con = cons[g]
        k = con.coordinate
        if k is not None:
            zb[k] = con.gap                          # on the guard exactly
        za = zb.copy()
        if g in S:
            kind, S = EXIT, S - {g}
        elif con.kind == "elastic":
            kind, S = ENTRY, S | {g}
        else:
            kind = IMPACT
            if Minv is None:
                Minv = np.linalg.inv(np.asarray(model.mass, dtype=float))
            n = model.n
            za[n:] = con.reset_matrix(Minv) @ zb[n:]
        T += hit.t
        yield Event(kind, g, T, ta, zb, za, tuple(sorted(S)))
        z, tau, start = za, ta, g


def saltation(model, event, omega):
    """The saltation matrix of an elastic switch (ENTRY or EXIT; 2N x 2N, mass order)::

        S = I + (F+ - F-) grad(h)^T / (grad(h) . F-),

    F-, F+ the vector fields of the phases before and after, at the switching state and
    time [di Bernardo et al.].  The guard h_i = sign (c^T x - g) depends on x
    alone and both fields have x' = v, so grad(h) . (F+ - F-) = 0 and det S = 1, with or
    without a jump of the damping force (the spring force vanishes at c^T x = g)."""
    if event.kind not in (ENTRY, EXIT):
        raise ParameterError("event.kind", event.kind, '"entry" or "exit" (elastic switches)')
    after = frozenset(event.active)
    before = after - {event.constraint} if event.kind == ENTRY else after | {event.constraint}
    n, z, t = model.n, event.before, 0.0
    # the fields at the switching phase: sin(omega t + tau) with t = 0, tau = event.tau
    phase_of = phases_of(model)
    Fm = phase_of(model, tuple(sorted(before))).field(z, t, omega, event.tau)
    Fp = phase_of(model, tuple(sorted(after))).field(z, t, omega, event.tau)
    con = model.constraints[event.constraint]
    grad = np.concatenate([con.sign * np.array(con.normal), np.zeros(n)])
    return np.eye(2 * n) + np.outer(Fp - Fm, grad) / (grad @ Fm)
