"""A numerical flow of a model with smooth nonlinear forces (issue 28).

Between impacts::

    M x'' + C x' + K x + f(x, v) = P sin(omega t + tau)

with f the model's forces (:attr:`symvi.model.Model.nonlinear`), compiled once per model
into a short postfix program (:func:`symvi.flow._program.program`) that one cached kernel
interprets: no code is generated or compiled per model, and ``x**3`` at x = 0 is 0
(integer powers are products).  Two integrators of a flight, one run loop (:func:`_run`,
the integrator by a flag):

* ``"taylor"`` (the default): the Taylor method of :mod:`symvi.flow.taylor` (the program
  interpreted on series, Jorba & Zou's order 20 and step), events on the solution's own
  polynomial over each step;
* ``"dop853"``: Dormand and Prince's explicit Runge-Kutta method of order 8 with its error
  estimator of orders 5 and 3 and its dense output of order 7 [Hairer, Norsett & Wanner,
  Solving ODEs I, II.10; the coefficients are SciPy's ``dop853_coefficients``], events on
  the dense output (stops on masses only).

Chosen by measurement (``benchmarks/bench_nonlinear_flow.py``, ``benchmarks/README.md``;
the 1-DOF impact Duffing oscillator, the same run): the Taylor method locates the first
impact to 2.8e-16 relative against mpmath at 30 digits (DOP853: 7.5e-14), and runs 22
times as many impacts a second (9.7e4 against 4.5e3, the exact linear flow 8.3e5 in the
same run; 11 steps an impact against 65, and no Runge-Kutta steps to refine an event).
It is still short of the issue's 2e5: three quarters of its time are the series, 28
orders a step (the benchmark's breakdown of a step).

Events of DOP853.  Each constraint's guard h = sign (x_k - b) (rigid stops on masses,
either side) is watched on every accepted step.  No contact of the dense output is
stepped over: over a step the guard's interpolant is a polynomial of degree 7 in theta =
(t - t_n) / h; its Bernstein coefficients bound it (the convex hull property,
:mod:`symvi.flow._hull`), and the leftmost sub-interval whose hull reaches 0 is found by
halving (de Casteljau) down to ROOT_THETA.  So a crossing of the interpolant is never
missed, however short the excursion; steps are bounded by STEP_BOUND of the shortest
period (forcing and linear modes), which keeps the interpolant within the step's accuracy.
The event time is then refined by Newton on full Runge-Kutta steps from the step's start
(h(t_e) with h' = sign v_k), so it carries the integration's accuracy, not the
interpolant's.  Just after an impact on constraint k its guard starts at 0 (x_k = b
exactly) and its first step looks at h / theta.

Constraints.  With the Taylor method every rigid constraint a Model carries: a guard
h = sign (c . x - g) on any normal c (a stop on a mass, an impact between two masses, a
two-sided clearance as two constraints); the section points are written in the flow's
frame (:func:`symvi.flow.linear.frame_of`), as the exact flow's runs.  At an impact
v+ = R v- (the constraint's reset, :meth:`symvi.model.Constraint.reset_matrix`: v_k+ =
-r v_k- on a diagonal M, the two-body law along M^-1 c between masses).  An approach speed
at or below the grazing speed GRAZING_SPEED_FACTOR sqrt(2 |h''| delta), delta = RTOL
max(1, |b|, |x|), is a grazing contact (sticking when h'' > 0 there): the run stops with
the reasons of :mod:`symvi.flow.compiled` (grazing, sticking, chatter, no-impact,
non-finite); a converging chatter is followed to its grazing contact, and
:func:`symvi.flow.nlsticking.run_through` goes on from a sticking through the held phase
and the release.
"""
import contextlib
import math
import warnings

import numba as nb
import numpy as np
from numba.core.errors import NumbaExperimentalFeatureWarning

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from ..errors import ParameterError
from ..numerics.tolerances import GRAZING_SPEED_FACTOR
from . import compiled as cf
from . import taylor, taylor_kernel
from .taylor import _taylor_flight
from ._hull import ROOT_THETA, _bernstein, _first_root  # noqa: F401  (the hull's owner)
from ._program import (FUNCS, MAX_STACK, OP_ADD, OP_CONST, OP_FUNC, OP_MUL,  # noqa: F401
                       OP_POW, OP_POWI, OP_VAR, _eval, _func, program)

#: relative and absolute tolerances of the step control (the issue's accuracy: ~1e-13)
RTOL = 3e-14
ATOL = 3e-14
#: a step is at most this fraction of the shortest period (forcing, linear modes)
STEP_BOUND = 1.0 / 16.0
#: steps of one flight before it gives up (as no impact)
MAX_STEPS = 2_000_000

# --- DOP853 (SciPy's dop853_coefficients: Hairer's dop853.f) -----------------------------
_NS = 12                 # stages of a step (K has _NS + 1 rows: the last is f at the end)
_NX = 16                 # stages with the three extra ones of the dense output


def _coefficients():
    from scipy.integrate._ivp import dop853_coefficients as d
    A = np.ascontiguousarray(d.A, dtype=np.float64)
    return (A, np.ascontiguousarray(d.B, dtype=np.float64),
            np.ascontiguousarray(d.C, dtype=np.float64),
            np.ascontiguousarray(d.E3, dtype=np.float64),
            np.ascontiguousarray(d.E5, dtype=np.float64),
            np.ascontiguousarray(d.D, dtype=np.float64))


_A, _B, _C, _E3, _E5, _D = _coefficients()

@nb.njit(cache=True)
def _rhs(sy, t, y, out):
    """y' = (v, M^-1 (P sin(omega t + tau) - C v - K x - f(x, v))), y = (x, v) in mass order."""
    Minv, K, C, P, ops, off, u, stack, w, tau, rhs = sy
    n = P.shape[0]
    for i in range(2 * n):
        u[i] = y[i]
    s = math.sin(w[0] * t + tau[0])
    for i in range(n):
        r = P[i] * s - _eval(ops, off[i], off[i + 1], u, stack)
        for j in range(n):
            r -= C[i, j] * y[n + j] + K[i, j] * y[j]
        rhs[i] = r
    for i in range(n):
        out[i] = y[n + i]
        a = 0.0
        for j in range(n):
            a += Minv[i, j] * rhs[j]
        out[n + i] = a


@nb.njit(cache=True)
def _combine(y, h, K, coef, m, out):
    """out = y + h sum_{q < m} coef[q] K[q]: a stage's argument (coef = _A[s], m = s) or
    the step's end (_B, _NS)."""
    for i in range(y.shape[0]):
        acc = 0.0
        for q in range(m):
            acc += coef[q] * K[q, i]
        out[i] = y[i] + h * acc


@nb.njit(cache=True)
def _dop853(sy, t, y, h, Kst, ynew, tmp):
    """One DOP853 step of size h from (t, y), Kst[0] = f(t, y) given: ynew and the stages
    Kst[0.._NS] (the last: f at the end)."""
    for s in range(1, _NS):
        _combine(y, h, Kst, _A[s], s, tmp)
        _rhs(sy, t + _C[s] * h, tmp, Kst[s])
    _combine(y, h, Kst, _B, _NS, ynew)
    _rhs(sy, t + h, ynew, Kst[_NS])


@nb.njit(cache=True)
def _error(Kst, y, ynew, h, rtol, atol):
    """DOP853's error norm of the step (SciPy's ``_estimate_error_norm``)."""
    dim = y.shape[0]
    e5 = 0.0
    e3 = 0.0
    for i in range(dim):
        sc = atol + rtol * max(abs(y[i]), abs(ynew[i]))
        a5 = 0.0
        a3 = 0.0
        for j in range(_NS + 1):
            a5 += _E5[j] * Kst[j, i]
            a3 += _E3[j] * Kst[j, i]
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    den = (e5 + 0.01 * e3) * dim
    if den == 0.0:                          # both zero, or underflowed (a state at rest)
        return 0.0
    return abs(h) * e5 / math.sqrt(den)


@nb.njit(cache=True)
def _dense(sy, t, y, ynew, h, Kst, Kx, F, tmp):
    """The dense output's seven coefficient rows F of the step (SciPy's DOP853 dense
    output): y(theta) = y + theta (F0 + (1 - theta) (F1 + theta (F2 + ...)))."""
    dim = y.shape[0]
    for s in range(_NS + 1):
        for i in range(dim):
            Kx[s, i] = Kst[s, i]
    for s in range(_NS + 1, _NX):
        _combine(y, h, Kx, _A[s], s, tmp)
        _rhs(sy, t + _C[s] * h, tmp, Kx[s])
    for i in range(dim):
        dy = ynew[i] - y[i]
        F[0, i] = dy
        F[1, i] = h * Kx[0, i] - dy
        F[2, i] = 2.0 * dy - h * (Kx[_NS, i] + Kx[0, i])
        for r in range(4):
            acc = 0.0
            for j in range(_NX):
                acc += _D[r, j] * Kx[j, i]
            F[3 + r, i] = h * acc


@nb.njit(cache=True)
def _guard_poly(y, F, k, gap, sign, p):
    """The monomial coefficients p[0..7] in theta of the guard sign (x_k - gap) on the
    dense output."""
    for i in range(8):
        p[i] = 0.0
    p[0] = F[6, k]
    for r in range(5, -2, -1):
        # times theta (even rounds) or (1 - theta) (odd), then add F[r]
        if (5 - r) % 2 == 0:
            for i in range(7, 0, -1):
                p[i] = p[i - 1]
            p[0] = 0.0
        else:
            for i in range(7, 0, -1):
                p[i] = p[i] - p[i - 1]
        if r >= 0:
            p[0] += F[r, k]
    p[0] += y[k] - gap
    for i in range(8):
        p[i] *= sign


@nb.njit(cache=True)
def _flight(sy, cons, z, just_hit, t_max, hmax, hh, work):
    """Integrate from z (mass order, time 0) to the first contact of any constraint, or
    t_max.  On an impact z is the state just before it.  Returns (status, t_e, constraint,
    approach speed, h'' at the contact, steps); hh[0] carries the step size between calls.

    cons: one row per constraint (mass index, gap, sign)."""
    Kst, Kx, F, y, ynew, tmp, p, b, stackb, lo_hi, ye = work
    dim = z.shape[0]
    n = dim // 2
    m = cons.shape[0]
    for i in range(dim):
        y[i] = z[i]
    t = 0.0
    _rhs(sy, t, y, Kst[0])
    h = min(hh[0], hmax)
    steps = 0
    first = True
    rtol, atol = RTOL, ATOL
    while steps < MAX_STEPS:
        if t >= t_max:
            return cf.NO_IMPACT, t, -1, 0.0, 0.0, steps
        h = min(h, hmax)
        _dop853(sy, t, y, h, Kst, ynew, tmp)
        err = _error(Kst, y, ynew, h, rtol, atol)
        steps += 1
        if not math.isfinite(err):
            h *= 0.2
            if h < 1e-300:
                return cf.NO_IMPACT, t, -2, 0.0, 0.0, steps
            _rhs(sy, t, y, Kst[0])
            continue
        if err > 1.0:
            h *= max(0.2, 0.9 * err ** (-1.0 / 8.0))
            _rhs(sy, t, y, Kst[0])
            continue
        # accepted: look for the first contact on the dense output of [t, t + h]
        _dense(sy, t, y, ynew, h, Kst, Kx, F, tmp)
        best = 2.0
        bc = -1
        for c in range(m):
            k = int(cons[c, 0])
            _guard_poly(y, F, k, cons[c, 1], cons[c, 2], p)
            if first and c == just_hit:
                for i in range(7):          # h starts at 0: look at h / theta
                    p[i] = p[i + 1]
                p[7] = 0.0
            _bernstein(p, b)
            th = _first_root(b, stackb, lo_hi)
            if 0.0 <= th < best:
                best = th
                bc = c
        if bc >= 0:
            # Newton on full steps from the step's start: h(t_e) = 0, h' = sign v_k
            k = int(cons[bc, 0])
            gap, sign = cons[bc, 1], cons[bc, 2]
            he = best * h
            for it in range(8):
                he = max(he, 0.0)
                _dop853(sy, t, y, he, Kx, ye, tmp)   # Kx: scratch (Kx[0] = f(t, y))
                g = sign * (ye[k] - gap)
                gd = sign * ye[n + k]
                if gd <= 0.0:
                    break
                dh = g / gd
                if abs(dh) <= 4e-16 * max(t + he, 1e-300) or (he == 0.0 and dh > 0.0):
                    break
                he -= dh
            for i in range(dim):
                z[i] = ye[i]
            _rhs(sy, t + he, ye, tmp)
            hh[0] = h
            return cf.IMPACT, t + he, bc, sign * ye[n + k], sign * tmp[n + k], steps
        t += h
        for i in range(dim):
            y[i] = ynew[i]
            Kst[0, i] = Kst[_NS, i]
        first = False
        fac = 10.0 if err == 0.0 else min(10.0, max(0.2, 0.9 * err ** (-1.0 / 8.0)))
        h *= fac
    return cf.NO_IMPACT, t, -2, 0.0, 0.0, steps


@nb.njit(cache=True)
def _run(sy, tj, cons, normals, R, SEC, z, tau, k, n_keep, transient, hmax, t_max, sec,
         times, vimp, hits, work, taylor):
    """The run of the nonlinear map from z (mass order, on constraint k's guard) at phase
    tau: stores section points (SEC[c] z: constraint c's section layout), times, approach
    speeds and the constraint hit, as :func:`symvi.flow.compiled.run` does.  The flight:
    the Taylor method's (``taylor``, :func:`symvi.flow.taylor._taylor_flight`, scratch tj)
    or DOP853's (:func:`_flight`, scratch work; stops on masses).  k = -1: z lies on no
    guard (a start after a release, :mod:`symvi.flow.nlsticking`).  As
    :func:`symvi.flow.compiled._run_into`, a short flight counts toward a chatter stop
    unless the sequence converges (the same constraint, pushed into it, a smaller approach
    speed): that one is followed to its grazing contact, whose sticking the caller
    continues.  Returns (stop code, number stored, steps, the constraint of z at the end,
    its phase, its time since the start, the images accepted, transient included); on a
    stop z is left at the last state accepted (just after its impact)."""
    dim = z.shape[0]
    n = dim // 2
    w = sy[8][0]
    hh = np.array([hmax])
    v = np.empty(n)
    T = 0.0
    short = 0
    t_chat = cf.CHATTER_FLIGHT * 2.0 * math.pi / w
    steps = 0
    zs = z.copy()
    c_prev, vm_prev = -1, np.inf
    for it in range(transient + n_keep):
        kept = it - transient
        sy[9][0] = tau
        for i in range(dim):
            zs[i] = z[i]
        if taylor:
            st, te, c, vm, acc, ns = _taylor_flight(sy, tj, cons, normals, z, k, t_max, hmax)
        else:
            st, te, c, vm, acc, ns = _flight(sy, cons, z, k, t_max, hmax, hh, work)
        steps += ns
        if st != cf.IMPACT:
            for i in range(dim):
                z[i] = zs[i]
            return (cf.STOP_NO_IMPACT if c == -1 else cf.STOP_NONFINITE, max(kept, 0), steps,
                    k, tau, T, it)
        L = max(1.0, abs(cons[c, 1]))
        for i in range(n):
            L = max(L, abs(z[i]))
        if vm <= GRAZING_SPEED_FACTOR * math.sqrt(2.0 * abs(acc) * RTOL * L):
            for i in range(dim):
                z[i] = zs[i]
            return ((cf.STOP_STICKING if acc > 0.0 else cf.STOP_GRAZING), max(kept, 0), steps,
                    k, tau, T, it)
        # v+ = R v- (the constraint's reset); on a mass's stop the section is x_k = gap
        for i in range(n):
            a = 0.0
            for j in range(n):
                a += R[c, i, j] * z[n + j]
            v[i] = a
        ok = True
        for i in range(n):
            z[n + i] = v[i]
        kc = int(cons[c, 0])
        if kc >= 0:
            z[kc] = cons[c, 1]
        for i in range(dim):
            ok = ok and math.isfinite(z[i]) and abs(z[i]) <= 1e6
        if not ok:
            for i in range(dim):
                z[i] = zs[i]
            return cf.STOP_NONFINITE, max(kept, 0), steps, k, tau, T, it
        k = c
        tau = (tau + w * te) % (2.0 * math.pi)
        T += te
        conv = c == c_prev and acc > 0.0 and vm < vm_prev
        short = short + 1 if te < t_chat and not conv else 0
        c_prev, vm_prev = c, vm
        if kept >= 0:
            for i in range(dim - 1):
                a = 0.0
                for j in range(dim):
                    if SEC[c, i, j] != 0.0:
                        a += SEC[c, i, j] * z[j]
                sec[kept, i] = a
            sec[kept, dim - 1] = tau
            times[kept] = T
            vimp[kept] = vm
            hits[kept] = c
        if short >= cf.CHATTER_COUNT:
            return cf.STOP_CHATTER, max(kept + 1, 0), steps, k, tau, T, it + 1
    return cf.COMPLETED, n_keep, steps, k, tau, T, transient + n_keep


@nb.njit(cache=True)
def _integrate(sy, z, t_end, hmax, work):
    """z(t_end) by the adaptive steps of :func:`_flight`, the last one cut to end there."""
    Kst, Kx, F, y, ynew, tmp, p, b, stackb, lo_hi, ye = work
    dim = z.shape[0]
    for i in range(dim):
        y[i] = z[i]
    t = 0.0
    _rhs(sy, t, y, Kst[0])
    h = hmax
    while t < t_end:
        h = min(h, hmax, t_end - t)
        _dop853(sy, t, y, h, Kst, ynew, tmp)
        err = _error(Kst, y, ynew, h, RTOL, ATOL)
        if err > 1.0 or not math.isfinite(err):
            h *= 0.2 if not math.isfinite(err) else max(0.2, 0.9 * err ** (-1.0 / 8.0))
            continue
        t = t + h if t_end - t > h else t_end
        for i in range(dim):
            y[i] = ynew[i]
            Kst[0, i] = Kst[_NS, i]
        h *= 10.0 if err == 0.0 else min(10.0, max(0.2, 0.9 * err ** (-1.0 / 8.0)))
    return y.copy()


#: the integrators of a flight: the Taylor method (the default, chosen by measurement: the
#: module docstring) and DOP853
METHODS = ("taylor", "dop853")


class NonlinearFlow:
    """The numerical flow of a model with nonlinear forces and rigid constraints.

    ``NonlinearFlow(model, method="taylor")``; :meth:`state` integrates without events (a
    flight's reference), :meth:`first_impact` finds the first contact, :meth:`run` iterates
    the impact map from a section point (what :func:`symvi.simulate` runs).  Every rigid
    constraint a Model carries: stops on masses, either side, and between masses (guard
    c . x - g, reset :meth:`symvi.model.Constraint.reset_matrix`), section points in the
    flow's frame (:func:`symvi.flow.linear.frame_of`) as the exact flow's; ``"dop853"``
    takes stops on masses only.  Elastic stops are refused here: their contact phases run in
    the walk of :mod:`symvi.flow.contact` (:mod:`symvi.flow.nlcontact`)."""

    def __init__(self, model, method="taylor"):
        if method not in METHODS:
            raise ParameterError("method", method, " or ".join(f'"{m}"' for m in METHODS))
        for k, s in enumerate(model.stops, 1):
            if s.stiffness is not None:
                raise ParameterError("stop" if len(model.stops) == 1 else f"stop[{k}]", s,
                                     "rigid stops (this run loop's; with an elastic stop the "
                                     "walk of symvi.flow.contact runs each contact phase on "
                                     "the Taylor flow: symvi.flow.nlcontact)")
        cons = model.constraints
        if method == "dop853" and any(c.coordinate is None for c in cons):
            raise ParameterError("method", method, '"taylor" for a stop between masses '
                                 "(DOP853's events read stops on masses)")
        self.model, self.method = model, method
        n = self.n = model.n
        names = [f"x{i + 1}" for i in range(n)] + [f"v{i + 1}" for i in range(n)]
        forces = model._nl
        exprs = forces.exprs(n) if forces is not None else (0,) * n
        pnames = list(forces.names) if forces is not None else []
        self.ops, self.off, depth = program(exprs, names + pnames)
        self.tape = taylor.tape(self.ops, self.off, 2 * n)
        self.pars = np.array([forces.value(p) for p in pnames], dtype=float)
        self.Minv = np.linalg.inv(model.mass)
        #: one row per constraint: (the mass of a stop on a mass, NaN between masses; gap;
        #: sign), and the kernels' copy with -1 for NaN
        self.cons = np.array([[math.nan if c.coordinate is None else c.coordinate, c.gap,
                               c.sign] for c in cons], dtype=float)
        self._table = np.nan_to_num(self.cons, nan=-1.0)
        self.normals = np.array([c.normal for c in cons], dtype=float)
        self.R = np.array([c.reset_matrix(self.Minv) for c in cons], dtype=float)
        w2 = np.linalg.eigvals(self.Minv @ model.stiffness).real
        self.omega_max = math.sqrt(max(float(w2.max()), 0.0))
        self._depth = max(depth, 1)
        from .linear import frame_of
        perm, T, _ = frame_of(model)           # the frame q = T x of the sections
        self.T = np.eye(n)[list(perm)] if T is None else np.asarray(T, dtype=float)
        self._Tinv = self.T.T if T is None else np.linalg.inv(self.T)   # exact: a permutation
        #: stops on masses only: each constraint's section layout as mass-order state
        #: indices (None with a constraint between masses: read SEC)
        self.sidx = None if T is not None else np.array(
            [[perm[q] if q < n else n + perm[q - n] for q in
              cf.section_index(n, perm.index(c.coordinate))] for c in cons], dtype=np.int64)
        # each constraint's section layout as rows over the mass-order state
        self.SEC = np.zeros((len(cons), 2 * n - 1, 2 * n))
        self._pos = []
        for j, c in enumerate(cons):
            p = next(i for i in range(n) if tuple(self.T[i]) == c.normal)
            self._pos.append(p)
            for i, q in enumerate(cf.section_index(n, p)):
                if q < n:
                    self.SEC[j, i, :n] = self.T[q]
                else:
                    self.SEC[j, i, n:] = self.T[q - n]

    def _system(self, omega, tau):
        n = self.n
        u = np.empty(2 * n + len(self.pars))
        u[2 * n:] = self.pars
        return (self.Minv, np.ascontiguousarray(self.model.stiffness),
                np.ascontiguousarray(self.model.damping),
                np.ascontiguousarray(self.model.forcing), self.ops, self.off, u,
                np.empty(self._depth + 1), np.array([float(omega)]), np.array([float(tau)]),
                np.empty(n))

    def _work(self):
        dim = 2 * self.n
        return (np.empty((_NS + 1, dim)), np.empty((_NX, dim)), np.empty((7, dim)),
                np.empty(dim), np.empty(dim), np.empty(dim), np.empty(8), np.empty(8),
                np.empty((96, 8)), np.empty((96, 2)), np.empty(dim))

    def _taylor_work(self, own=None):
        return taylor.work(*self.tape, 2 * self.n, kernel=own)

    def hmax(self, omega, frac=STEP_BOUND):
        """DOP853's step bound: STEP_BOUND (or ``frac``) of the shortest period (forcing,
        linear modes)."""
        return frac * 2.0 * math.pi / max(omega, self.omega_max, 1e-12)

    def _cap(self, omega):
        """The step bound of this flow's method (:data:`symvi.flow.taylor.STEP_CAP` of the
        shortest period for the Taylor method)."""
        return self.hmax(omega, taylor.STEP_CAP if self.method == "taylor" else STEP_BOUND)

    def rhs(self, omega, tau, t, z):
        """The vector field at (t, z), z = (x, v) in mass order."""
        out = np.empty(2 * self.n)
        _rhs(self._system(omega, tau), float(t), np.asarray(z, dtype=float), out)
        return out

    def first_impact(self, omega, z0, tau, t_max=None, just_hit=-1):
        """(status, t_e, constraint, z_e-): the first contact from z0 (mass order) at phase
        tau; status a name of :data:`symvi.flow.compiled.STATUS_NAMES` ("impact",
        "no-impact"), or "non-finite" where the forces or the solution are not finite (a
        force like sqrt(x1) or 1/x1 at x1 = 0); z_e- the state just before the impact.
        ``just_hit``: the constraint z0 lies on (leaving it)."""
        z = np.array(z0, dtype=float)
        t_max = 1000 * 2 * math.pi / omega if t_max is None else float(t_max)
        h = self._cap(omega)
        sy = self._system(omega, tau)
        if self.method == "taylor":
            st, te, c, _, _, _ = taylor._taylor_flight(sy, self._taylor_work(), self._table,
                                                       self.normals, z, int(just_hit),
                                                       t_max, h)
        else:
            st, te, c, _, _, _ = _flight(sy, self._table, z, int(just_hit), t_max, h,
                                         np.array([h]), self._work())
        return "non-finite" if c == -2 else cf.STATUS_NAMES[st], te, c, z

    def state(self, omega, z0, tau, t):
        """z(t) from z0 (mass order) at phase tau, ignoring the constraints (a flight's
        reference: the same steps, no events)."""
        z = np.array(z0, dtype=float)
        sy = self._system(omega, tau)
        h = self._cap(omega)
        if self.method == "taylor":
            return taylor._taylor_integrate(sy, self._taylor_work(), z, float(t), h)
        return _integrate(sy, z, float(t), h, self._work())

    def start(self, y0):
        """The state (mass order) of a section point y0 of the first constraint (the
        flow's frame, :func:`symvi.flow.linear.frame_of`)."""
        n = self.n
        q = np.empty(2 * n)
        q[self._pos[0]] = self.cons[0, 1]
        for i, j in enumerate(cf.section_index(n, self._pos[0])):
            q[j] = y0[i]
        return np.concatenate([self._Tinv @ q[:n], self._Tinv @ q[n:]])

    def run(self, omega, y0, n_keep, transient=0):
        """(code, section (n, 2N), t, approach speeds, hits, steps) of the run from y0, a
        section point of the first constraint (:func:`symvi.flow.compiled.run`'s
        layout)."""
        dim = 2 * self.n
        z = self.start(y0)
        sec = np.empty((n_keep, dim))
        times = np.empty(n_keep)
        vimp = np.empty(n_keep)
        hits = np.empty(n_keep, dtype=np.int64)
        code, kk, steps = self._run_into(omega, z, float(y0[-1]), 0, transient, sec, times,
                                         vimp, hits)[:3]
        return code, sec[:kk], times[:kk], vimp[:kk], hits[:kk], steps

    def _run_into(self, omega, z, tau, k, transient, sec, times, vimp, hits):
        """:func:`_run` from z (mass order, in place) at phase tau on constraint k (-1: on
        none), storing into the given arrays (their length: the images to store): the
        loop's return (:func:`symvi.flow.nlsticking.run_through` resumes it)."""
        own = None
        if self.method == "taylor":               # a long run: the tape's own kernel
            own = taylor_kernel.for_run(self.tape[0], self.tape[2], 2 * self.n,
                                        len(times) + transient)
        # numba calls a kernel taken by address experimental when it compiles the run for it;
        # the filter only then (catch_warnings swaps the process's filters)
        with warnings.catch_warnings() if own is not None else contextlib.nullcontext():
            if own is not None:
                warnings.filterwarnings("ignore", category=NumbaExperimentalFeatureWarning)
            out = _run(self._system(omega, tau), self._taylor_work(own), self._table,
                       self.normals, self.R, self.SEC, z, float(tau), int(k), len(times),
                       transient, self._cap(omega), 1000 * 2 * math.pi / omega, sec, times,
                       vimp, hits, self._work(), self.method == "taylor")
        if own is None and self.method == "taylor":
            taylor_kernel.ran(self.tape[0], self.tape[2], 2 * self.n, out[6])
        return out
