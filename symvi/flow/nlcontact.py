"""Elastic stops with nonlinear forces: each contact phase on the Taylor flow (issue 28).

The contact law is :mod:`symvi.flow.contact`'s: with the set S of elastic constraints in
contact (normal c_i, gap g_i, stiffness k_i, damping c_si)::

    M x'' + C_S x' + K_S x + f(x, v) - f_S = P sin(omega t + tau),
    K_S = K + sum_{i in S} k_i c_i c_i^T,   C_S = C + sum_{i in S} c_si c_i c_i^T,
    f_S = sum_{i in S} k_i g_i c_i,

f the model's smooth forces (:attr:`symvi.model.Model.nonlinear`).  The phase's vector field
is the Taylor flow's (:mod:`symvi.flow.taylor`) with the linear part (K_S, C_S) and the
forces' program with the constant -f_S_i appended to force i (one more constant and one
more sum in the postfix program of :func:`symvi.flow._program.program`): no code per
phase, the same kernels.

Events.  :class:`NonlinearPhase` has the interface the walk of :mod:`symvi.flow.contact`
reads of :class:`symvi.flow.contact.Phase` (``motion(omega, z0, tau)``, then
``first_event(G, level, start, t_max)`` and ``state(t)``), so :func:`symvi.flow.contact.walk`
runs free flights, contact phases, entries (h_i = 0, h_i' > 0), exits (h_i = 0, h_i' < 0)
and rigid impacts of a nonlinear model unchanged.  Each guard h = G . x - level (h_i
outside S, -h_i inside) is a row of :func:`symvi.flow.taylor._taylor_flight`'s constraints
(normal G, gap level, sign +1): over each step the guard is the solution's own polynomial
and its Bernstein hull bounds it, so no contact is stepped over.  An approach speed
h' <= GRAZING_SPEED_FACTOR sqrt(2 |h''| RTOL L) (L = max(1, |level|, |x|)) is a tangency,
as in the rigid run of :mod:`symvi.flow.nonlinear`: GRAZING, which the walk reads as
sticking when h'' > 0 there.

Orbits.  :class:`ContactView` shows one phase to the shooting system of
:mod:`symvi.orbits.periodic` as :class:`symvi.flow.nljet.FlowView` shows the free flight:
the linear part's geometry, each flight (z, Phi, dz/dtau, dz/dt) and each impact map's jet
(:func:`symvi.flow.nljet.map_jet`, an exit's guard -h) from the series of the phase's field
(:mod:`symvi.flow.jet_taylor`).  No jump at a switch: the elastic resets are the identity.
Series variables: those of :func:`symvi.flow.nljet.check_parameter`.  An elastic stop's
gap, stiffness or damping and an entry of M, K, C, P move the phase's field, K_S(p), C_S(p),
M(p), P(p) and f_S(p), each linear in p (:meth:`NonlinearPhase.rates`: -f_S is a parameter
slot of the forces' program, so its rate enters the series as a named force's does); a
gap moves the flights' ends too (the section x_a = g, the level of an entry's guard h and
of an exit's -h: :func:`symvi.flow.nljet.impact_series`).
"""
import functools
import math
import threading
from dataclasses import replace

import numpy as np

from ..errors import ParameterError
from ..numerics.tolerances import CONTACT_ULPS, GRAZING_SPEED_FACTOR
from ..numerics.tolerances import EPS64 as _EPS
from . import compiled as cf
from . import taylor
from ._events import GRAZING, NO_EVENT, NONFINITE, Hit
from ._program import OP_ADD, OP_VAR, program
from .linear import contact_matrices, contact_tangent
from .nljet import FlowView
from .nonlinear import RTOL, _rhs


class NonlinearPhase:
    """One contact phase S of a model with nonlinear forces (module docstring), in mass
    order: M, K_S, C_S, f_S, the forces' program with -f_S, and the Taylor tape."""

    def __init__(self, model, active):
        self.active = tuple(sorted(active))
        if any(model.constraints[i].kind != "elastic" for i in self.active):
            raise ParameterError("active", self.active, "indices of elastic constraints")
        n = self.n = model.n
        K, C, f = (np.array(a, dtype=float) if a is not None else np.zeros(n)
                   for a in contact_matrices(model, self.active))
        self.K, self.C, self.f = np.ascontiguousarray(K), np.ascontiguousarray(C), f
        self.P = np.ascontiguousarray(model.forcing, dtype=float)
        self.Minv = np.linalg.inv(np.asarray(model.mass, dtype=float))
        forces = model._nl
        names = [f"x{i + 1}" for i in range(n)] + [f"v{i + 1}" for i in range(n)]
        pnames = list(forces.names)
        ops, off, depth = program(forces.exprs(n), names + pnames)
        # the constant force f_S on the left-hand side: force i becomes f_i - f_S_i, -f_S_i
        # a slot of the program after the forces' parameters (a series flight moves it
        # with an elastic stop's gap or stiffness: :meth:`rates`), on every coordinate an
        # active normal touches (f_S_i may be 0 there: a stop at gap 0)
        touched = np.zeros(n, dtype=bool)
        for i in self.active:
            touched |= np.asarray(model.constraints[i].normal, dtype=float) != 0.0
        #: per force i, its -f_S slot among the program's parameters (-1: none)
        self.fslots = np.full(n, -1, dtype=np.int64)
        rows, offs, extra = [], [0], []
        for i in range(n):
            rows.extend(ops[off[i]:off[i + 1]])
            if touched[i]:
                self.fslots[i] = len(pnames) + len(extra)
                rows += [(OP_VAR, 2 * n + self.fslots[i]), (OP_ADD, 2.0)]
                extra.append(-f[i])
            offs.append(len(rows))
        self.ops = np.array(rows, dtype=np.float64).reshape(-1, 2)
        self.off = np.array(offs, dtype=np.int64)
        self._depth = max(depth, 2)
        self.tape = taylor.tape(self.ops, self.off, 2 * n)
        self.pars = np.array([forces.value(p) for p in pnames] + extra, dtype=float)
        #: the Model this phase is of (:meth:`rates` reads its contact law)
        self.source = model
        w2 = np.linalg.eigvals(self.Minv @ K).real
        self.omega_max = math.sqrt(max(float(w2.max()), 0.0))
        self._local = threading.local()
        #: the phase's matrices where the series flights of :mod:`symvi.flow.jet_taylor`
        #: read a flow's model (stiffness, damping, forcing, the forces' parameters)
        self.model = _PhaseMatrices(self.K, self.C, self.P, forces)

    def rates(self, tangent):
        """(tangent, dpars): how this phase's field moves along a
        :class:`symvi.model.parameters.Tangent` (its M, K, C, P, a stop's gap, stiffness
        or damping), as the series flights of :mod:`symvi.flow.jet_taylor` read it: the
        tangent with K_S's and C_S's rates (:func:`symvi.flow.linear.contact_tangent`) and
        the rate of each program parameter, -df_S_i in the -f_S slots."""
        dK, dC, df = contact_tangent(self.source, self.active, tangent)
        dpars = np.zeros(len(self.pars))
        for i, q in enumerate(self.fslots):   # df_S_i = 0 off the slots (c_i = 0 there)
            if q >= 0:
                dpars[q] = -df[i]
        return replace(tangent, dK=dK, dC=dC), dpars

    def hmax(self, omega, frac=taylor.STEP_CAP):
        """``frac`` of the shortest period (forcing, the phase's linear modes), as
        :meth:`symvi.flow.nonlinear.NonlinearFlow.hmax`."""
        return frac * 2.0 * math.pi / max(omega, self.omega_max, 1e-12)

    def rhs(self, omega, tau, t, z):
        """The vector field at (t, z), z = (x, v) in mass order."""
        return self.field(z, t, omega, tau)

    def system(self, omega, tau):
        """The kernels' system tuple (:meth:`symvi.flow.nonlinear.NonlinearFlow._system`'s
        layout) of this phase at omega, phase tau."""
        n = self.n
        u = np.empty(2 * n + len(self.pars))
        u[2 * n:] = self.pars
        return (self.Minv, self.K, self.C, self.P, self.ops, self.off, u,
                np.empty(self._depth + 1), np.array([float(omega)]), np.array([float(tau)]),
                np.empty(n))

    def work(self):
        """The Taylor kernels' scratch, one per phase and thread (a walk runs one flight at
        a time; a plane's threads may walk the same phase at once)."""
        w = getattr(self._local, "work", None)
        if w is None:
            w = self._local.work = taylor.work(*self.tape, 2 * self.n)
        return w

    def cap(self, omega):
        """The step bound: :data:`symvi.flow.taylor.STEP_CAP` of the shortest period
        (forcing and the phase's linear modes)."""
        return self.hmax(omega)

    def field(self, z, t, omega, tau):
        """z' = (v, M^-1 (P sin(omega t + tau) + f_S - C_S v - K_S x - f(x, v)))."""
        out = np.empty(2 * self.n)
        _rhs(self.system(omega, tau), float(t), np.asarray(z, dtype=float), out)
        return out

    def motion(self, omega, z0, tau):
        """The motion of this phase from state z0 (mass order) at phase tau."""
        return NonlinearMotion(self, float(omega), np.asarray(z0, dtype=float), float(tau))


class _PhaseMatrices:
    """What a series flight reads of a flow's model, for one phase: K_S as the stiffness,
    C_S as the damping, P, and the forces (whose program :class:`NonlinearPhase` holds, -f_S
    appended); how they move with a parameter is :meth:`NonlinearPhase.rates`."""

    def __init__(self, K, C, P, forces):
        self.stiffness, self.damping, self.forcing, self._nl = K, C, P, forces


@functools.lru_cache(maxsize=64)
def phase(model, active=()):
    """The :class:`NonlinearPhase` of ``model`` with the elastic constraints ``active``."""
    return NonlinearPhase(model, tuple(sorted(active)))


class NonlinearMotion:
    """One phase's motion from z0 at phase tau on the Taylor flow: :meth:`first_event` as
    :meth:`symvi.flow.contact.PhaseMotion.first_event`, :meth:`state` the state at a
    time (the event's own, or integrated)."""

    def __init__(self, ph, omega, z0, tau):
        self.phase, self.omega, self.z0, self.tau = ph, omega, z0.copy(), tau
        self._end = None                  # (t, z) of the last event found

    def first_event(self, G, level, start=None, t_max=None):
        """First t > 0 with h_g = G[g] . x - level[g] = 0 for some guard g (h < 0 before),
        from a start on guard ``start`` (h = 0, leaving: h' < 0) or off every guard (None);
        a :class:`symvi.flow.contact.Hit`.  A start at or past another guard (a corner), or
        on ``start`` not leaving it, is a GRAZING at t = 0."""
        ph, om = self.phase, self.omega
        n = ph.n
        if t_max is None:
            t_max = 2000 * math.pi / om
        G = np.ascontiguousarray(G, dtype=float)
        level = np.asarray(level, dtype=float)
        z = self.z0.copy()
        hh = G @ z[:n] - level
        hd = G @ z[n:]
        eps_h = CONTACT_ULPS * _EPS * (np.abs(G) @ np.abs(z[:n]) + np.abs(level) + 1.0)
        for g in range(len(G)):
            if (not hd[g] < 0) if g == start else hh[g] >= -eps_h[g]:
                return Hit(GRAZING, 0.0, g, self._h2(G[g], z, 0.0), 0)
        cons = np.zeros((len(G), 3))
        cons[:, 0], cons[:, 1], cons[:, 2] = -1.0, level, 1.0
        st, te, c, vm, acc, steps = taylor._taylor_flight(
            ph.system(om, self.tau), ph.work(), cons, G, z,
            -1 if start is None else int(start), float(t_max), ph.cap(om))
        if st != cf.IMPACT:                 # c = -2: the series stopped being finite
            return Hit(NONFINITE if c == -2 else NO_EVENT, float(te), 0, 0.0, int(steps))
        self._end = (float(te), z)
        L = max(1.0, abs(level[c]), float(np.abs(z[:n]).max()))
        if vm <= GRAZING_SPEED_FACTOR * math.sqrt(2.0 * abs(acc) * RTOL * L):
            return Hit(GRAZING, float(te), int(c), float(acc), int(steps))
        return Hit("event", float(te), int(c), float(acc), int(steps))

    def _h2(self, g, z, t):
        """h'' = G . a of one guard at state z, time t."""
        return float(g @ self.phase.field(z, t, self.omega, self.tau)[self.phase.n:])

    def state(self, t):
        """z(t), mass order: the last event's state, or integrated from z0 without events."""
        if self._end is not None and t == self._end[0]:
            return self._end[1].copy()
        ph = self.phase
        return taylor._taylor_integrate(ph.system(self.omega, self.tau), ph.work(),
                                        self.z0.copy(), float(t), ph.cap(self.omega))


class ContactView(FlowView):
    """One contact phase S of a nonlinear model as the shooting system of
    :mod:`symvi.orbits.periodic` reads a flow (:class:`symvi.flow.nljet.FlowView`, whose
    geometry, forcing and flights it inherits): the geometry (guards, resets, levels,
    frames) of the linear part's phase (:meth:`symvi.flow.linear.LinearFlow.contact`),
    every flight the series of :func:`symvi.flow.nljet.flight_first` on the phase's field
    (:class:`NonlinearPhase`: K_S, C_S, the forces less f_S), so the variational
    equations are the phase's."""

    GEOMETRY = FlowView.GEOMETRY | {"active"}
    offset = None
    free = False

    def __init__(self, model, active=()):
        from .compiled import section_index
        from .linear import LinearFlow
        self.model = model
        self.lin = LinearFlow.contact(model.linear_part, active)
        self.phase = phase(model, active)
        dim = 2 * model.n
        #: z_mass = S z_flow and its inverse (a permutation, or T^-1 on x and on v)
        self.S = np.array([self.lin.to_mass(e) for e in np.eye(dim)]).T
        self.Sinv = np.array([self.lin.to_flow(e) for e in np.eye(dim)]).T
        #: what the impact map's series (:func:`symvi.flow.nljet.map_jet`) read: the
        #: phase's field (``nl``), and per constraint (position, gap, level, guard, reset)
        #: in flow order with the guard of each constraint in contact turned to its exit's,
        #: -h (a flight of this phase ends on an exit of those: approached, -h' > 0)
        self.nl = self.phase
        self.rows = [np.asarray(r, dtype=float).copy() for r in self.lin.constraint_rows()]
        n = model.n
        for i in self.phase.active:
            self.rows[i][2:3 + n] *= -1.0
        self.exits = frozenset(self.phase.active)
        self.positions = tuple(int(r[0]) for r in self.rows)
        self.frames = tuple(section_index(n, q) for q in self.positions)

    @classmethod
    def of(cls, model, active=()):
        """The view of ``model``'s phase ``active``, built once (:func:`view`)."""
        return view(model, active)


@functools.lru_cache(maxsize=64)
def view(model, active=()):
    """The :class:`ContactView` of ``model``'s phase ``active`` (cached)."""
    return ContactView(model, tuple(sorted(active)))
