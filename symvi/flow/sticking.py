"""Complete chatter and sticking on a rigid stop: the accumulation point, the sticking
phase and the release, so that a run goes on through them (issue 27, item 4).

Chatter.  After an impact on the stop of guard h = g . x - level (h < 0 off the stop)
with approach speed u_n = h'(t_n-) > 0, the reset gives h'(t_n+) = -r u_n =: -w_n (the
rigid reset v+ = R v-, R = I - (1 + r) q g^T / (g . q), q = M^-1 g).  With the guard's
acceleration a = h'' > 0 (pushed into the stop) and b = h''' near the stop, the flight
h(t_n + s) = -w s + a s^2/2 + b s^3/6 + O(s^4) returns after

    s_n = 2 w_n / a - 4 b w_n^2 / (3 a^3) + O(w^3),
    u_{n+1} = w_n + (2/3) b w_n^2 / a^2 + O(w^3),

and at the impact h'' jumps by kappa (1 + r) u (damping: kappa = g . M^-1 C q / (g . q),
2 zeta for x'' + 2 zeta x' + x = ...), so after the flight and the impact
a_{n+1} = a_n + beta w_n, beta = 2 b / a + kappa (1 + r).  Summing the geometric sequence
w_n = r^n w_0 (1 + e_n), e_n = (2/3)(b w_0/a^2)(1 - r^n)/(1 - r), the accumulation point
of the infinite sequence [Budd & Dux 1994, Chattering and related behaviour, eqs. of the
chatter map] lies after

    t_inf - t_0 = 2 w_0 / (a (1 - r))
                  + 2 w_0^2 r delta / (a (1 - r)(1 - r^2)) - 4 b w_0^2 / (3 a^3 (1 - r^2))
                  + O(w_0^3),    delta = -(4/3) b / a^2 - kappa (1 + r) / a,

(:func:`accumulation_time`): the leading term has an O(w_0^2) error, the two terms an
O(w_0^3) one.  The run steps the impacts exactly (the compiled loop) until the finder
calls one grazing (approach speed below v_graze = 8 sqrt(2 M2 eps_h), ~1e-7 of the
motion's scale): from that last near-contact (h, h') the sequence is summed in closed
form, t_rem = s_0 + 2 r u / (a (1 - r)) with the contact after s_0 at speed
u = sqrt(h'^2 - 2 a h), an error O(u^2) ~ 1e-14.  The state: every velocity jump of the
sequence is along q, and so is its effect on the positions, so the free flight's state
at t_inf is put back on the stop along q (g . x = level, g . v = 0: the impulse of the
whole sequence, for any mass matrix and reset), with the same O(u^2) error.  No impact is
stepped below the grazing speed: the cost of one chatter is log(u_0/v_graze)/log(1/r)
exact flights plus O(1).

Sticking.  Held on the stop (x_p = xp on the frame coordinate of the guard, g = sigma
e_p, v_p = 0), the other coordinates y move by the reduced linear system (rows o != p of
M x'' + C x' + K x = P sin(omega t + tau) + lambda g, with x_p'' = 0)

    M_oo y'' + C_oo y' + K_oo y = P_o sin(omega t + tau) - K_op xp,

exact in modal form (:func:`symvi.flow.linear.modal_form`, the steady response by
:func:`symvi.flow._steady.steady_state`, plus the static part).  The contact force
holds the mass while mu = g . M^-1 (P sin - C v - K x) > 0 (the free guard acceleration:
the force is -lambda g with lambda = mu / (g . M^-1 g) >= 0), a linear function of (y, y')
and the forcing; sticking ends where mu changes sign (release).  Every other guard is
watched along the same motion.  Each watched function has the modal form
F(t) = Re sum_j d_j e^{lambda_j t} + A sin + B cos + G, found with the reference finder's
safe step (the root of F + F' s + M2 s^2/2, M2 >= |F''| from t on), so no event is
stepped over.  For one mass (N = 1) the reduced system is empty: mu(t) = P sin(omega t +
tau) - k xp.

Release.  At the release h = h' = 0 and h'' = mu (g . M^-1 g) = 0, h''' < 0: the
compiled finder starts such a flight with its own safe step
(:func:`symvi.flow.compiled._release_time`).

Not continued (the run stops, with the reason in :func:`run_through`): r >= 1 (no
accumulation), a second stop met while sticking, a reduced system with a free mass, a
sticking phase longer than the run's flight bound (1000 forcing periods), repeated
stickings with no impact between them.

References
----------
[Budd & Dux] C. Budd, F. Dux, Chattering and related behaviour in impact oscillators,
Phil. Trans. R. Soc. A 347 (1994) 365-389.
"""
import math

import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from ..numerics.backend import FLOAT64
from ..numerics.tolerances import CONTACT_ULPS
from ..numerics.tolerances import EPS64 as _EPS
from . import compiled as cf
from ._steady import steady_state
from .linear import LinearFlow, modal_form, null_dim

__all__ = ["accumulation_time", "accumulate", "Stuck", "run_through"]

_TWO_PI = 2.0 * math.pi
#: stickings in a row with no impact between them before a run gives up
MAX_IDLE_STICKS = 1000
#: events of one sticking phase's finder before it gives up
_MAX_STEPS = 200_000


def accumulation_time(w0, a, r, b=0.0, kappa=0.0):
    """t_inf - t_0 of the chatter sequence after an impact with rebound speed w0 (module
    docstring): leading order 2 w0 / (a (1 - r)), and the O(w0^2) terms from the guard's
    jerk b = h''' and the damping's jump factor kappa; error O(w0^3)."""
    if not 0.0 <= r < 1.0 or not a > 0.0:
        raise ValueError(f"an accumulation needs 0 <= r < 1 and a > 0 (r = {r!r}, a = {a!r})")
    delta = -(4.0 / 3.0) * b / a ** 2 - kappa * (1.0 + r) / a
    return (2.0 * w0 / (a * (1.0 - r))
            + 2.0 * w0 ** 2 * r * delta / (a * (1.0 - r) * (1.0 - r * r))
            - 4.0 * b * w0 ** 2 / (3.0 * a ** 3 * (1.0 - r * r)))


@nb.njit(cache=True, inline="always")
def _watched(lam, d, A, B, G, omega, tau, t, i):
    """Watched function i at t: (F, F', M2 >= |F''| from t on), F = Re sum_j d_ij
    e^{lambda_j t} + A_i sin + B_i cos + G_i (the phase omega t + tau)."""
    F = F1 = M2 = 0.0
    for j in range(lam.shape[0]):
        e = np.exp(lam[j] * t)
        de = d[i, j] * e
        F += de.real
        F1 += (de * lam[j]).real
        M2 += abs(d[i, j]) * abs(lam[j]) ** 2 * math.exp(lam[j].real * t)
    ph = omega * t + tau
    sp, cp = math.sin(ph), math.cos(ph)
    F += A[i] * sp + B[i] * cp + G[i]
    F1 += omega * (A[i] * cp - B[i] * sp)
    M2 += math.sqrt(A[i] * A[i] + B[i] * B[i]) * omega * omega
    return F, F1, M2


@nb.njit(cache=True)
def _root_of(lam, d, A, B, G, omega, tau, i, ta, tb, Fb, F1b):
    """The root of watched function i in (ta, tb] (F(ta) < 0, F(tb) >= -eps): regula falsi
    (Illinois) on the bracket when F(tb) >= 0, else Newton from tb.  An empty bracket
    (ta = tb: the event at the held phase's start, e.g. a contact force already zero at
    the accumulation point) is its own root."""
    if tb <= ta:
        return tb
    if Fb >= 0.0:
        if Fb == 0.0:
            return tb
        Fa = _watched(lam, d, A, B, G, omega, tau, ta, i)[0]
        side = 0
        for _ in range(200):
            tm = (ta * Fb - tb * Fa) / (Fb - Fa)
            if not ta < tm < tb:
                tm = 0.5 * (ta + tb)
            Fm = _watched(lam, d, A, B, G, omega, tau, tm, i)[0]
            if Fm >= 0.0:
                tb, Fb = tm, Fm
                if side == 1:
                    Fa *= 0.5
                side = 1
            else:
                ta, Fa = tm, Fm
                if side == -1:
                    Fb *= 0.5
                side = -1
            if tb - ta <= 4.0 * _EPS * tb or Fm == 0.0:
                break
        return tb if abs(Fb) <= abs(Fa) else ta
    t = tb
    for _ in range(4):
        F, F1, _ = _watched(lam, d, A, B, G, omega, tau, t, i)
        if not F1 > 0.0:
            break
        dt = -F / F1
        t += dt
        if abs(dt) <= 4.0 * _EPS * max(t, 1.0):
            break
    return t


@nb.njit(cache=True)
def _held_event(lam, d, A, B, G, eps, omega, tau, t_max):
    """The first event of the held motion: (i, t), i the watched function that reaches 0
    first (-1: none before t_max).  Each step is the reference finder's safe step, the
    first root of F + F' s + M2 s^2/2 over every watched function, so none is stepped
    over."""
    nf = A.shape[0]
    t, t_prev = 0.0, 0.0
    for _ in range(_MAX_STEPS):
        best_i, best_t = -1, np.inf
        step = np.inf
        for i in range(nf):
            F, F1, M2 = _watched(lam, d, A, B, G, omega, tau, t, i)
            if F >= -eps[i]:
                tr = _root_of(lam, d, A, B, G, omega, tau, i, t_prev, t, F, F1)
                if tr < best_t:
                    best_i, best_t = i, tr
                continue
            disc = F1 * F1 - 2.0 * M2 * F
            if disc >= 0.0:
                den = F1 + math.sqrt(disc)
                if den > 0.0:
                    step = min(step, -2.0 * F / den)
        if best_i >= 0:
            return best_i, best_t
        if t > t_max or step == np.inf:
            return -1, max(t, t_max)
        t_prev, t = t, t + step
    return -1, t


def _row(c, j):
    """Constraint j of the constants' table: (p, level, guard, R)."""
    n = int(c[cf._NN])
    _, _, _, oc, cb = cf.offsets(n)
    o = oc + j * cb
    guard = np.array(c[o + cf._CB:o + cf._CB + n])
    R = np.array(c[o + cf._CB + n:o + cb]).reshape(n, n)
    return int(c[o + cf._P]), float(c[o + cf._LEVEL]), guard, R


def _restitution(guard, R):
    """r of the rigid reset R (g . R g = -r |g|^2)."""
    return -float(guard @ R @ guard) / float(guard @ guard)


def accumulate(c, y, k):
    """The accumulation point of the chatter that the compiled loop stopped at: from the
    section point y of constraint k, the flight ends grazing a guard g pushed into it
    (h'' > 0).  Returns (t, z, g): the time from y to the accumulation point, the state
    there (flow order, on the stop, g . v = 0), the constraint; or (None, reason, g)."""
    st, tc, z, acc, _, g = cf.first_impact_from(c, y, k=k)
    if st != cf.GRAZING or not acc > 0.0:
        return None, "the last flight does not end on a stop that holds the mass", g
    n = int(c[cf._NN])
    p, level, guard, R = _row(c, g)
    r = _restitution(guard, R)
    if not 0.0 <= r < 1.0:
        return None, f"restitution r = {r:g} on stop {g + 1}: no accumulation of impacts", g
    x, v = z[:n], z[n:]
    h, h1, a = float(guard @ x - level), float(guard @ v), float(acc)
    u = math.sqrt(max(h1 * h1 - 2.0 * a * h, 0.0))
    t_rem = (-h1 + u) / a + 2.0 * r * u / (a * (1.0 - r))
    t = tc + t_rem
    z = cf.state_from(c, y, t, k)
    # the sequence's impulses (and their displacements) are along q = (I - R) g
    q = (np.eye(n) - R) @ guard
    gq = float(guard @ q)
    z[:n] -= (float(guard @ z[:n]) - level) / gq * q
    z[n:] -= float(guard @ z[n:]) / gq * q
    z[p] = level / guard[p]
    z[n + p] = 0.0
    return t, z, g


class Stuck:
    """The motion held on stop g (module docstring: the reduced system) for one
    (constants, model flow); :meth:`run` finds the release or another stop."""

    def __init__(self, c, flow, g):
        n = flow.n
        self.n, self.g, self.omega = n, g, float(c[cf._OM])
        p, level, guard, _ = _row(c, g)
        if np.count_nonzero(guard) != 1 or guard[p] == 0.0:
            raise ValueError(f"stop {g + 1}: a guard off its frame coordinate")
        self.p, self.xp = p, level / guard[p]
        o = [i for i in range(n) if i != p]
        self.o = o
        M, K, C, P = (np.asarray(a, dtype=float) for a in (flow.M, flow.K, flow.C, flow.P))
        gM = guard @ np.linalg.inv(M)
        nr = n - 1
        # mu = gM (P sin - C v - K x); watched as F = -mu (< 0 while stuck)
        a_rows = [np.concatenate([gM @ K[:, o], gM @ C[:, o]])]
        alpha, gamma = [-float(gM @ P)], [float(gM @ K[:, p]) * self.xp]
        self.kinds = [-1]                            # -1: the release; j: stop j met
        for j in range(int(c[cf._NC])):
            if j == g:
                continue
            pj, lj, gj, _ = _row(c, j)
            a_rows.append(np.concatenate([gj[o], np.zeros(nr)]))
            alpha.append(0.0)
            gamma.append(float(gj[p]) * self.xp - lj)
            self.kinds.append(j)
        self.a = np.array(a_rows).reshape(len(a_rows), 2 * nr)
        self.alpha, self.gamma = np.array(alpha), np.array(gamma)
        self.gM = gM
        if nr:
            Mr, Kr, Cr = M[np.ix_(o, o)], K[np.ix_(o, o)], C[np.ix_(o, o)]
            if null_dim(Kr):
                raise ValueError(f"stop {g + 1}: the masses left free while it holds its "
                                 "mass have no spring (a free reduced system)")
            Mi = np.linalg.inv(Mr)
            Ar = np.block([[np.zeros((nr, nr)), np.eye(nr)], [-Mi @ Kr, -Mi @ Cr]])
            _, lam, W, Winv, _ = modal_form(FLOAT64, Mr, Kr, Cr, Ar, bool(np.any(Cr != 0)))
            U, V = steady_state(Kr, Mr, Cr, P[o], self.omega)[:2]
            self.lam = np.asarray(lam, dtype=complex)
            self.W, self.Winv = np.asarray(W, dtype=complex), np.asarray(Winv, dtype=complex)
            self.S = np.concatenate([U, -self.omega * V])       # Yp = S sin + Cc cos
            self.Cc = np.concatenate([V, self.omega * U])
            self.ys = np.concatenate([np.linalg.solve(Kr, -K[o, p] * self.xp), np.zeros(nr)])
        else:
            self.lam = np.zeros(0, dtype=complex)
            self.W = self.Winv = np.zeros((0, 0), dtype=complex)
            self.S = self.Cc = self.ys = np.zeros(0)
        # forcing amplitudes and constants of each watched function
        self.A = self.a @ self.S + self.alpha
        self.B = self.a @ self.Cc
        self.G = self.a @ self.ys + self.gamma

    def _coeffs(self, Y0, tau):
        """Modal coefficients c of Y(t) - Yp - ys and, per watched function, d_ij."""
        Yp0 = self.S * math.sin(tau) + self.Cc * math.cos(tau)
        cc = self.Winv @ (Y0 - Yp0 - self.ys)
        return cc, (self.a @ self.W) * cc[None, :]

    def state(self, cc, tau, t):
        """The full state (flow order) at t of the held motion from coefficients cc."""
        n, nr, p = self.n, self.n - 1, self.p
        z = np.zeros(2 * n)
        z[p] = self.xp
        if nr:
            ph = self.omega * t + tau
            Y = ((self.W @ (cc * np.exp(self.lam * t))).real + self.S * math.sin(ph)
                 + self.Cc * math.cos(ph) + self.ys)
            z[self.o] = Y[:nr]
            z[[n + i for i in self.o]] = Y[nr:]
        return z

    def run(self, z0, tau, t_max):
        """From z0 held on the stop at forcing phase tau: (kind, t, z) of the first event,
        kind -1 the release, j >= 0 stop j met; (None, t, None) if none before t_max."""
        n, nr = self.n, self.n - 1
        Y0 = np.concatenate([z0[self.o], z0[[n + i for i in self.o]]]) if nr else np.zeros(0)
        cc, d = self._coeffs(Y0, tau)
        eps = CONTACT_ULPS * _EPS * (np.abs(d).sum(axis=1) + np.hypot(self.A, self.B)
                                     + np.abs(self.G) + 1e-300)
        i, te = _held_event(self.lam, np.ascontiguousarray(d), self.A, self.B, self.G, eps,
                            self.omega, float(tau), float(t_max))
        if i < 0:
            return None, te, None
        return self.kinds[i], te, self.state(cc, tau, te)


def _section(z, p, n, tau):
    """The section point of the constraint at position p for state z, v_p = 0 exactly."""
    y = np.empty(2 * n)
    y[0] = 0.0
    for i in range(n):
        if i != p:
            q = i + 1 if i < p else i
            y[q], y[n - 1 + q] = z[i], z[n + i]
    y[2 * n - 1] = tau % _TWO_PI
    return y


def run_through(model, c, y0, n_keep, transient=0, k=0):
    """The compiled run loop continued through complete chatter and sticking.

    Calls :func:`symvi.flow.compiled._run_into` as :func:`symvi.flow.compiled.run` does
    (a run that never sticks is the same call, bit for bit); where it stops at sticking
    (a grazing contact pushed into the stop, the end of a converging chatter), the
    accumulation point (:func:`accumulate`), the sticking phase and the release
    (:class:`Stuck`) are computed and the loop resumes from the release.  Returns
    (code, section (n, 2N), t (n,), approach speeds (n,), hits (n,), sticks (m, 3):
    (t_stick, t_release, constraint) per sticking phase, t_release NaN for one still
    held when the run stopped; reason: why a stopped run could not go on, "" else)."""
    c = np.ascontiguousarray(c, dtype=np.float64)
    n = int(c[cf._NN])
    dim = 2 * n
    sec = np.empty((n_keep, dim))
    times = np.empty(n_keep)
    vimp = np.empty(n_keep)
    which = np.empty(n_keep, dtype=np.int64)
    y = np.array(np.asarray(y0, dtype=np.float64)[:dim])
    kept, done, t_off, idle = 0, 0, 0.0, 0
    sticks, stuck, reason = [], {}, ""
    flow = None
    omega, t_max = float(c[cf._OM]), float(c[cf._TMAX])
    while True:
        code, kk, _, _, k, it, T = cf._run_into(
            c, y, np.int64(k), n_keep - kept, max(transient - done, 0), sec[kept:],
            times[kept:], vimp[kept:], which[kept:], cf._NONE, cf._NONE, np.inf)
        if t_off:
            times[kept:kept + kk] += t_off
        kept, done = kept + kk, done + it
        idle = 0 if it else idle + 1
        if code != cf.STOP_STICKING:
            if code == cf.STOP_CHATTER:
                reason = "short flights that do not converge to an accumulation point"
            break
        if idle > MAX_IDLE_STICKS:
            reason = f"{MAX_IDLE_STICKS} stickings with no impact between them"
            break
        t0 = t_off + T
        ta, z, g = accumulate(c, y, k)
        if ta is None:
            reason = z
            break
        if g not in stuck:
            if flow is None:
                flow = LinearFlow.of(model)
            try:
                stuck[g] = Stuck(c, flow, g)
            except ValueError as exc:
                reason = str(exc)
                break
        S = stuck[g]
        tau = y[dim - 1] + omega * ta
        kind, ts, zr = S.run(z, tau, t_max)
        t_stick = t0 + ta
        if kind is None:
            sticks.append((t_stick, math.nan, g))
            reason = f"held on stop {g + 1} for longer than {t_max:g} time units"
            break
        sticks.append((t_stick, t_stick + ts, g))
        if kind != -1:
            reason = f"stop {kind + 1} met while stop {g + 1} holds its mass"
            break
        y = _section(zr, S.p, n, tau + omega * ts)
        k = g
        t_off = t_stick + ts
    st = np.array(sticks, dtype=float).reshape(-1, 3)
    return code, sec[:kept], times[:kept], vimp[:kept], which[:kept], st, reason
