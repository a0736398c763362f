"""Compiled float64 twin of :meth:`symvi.orbits.periodic.Problem.evaluate`.

One numba call (cached on disk) computes, for the n-p shooting system of
:mod:`symvi.orbits.periodic`, every flight (z(t), Phi(t) = Re(W e^{lambda t} W^-1),
dz/dtau, dz/dt, eq. (19) generalised), the residual G, its Jacobian G_u and
dG/domega, with the formulas and the order of operations of the numpy reference
(``Problem._evaluate_numpy``), so that the two agree to rounding
(tests/continuation/test_compiled_shooting.py).  Also compiled: the map Jacobians
DP_i with the flight time eliminated and their product (eq. (30)).  And, in Python,
the constants of the compiled first-impact finder of :mod:`symvi.flow.compiled` at
a new omega without rebuilding the modal part (:func:`finder_constants`), and the
flow as :func:`symvi.orbits.admissibility.check_flight`'s callers use it with that
finder (:class:`CompiledFinder`).
"""
import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from ..flow import compiled as _fc
from ..flow.linear import OMEGA_RANGE, FirstImpact
from ..maps.section import Section

_OMEGA_MIN = 2 * OMEGA_RANGE[0]

_TWO_PI = 2.0 * math.pi


def flight_views(FL, PHI, i):
    """(z0, tau, z, Phi, dz/dtau, dz/dt) of impact i from the output of :func:`shoot`."""
    row = FL[i]
    d = PHI.shape[1]
    return row[:d], row[d], row[d + 1:2 * d + 1], PHI[i], row[2 * d + 1:3 * d + 1], row[3 * d + 1:]


@nb.njit(cache=True, inline="always")
def _zp(U, V, w, ph, out):
    """(x_p, v_p) at phase ph: Forcing.zp."""
    n = U.shape[0]
    s, c = math.sin(ph), math.cos(ph)
    for i in range(n):
        out[i] = U[i] * s + V[i] * c
        out[n + i] = w * (U[i] * c - V[i] * s)


@nb.njit(cache=True, inline="always")
def _zp_phase(U, V, w, ph, out):
    """d zp / d phase: Forcing.zp_phase."""
    n = U.shape[0]
    s, c = math.sin(ph), math.cos(ph)
    for i in range(n):
        out[i] = U[i] * c - V[i] * s
        out[n + i] = -w * (U[i] * s + V[i] * c)


@nb.njit(cache=True, inline="always")
def _zp_omega(U, V, dU, dV, w, ph, out):
    """d zp / d omega at fixed phase: Forcing.zp_omega."""
    n = U.shape[0]
    s, c = math.sin(ph), math.cos(ph)
    for i in range(n):
        out[i] = dU[i] * s + dV[i] * c
        out[n + i] = (U[i] * c - V[i] * s) + w * (dU[i] * c - dV[i] * s)


@nb.njit(cache=True, inline="always")
def _matvec(Mx, x, out):
    d = x.shape[0]
    for a in range(d):
        s = 0.0
        for b in range(d):
            s += Mx[a, b] * x[b]
        out[a] = s


@nb.njit(cache=True)
def shoot(lam, W, Winv, A, NIL, U, V, dU, dV, w, tab, idx, sig, n_periods, u, p, jac, dom):
    """Flights, G, G_u (if ``jac``) and dG/domega (if ``dom``) at u; see the module docstring.

    The constraints enter as the flow holds them, ``tab`` = the rows of
    :meth:`LinearFlow.constraint_rows` (per constraint: the position of its coordinate in
    the flow's order, its gap, the guard's level, the signed guard normal g (impact
    condition g . x - level = 0), the reset R (v+ = R v-)), ``idx`` the flow-order index
    of each section coordinate on each constraint's section
    (:func:`symvi.flow.compiled.section_index`) and ``sig`` (p + 1 entries) the constraint
    of each impact: point i lies on the section of constraint sig[i], and its flight ends
    on sig[i + 1] (sig[p] = sig[0] for an orbit; a single flight, p = 1, may end on
    another constraint than it starts from: the tangent map of a run).

    ``NIL`` is the free modes' nilpotent part of e^{At} (:attr:`LinearFlow.modal_nil64`;
    an empty (0, 0) array without free modes): Phi(t) = Re(W e^{Lambda t} W^-1) + t NIL.

    Returns (G, Gu, Gw, FL, PHI): per impact i, FL[i] holds (z0, tau, z, dz/dtau, dz/dt)
    (the start state in the flow's order, its phase, and at the end of the flight the
    state and its derivatives; :data:`FLIGHT_SLICES`) and PHI[i] = dz/dz0 there.
    """
    d = lam.shape[0]
    N = d // 2
    m = p * (d + 1)
    G = np.empty(m)
    Gu = np.zeros((m, m)) if jac else np.zeros((0, 0))
    Gw = np.empty(m) if dom else np.empty(0)
    FL = np.empty((p, 4 * d + 1))
    PHI = np.empty((p, d, d))
    e = np.empty(d, np.complex128)
    a0 = np.empty(d)
    a1 = np.empty(d)
    a2 = np.empty(d)
    hom = np.empty(d)
    zp = np.empty(d)                                # the state after the reset
    RP = np.empty((d, d + 2))                       # (Phi, dzt, dzdt) with R on the v rows
    gP = np.empty(d + 2)                            # g . (Phi[:N, :], dzt[:N], dzdt[:N])
    for i in range(p):
        y = u[i * d:(i + 1) * d]
        t = u[p * d + i]
        ka, kb = sig[i], sig[i + 1]
        ia, ib = idx[ka], idx[kb]
        level = tab[kb, 2]
        g = tab[kb, 3:3 + N]
        R = tab[kb, 3 + N:3 + N + N * N]
        z0 = FL[i, :d]
        z0[int(tab[ka, 0])] = tab[ka, 1]            # x_p = gap on the start's section
        for q in range(d - 1):
            z0[ia[q]] = y[q]
        tau = y[d - 1]
        FL[i, d] = tau
        # Phi(t) = Re((W e^{lambda t}) W^-1)
        for k in range(d):
            e[k] = np.exp(lam[k] * t)
        Phi = PHI[i]
        for a in range(d):
            for c in range(d):
                s = 0j
                for k in range(d):
                    s += (W[a, k] * e[k]) * Winv[k, c]
                Phi[a, c] = s.real
        if NIL.shape[0] > 0:                        # the free modes' drift (a Jordan block)
            for a in range(d):
                for c in range(d):
                    Phi[a, c] += t * NIL[a, c]
        ph = tau + w * t
        # hom = Phi (z0 - zp(tau)); z = hom + zp(ph)
        _zp(U, V, w, tau, a0)
        for k in range(d):
            a0[k] = z0[k] - a0[k]
        _matvec(Phi, a0, hom)
        _zp(U, V, w, ph, a1)
        z = FL[i, d + 1:2 * d + 1]
        for k in range(d):
            z[k] = hom[k] + a1[k]
        # dz/dtau = zp_phase(ph) - Phi zp_phase(tau); dz/dt = A hom + w zp_phase(ph)
        _zp_phase(U, V, w, tau, a0)
        _matvec(Phi, a0, a2)
        _zp_phase(U, V, w, ph, a1)
        dzt = FL[i, 2 * d + 1:3 * d + 1]
        for k in range(d):
            dzt[k] = a1[k] - a2[k]
        _matvec(A, hom, a2)
        dzdt = FL[i, 3 * d + 1:]
        for k in range(d):
            dzdt[k] = a2[k] + w * a1[k]
        # residual: h_i (impact law to the next point) and g_i (impact condition)
        j = (i + 1) % p
        yj = u[j * d:(j + 1) * d]
        wrap = _TWO_PI * n_periods if j == 0 else 0.0
        r0 = i * d
        ct = p * d + i
        _reset(R, z, N, zp)
        for q in range(N):
            zp[q] = z[q]
        for q in range(d - 1):
            G[r0 + q] = zp[ib[q]] - yj[q]
        G[r0 + d - 1] = tau + w * t - (yj[d - 1] + wrap)
        G[ct] = _guard(g, z, N) - level
        if jac:
            # the reset and the guard applied once to the columns (Phi, dz/dtau, dz/dt)
            for col in range(d + 2):
                for a in range(N):
                    RP[a, col] = _col(Phi, dzt, dzdt, a, col, d)
                    s = 0.0
                    for k in range(N):
                        s += R[a * N + k] * _col(Phi, dzt, dzdt, N + k, col, d)
                    RP[N + a, col] = s
                s = 0.0
                for k in range(N):
                    s += g[k] * _col(Phi, dzt, dzdt, k, col, d)
                gP[col] = s
            for c in range(d):              # dz/dy: Phi[:, ia] then dz/dtau
                col = d if c == d - 1 else ia[c]
                for q in range(d - 1):
                    Gu[r0 + q, r0 + c] = RP[ib[q], col]
                Gu[ct, r0 + c] = gP[col]
            Gu[r0 + d - 1, r0 + d - 1] = 1.0
            for q in range(d):
                Gu[r0 + q, j * d + q] -= 1.0
            for q in range(d - 1):
                Gu[r0 + q, ct] = RP[ib[q], d + 1]
            Gu[r0 + d - 1, ct] = w
            Gu[ct, ct] = gP[d + 1]
        if dom:
            # dz/domega = zp_omega(ph) + t zp_phase(ph) - Phi zp_omega(tau)
            _zp_omega(U, V, dU, dV, w, tau, a0)
            _matvec(Phi, a0, a2)
            _zp_omega(U, V, dU, dV, w, ph, a0)
            for k in range(d):
                a0[k] = (a0[k] + t * a1[k]) - a2[k]
            _reset(R, a0, N, zp)
            for q in range(N):
                zp[q] = a0[q]
            for q in range(d - 1):
                Gw[r0 + q] = zp[ib[q]]
            Gw[r0 + d - 1] = t
            Gw[ct] = _guard(g, a0, N)
    return G, Gu, Gw, FL, PHI


@nb.njit(cache=True)
def shoot1(lam, W, Winv, A, U, V, dU, dV, w, con, n_periods, u, p, jac, dom):
    """:func:`shoot` for a model of one constraint, ``con`` = :attr:`LinearFlow.constraint64`
    (b, level, guard, R), on the section x_0 = b (the first coordinate of the flow's order)."""
    d = lam.shape[0]
    N = d // 2
    tab = np.empty((1, con.shape[0] + 1))
    tab[0, 0] = 0.0
    tab[0, 1:] = con
    idx = np.empty((1, d - 1), np.int64)           # section_index(N, 0)
    idx[0, 0] = N
    for q in range(1, N):
        idx[0, q] = q
        idx[0, N - 1 + q] = N + q
    return shoot(lam, W, Winv, A, np.empty((0, 0)), U, V, dU, dV, w, tab, idx,
                 np.zeros(p + 1, np.int64), n_periods, u, p, jac, dom)


@nb.njit(cache=True, inline="always")
def _reset(R, z, N, out):
    """out[N:2N] = R z[N:2N]: the constraint's reset (R row-major) of the velocities of z."""
    for a in range(N):
        s = 0.0
        for k in range(N):
            s += R[a * N + k] * z[N + k]
        out[N + a] = s


@nb.njit(cache=True, inline="always")
def _col(Phi, dzt, dzdt, a, col, d):
    """Entry a of column ``col`` of (Phi | dz/dtau | dz/dt)."""
    if col < d:
        return Phi[a, col]
    return dzt[a] if col == d else dzdt[a]


@nb.njit(cache=True, inline="always")
def _guard(g, z, N):
    """g . x of the state z: the guard's coordinate (x_k for the stop on mass k)."""
    s = 0.0
    for k in range(N):
        s += g[k] * z[k]
    return s


@nb.njit(cache=True)
def monodromy(Gu, p, d):
    """(DP_i for each impact, their product, ok): DP_i = dh/dy - dh/dt (dg/dt)^-1 dg/dy,
    eq. (30), from the blocks of G_u; ok is False where an impact velocity dg/dt is 0."""
    mats = np.empty((p, d, d))
    for i in range(p):
        r0, ct = i * d, p * d + i
        dgdt = Gu[ct, ct]
        if dgdt == 0.0:
            return mats, np.empty((d, d)), False
        for a in range(d):
            f = Gu[r0 + a, ct]
            for c in range(d):
                v = Gu[r0 + a, r0 + c]
                if p == 1 and a == c:
                    v += 1.0                       # G_u holds dh/dy minus y_{i+1}
                mats[i, a, c] = v - (f * Gu[ct, r0 + c]) / dgdt
    M = mats[0].copy()
    for i in range(1, p):
        M = mats[i] @ M
    return mats, M, True


def finder_constants(flow, F):
    """The constants array of :mod:`symvi.flow.compiled` at F.omega: the flow's
    omega-independent part (made once by :func:`symvi.flow.compiled.constants` and kept
    on the flow) with the omega-dependent entries set as ``constants`` sets them (a
    test asserts equality), ~2 us instead of ~70 us."""
    base = flow.__dict__.get("_finder_base")
    if base is None or len(base[4]) != len(flow.model.constraints):
        # (a flow copied for a model with other stops shares the modal data, not the table)
        base = flow.__dict__["_finder_base"] = _finder_base(flow) + (
            flow.constraint, flow.model.constraints)
    c, lmax, grow = base[0].copy(), base[1], base[2]
    if flow.model.constraints[1:] != base[4][1:]:
        # a copied flow (a new gap or r of another stop) shares the base: every row anew
        _fc.set_constraints(c, flow.n, _fc.table(flow))
    elif flow.constraint is not base[3]:
        _fc.set_constraint(c, flow)                # a copied flow (new stop) shares the base
    w = float(F.omega)
    n = flow.n
    U, V = F.U, F.V
    t_max = 2000 * math.pi / w
    c[_fc._OM], c[_fc._TMAX] = w, t_max
    _fc.set_guard_forcing(c, flow, U, V)
    c[_fc._LMAX] = max(lmax, w)
    c[_fc._GROW] = math.exp(grow * 4 * t_max)
    ou = _fc.offsets(n)[2]
    c[ou:ou + n], c[ou + n:ou + 2 * n] = U, V
    return c


def _finder_base(flow):
    """(constants at some omega, max |lambda|, max(0, max Re lambda)) of the flow."""
    lam = np.asarray(flow.lam, dtype=complex)
    w = max(0.5 * float(np.min(flow.omegas)), _OMEGA_MIN)    # below every natural frequency
    return _fc.constants(flow.model, w), max(abs(lam)), max(0.0, float(np.max(lam.real)))


class CompiledFinder:
    """The flow as :func:`symvi.orbits.periodic.admissible` uses it (``perm``,
    ``motion(F, z0, tau)``), its first-impact finder the compiled twin of
    :mod:`symvi.flow.compiled`; the constants are made at the first motion asked for
    (one forcing F per finder)."""

    def __init__(self, flow):
        self.perm, self.flow, self._c = flow.perm, flow, None

    def motion(self, F, z0, tau):
        return self.motion_from(F, Section.of(self.flow.model).point(z0, tau))

    def motion_from(self, F, y, k=0):
        """The flight from point y of constraint k's section."""
        if self._c is None:
            self._c = finder_constants(self.flow, F)
        return _CompiledMotion(self._c, y, k)


@dataclass(frozen=True)
class Contact(FirstImpact):
    """A :class:`FirstImpact` with the constraint met (0-based index)."""

    constraint: int = 0


class _CompiledMotion:
    def __init__(self, c, y, k=0):
        self.c, self.y, self.k = c, np.array(y, dtype=float), int(k)

    def first_impact(self, t_max=None):
        st, t, z, _, steps, g = _fc.first_impact_from(self.c, self.y, t_max, self.k)
        return Contact(_fc.STATUS_NAMES[st], t, z, steps, int(g))
