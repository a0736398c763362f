"""Complete chatter and sticking on a rigid stop with nonlinear forces (issue 28): the
accumulation point, the held motion and the release, so that a run of
:class:`symvi.flow.nonlinear.NonlinearFlow` goes on through them as the linear run of
:mod:`symvi.flow.sticking` does.

Between impacts (mass order) M x'' + C x' + K x + f(x, v) = P sin(omega t + tau); a
constraint's guard is h = gh . x - level (gh = sign c, level = sign gap; h < 0 off the
stop), q = M^-1 gh, and its reset v+ = R v- has R q = -r q, gh^T R = -r gh^T (a stop on a
mass and the two-body law alike), so r = -gh . R q / (gh . q).

Chatter.  The accumulation time is :func:`symvi.flow.sticking.accumulation_time`'s
formula (the chatter map, [Budd & Dux 1994]) with its three coefficients read from the
nonlinear vector field at the impact (x, v+), phase phi = omega t + tau:

    a     = h''  = gh . M^-1 F(t, x, v+),   F = P sin(phi) - C v - K x - f(x, v),
    b     = h''' = d/dt (gh . M^-1 F) along the flow
               = gh . M^-1 (P omega cos(phi) - (C + f_v) v' - (K + f_x) v),   v' = M^-1 F,
    kappa = gh . M^-1 (C + f_v) q / (gh . q):

the impact changes v by -(1 + r) u q / (gh . q) at the fixed x, so h'' jumps by
kappa (1 + r) u to first order (f smooth in v); for linear forces (f = 0) these are the
linear module's a, b and kappa.  a and b are the solution's own Taylor coefficients at
the impact (h'' = 2 gh . x_2, h''' = 6 gh . x_3, :func:`symvi.flow.taylor._coefficients`);
kappa takes f_v q by central differences of the vector field (its O(eps^2) error enters
t_inf at O(w^2 eps^2)).  The run steps the impacts exactly (the Taylor flight) until one
comes at the loop's grazing speed (:mod:`symvi.flow.nonlinear`, ~1e-6); from that contact
at speed u the rest of the sequence, started with the rebound w0 = r u, lasts
accumulation_time(r u, a, r, b, kappa) (error O(u^3)), and the free flight's state at
t_inf is put back on the stop along q (g . x = level, g . v = 0: the impulse of the whole
sequence), as in :func:`symvi.flow.sticking.accumulate`.

Sticking.  Held on the stop (h = h' = 0), the contact force lambda gh keeps h'' = 0:
M x'' = F + lambda gh with lambda = -mu / (gh . q), mu = gh . M^-1 F(t, x, v) the free
guard acceleration, so

    x'' = M^-1 F - q mu / (gh . q)        (x_p fixed, v_p = 0 for a stop on mass p),

the reduced system with the nonlinear forces, written over the full state.  The stop
holds the mass while mu > 0; the release is where mu changes sign.  For one mass mu(t) =
gh M^-1 (P sin(omega t + tau) - k xp - f(xp, 0)) = A sin(omega t + tau) + B0, a sinusoid
plus a constant: the release is the first falling root, omega t + tau = pi - asin(-B0/A)
(A > 0) or asin(-B0/A) (A < 0) modulo 2 pi, in closed form (:func:`release_one`).  For
N > 1 the reduced system runs on the Taylor method (:func:`_held`: the series of the
projected field, mu's series beside them); over each step -mu and every other guard are
polynomials in theta, read by the Bernstein hull (:func:`symvi.flow._hull._first_bracket`,
as the free flight's events), so neither the release nor another stop is stepped over;
the state is put back on the stop after each step (the projection's rounding drift).

Release.  At the release h = h' = 0, h'' = mu = 0 (to the root's accuracy) and h''' < 0:
the free flight's guard polynomial over its first Taylor step is h''' theta^3 + ... with
h = h' = h'' = 0 dropped, and the flight is started a safe distance in (:func:`leave`,
half the first place the hull of h / theta^3 or of another guard may reach 0, the full
guard checked < 0 there), from where the run loop resumes with no guard just hit.

Not continued (the run stops, with the reason in :func:`run_through`): r >= 1, a last
flight that does not end pushed into a stop, another stop met while held, held past the
flight bound (1000 forcing periods), a held step that fails (non-finite series), no
transversal release (h''' >= 0), repeated stickings with no impact between them.

References
----------
[Budd & Dux] C. Budd, F. Dux, Chattering and related behaviour in impact oscillators,
Phil. Trans. R. Soc. A 347 (1994) 365-389.
"""
import math

import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from . import compiled as cf
from . import taylor
from ._hull import _bernstein, _first_bracket
from .sticking import MAX_IDLE_STICKS, accumulation_time
from .taylor import (_acceleration, _at, _guard_coeffs, _jorba_zou_h, _prepare, _refine,
                     _series)

__all__ = ["chatter_coefficients", "accumulate", "release_one", "Held", "leave",
           "run_through"]

_TWO_PI = 2.0 * math.pi
#: steps of one held phase before it gives up (as held past the bound)
_MAX_STEPS = 2_000_000
#: the relative size of the central differences of kappa's f_v q
_FD = 1e-5


def _geometry(flow, g):
    """(gh, level, q, gh . q, r) of constraint g (module docstring), mass order."""
    sign = float(flow.cons[g, 2])
    gh = sign * flow.normals[g]
    q = flow.Minv @ gh
    gq = float(gh @ q)
    r = -float(gh @ flow.R[g] @ q) / gq
    return gh, sign * float(flow.cons[g, 1]), q, gq, r


def _put_on(flow, g, z, gh, level, q, gq):
    """z (mass order, in place) put on constraint g along q: gh . x = level, gh . v = 0
    (exactly, for a stop on a mass)."""
    n = flow.n
    z[:n] -= (float(gh @ z[:n]) - level) / gq * q
    z[n:] -= float(gh @ z[n:]) / gq * q
    kc = flow.cons[g, 0]
    if not math.isnan(kc):
        z[int(kc)] = flow.cons[g, 1]
        z[n + int(kc)] = 0.0
    return z


def _series_at(flow, omega, tau, z):
    """The solution's Taylor coefficients X (2N, p + 1) at z, phase tau (a copy), and the
    flow's (system, scratch) they were made with."""
    sy, tj = flow._system(omega, tau), flow._taylor_work()
    _prepare(sy, tj)
    X = tj[8]
    taylor._coefficients(sy, tj, 0.0, np.ascontiguousarray(z, dtype=float), X)
    return X.copy(), sy, tj


def chatter_coefficients(flow, omega, z, tau, g):
    """(a, b, kappa) of the chatter map at the state z (mass order, just after an impact
    on constraint g, phase tau): h'', h''' and the damping's jump factor with the
    nonlinear forces (module docstring)."""
    n = flow.n
    gh, _, q, gq, _ = _geometry(flow, g)
    X = _series_at(flow, omega, tau, z)[0]
    a = 2.0 * float(gh @ X[:n, 2])
    b = 6.0 * float(gh @ X[:n, 3])
    e = _FD * max(1.0, float(np.abs(z[n:]).max())) / max(float(np.abs(q).max()), 1e-300)
    zp, zm = np.array(z, dtype=float), np.array(z, dtype=float)
    zp[n:] += e * q
    zm[n:] -= e * q
    # kappa = gh . M^-1 (C + f_v) q / gh . q = -d(gh . v')/dv . q / gh . q
    dv = (flow.rhs(omega, tau, 0.0, zp)[n:] - flow.rhs(omega, tau, 0.0, zm)[n:]) / (2 * e)
    return a, b, -float(gh @ dv) / gq


def accumulate(flow, omega, z, tau, k):
    """The accumulation point of the chatter the run loop stopped at: from z (mass order,
    just after an impact on constraint k, or on none for k = -1) at phase tau, the flight
    ends at a contact pushed into the stop at the grazing speed.  Returns (t, z, g): the
    time from z to the accumulation point, the state there (on the stop, gh . v = 0),
    the constraint; or (None, reason, g)."""
    st, te, g, ze = flow.first_impact(omega, z, tau, just_hit=k)
    if st != "impact":
        return None, "the last flight does not end on a stop that holds the mass", g
    n = flow.n
    gh, level, q, gq, r = _geometry(flow, g)
    tc = tau + omega * te
    if not float(gh @ flow.rhs(omega, tc, 0.0, ze)[n:]) > 0.0:
        return None, "the last flight does not end on a stop that holds the mass", g
    if not 0.0 <= r < 1.0:
        return None, f"restitution r = {r:g} on stop {g + 1}: no accumulation of impacts", g
    u = float(gh @ ze[n:])
    zi = np.concatenate([ze[:n], flow.R[g] @ ze[n:]])     # just after the contact's impact
    a, b, kappa = chatter_coefficients(flow, omega, zi, tc, g)
    if not a > 0.0:
        return None, "the last flight does not end on a stop that holds the mass", g
    t_rem = accumulation_time(r * max(u, 0.0), a, r, b, kappa)
    # the free flight on to t_inf, put back on the stop (the sequence's impulse is along q)
    zs = flow.state(omega, ze, tc, t_rem) if t_rem > 0.0 else ze.copy()
    return te + t_rem, _put_on(flow, g, zs, gh, level, q, gq), g


def release_one(A, B0, omega, tau):
    """The release of one held mass: the first t >= 0 where mu(t) = A sin(omega t + tau)
    + B0 falls through 0 (module docstring), 0 when mu(0) <= 0, None when mu > 0 for all
    t."""
    if not A * math.sin(tau) + B0 > 0.0:
        return 0.0
    s = -B0 / A if A != 0.0 else math.inf
    if not -1.0 < s < 1.0:
        return None
    phi = math.pi - math.asin(s) if A > 0.0 else math.asin(s)
    return ((phi - tau) % _TWO_PI) / omega


@nb.njit(cache=True, error_model="numpy")
def _held_coefficients(sy, tj, t, y, X, gh, q, gq, mu, acc):
    """X[:, 0..p] <- the Taylor coefficients of the held motion through (t, y) (module
    docstring: x'' = M^-1 F - q mu / (gh . q)), and mu[0..p-1] those of mu = gh . M^-1 F;
    the linear part Q of :func:`symvi.flow.taylor._prepare` (the loop of
    :func:`symvi.flow.taylor._coefficients`, its acceleration
    :func:`symvi.flow.taylor._acceleration`, with the projection)."""
    Minv = sy[0]
    u, w, tau = sy[6], sy[8][0], sy[9][0]
    tp, vals, roots, S, A, sn, cs, Q = tj[0], tj[1], tj[2], tj[3], tj[4], tj[5], tj[6], tj[7]
    dim = y.shape[0]
    n = dim // 2
    p = X.shape[1] - 1
    L = tp.shape[0] if roots.shape[0] > 0 else 0
    nf = n if L > 0 else 0
    first = tj[16]
    sn[0] = math.sin(w * t + tau)
    cs[0] = math.cos(w * t + tau)
    for i in range(dim):
        X[i, 0] = y[i]
    for k in range(p):
        if k > 0:
            sn[k] = w * cs[k - 1] / k
            cs[k] = -w * sn[k - 1] / k
        if L:
            _series(tp, vals, k, S, A, X, u, dim, dim if k == 0 else first)
        m = 0.0
        for i in range(n):
            a = _acceleration(Q, Minv, X, S, roots, sn, k, i, nf)
            acc[i] = a
            m += gh[i] * a
        mu[k] = m
        for i in range(n):
            X[n + i, k + 1] = (acc[i] - q[i] * m / gq) / (k + 1)
            X[i, k + 1] = X[n + i, k] / (k + 1)
    mu[p] = 0.0


@nb.njit(cache=True)
def _event(gp, b, stackb, lo_hi, br, scale):
    """The first theta in [0, 1] where the polynomial gp (monomial coefficients, < 0 at
    the start of the search) may reach 0 on the Bernstein hull, refined on the polynomial;
    -1.0 if none (the free flight's event search, :func:`symvi.flow.taylor._taylor_flight`)."""
    ub = gp[0]
    for i in range(1, gp.shape[0]):
        ub += max(gp[i], 0.0)
    if ub < 0.0:
        return -1.0
    _bernstein(gp, b)
    st = _first_bracket(b, stackb, lo_hi, br)
    if st == 0:
        return -1.0
    if st == 1:
        return br[0]
    if st == 2:
        return _refine(gp, br[0], br[1], scale)
    return 0.5 * (br[0] + br[1])


@nb.njit(cache=True, error_model="numpy")
def _held(sy, tj, cons, normals, gk, gh, q, gq, level, z, t_max, hmax, mu, acc):
    """The held motion on constraint gk from z (mass order, on the stop; in place: the
    state at the event) to its first event: (kind, t, steps), kind -1 the release (mu
    through 0), c >= 0 constraint c met, -2 none before t_max, -3 a failed step."""
    X, gp, b, stackb, lo_hi, br, ye = tj[8], tj[9], tj[10], tj[11], tj[12], tj[13], tj[14]
    dim = z.shape[0]
    n = dim // 2
    p = X.shape[1] - 1
    m = cons.shape[0]
    _prepare(sy, tj)
    for i in range(dim):
        ye[i] = z[i]
    t = 0.0
    for steps in range(1, _MAX_STEPS + 1):
        if t >= t_max:
            return -2, t, steps
        _held_coefficients(sy, tj, t, ye, X, gh, q, gq, mu, acc)
        h = _jorba_zou_h(X, hmax)
        if not (math.isfinite(h) and h > 0.0):
            return -3, t, steps
        best = 2.0
        kind = -2
        hk = 1.0
        for k in range(p + 1):               # the release: -mu reaches 0
            gp[k] = -mu[k] * hk
            hk *= h
        th = _event(gp, b, stackb, lo_hi, br, 1.0 + t / h)
        if th >= 0.0:
            best, kind = th, -1
        for c in range(m):
            if c == gk:
                continue
            _guard_coeffs(X, normals, c, cons[c, 1], cons[c, 2], h, gp)
            th = _event(gp, b, stackb, lo_hi, br, 1.0 + t / h)
            if 0.0 <= th < best:
                best, kind = th, c
        if kind != -2:
            _at(X, best * h, z, None)
            return kind, t + best * h, steps
        _at(X, h, ye, None)
        # back on the stop along q: the projection's rounding drift
        hx = -level
        hv = 0.0
        for i in range(n):
            hx += gh[i] * ye[i]
            hv += gh[i] * ye[n + i]
        for i in range(n):
            ye[i] -= hx / gq * q[i]
            ye[n + i] -= hv / gq * q[i]
        kc = int(cons[gk, 0])
        if kc >= 0:
            ye[kc] = cons[gk, 1]
            ye[n + kc] = 0.0
        t += h
    return -3, t, _MAX_STEPS


class Held:
    """The motion held on constraint g of a :class:`~symvi.flow.nonlinear.NonlinearFlow`
    at omega (module docstring: the reduced system); :meth:`run` finds the release or
    another stop."""

    def __init__(self, flow, omega, g):
        self.flow, self.omega, self.g = flow, float(omega), g
        self.gh, self.level, self.q, self.gq, _ = _geometry(flow, g)

    def run(self, z0, tau, t_max):
        """From z0 (mass order, on the stop) at phase tau: (kind, t, z) of the first event,
        kind -1 the release, j >= 0 stop j met; (None, t, None) if none before t_max,
        (-3, t, None) if a step failed (a non-finite series)."""
        flow, n, w = self.flow, self.flow.n, self.omega
        z = _put_on(flow, self.g, np.array(z0, dtype=float), self.gh, self.level, self.q,
                    self.gq)
        if n == 1:
            # mu = A sin(omega t + tau) + B0 (module docstring): the release in closed form
            A = float(self.gh[0] * flow.Minv[0, 0] * flow.model.forcing[0])
            B0 = float(self.gh[0] * flow.rhs(w, 0.0, 0.0, z)[1])
            for j in range(len(flow.cons)):   # another stop: its guard is constant here
                if j != self.g and flow.model.constraints[j].guard(z[:1]) >= 0.0:
                    return j, 0.0, z
            t = release_one(A, B0, w, float(tau))
            if t is None or t > t_max:
                return None, t_max, None
            return -1, t, z
        sy = flow._system(w, tau)
        tj = flow._taylor_work()
        p = tj[8].shape[1] - 1
        kind, t, _ = _held(sy, tj, flow._table, flow.normals, self.g, self.gh, self.q,
                           self.gq, self.level, z, float(t_max), flow._cap(w),
                           np.empty(p + 1), np.empty(n))
        if kind < -1:
            return (None if kind == -2 else -3), t, None
        if kind == -1:
            z = _put_on(flow, self.g, z, self.gh, self.level, self.q, self.gq)
        return kind, t, z


def leave(flow, omega, z, tau, g):
    """The free flight's start from a release on constraint g (module docstring): (s,
    z(s)) a safe time s > 0 in, or None when the motion does not leave the stop (h'''
    >= 0)."""
    X, sy, tj = _series_at(flow, omega, tau, z)
    h = _jorba_zou_h(X, flow._cap(omega))
    p = X.shape[1] - 1
    gp, b, stackb, lo_hi, br = (np.empty(p + 1), np.empty(p + 1), tj[11], tj[12],
                                np.empty(2))
    _guard_coeffs(X, flow.normals, g, flow.cons[g, 1], flow.cons[g, 2], h, gp)
    full = gp.copy()
    rest = np.zeros(p + 1)
    rest[:p - 2] = gp[3:]                     # h / theta^3: h, h', h'' = 0 dropped
    if not rest[0] < 0.0:
        return None
    th = _event(rest, b, stackb, lo_hi, br, 1.0)
    safe = 1.0 if th < 0.0 else th
    for c in range(len(flow.cons)):
        if c != g:
            _guard_coeffs(X, flow.normals, c, flow.cons[c, 1], flow.cons[c, 2], h, gp)
            th = _event(gp, b, stackb, lo_hi, br, 1.0)
            if th >= 0.0:
                safe = min(safe, th)
    th = 0.5 * safe
    if not taylor._poly(full, th)[0] < 0.0 or th <= 0.0:
        return None
    out = np.empty(2 * flow.n)
    _at(X, th * h, out, None)
    return th * h, out


def run_through(flow, omega, y0, n_keep, transient=0):
    """The run loop of :mod:`symvi.flow.nonlinear` continued through complete chatter and
    sticking, as :func:`symvi.flow.sticking.run_through` continues the compiled one: where
    it stops at sticking, the accumulation point (:func:`accumulate`), the held phase and
    the release (:class:`Held`, :func:`leave`) are computed and the loop resumes after the
    release.  ``y0`` a section point of the first constraint.  Returns (code, section (n,
    2N), t (n,), approach speeds (n,), hits (n,), sticks (m, 3): (t_stick, t_release,
    constraint), t_release NaN for one still held when the run stopped; reason: why a
    stopped run could not go on, "" else)."""
    omega = float(omega)
    dim = 2 * flow.n
    sec = np.empty((n_keep, dim))
    times = np.empty(n_keep)
    vimp = np.empty(n_keep)
    which = np.empty(n_keep, dtype=np.int64)
    z, tau, k = flow.start(y0), float(y0[-1]), 0
    kept, done, t_off, idle = 0, 0, 0.0, 0
    sticks, held, reason = [], {}, ""
    t_max = 1000 * _TWO_PI / omega
    while True:
        code, kk, _, k, tau, T, it = flow._run_into(
            omega, z, tau, k, max(transient - done, 0), sec[kept:], times[kept:],
            vimp[kept:], which[kept:])
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
        ta, zs, g = accumulate(flow, omega, z, tau, k)
        if ta is None:
            reason = zs
            break
        if g not in held:
            held[g] = Held(flow, omega, g)
        tau_s = tau + omega * ta
        kind, ts, zr = held[g].run(zs, tau_s, t_max)
        t_stick = t0 + ta
        if kind is None:
            sticks.append((t_stick, math.nan, g))
            reason = f"held on stop {g + 1} for longer than {t_max:g} time units"
            break
        if kind == -3:
            sticks.append((t_stick, math.nan, g))
            reason = f"the held motion on stop {g + 1} failed to step (non-finite series)"
            break
        sticks.append((t_stick, t_stick + ts, g))
        if kind != -1:
            reason = f"stop {kind + 1} met while stop {g + 1} holds its mass"
            break
        tau_r = tau_s + omega * ts
        out = leave(flow, omega, zr, tau_r, g)
        if out is None:
            reason = f"no release from stop {g + 1}: the free motion does not leave it"
            break
        s, z = out
        tau, k = (tau_r + omega * s) % _TWO_PI, -1
        t_off = t_stick + ts + s
    st = np.array(sticks, dtype=float).reshape(-1, 3)
    return code, sec[:kept], times[:kept], vimp[:kept], which[:kept], st, reason
