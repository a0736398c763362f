"""Orbits with p impacts in n forcing periods (n-p orbits) of any model, by multiple shooting.

Unknowns u = (y_0, ..., y_{p-1}, t_1, ..., t_p): the section points just after
each impact (layout of :class:`symvi.maps.Section`, tau not reduced mod 2 pi)
and the flight times.  Through the exact flow z(t; y) of :mod:`symvi.flow.linear`
(eq. (19) generalised), with k the stop's mass::

    g_i = x_k(t_{i+1}; y_i) - b = 0                        impact condition, eq. (26)
    h_i = R(z(t_{i+1}; y_i)) - y_{i+1} = 0                 impact law, eq. (2);
          y_p = y_0 + 2 pi n e_tau                         n forcing periods in all

p (2N + 1) equations in as many unknowns.  With the times as unknowns the
system stays regular where an orbit grazes (there the impact map P itself is
singular, eq. (30)), so a branch can be followed up to and through grazing and
the grazing point located as a regular zero.  Eliminating each time gives the
Jacobian of one impact map, DP_i = dh/dy - dh/dt (dg/dt)^-1 dg/dy (the implicit
function theorem of eq. (30)); their product is the monodromy matrix whose
eigenvalues are the multipliers.  Second and third derivatives come from the
generated jets at each impact, composed by the chain rule (:func:`compose`).

G, its Jacobian and dG/domega are evaluated by a compiled float64 kernel
(:mod:`symvi.orbits._shooting`), the admissibility of each flight by the compiled
first-impact finder of :mod:`symvi.flow.compiled`; ``Problem.compiled = False``
selects the numpy reference of both (the same results to rounding).
"""
import math
from dataclasses import dataclass, field

import numpy as np

from ..codegen.layout import phase_tangent, reset_derivative, tangent_data
from ..errors import ConvergenceError, ParameterError, SingularCaseError
from ..flow.compiled import STATUS_NAMES
from ..flow.compiled import section_index
from ..flow.compiled import table as _table
from ..flow.compiled import step as compiled_step
from ..flow.linear import IMPACT, LinearFlow
from ..maps.section import Section
from ..model import Signature
from ..model.parameters import NamedParameter, StopParameter
#: Newton: relative size of the last correction at convergence (and NEWTON_MAXIT below)
from ..numerics.tolerances import NEWTON_TOL
from . import _shooting
from .admissibility import check_flight, neutral, stable_of

#: Newton: iteration limit
NEWTON_MAXIT = 30
#: no free modes: the shooting kernel's empty NIL
_NO_NIL = np.empty((0, 0))
#: relative distance of y_{i+p/2} from S y_i below which an orbit is called symmetric
SYMMETRY_TOL = 1e-7


# --------------------------------------------------------------------------- the system
class Problem:
    """G(u; lam) = 0 of the n-p orbits of ``model``, continued in ``param`` (or none).

    ``signature`` (a :class:`symvi.model.Signature`, default (0,) * p) names the
    constraint each impact hits; every impact reads its guard and reset from the flow
    (:meth:`symvi.flow.linear.LinearFlow._constrain`), so with one stop all are the same.

    ``param`` is a name or a :class:`symvi.model.parameters.Parameter`, parsed here once
    (:attr:`parameter`; :attr:`param` keeps its name); ``omega`` is the forcing frequency
    when it is not omega.  ``compiled``
    (default) evaluates G and its derivatives by the numba kernel of
    :mod:`symvi.orbits._shooting`; False uses the numpy reference (same results to
    rounding).
    """

    compiled = True

    def __init__(self, model, n, p, omega=None, param=None, signature=None):
        _check_np(n, p)
        if not model.elastic:                # contact phases: LinearFlow.contact
            model.require_rigid_stops()
        #: smooth nonlinear forces: the flights are the series of symvi.flow.nljet (its
        #: FlowView), evaluated by the numpy reference
        self.nonlinear = model.nonlinear is not None
        if self.nonlinear:
            self.compiled = False
        # the lens on (model, omega), parsed once: a bad name raises ParameterError here
        self.parameter = None if param is None else model.parameter(param)
        self.param = None if param is None else self.parameter.name
        self.model, self.n_periods, self.p = model, int(n), int(p)
        # which constraint each impact hits: point i lies on the section of sig[i]
        sig = Signature.single(p) if signature is None else (
            signature if isinstance(signature, Signature) else Signature(signature))
        if sig.p != self.p:
            raise ParameterError("signature", sig.hits, f"{self.p} constraint indices (p = {self.p})")
        self.signature = sig.check(model)
        #: with elastic stops: the constraints in contact during each flight; each flight
        #: is the exact flow of its phase (:meth:`LinearFlow.contact`) and the numpy
        #: reference evaluates the system (the compiled kernel takes one flow)
        self.elastic = model.elastic
        if self.nonlinear and self.parameter is not None:
            from ..flow.nljet import check_parameter      # the one owner of what they take
            check_parameter(model, self.parameter)
        self.phases = sig.phases(model) if self.elastic else None
        self.kinds = sig.kinds(model) if self.elastic else None
        if self.elastic:
            self.compiled = False
        self.sig = np.array(sig.hits, dtype=np.int64)
        self._sig_ring = np.append(self.sig, self.sig[0])    # the kernel's: sig[p] = sig[0]
        self.omega = omega
        self._flow = None
        self._last = None
        self._checked = None                 # the last omega check_omega accepted
        N = model.n
        self.N, self.d = N, 2 * N
        # per constraint: its position in the flow's order and the flow-order index of each
        # section coordinate (y[:2N-1] = z0[idx], v_k+ first; Section.of for the first)
        self.sec, self.positions, self.frames, self.sections = _layout(model)
        self.idx = self.frames[0]
        #: several constraints: the flights watch every guard (the compiled finder)
        self.several = len(model.constraints) > 1 or self.elastic
        #: the mirror of each constraint under x -> -x, t -> t + n pi / omega, when the
        #: model has that symmetry and an n-p orbit can have it (p even, n odd)
        self.mirror = (_mirror(model) if self.p % 2 == 0 and self.n_periods % 2 == 1
                       else None)

    @property
    def size(self):
        return self.p * (self.d + 1)

    def at(self, lam, check=True):
        """(model, flow, forcing) at parameter value lam; ``check`` validates omega
        (ParameterError / SingularCaseError at a forcing resonance)."""
        par = self.parameter
        if par is None:
            model, omega = self.model, self.omega
        elif par.is_forcing_frequency:
            model, omega = self.model, lam
        else:
            model, omega = par.apply(self.model, float(lam)), self.omega
        if model is self.model:
            flow = self._flow
            if flow is None:
                flow = self._flow = free_flow(model)
        else:
            flow = free_flow(model)
        if self.elastic and check and not self.nonlinear:
            for S in set(self.phases):             # a forcing resonance of a contact phase
                LinearFlow.contact(model, S).check_omega(omega, warn=False)
        if not check:
            omega = float(omega)
        elif model is self.model and omega is not None and omega == self._checked:
            omega = float(omega)                   # validated before (a pure function)
        else:
            omega = flow.check_omega(omega, warn=False)
            if model is self.model:
                self._checked = omega
        return model, flow, flow.forcing(omega)

    def split(self, u):
        d, p = self.d, self.p
        return u[:p * d].reshape(p, d), u[p * d:]

    def flights(self, u, lam, check=True):
        """Per impact: (z0, tau, z(t), Phi, dz/dtau, dz/dt) and the (model, flow, forcing)."""
        u = np.ascontiguousarray(u, dtype=float)
        key = (u.tobytes(), lam)
        if self._last is None or self._last[0] != key:    # a point is asked for twice
            if self.compiled:
                self._shoot(u, lam, check, False, False)
            else:
                self._flights_numpy(u, lam, check, key)
        fl, ctx = self._last[1][:2]
        if not isinstance(fl, list):                  # compiled: per-impact views, once
            fl = [_shooting.flight_views(*fl, i) for i in range(self.p)]
            self._last = (key, (fl, ctx) + self._last[1][2:])
        return fl, ctx

    def _flights_numpy(self, u, lam, check, key):
        model, flow, F = self.at(lam, check)
        Y, T = self.split(u)
        out = []
        rows = _table(flow)
        phases = self.phase_flows(model, flow, F)
        for i in range(self.p):
            k = self.sig[i]
            z0 = np.empty(self.d)
            z0[self.positions[k]] = rows[k][1]
            z0[self.frames[k]] = Y[i][:-1]
            tau = Y[i][-1]
            fi, Fi = phases[i]
            if self.nonlinear and self._moves_field(self.parameter, i):
                # one series flight gives dz/dlam too (:meth:`_dparam_series` reads it;
                # a rigid stop's gap or restitution moves no flight, only its ends)
                *f, dzp = fi.flight(Fi, z0, tau, T[i], param=self.parameter)
                out.append((z0, tau) + tuple(f) + (dzp,))
            else:
                out.append((z0, tau) + fi.flight(Fi, z0, tau, T[i]))
        self._last = (key, (out, (model, flow, F)))

    def _shoot(self, u, lam, check, jac, dom):
        """The compiled kernel at (u, lam): (G, Gu, dG/domega, context); the flights cached."""
        model, flow, F = ctx = self.at(lam, check)
        lam_, W, Winv, A, NIL = flow.modal_nil64
        G, Gu, Gw, *fl = _shooting.shoot(lam_, W, Winv, A, NIL if flow.free else _NO_NIL,
                                         F.U, F.V, F.dU, F.dV, F.omega,
                                         _table(flow), self.frames, self._sig_ring,
                                         self.n_periods,
                                         u, self.p, bool(jac), bool(dom))
        self._last = ((u.tobytes(), lam), (tuple(fl), ctx, G))
        return G, Gu, Gw, ctx

    def evaluate(self, u, lam, jac=True, dparam=False, check=True):
        """(G, dG/du, dG/dlam) at (u, lam); the derivatives are None when not asked for.

        Compiled (:mod:`symvi.orbits._shooting`) unless ``compiled`` is False; the numpy
        reference is :meth:`_evaluate_numpy`."""
        if not self.compiled:
            return self._evaluate_numpy(u, lam, jac, dparam, check)
        u = np.ascontiguousarray(u, dtype=float)
        if not (jac or dparam):                  # the residual at the last point: kept
            last = self._last
            if last is not None and len(last[1]) > 2 and last[0] == (u.tobytes(), lam):
                return last[1][2].copy(), None, None
        dom = dparam and self.parameter is not None and self.parameter.is_forcing_frequency
        G, Gu, Gl, (model, flow, F) = self._shoot(u, lam, check, jac, dom)
        if dparam and not dom:
            fl = self.flights(u, lam, check=False)[0]
            Gl = self._dparam(fl, model, flow, F, self.split(u)[1], self.parameter)
        return G, Gu if jac else None, Gl if dparam else None

    def _evaluate_numpy(self, u, lam, jac=True, dparam=False, check=True):
        """The reference of :meth:`evaluate`: the same system through :meth:`flights` and numpy."""
        fl, (model, flow, F) = self.flights(u, lam, check)
        d, p, w = self.d, self.p, F.omega
        Y, T = self.split(u)
        m = self.size
        G = np.empty(m)
        ends = self._ends(flow)
        Gu = np.zeros((m, m)) if jac else None
        for i, (z0, tau, z, Phi, dzt, dzdt, *_) in enumerate(fl):
            j = (i + 1) % p
            E, g, level = ends[i]
            target = Y[j].copy()
            if j == 0:
                target[-1] += 2 * math.pi * self.n_periods
            G[i * d:i * d + d - 1] = E @ z - target[:-1]
            G[i * d + d - 1] = tau + w * T[i] - target[-1]
            G[p * d + i] = g @ z[:self.N] - level
            if jac:
                dzdy = np.empty((d, d))
                dzdy[:, :d - 1] = Phi[:, self.frames[self.sig[i]]]
                dzdy[:, d - 1] = dzt
                r0 = slice(i * d, i * d + d)
                Gu[r0.start:r0.start + d - 1, i * d:i * d + d] = E @ dzdy
                Gu[r0.start + d - 1, i * d + d - 1] = 1.0
                Gu[r0, j * d:j * d + d] -= np.eye(d)
                Gu[r0.start:r0.start + d - 1, p * d + i] = E @ dzdt
                Gu[r0.start + d - 1, p * d + i] = w
                Gu[p * d + i, i * d:i * d + d] = g @ dzdy[:self.N]
                Gu[p * d + i, p * d + i] = g @ dzdt[:self.N]
        Gl = self._dparam(fl, model, flow, F, T, self.parameter) if dparam else None
        return G, Gu, Gl

    def _ends(self, flow):
        """Per flight i: (E, g, level) of the constraint it ends on, sig[i + 1] (the rows of
        :meth:`LinearFlow.constraint_rows`): the section point after the impact is E z
        (:meth:`_reset_rows`), the impact condition g . x - level = 0."""
        N, rows = self.N, _table(flow)
        hit = self.__dict__.get("_ends_of")
        if hit is not None and hit[0] is rows and hit[1] is flow.reset:
            return hit[2]
        out = []
        for i in range(self.p):
            k = int(self.sig[(i + 1) % self.p])
            row = rows[k]
            R = flow.reset if k == 0 else row[3 + N:].reshape(N, N)
            out.append((self._reset_rows(R, k=k), flow.guard if k == 0 else row[3:3 + N],
                        flow.level if k == 0 else row[2]))
        self._ends_of = (rows, flow.reset, out)      # one flow's, kept for the next ask
        return out

    def approach_speeds(self, fl, flow):
        """The approach speed guard . v- at the end of each flight (``fl``: the flights of
        :meth:`flights`) towards the constraint it ends on (v_k- for a stop on mass k):
        > 0 on the physical branch, -> 0 at a grazing impact."""
        if not self.several:
            return tuple(float(flow.approach(f[2])) for f in fl)
        ends, N = self._ends(flow), self.N
        speeds = [float(ends[i][1] @ f[2][N:]) for i, f in enumerate(fl)]
        if self.elastic:                   # an exit leaves its stop: -h' > 0 there
            kinds = self.kinds
            speeds = [-v if kinds[(i + 1) % self.p] == "exit" else v
                      for i, v in enumerate(speeds)]
        return tuple(speeds)

    def half(self, u, mats, tol=None):
        """H = S DP_{p/2-1} ... DP_0 of a symmetric orbit (``mats`` the DP_i of
        :meth:`monodromy`), else None.  S is the mirror x -> -x on the section (every
        coordinate but tau changes sign; a constraint and its mirror share the section's
        frame) and the orbit is symmetric when y_{i+p/2} = S y_i with tau advanced by n pi
        and the impact i + p/2 on the mirror of impact i's stop.  Then DP_{i+p/2} =
        S DP_i S, so the monodromy is H^2: a multiplier -1 of H is the +1 of a
        symmetry-breaking pitchfork, +1 of H a fold of symmetric orbits."""
        if self.mirror is None:
            return None
        h, d = self.p // 2, self.d
        Y = self.split(u)[0]
        for i in range(h):
            if self.sig[i + h] != self.mirror[self.sig[i]]:
                return None
            a, b = Y[i], Y[i + h]
            scale = (SYMMETRY_TOL if tol is None else tol) * (1.0 + float(np.max(np.abs(a))))
            if (np.max(np.abs(a[:-1] + b[:-1])) > scale or
                    abs(b[-1] - a[-1] - math.pi * self.n_periods) > scale):
                return None
        H = mats[0]
        for D in mats[1:h]:
            H = D @ H
        S = -np.ones(d)
        S[-1] = 1.0
        return S[:, None] * H

    def _reset_rows(self, R, one=1.0, k=0):
        """E ((2N - 1) x 2N): the section point (without tau) on constraint k's section
        after the impact in state z is E z, with the constraint's reset R (flow order) in
        the velocity rows (v_k+ = -r v_k- for the stop) and ``one`` on the positions."""
        N, d = self.N, self.d
        B = np.zeros((d, d))
        for q in range(N):
            B[q, q] = one
        B[N:, N:] = R
        return B[self.frames[k]]

    def derivative(self, u, lam, name):
        """dG/d(name) at (u, lam), fixed u, for any named parameter or omega (not only
        the continued one): a two-parameter curve needs both.  ``name``: a name or a
        :class:`symvi.model.parameters.Parameter`."""
        name = self.model.parameter(name)
        if self.compiled and name.is_forcing_frequency:
            u = np.ascontiguousarray(u, dtype=float)
            return self._shoot(u, lam, False, False, True)[2]
        fl, (model, flow, F) = self.flights(u, lam, check=False)
        return self._dparam(fl, model, flow, F, self.split(u)[1], name)

    def phase_flows(self, model, flow, F):
        """Per flight i: (flow, forcing) of its phase, the free flow's for rigid stops;
        with elastic stops :meth:`LinearFlow.contact` of the constraints in contact."""
        if not self.elastic:
            return [(flow, F)] * self.p
        key = (model, F.omega)
        hit = self.__dict__.get("_phase_flows")
        if hit is None or hit[0] != key:
            fs = {S: contact_flow(model, S) for S in set(self.phases)}
            fs = {S: (f, f.forcing(F.omega)) for S, f in fs.items()}
            hit = self._phase_flows = (key, [fs[S] for S in self.phases])
        return hit[1]

    def _dparam(self, fl, model, flow, F, T, name):
        """dG/dname at fixed u, exact (omega: dU, dV; any other: its tangent); ``name`` a
        :class:`symvi.model.parameters.Parameter` (or a name, parsed here).  A contact
        phase's flow moves with its constraints' stiffness and damping (K_S, C_S) and its
        offset zs = K_S^-1 f_S with their gaps too (:func:`phase_tangent`)."""
        name = self.model.parameter(name)
        if self.nonlinear:
            return self._dparam_series(fl, model, flow, F, T, name)
        d, p, bk, N = self.d, self.p, flow.bk, self.N
        out = np.zeros(self.size)
        ends = self._ends(flow)
        phases = self.phase_flows(model, flow, F)
        if name.is_forcing_frequency:
            for i, (z0, tau, z, Phi, dzt, dzdt) in enumerate(fl):
                E, g, _ = ends[i]
                F = phases[i][1]
                ph = tau + F.omega * T[i]
                dz = F.zp_omega(ph, bk) + T[i] * F.zp_phase(ph, bk) - Phi @ F.zp_omega(tau, bk)
                out[i * d:i * d + d - 1] = E @ dz
                out[i * d + d - 1] = T[i]
                out[p * d + i] = g @ dz[:N]
            return out
        tan = name.tangent(model)
        ks = tan.stop                            # the stop whose gap or restitution moves
        # the reset of each stop moves with its restitution (dR = -dr Q) and, for a rigid
        # impulse along M^-1 c, with the masses (dQ from dq = -M^-1 dM q): dE_k z
        dE = [self._dreset_rows(flow, model, k, tan) for k in range(len(model.constraints))]
        for i, (z0, tau, z, Phi, dzt, dzdt) in enumerate(fl):
            E, g, _ = ends[i]
            kb = self.sig[(i + 1) % p]
            start, end = self.sig[i] == ks, kb == ks
            fi, F = phases[i]
            tan_i, dzs = (tan, None) if fi.offset is None else phase_tangent(fi, tan)
            pE0, _, pU, pV, pr, pb = tangent_data(fi, F, T[i], tan_i)
            dF = type(F)(F.omega, pU, pV, None, None)
            ph = tau + F.omega * T[i]
            dz0 = np.zeros(d)
            dz0[self.positions[self.sig[i]]] = pb if start else 0.0
            w0 = z0 if fi.offset is None else z0 - fi.offset
            dz = pE0 @ (w0 - F.zp(tau, bk)) + Phi @ (dz0 - dF.zp(tau, bk)) + dF.zp(ph, bk)
            if dzs is not None:                  # z = Phi (z0 - zp - zs) + zp + zs
                dz = dz + dzs - Phi @ dzs
            out[i * d:i * d + d - 1] = E @ dz
            if dE[kb] is not None:
                out[i * d:i * d + d - 1] += dE[kb] @ z
            out[p * d + i] = g @ dz[:N] - (model.constraints[ks].sign * pb if end else 0.0)
        return out

    def _moves_field(self, par, i):
        """Whether ``par`` moves the field of flight i (a nonlinear model): all but None and
        a stop's gap or restitution, which move the flights' ends only, except an elastic
        stop's numbers in a flight of a phase with that stop in contact (K_S, C_S, f_S)."""
        if par is None:
            return False
        if not isinstance(par, StopParameter):
            return True
        return (par.stop_of(self.model).kind == "elastic" and self.elastic
                and par.i in self.phases[i])

    def _dparam_series(self, fl, model, flow, F, T, name):
        """:meth:`_dparam` of a nonlinear model: dz/dp of each flight from its first-order
        series in its phase (:meth:`symvi.flow.nljet.FlowView.flight`); a stop's gap or
        restitution moves the flights' ends (:meth:`_dstop`), an elastic stop's numbers
        the field of the phases in contact with it too (K_S, C_S, f_S); an entry of M
        moves the reset of an impulse along M^-1 c too (dE z, as on the linear path)."""
        from ..flow.nljet import check_parameter
        check_parameter(model, name)
        stop = isinstance(name, StopParameter)
        out = (self._dstop(fl, model, flow, name.tangent(model)) if stop
               else np.zeros(self.size))
        d, p, N = self.d, self.p, self.N
        ends = self._ends(flow)
        mine = self.parameter is not None and name.name == self.parameter.name
        dE = [None] * len(model.constraints)
        if not (stop or name.is_forcing_frequency or isinstance(name, NamedParameter)):
            tan = name.tangent(model)
            dE = [self._dreset_rows(flow.lin, model, k, tan)
                  for k in range(len(model.constraints))]
        phases = self.phase_flows(model, flow, F)       # each flight in its phase's field
        for i, (z0, tau, z, *rest) in enumerate(fl):
            if not self._moves_field(name, i):
                continue
            E, g, _ = ends[i]
            fi, Fi = phases[i]
            dz = rest[3] if mine and len(rest) > 3 else \
                fi.flight(Fi, z0, tau, T[i], param=name)[4]
            out[i * d:i * d + d - 1] += E @ dz
            kb = self.sig[(i + 1) % p]
            if dE[kb] is not None:
                out[i * d:i * d + d - 1] += dE[kb] @ z
            out[i * d + d - 1] = T[i] if name.is_forcing_frequency else 0.0
            out[p * d + i] += g @ dz[:N]
        return out

    def _dstop(self, fl, model, flow, tan):
        """dG/d(gap or restitution of stop ``tan.stop``) with the flights' own Phi: a flight
        starting on that stop starts from the moved section (dz0 = db e_k, dz = Phi dz0),
        one ending on it meets the moved level (-sign db) and takes the moved reset
        (dE z, dE = -dr Q): the linear path's terms (:meth:`_dparam`) with the flight's
        state transition matrix in place of e^{At}."""
        d, p, N = self.d, self.p, self.N
        out = np.zeros(self.size)
        ends, ks = self._ends(flow), tan.stop
        # the resets' derivatives in the linear part's frames, where FlowView reads them
        dE = [self._dreset_rows(flow.lin, model, k, tan) for k in range(len(model.constraints))]
        for i, (z0, tau, z, Phi, *_) in enumerate(fl):
            E, g, _ = ends[i]
            kb = self.sig[(i + 1) % p]
            dz0 = np.zeros(d)
            if self.sig[i] == ks:
                dz0[self.positions[ks]] = tan.db
            dz = Phi @ dz0
            out[i * d:i * d + d - 1] = E @ dz
            if dE[kb] is not None:
                out[i * d:i * d + d - 1] += dE[kb] @ z
            out[p * d + i] = g @ dz[:N] - (model.constraints[ks].sign * tan.db
                                           if kb == ks else 0.0)
        return out

    def _dreset_rows(self, flow, model, k, tan):
        """The rows of :meth:`_reset_rows` for dR_k/dparam of constraint k (flow order), or
        None where it is zero: its restitution moves it if the tangent's stop is k, the
        masses if its impulse is along M^-1 c (:func:`symvi.codegen.layout.reset_derivative`)."""
        con = model.constraints[k]
        if con.kind == "elastic":                  # no jump: its reset is the identity
            return None
        dr = tan.dr if tan.stop == k else 0.0
        if not dr and not (con.impulse is None and np.any(np.asarray(tan.dM) != 0)):
            return None
        return self._reset_rows(reset_derivative(flow, con, dr, tan.dM), one=0.0, k=k)

    def monodromy(self, u, Gu):
        """The map Jacobians DP_i (eq. (30): the time eliminated) and their product."""
        if self.compiled:
            mats, M, ok = _shooting.monodromy(np.ascontiguousarray(Gu, dtype=float), self.p,
                                              self.d)
            if not ok:
                raise _no_map_jacobian()
            return list(mats), M
        d, p = self.d, self.p
        mats = []
        for i in range(p):
            r0, c0, ct = i * d, i * d, p * d + i
            dhdy = Gu[r0:r0 + d, c0:c0 + d] + (np.eye(d) if p == 1 else 0)  # minus y_{i+1}
            dhdt = Gu[r0:r0 + d, ct]
            dgdy, dgdt = Gu[ct, c0:c0 + d], Gu[ct, ct]
            if dgdt == 0:
                raise _no_map_jacobian()
            mats.append(dhdy - np.outer(dhdt, dgdy) / dgdt)
        M = mats[0]
        for D in mats[1:]:
            M = D @ M
        return mats, M


def _layout(model):
    """(section, positions, frames, sections) of a model's constraints (see
    :class:`Problem`): they depend on the normals alone, so a curve that builds a problem
    per corrector step in a gap or a matrix entry computes them once."""
    key = (model.n, tuple(c.normal for c in model.constraints))
    hit = _LAYOUTS.get(key)
    if hit is None:
        N = model.n
        sec = Section.of(model)
        perm = sec.perm
        flow = LinearFlow.free(model.linear_part)
        positions = tuple(flow.position(c) for c in model.constraints)
        frames = np.array([section_index(N, q) for q in positions])
        sections = tuple(Section(N, (perm[q],) + tuple(perm[i] for i in range(N) if i != q),
                                 sec.labels) for q in positions)
        if len(_LAYOUTS) > 256:
            _LAYOUTS.clear()
        hit = _LAYOUTS[key] = (sec, positions, frames, sections)
    return hit


_LAYOUTS = {}


def _mirror(model):
    """σ with constraint σ[k] the mirror of constraint k under x -> -x (the same normal and
    law, the other side, the gap negated), or None when some constraint has none: then
    the model has no symmetry x -> -x, t -> t + pi / omega (M, C, K are linear and a
    harmonic forcing changes sign over half a period: the stops decide)."""
    cs = model.constraints
    out = []
    for c in cs:
        match = [j for j, o in enumerate(cs) if o.normal == c.normal and o.side != c.side
                 and o.restitution == c.restitution and o.impulse == c.impulse
                 and o.stiffness == c.stiffness and o.damping == c.damping
                 and o.gap == -c.gap]
        if not match:
            return None
        out.append(match[0])
    return tuple(out)


def _no_map_jacobian():
    return SingularCaseError("grazing", "the impact velocity is zero: the impact map's "
                             "Jacobian (eq. (30)) does not exist")


def _check_np(n, p):
    for name, v in (("n", n), ("p", p)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 1 <= v <= 64:
            raise ParameterError(name, v, "an integer from 1 to 64")


def newton(problem, u, lam, *, tol=NEWTON_TOL, maxit=NEWTON_MAXIT):
    """Solve G(u; lam) = 0 from u; the converged u, or ConvergenceError with the residual."""
    u = np.array(u, dtype=float)
    best = math.inf
    problem.at(lam)                      # validates the parameters once
    for _ in range(maxit):
        G, Gu, _ = problem.evaluate(u, lam, check=False)
        res = float(np.max(np.abs(G)))
        best = min(best, res)
        if not np.all(np.isfinite(Gu)):
            break
        try:
            du = np.linalg.solve(Gu, -G)
        except np.linalg.LinAlgError:
            raise ConvergenceError(f"the shooting Jacobian is singular at residual {res:.3g} "
                                   "(a fold or a non-isolated orbit)", res) from None
        # damp steps that would make a flight time non-positive
        T = problem.split(u)[1]
        dT = problem.split(du)[1]
        a = 1.0
        while np.any(T + a * dT <= 0) and a > 1e-3:
            a /= 2
        u = u + a * du
        if a == 1.0 and np.max(np.abs(du)) <= tol * (1 + np.max(np.abs(u))):
            G = problem.evaluate(u, lam, jac=False, check=False)[0]
            res = float(np.max(np.abs(G)))
            if res <= 1e3 * tol * (1 + np.max(np.abs(u))):
                return u
            best = min(best, res)
    raise ConvergenceError(f"Newton did not converge in {maxit} iterations: the smallest "
                           f"residual |G| reached was {best:.3g}", best)


# --------------------------------------------------------------------------- the orbit
@dataclass(frozen=True)
class PeriodicOrbit:
    """An n-p orbit: p impacts in n forcing periods.

    ``points[i]`` is the section point just after impact i (tau in [0, 2 pi)),
    ``times[i]`` the flight from it to the next impact, ``impact_velocities[i]``
    the stop mass's velocity just before that impact (> 0 on the physical branch).
    """

    model: object = field(repr=False)
    omega: float
    n: int
    p: int
    points: tuple
    times: tuple
    impact_velocities: tuple
    names: tuple
    multipliers: tuple
    stable: bool
    admissible: bool
    reason: str
    residual: float
    u: np.ndarray = field(repr=False, default=None)
    #: the constraint of each impact: point i lies on the section of signature[i]
    signature: tuple = None
    #: the names of each point's coordinates (its constraint's section)
    point_names: tuple = None
    #: True / False: the orbit is / is not mirror-symmetric (:meth:`Problem.half`); None:
    #: the model or the orbit's n-p has no such symmetry
    symmetric: bool = None
    #: the multipliers of the half map H (H^2 is the monodromy) of a symmetric orbit
    half_multipliers: tuple = None
    #: the elastic constraints in contact during flight 0 (:class:`symvi.model.Signature`)
    contact: tuple = ()

    @property
    def y(self):
        return self.points[0]

    @property
    def itinerary(self):
        """The orbit's :class:`symvi.model.Signature`: its events and what is in contact."""
        return Signature(self.signature if self.signature is not None else (0,) * self.p,
                         self.contact)

    @property
    def neutral(self):
        """A conservative model's orbit with every multiplier on the unit circle
        (:func:`symvi.orbits.admissibility.neutral`)."""
        return neutral(self.multipliers, self.model)

    @property
    def signature_names(self):
        """["stop1", "stop2", ...]: the constraint of each impact, 1-based."""
        sig = self.signature if self.signature is not None else (0,) * self.p
        if self.model.elastic:               # each elastic event names its kind
            return Signature(sig, self.contact).names(self.model)
        return [f"stop{k + 1}" for k in sig]

    def jet(self, order=3):
        """(A, d2, ..., d_order) of P^p at points[0], the generated jets of each impact
        composed (:func:`compose`); order 2 or 3 returns (A, d2, d3) with d3 None for 2,
        as before; orders 4 and 5 (the jets of :mod:`symvi.codegen.high`, curves only)
        return (A, d2, d3, d4[, d5])."""
        Y = self.u[:self.p * 2 * self.model.n].reshape(self.p, -1)
        if self.model.nonlinear is not None:
            return self._series_jet(Y, order)
        flow = LinearFlow.free(self.model)
        F = flow.forcing(self.omega)
        jets = []
        several = len(self.model.constraints) > 1 or self.model.elastic
        # each flight in its phase's flow (the free flow without elastic stops)
        phases = (Signature(self.signature, self.contact).phases(self.model)
                  if self.model.elastic else None)
        for i in range(self.p):
            if several:
                from ..codegen.jets import flight_jet
                sig = self.signature
                fi = flow if phases is None else LinearFlow.contact(self.model, phases[i])
                v = flight_jet(fi, fi.forcing(self.omega), tuple(Y[i]), float(self.times[i]),
                               order, sig[i], sig[(i + 1) % self.p])
                jets.append((v["J"], v["d2"] if order >= 2 else None,
                             v.get("d3") if order >= 3 else None)
                            + tuple(v[f"d{k}"] for k in range(4, order + 1)))
            elif order <= 3:
                from ..codegen.jets import evaluate
                v = evaluate(flow, F, tuple(Y[i]), float(self.times[i]), order)
                jets.append((v["J"], v["d2"], v.get("d3") if order >= 3 else None))
            else:
                from ..codegen.high import high_jet
                h = high_jet(self.model, self.omega, tuple(Y[i]), float(self.times[i]),
                             order=order)
                jets.append((h.jacobian, h.d2, h.d3, h.d4) + ((h.d5,) if order >= 5 else ()))
        return compose(jets)

    def _series_jet(self, Y, order):
        """:meth:`jet` of a nonlinear model: each impact's map from the series of its
        flight (:func:`symvi.flow.nljet.map_jet`), composed."""
        from ..flow.nljet import map_jet
        view = free_flow(self.model)
        sig = self.signature if self.signature is not None else (0,) * self.p
        # with elastic stops each flight in its phase's view (an exit's guard is -h there)
        phases = (Signature(sig, self.contact).phases(self.model) if self.model.elastic
                  else None)
        jets = []
        for i in range(self.p):
            if phases is not None:
                view = contact_flow(self.model, phases[i])
            v = map_jet(view, self.omega, tuple(Y[i]), float(self.times[i]), max(order, 2),
                        int(sig[i]), int(sig[(i + 1) % self.p]))
            jets.append((v["J"],) + tuple(v[f"d{k}"] for k in range(2, max(order, 2) + 1)))
        out = compose(jets)
        return out + (None,) if order == 2 else out

    def as_dict(self):
        return {"n": self.n, "p": self.p, "omega": self.omega,
                "signature": self.signature_names,
                "y": [float(v) for v in self.y], "names": list(self.names),
                "points": [[float(v) for v in y] for y in self.points],
                "times": [float(t) for t in self.times],
                "impact_velocities": [float(v) for v in self.impact_velocities],
                "multipliers": [[z.real, z.imag] for z in self.multipliers],
                "stable": bool(self.stable), "neutral": self.neutral,
                "admissible": bool(self.admissible),
                "reason": self.reason, "residual": self.residual,
                **({"symmetric": self.symmetric} if self.symmetric is not None else {}),
                **({"point_names": [list(n) for n in self.point_names]}
                   if self.point_names is not None and len(set(self.point_names)) > 1 else {})}


def compose(jets):
    """Jet of F_{p-1} o ... o F_0 from the jets (J, d2, d3, ...) of each map at its point:
    raw derivative tensors to any order, by Faa di Bruno's formula over set partitions,

        D^k (g o f)[h_1..h_k] = sum over partitions P of {1..k} of
                                D^{|P|} g [D^{|B|} f [h_B] for B in P],

    (None entries propagate: a missing order stays missing)."""
    out = list(jets[0])
    for g in jets[1:]:
        K = len(out)
        new = [g[0] @ out[0]]
        for k in range(2, K + 1):
            if any(t is None for t in out[:k]) or any(t is None for t in g[:k]):
                new.append(None)
                continue
            new.append(sum(_faa_term(g, out, blocks) for blocks in _partitions(k)))
        out = new
    return tuple(out)


_LETTERS = "abcdefghijklmnopqrstuvwxyz"


def _faa_term(g, f, blocks):
    """D^m g[D^{|B_1|} f[h_{B_1}], ..., D^{|B_m|} f[h_{B_m}]] as a tensor in (i, h_1..h_k)."""
    m = len(blocks)
    k = sum(len(b) for b in blocks)
    outs = _LETTERS[:k]                         # the free slots h_1..h_k
    inner = _LETTERS[k:k + m]                   # the contracted slots of g
    spec = ["z" + inner]
    ops = [g[m - 1]]
    for c, b in zip(inner, blocks):
        spec.append(c + "".join(outs[j] for j in b))
        ops.append(f[len(b) - 1])
    return np.einsum(",".join(spec) + "->z" + outs, *ops, optimize=True)


_PARTS = {}


def _partitions(k):
    """Set partitions of {0..k-1}, as tuples of blocks (cached)."""
    if k not in _PARTS:
        def rec(items):
            if not items:
                yield ()
                return
            first, rest = items[0], items[1:]
            for p in rec(rest):
                yield ((first,),) + p
                for i in range(len(p)):
                    yield p[:i] + ((first,) + p[i],) + p[i + 1:]
        _PARTS[k] = tuple(rec(tuple(range(k))))
    return _PARTS[k]


def eigenvalues(M):
    ev = np.linalg.eigvals(M)
    return tuple(sorted((complex(z) for z in ev), key=lambda z: (-abs(z), -z.imag)))


def orbit_of(problem, u, lam, Gu=None, admissibility=True):
    """The :class:`PeriodicOrbit` at a solution u of ``problem`` at lam."""
    if Gu is None:
        G, Gu, _ = problem.evaluate(u, lam)
    else:
        G = problem.evaluate(u, lam, jac=False, check=False)[0]
    fl, (model, flow, F) = problem.flights(u, lam, check=False)
    Y, T = problem.split(u)
    mats, M = problem.monodromy(u, Gu)
    mult = eigenvalues(M)
    H = problem.half(u, mats)
    sym = None if problem.mirror is None else H is not None
    vimp = problem.approach_speeds(fl, flow)
    finder = _shooting.CompiledFinder(flow) if problem.compiled else flow
    ok, why = admissible(problem, fl, finder, F, T, model) if admissibility else (True, "")
    two_pi = 2 * math.pi
    pts = tuple(tuple(float(v) for v in y[:-1]) + (float(y[-1] % two_pi),) for y in Y)
    names = tuple(problem.sections[k].names for k in problem.sig)
    return PeriodicOrbit(model, float(F.omega), problem.n_periods, problem.p, pts,
                         tuple(float(t) for t in T), vimp, names[0], mult,
                         stable_of(mult[:1], ok, model), ok, why, float(np.max(np.abs(G))),
                         np.array(u, dtype=float), problem.signature.hits, names, sym,
                         None if H is None else eigenvalues(H), problem.signature.contact)


def admissible(problem, fl, flow, F, T, model=None):
    """(ok, reason): :func:`symvi.orbits.admissibility.check_flight` for every flight; with
    several constraints every guard is watched (the compiled finder) and each flight must
    end on the constraint its signature names.  ``model``: the problem's model at the
    continued parameter's value (default its own), whose contact phases walk the flights."""
    if problem.elastic:
        return _admissible_phases(problem, fl, getattr(flow, "flow", flow), F, T,
                                  problem.model if model is None else model)
    if len(problem.model.constraints) > 1:
        return _admissible_stops(problem, fl, getattr(flow, "flow", flow), F, T)
    k, g = flow.perm[0] + 1, getattr(flow, "flow", flow).approach      # flow or CompiledFinder
    for i, (z0, tau, z, *_rest) in enumerate(fl):
        ok, why = check_flight(flow.motion(F, z0, tau).first_impact, T[i], g(z0), g(z),
                               mass=k, flight=i + 1)
        if not ok:
            return ok, why
    return True, ""


def _admissible_phases(problem, fl, flow, F, T, model):
    """:func:`admissible` with contact phases: each flight is checked by the walk of
    :mod:`symvi.flow.contact` in its phase of ``model`` (at the continued parameter's
    value: a stop's stiffness, damping or gap, a matrix entry move the phases), which
    watches every guard (the entries, exits and rigid impacts) with its provably safe
    step."""
    from ..flow import contact
    N, p = problem.N, problem.p
    ends = problem._ends(flow)
    rows = _table(flow)
    for i, (z0, tau, z, *_rest) in enumerate(fl):
        ka, kb = int(problem.sig[i]), int(problem.sig[(i + 1) % p])
        S = problem.phases[i]
        mo = contact.phases_of(model)(model, S).motion(F.omega, flow.to_mass(z0), tau)
        G, lv = contact.guards(model, S)
        sa = -1.0 if ka in S else 1.0              # the walk's guards: -h in contact
        sb = -1.0 if kb in S else 1.0
        v0 = sa * float(rows[ka][3:3 + N] @ z0[N:])
        v1 = sb * float(ends[i][1] @ z[N:])

        def first(t_max, mo=mo, G=G, lv=lv, ka=ka):
            return _ContactHit(mo.first_event(G, lv, start=ka, t_max=t_max))

        ok, why = check_flight(first, T[i], v0, v1, mass=None, flight=i + 1, stops=(ka, kb))
        if not ok:
            return ok, why
    return True, ""


class _ContactHit:
    """A :class:`symvi.flow.contact.Hit` as :func:`check_flight` reads a first contact."""

    def __init__(self, hit):
        from ..flow import contact
        from ..flow.linear import GRAZING, NO_IMPACT
        self.status = {"event": IMPACT, contact.GRAZING: GRAZING}.get(hit.status, NO_IMPACT)
        self.t, self.steps, self.constraint = hit.t, hit.steps, hit.guard


def free_flow(model):
    """The free flight of ``model`` as the shooting system reads it: the exact linear flow
    (:meth:`LinearFlow.free`), or for nonlinear forces the series' view of the nonlinear
    flow (:class:`symvi.flow.nljet.FlowView`; with elastic stops the free phase's
    :class:`symvi.flow.nlcontact.ContactView`)."""
    if model.nonlinear is None:
        return LinearFlow.free(model)
    if model.elastic:
        return contact_flow(model, ())
    from ..flow.nljet import FlowView
    return FlowView.of(model)


def contact_flow(model, active):
    """Contact phase ``active`` of ``model`` as the shooting system reads a flow: the exact
    :meth:`LinearFlow.contact`, or with nonlinear forces the series' view of the phase's
    Taylor flow (:class:`symvi.flow.nlcontact.ContactView`)."""
    if model.nonlinear is None:
        return LinearFlow.contact(model, active)
    from ..flow.nlcontact import view
    return view(model, tuple(sorted(active)))


def _admissible_stops(problem, fl, flow, F, T):
    """:func:`admissible` with several constraints: a finder that watches every guard, the
    compiled one (the Python finder watches one guard) or a nonlinear flow's own."""
    finder = None if problem.nonlinear else _shooting.CompiledFinder(flow)
    ends, N, p = problem._ends(flow), problem.N, problem.p
    rows = _table(flow)
    for i, (z0, tau, z, *_rest) in enumerate(fl):
        ka, kb = int(problem.sig[i]), int(problem.sig[(i + 1) % p])
        ga = rows[ka][3:3 + N]
        first = (flow.motion(F, z0, tau) if finder is None else
                 finder.motion_from(F, np.append(z0[problem.frames[ka]], tau), ka))
        ok, why = check_flight(first.first_impact, T[i],
                               float(ga @ z0[N:]), float(ends[i][1] @ z[N:]), mass=None,
                               flight=i + 1, stops=(ka, kb))
        if not ok:
            return ok, why
    return True, ""


# --------------------------------------------------------------------------- the solver
def _fixed(model, fixed):
    """(model with the fixed parameters set, omega) from ``**fixed``."""
    fixed = dict(fixed)
    if "omega" not in fixed:
        raise ParameterError("omega", None, "a forcing frequency: pass omega=...")
    omega = fixed.pop("omega")
    if fixed:
        model = model.with_(**fixed)
    return model, omega


def periodic_orbit(model, *, n, p, guess, signature=None, **fixed):
    """The n-p orbit of ``model`` (p impacts in n forcing periods) near ``guess``.

    ``fixed`` sets omega (required) and any other named parameter.  ``guess`` is
    a section point y (the other p - 1 impacts follow from the map), a
    sequence of p section points, a :class:`PeriodicOrbit`, or a simulation
    result of :func:`symvi.simulate` (its last p impacts).  ``signature`` names the
    constraint of each impact (point i lies on its section; default: the stops the
    simulation's last p impacts hit, else the first stop).  Newton on the
    shooting system of the module docstring; ConvergenceError (with the residual
    reached) when it does not converge, never an orbit that is not one.
    """
    from ..model import Model
    if not isinstance(model, Model):
        raise ParameterError("model", model, "a symvi.Model")
    model, omega = _fixed(model, fixed)
    if signature is None and getattr(guess, "hits", None) is not None and \
            len(guess.hits) >= p:
        signature = tuple(int(k) for k in guess.hits[-p:])
    if signature is not None and getattr(guess, "active", None) is not None and \
            not isinstance(signature, Signature):
        # a run through contact phases: what was in contact after its (-p)th event
        signature = Signature(signature, guess.active[-p])
    if signature is None and isinstance(guess, PeriodicOrbit):
        signature = Signature(guess.signature, guess.contact)
    problem = Problem(model, n, p, omega=omega, signature=signature)
    u0 = initial_guess(problem, guess)
    u = newton(problem, u0, None)
    return orbit_of(problem, u, None)


def detect_period(sim, p_max=16, tol=1e-6):
    """(n, p) of the periodic attractor a simulation has converged to: the smallest p with
    y_{-1} = y_{-1-p} (tau mod 2 pi) to ``tol``, n from the time between them; None if none."""
    sec, t = np.asarray(sim.section, dtype=float), np.asarray(sim.t, dtype=float)
    if sec.ndim != 2 or len(sec) < 2:
        return None
    hits = getattr(sim, "hits", None)
    two_pi = 2 * math.pi
    scale = 1 + np.max(np.abs(sec[-1, :-1]))
    for p in range(1, min(p_max, len(sec) - 1) + 1):
        a, b = sec[-1], sec[-1 - p]
        if hits is not None and len(hits) == len(sec) and (
                tuple(hits[-p:]) != tuple(hits[-2 * p:-p]) if 2 * p <= len(hits) else
                hits[-1] != hits[-1 - p]):
            continue                               # not the same itinerary twice
        dtau = abs((a[-1] - b[-1] + math.pi) % two_pi - math.pi)
        if np.max(np.abs(a[:-1] - b[:-1])) <= tol * scale and dtau <= tol:
            n = (t[-1] - t[-1 - p]) * sim.omega / two_pi
            if abs(n - round(n)) <= 1e-4 and round(n) >= 1:
                return int(round(n)), p
    return None


def from_simulation(sim, *, p_max=16, tol=1e-6):
    """The n-p orbit a simulation (:func:`symvi.simulate` of a Model) has converged to,
    refined by Newton; ConvergenceError when the run has not settled on a periodic orbit."""
    from ..model import Model
    if not isinstance(sim.params, Model):
        raise ParameterError("sim", "a paper-preset simulation", "a simulation of a "
                             "symvi.Model (use Model.luo_xie for the paper's model)")
    found = detect_period(sim, p_max, tol)
    if found is None:
        raise ConvergenceError(f"the simulation has not settled on a periodic orbit of at "
                               f"most {p_max} impacts (to {tol:g})", math.inf)
    n, p = found
    return periodic_orbit(sim.params, n=n, p=p, guess=sim, omega=sim.omega)


def initial_guess(problem, guess):
    """The unknown vector u from a guess (see :func:`periodic_orbit`)."""
    from ..maps.impact import step
    d, p = problem.d, problem.p
    model, flow, F = problem.at(None)
    if isinstance(guess, PeriodicOrbit):
        pts = [np.array(y, dtype=float) for y in guess.points]
        if len(pts) != p:
            raise ParameterError("guess", f"a {guess.n}-{guess.p} orbit",
                                 f"an orbit with p = {p} impacts")
    elif hasattr(guess, "section"):             # a simulation result
        sec = np.asarray(guess.section, dtype=float)
        if sec.ndim != 2 or sec.shape[0] < p or sec.shape[1] != d:
            raise ParameterError("guess", "simulation", f"at least p = {p} recorded impacts")
        pts = list(sec[-p:])
    else:
        arr = np.asarray(guess, dtype=float) if not isinstance(guess, str) else None
        if arr is None or arr.ndim not in (1, 2) or arr.shape[-1] != d:
            raise ParameterError("guess", guess, f"a section point of {d} numbers "
                                 f"({', '.join(problem.sec.names)}) or {p} of them")
        pts = [arr] if arr.ndim == 1 else list(arr)
        if len(pts) not in (1, p):
            raise ParameterError("guess", f"{len(pts)} points", f"1 or p = {p} section points")
    if problem.elastic:                      # the walk through the contact phases
        from ._phases import flights
        Y, T = flights(problem, flow, F, pts)
        return np.concatenate([np.concatenate(Y), T])
    # flight times (and the missing points) from the map itself (compiled: its twin)
    several = len(model.constraints) > 1
    c = (_shooting.finder_constants(flow, F) if (problem.compiled or several)
         and not problem.nonlinear else None)
    T, Y = [], [np.array(pts[0], dtype=float)]
    cur = Y[0]
    for i in range(p):
        if problem.nonlinear:
            status, t, nxt, hit = flow.step(F, cur, int(problem.sig[i]))
            want = int(problem.sig[(i + 1) % p])
            if status == IMPACT and hit != want:
                raise ConvergenceError(f"the guess meets stop {hit + 1} at impact {i + 1}, "
                                       f"not stop {want + 1} as the signature says", math.inf)
        elif c is None:
            s = step(flow, F, cur)
            status, t, nxt = s.status, s.t, np.array(s.y, dtype=float)
        else:
            st, t, nxt, _, _, _, hit = compiled_step(c, cur, int(problem.sig[i]))
            status = STATUS_NAMES[st]
            want = int(problem.sig[(i + 1) % p])
            if status == IMPACT and hit != want:
                raise ConvergenceError(f"the guess meets stop {hit + 1} at impact {i + 1}, "
                                       f"not stop {want + 1} as the signature says", math.inf)
        if status != IMPACT:
            raise ConvergenceError(f"the guess does not lead to an impact ({status}) "
                                   f"at impact {i + 1}", math.inf)
        T.append(float(t))
        nxt[-1] = cur[-1] + F.omega * t            # tau unwrapped
        if i + 1 < p:
            if len(pts) == p:
                nxt = np.array(pts[i + 1], dtype=float)
                nxt[-1] = _unwrap(nxt[-1], cur[-1] + F.omega * t)
            Y.append(nxt)
        cur = nxt
    return np.concatenate([np.concatenate(Y), T])


def _unwrap(tau, near):
    return tau + 2 * math.pi * round((near - tau) / (2 * math.pi))


__all__ = ["ConvergenceError", "PeriodicOrbit", "Problem", "compose", "detect_period",
           "from_simulation", "newton", "orbit_of", "periodic_orbit"]
