"""Exact flow of any model between impacts, and the first-impact finder.

State z = (x, v) in the *stop-first* order (the stop's mass first, then the
others in mass order; :attr:`LinearFlow.perm`).  Between impacts::

    z' = A z + B sin(omega t + tau),  A = [[0, I], [-M^-1 K, -M^-1 C]],

solved exactly as z(t) = Phi(t) (z0 - zp(0)) + zp(t), Phi(t) = e^{A t}, with

* the particular (steady-state) solution x_p(t) = U sin(phi) + V cos(phi),
  phi = omega t + tau, where U + i V = X solves (K - omega^2 M + i omega C) X = P;
* Phi(t) = Re(W diag(e^{lambda_j t}) W^-1) from the eigen-decomposition of A.
  Undamped models use the mass-normalised modes (lambda = +-i omega_j, an exact
  closed form for W^-1); damped ones the eigenvectors of A, refused when they
  are ill-conditioned (a defective, e.g. critically damped, mode).
* With free modes (K singular: a mass on no spring, as in an impact damper), the
  rigid ones (K phi = C phi = 0) form a Jordan block at lambda = 0 and
  Phi(t) = Re(W e^{Lambda t} W^-1) + t NIL, NIL = [[0, G], [0, 0]] nilpotent
  (:func:`_free_modal`); NIL = 0 otherwise.  A null direction of K that
  C damps is a simple lambda = 0 of the damped form.

The stop is read through its constraint (:class:`symvi.model.Constraint`): the
flow's order puts its coordinate first, its guard is h = guard . x - level
(x_k - b for the stop on mass k) and its reset v+ = R v- (:meth:`LinearFlow._constrain`).

The first-impact finder steps along h(t) = x_k(t) - b < 0 with a provably safe
step, as :mod:`symvi.paper.modal_flow` does for the paper: with
M2 = sum_j |d_j| |lambda_j|^2 + |X_k| omega^2 >= |h''| (valid for all t >= 0
since Re lambda_j <= 0 for M positive definite, K and C semi-definite; the
drift of free modes adds delta t to h and nothing to h''),
h(t + s) <= h + h' s + M2 s^2 / 2, so no crossing occurs before the first root
of that quadratic (none at all when M2 = 0 and h' < 0: h is linear).  A crossing
with h' below a grazing speed is reported as grazing, never stepped over.  Damped
motion is covered by the same bound.

Both backends of :mod:`symvi.numerics.backend` (float64 through numpy, mpmath at the
flow's digits: ``LinearFlow.bk``) run this one implementation.
"""
import cmath
import copy
import functools
import math
import warnings
from dataclasses import dataclass

import mpmath
import numpy as np

from ..errors import NearSingularWarning, ParameterError, SingularCaseError
from ..model._checks import null_dim
from ..numerics.backend import FLOAT64, backend
# relative distance to a forcing resonance refused / warned about (as for the paper), and
# at which scans and branches through a natural frequency are cut (symvi.numerics.tolerances)
from ..numerics.tolerances import CONTACT_TIME_ULPS, CONTACT_ULPS, GRAZING_SPEED_FACTOR, OMEGA_RANGE
from ..numerics.tolerances import EPS64
from ..numerics.tolerances import FORCING_RESONANCE_CUT as RESONANCE_CUT
from ..numerics.tolerances import FORCING_RESONANCE_REFUSE as RESONANCE_REFUSE
from ..numerics.tolerances import FORCING_RESONANCE_WARN as RESONANCE_WARN
from ._steady import steady_state

IMPACT, GRAZING, NO_IMPACT = "impact", "grazing", "no-impact"

#: condition number of the eigenvector matrix of A above which a damped model is refused
EIGVEC_COND_MAX = 1e10


# --------------------------------------------------------------------------- the flow
@dataclass(frozen=True)
class Forcing:
    """Steady-state response at omega: x_p = U sin(phi) + V cos(phi), stop-first order,
    and its omega-derivative (dU, dV)."""

    omega: object
    U: np.ndarray
    V: np.ndarray
    dU: np.ndarray
    dV: np.ndarray

    def zp(self, phase, bk):
        """(x_p, v_p) at phase phi = omega t + tau, as one 2N vector."""
        s, c = bk.sin(phase), bk.cos(phase)
        return np.concatenate([self.U * s + self.V * c, self.omega * (self.U * c - self.V * s)])

    def zp_phase(self, phase, bk):
        """d zp / d phi at phase phi."""
        s, c = bk.sin(phase), bk.cos(phase)
        return np.concatenate([self.U * c - self.V * s, -self.omega * (self.U * s + self.V * c)])

    def zp_omega(self, phase, bk):
        """d zp / d omega at fixed phase (U, V and the velocity's factor omega move)."""
        s, c = bk.sin(phase), bk.cos(phase)
        return np.concatenate([self.dU * s + self.dV * c,
                               self.U * c - self.V * s + self.omega * (self.dU * c - self.dV * s)])


class LinearFlow:
    """The exact flow of one model in one backend (see the module docstring).

    ``LinearFlow.of(model, digits=None)`` is cached; ``digits`` selects mpmath
    (the flow then holds mpf data and must be used at that precision).  ``bk`` is the
    flow's backend (:mod:`symvi.numerics.backend`): FLOAT64 or ``backend(digits)``.
    """

    #: the elastic constraints in contact (a contact phase, :meth:`contact`; () for every
    #: flow of a model with elastic stops) or None (a model of rigid stops)
    active = None
    #: the static offset zs = (K_S^-1 f_S, 0) of a contact phase (flow order), else None
    offset = None

    def __init__(self, model, bk, active=None):
        self.model, self.bk = model, bk
        n = model.n
        model.require_linear()                     # nonlinear forces: flow/nonlinear.py
        if active is None:
            model.require_rigid_stops()            # what this flow takes (issue 25)
        else:
            self.active = tuple(sorted(active))
        con = model.constraints[0]
        self.perm, self.T, self.labels = frame_of(model)
        self.n = n
        if self.T is not None:
            self.Tinv = np.linalg.inv(self.T)
        Km, Cm, f = contact_matrices(model, self.active or ())
        # q = T x: M' = T^-T M T^-1 (and K', C'), P' = T^-T P (:meth:`framed`)
        M, K, C = (bk.arr(self.framed(a)) for a in (model.mass, Km, Cm))
        self.P = bk.arr(self.framed(model.forcing))
        self.M, self.K, self.C = M, K, C
        Minv = self.Minv = bk.inv(M)
        self._constrain(con)
        Z, I = np.zeros((n, n)), np.eye(n)
        self.A = np.block([[bk.arr(Z), bk.arr(I)], [-(Minv @ K), -(Minv @ C)]])
        self._forcing_cache = {}
        self._resonance_cache = {}
        # the modal form; NIL: the nilpotent part of e^{At} with free modes (zeros without)
        self.omegas, self.lam, self.W, self.Winv, nil = modal_form(
            bk, M, K, C, self.A, model.damped or bool(np.any(np.asarray(Cm) != 0)))
        if self.active:
            # K_S xs = f_S in the frame: K' (T x) = T^-T K x = T^-T f
            self.offset = np.concatenate([bk.solve(K, bk.arr(self.framed(f))),
                                          bk.arr(np.zeros(n))])
        self.free = nil is not None
        self.NIL = nil if self.free else bk.arr(np.zeros((2 * n, 2 * n)))

    def framed(self, a):
        """A matrix of forces over positions (M, K, C and their tangents) or a force
        vector (P) of mass order in the flow's coordinates q = T x: T^-T a T^-1 (made
        symmetric again: a congruence of a symmetric matrix), T^-T a; a permutation
        (:func:`frame_of`) just reorders them."""
        a = np.asarray(a)
        if self.T is None:
            p = list(self.perm)
            return a[np.ix_(p, p)] if a.ndim == 2 else a[p]
        Ti = self.Tinv
        return _sym(Ti.T @ a @ Ti) if a.ndim == 2 else Ti.T @ a

    def to_flow(self, z):
        """A state (x, v) of mass order in the flow's coordinates: (T x, T v), a
        reordering for a permutation (:func:`frame_of`)."""
        z = np.asarray(z)
        n = self.n
        if self.T is None:
            p = list(self.perm)
            return np.concatenate([z[:n][p], z[n:][p]])
        return np.concatenate([self.T @ z[:n], self.T @ z[n:]])

    def to_mass(self, z):
        """The inverse of :meth:`to_flow`."""
        z = np.asarray(z)
        n = self.n
        if self.T is None:
            out = np.empty(2 * n, dtype=z.dtype)
            p = list(self.perm)
            out[p], out[[n + j for j in p]] = z[:n], z[n:]
            return out
        return np.concatenate([self.Tinv @ z[:n], self.Tinv @ z[n:]])

    def framed_velocity(self, R):
        """A map of velocities (a reset, its derivative) of mass order in the flow's
        coordinates: T R T^-1 (v' = T v), a reordering for a permutation."""
        if self.T is None:
            p = list(self.perm)
            return R[np.ix_(p, p)]
        return self.T @ R @ self.Tinv

    def _constrain(self, con):
        """The constraint's data in the flow's order (:mod:`symvi.model._constraint`):
        ``b`` the gap (x_0 = b on the section), ``r`` the restitution, ``guard`` the
        signed normal and ``level`` the signed gap (h = guard . x - level < 0 off the stop),
        ``reset`` R with v+ = R v-.  The one place the flow reads the impact law."""
        bk = self.bk
        self.constraint = con
        self.b = bk.num(con.gap)
        self.r = None if con.restitution is None else bk.num(con.restitution)
        self.level = con.sign * self.b
        if self.bk is FLOAT64:
            # a curve in the gap or r builds a flow per corrector step: what does not
            # depend on the gap is computed once per (normal, side, impulse, r, order, M)
            key = (con.normal, con.side, con.impulse, con.restitution, self.perm,
                   None if con.impulse is not None else self._mass_key,
                   None if self.T is None else self.T.tobytes())
            hit = _CONSTRAINED.get(key)
            if hit is None:
                hit = _CONSTRAINED[key] = self._reset_data(con)
                if len(_CONSTRAINED) > 4096:       # bounded: a long scan in r stays small
                    _CONSTRAINED.pop(next(iter(_CONSTRAINED)))
            self.guard, self.reset, self._unit_guard, self.coordinate_law, tail = hit
            # (b, level, guard, R row-major): the layout the compiled kernels take
            # (symvi.flow.compiled.CONSTRAINT), one array for one dispatch
            self.constraint64 = np.concatenate(([float(self.b), float(self.level)], tail))
        else:
            self.guard, self.reset, self._unit_guard, self.coordinate_law, _ = \
                self._reset_data(con)
        self._resets = {}

    @functools.cached_property
    def _mass_key(self):
        return tuple(map(tuple, np.asarray(self.model.mass, dtype=float)))

    def _reset_data(self, con, r=None):
        """(guard, reset, unit guard, coordinate law, guard and reset as float64 row-major)
        of ``con`` at restitution ``r`` (default this flow's) in this flow's order; see
        :meth:`_constrain`."""
        r = self.r if r is None else r
        p = list(self.perm)
        if con.kind == "elastic":
            # an entry into or an exit from a contact phase: no jump (:mod:`.contact`)
            guard = self.bk.arr(con.sign * (np.array(con.normal)[p] if self.T is None else
                                            self.Tinv.T @ np.array(con.normal)))
            reset = self.bk.arr(np.eye(self.n))
            tail = None
            if self.bk is FLOAT64:
                reset = np.eye(self.n)
                tail = np.concatenate([guard, reset.ravel()])
                for a in (guard, reset, tail):
                    a.setflags(write=False)
            return guard, reset, False, False, tail
        Minv = None
        if con.impulse is None:                    # rigid: along M^-1 c (mass order)
            Minv = self.bk.inv(self.bk.arr(np.asarray(self.model.mass)))
        if self.T is None:
            guard = self.bk.arr(con.sign * np.array(con.normal)[p])
            reset = con.reset_matrix(Minv, order=p, r=r)
        else:                                      # v' = T v: R' = T R T^-1, c' = T^-T c
            guard = self.bk.arr(con.sign * (self.Tinv.T @ np.array(con.normal)))
            reset = self._framed_reset(con, Minv, r)
        if self.bk is not FLOAT64:
            reset = self.bk.arr(reset)
        # the stop on one mass, upper side: guard e_0 (approach speeds read directly)
        unit_guard = con.sign == 1.0 and (con.coordinate is not None if self.T is None else
                                          bool(np.all(guard == np.eye(self.n)[0])))
        # ... with v_0+ = -r v_0-, every other velocity kept (today's stop; the generated
        # jets take any guard and reset: symvi.codegen.layout.jet_constraint)
        law = np.eye(self.n, dtype=reset.dtype)
        law[0, 0] = -r
        coordinate_law = unit_guard and bool(np.all(reset == law))
        tail = None
        if self.bk is FLOAT64:
            tail = np.concatenate([guard, np.asarray(reset, dtype=float).ravel()])
            for a in (guard, reset, tail):          # shared by the flows of one cache entry
                a.setflags(write=False)
        return guard, reset, unit_guard, coordinate_law, tail

    def _framed_reset(self, con, Minv, r):
        """R' = T R T^-1 written in the frame (c' = e_k, q' = T q): (I - Q') - r Q' with
        Q' = q' e_k^T / q'_k, so that R' is the identity off its column k exactly (as the
        jets require, :func:`symvi.codegen.layout.jet_constraint`)."""
        k = self.position(con)
        q = self.T @ con.direction(Minv)
        Q = np.zeros((self.n, self.n), dtype=q.dtype)
        Q[:, k] = q / q[k]
        return (np.eye(self.n) - Q) - r * Q

    def reset_at(self, r):
        """The constraint's reset R (flow order) at restitution r (cached per flow)."""
        R = self._resets.get(r)
        if R is None:
            con = self.constraint
            Minv = None if con.impulse else self.bk.inv(self.bk.arr(np.asarray(self.model.mass)))
            R = (con.reset_matrix(Minv, order=list(self.perm), r=r) if self.T is None else
                 self._framed_reset(con, Minv, r))
            self._resets[r] = R
        return R

    def constraint_rows(self):
        """Every constraint of the model as the compiled kernels take it (float64, flow
        order; :func:`symvi.flow.compiled.constants`): (p, gap, level, guard, R row-major),
        p the position of its coordinate in the flow's order (its section is x_p = gap).
        The first is this flow's own (:meth:`_constrain`, shared by its copies)."""
        rows = [np.concatenate(([0.0], self.constraint64))]
        for con in self.model.constraints[1:]:
            tail = self._reset_data(con, con.restitution)[4]
            rows.append(np.concatenate(([float(self.position(con)), con.gap,
                                         con.sign * con.gap], tail)))
        return rows

    def position(self, con):
        """The position of ``con``'s coordinate in the flow's order (its section is x_p =
        gap there): its mass's place, or the row of T equal to its normal."""
        if self.T is None:
            return self.perm.index(con.coordinate)
        return next(i for i, row in enumerate(self.T) if tuple(row) == con.normal)

    def approach(self, z):
        """guard . v of a state z (flow order): > 0 moving towards the stop (v_k for the
        stop on mass k)."""
        n = self.n
        return z[n] if self._unit_guard else self.guard @ z[n:2 * n]

    def section_approach(self, y):
        """guard . v+ of a section point y just after an impact (y[0] = v_k+ for the stop
        on mass k; :class:`symvi.maps.Section`)."""
        if self._unit_guard:
            return y[0]
        n = self.n
        return self.guard[0] * y[0] + sum(self.guard[i] * y[n + i - 1] for i in range(1, n))

    @classmethod
    def contact(cls, model, active=()):
        """The float64 flow of ``model`` with the elastic constraints ``active`` in contact
        (:mod:`symvi.flow.contact`'s phase S in this flow's frame: K_S, C_S and the offset
        zs); ``active`` = () is the free flight of a model with elastic stops.  Every
        constraint is a guard; an elastic one's reset is the identity (no jump)."""
        from ..model import Model
        if not isinstance(model, Model):
            raise ParameterError("model", model, "a symvi.Model")
        active = tuple(sorted(int(i) for i in active))
        for i in active:
            if not 0 <= i < len(model.constraints) or model.constraints[i].kind != "elastic":
                raise ParameterError("active", active, "indices of elastic constraints")
        return _memo(_PHASES, (model, active), lambda: cls(model, FLOAT64, active), size=64)

    @classmethod
    def free(cls, model):
        """The float64 free flight of ``model``: :meth:`of`, or with elastic stops the free
        phase of :meth:`contact` (every constraint a guard, elastic resets the identity)."""
        return cls.contact(model) if model.elastic else cls.of(model)

    @classmethod
    def of(cls, model, digits=None):
        from ..model import Model
        if not isinstance(model, Model):
            raise ParameterError("model", model, "a symvi.Model")
        model.require_linear()              # before the caches shared by equal matrices
        if digits is None:
            return _flow_float(model)
        with mpmath.mp.workdps(digits):
            return _flow_mp(model, digits)

    @functools.cached_property
    def mass_scaled(self):
        """(K~, C~) = L^-1 (K, C) L^-T with M = L L^T (float64): the resonance measure."""
        Li = np.linalg.inv(np.linalg.cholesky(np.asarray(self.M, dtype=float)))
        return (Li @ np.asarray(self.K, dtype=float) @ Li.T,
                Li @ np.asarray(self.C, dtype=float) @ Li.T)

    @functools.cached_property
    def modal64(self):
        """(lambda, W, W^-1, A) as contiguous complex128 / float64 arrays (float backend):
        the modal data of the compiled kernels; shared by flows that differ in the stop.
        Refused with free modes: Re(W e^{Lambda t} W^-1) alone is not e^{At} there
        (:meth:`phis`, :func:`symvi.flow.compiled.phi_into` add t NIL)."""
        if self.free:
            raise SingularCaseError(
                "free-mass", "the model has a mass on no spring (a free mode): its flow is "
                "e^{At} = Re(W e^{Lambda t} W^-1) + t NIL, which this analysis does not take "
                "(symvi orbit, continue, curve and simulate do)")
        return self.modal_nil64[:4]

    @functools.cached_property
    def modal_nil64(self):
        """(lambda, W, W^-1, A, NIL) as contiguous complex128 / float64 arrays: the modal
        data with the free modes' nilpotent part (zeros without), for kernels that form
        Phi(t) themselves (:func:`symvi.flow.compiled.phi_into`)."""
        c = np.ascontiguousarray
        return (c(self.lam, dtype=complex), c(self.W, dtype=complex),
                c(self.Winv, dtype=complex), c(self.A, dtype=float), c(self.NIL, dtype=float))

    # ---- forcing ---------------------------------------------------------------
    def check_omega(self, omega, name="omega", warn=True):
        """A valid forcing frequency: finite, in range, not at a forcing resonance.

        Resonance: sigma_min(K~ - omega^2 I + i omega C~) / (2 omega^2) (K~, C~
        mass-scaled), which is |omega - omega_j| / omega_j for an undamped mode
        to first order; refused below 1e-10, warned about below 1e-4.
        """
        w = check_range(omega, name)
        rel, j = _memo(self._resonance_cache, w, lambda: _resonance(
            self.model, w, self if self.active is not None else None))
        wj = float(self.omegas[j])
        if rel < RESONANCE_REFUSE:
            raise SingularCaseError(
                "forcing-resonance",
                f"{name} = {w!r} is at the natural frequency omega_{j + 1} = {wj:.15g} of an "
                f"undamped mode (relative distance {rel:.1e}): the steady-state response is "
                f"infinite. Choose {name} != omega_{j + 1}.")
        if warn and rel < RESONANCE_WARN:
            warnings.warn(f"{name} = {w:.10g} is within {rel:.1e} (relative) of the natural "
                          f"frequency omega_{j + 1} = {wj:.10g}; results lose about "
                          f"{-math.log10(rel):.0f} digits", NearSingularWarning, stacklevel=2)
        return w

    def forcing(self, omega):
        """U, V and their omega-derivatives at omega (no checks; see :meth:`check_omega`)."""
        if self.bk is not FLOAT64:
            return self._forcing(omega)
        return _memo(self._forcing_cache, omega, lambda: self._forcing(omega))

    def _forcing(self, omega):
        bk = self.bk
        if bk is FLOAT64:                 # the same two solves, compiled (one LU)
            w = float(omega)
            return Forcing(w, *steady_state(self.K, self.M, self.C, self.P, w))
        w = bk.num(omega)
        i = 1j if bk is FLOAT64 else mpmath.mpc(0, 1)
        D = self.K - w * w * self.M + i * w * self.C
        X = bk.solve(D, self.P * (1 if bk is FLOAT64 else mpmath.mpf(1)))
        dX = bk.solve(D, (2 * w * self.M - i * self.C) @ X)
        re, im = bk.vreal, lambda v: bk.vreal(-i * v)
        return Forcing(w, re(X), im(X), re(dX), im(dX))

    # ---- the homogeneous part --------------------------------------------------
    def phi(self, t):
        """Phi(t) = e^{A t}, real 2N x 2N."""
        return self.phis(t, 0)[0]

    def phis(self, t, K):
        """[Phi(t) A^k for k = 0..K], one exponential for all.

        With free modes, e^{At} A^k = Re(W e^{Lambda t} Lambda^k W^-1) + t NIL, NIL, 0, ...
        for k = 0, 1, 2, ...
        (:meth:`_free_modal`: on the zero block e^{At} A^k = (I + t N_J) N_J^k, N_J^2 = 0)."""
        e = self.bk.vexp(self.lam * t)
        out = []
        for _ in range(K + 1):
            out.append(self.bk.vreal((self.W * e) @ self.Winv))
            e = e * self.lam
        if self.free:
            out[0] = out[0] + t * self.NIL
            if K >= 1:
                out[1] = out[1] + self.NIL
        return out

    def flight(self, forcing, z0, tau, t):
        """z(t) of the flight from z0 at phase tau and its first derivatives (variational
        equations, exact): (z, dz/dz0 = Phi(t), dz/dtau, dz/dt).  A contact phase adds its
        static offset: z = Phi (z0 - zp(tau) - zs) + zp(tau + omega t) + zs."""
        bk = self.bk
        Phi = self.phi(t)
        ph = tau + forcing.omega * t
        zpt, dzpt = forcing.zp(ph, bk), forcing.zp_phase(ph, bk)
        if self.offset is not None:
            z0 = z0 - self.offset
            zpt = zpt + self.offset
        hom = Phi @ (z0 - forcing.zp(tau, bk))
        return (hom + zpt, Phi, dzpt - Phi @ forcing.zp_phase(tau, bk),
                self.A @ hom + forcing.omega * dzpt)

    def motion(self, forcing, z0, tau):
        """The free flight from state z0 (stop-first order) at phase tau."""
        if self.active is not None:       # the walk of :mod:`.contact` watches every guard
            raise ParameterError("flow", f"contact phase {list(self.active)}",
                                 "a flow of rigid stops (elastic stops: symvi.flow.contact)")
        z0 = np.asarray(z0) if self.bk is FLOAT64 else self.bk.arr(z0)
        w = z0 - forcing.zp(tau, self.bk)
        return Motion(self, forcing, tau, self.Winv @ w, self.NIL @ w if self.free else None)

    def one_minus_exp(self, omega):
        """min_j |1 - e^{lambda_j 2 pi / omega}| and its mode index: 0 where the
        period-1 orbit is not isolated (omega_j / omega an integer, undamped mode)."""
        T = 2 * self.bk.pi / self.bk.num(omega)
        d = self.bk.vabs(1 - self.bk.vexp(self.lam * T))
        j = int(np.argmin([float(x) for x in d]))
        return d[j], j % self.n


_LINEAR = {}
#: (guard, reset, ...) of a constraint per (normal, side, impulse, r, order, M): see _constrain
_CONSTRAINED = {}


@functools.lru_cache(maxsize=256)
def _flow_float(model):
    # models that differ only in the stop's gap or restitution (a curve in b or r) share
    # the modal data, which a new stop does not change: only b and r are replaced
    con = model.require_rigid_stops().constraints[0]
    # a frame with other normals than coordinate vectors depends on every normal
    framed = any(c.coordinate is None for c in model.constraints)
    key = (con.normal, con.side, con.impulse,
           tuple(c.normal for c in model.constraints) if framed else None) + tuple(
        np.asarray(a, dtype=float).tobytes() for a in
        (model.mass, model.stiffness, model.damping, model.forcing))
    if key not in _LINEAR:
        return _memo(_LINEAR, key, lambda: LinearFlow(model, FLOAT64), size=64)
    flow = copy.copy(_LINEAR[key])
    flow.model = model
    flow._constrain(con)
    return flow


def _frame(con, n):
    """The flow's order of the masses: the constraint's coordinate first (the section
    x_0 = b), the others in mass order (:class:`symvi.maps.Section`)."""
    k = con.coordinate
    if k is None:
        raise ParameterError("constraint.normal", con.normal,
                             "a unit coordinate vector e_k (a stop on one mass); other "
                             "normals need a section frame (:func:`frame_of`)")
    return (k,) + tuple(j for j in range(n) if j != k)


def frame_of(model):
    """(perm, T, labels): the flow's coordinates, in which every constraint acts on one.

    Stops on masses only: a permutation, the first stop's mass first (:func:`_frame`;
    T and labels None).  A stop between masses (s = x_j - x_i, issue 25): q = T x with the
    distinct normals as the first rows of T (the first constraint's first), completed by
    unit vectors in mass order; perm is then (0, ..., N-1) over q, and labels[i] the
    (position, velocity) names of q_i ("x2-x1", "v2-v1").  Normals that are linearly
    dependent but not equal (the same masses named in the other order) are refused."""
    cons = model.constraints
    n = model.n
    if all(c.coordinate is not None for c in cons):
        return _frame(cons[0], n), None, None
    rows = []
    for k, c in enumerate(cons, start=1):
        if c.normal in rows:
            continue
        if np.linalg.matrix_rank(np.array(rows + [c.normal])) <= len(rows):
            raise ParameterError(f"stop[{k}]" if len(cons) > 1 else "stop", model.stops[k - 1],
                                 "stops on independent coordinates (two stops between the "
                                 "same masses name them in the same order, [i, j])")
        rows.append(c.normal)
    for j in range(n):
        e = tuple(1.0 if i == j else 0.0 for i in range(n))
        if len(rows) < n and np.linalg.matrix_rank(np.array(rows + [e])) > len(rows):
            rows.append(e)
    return tuple(range(n)), np.array(rows, dtype=float), tuple(_label(r) for r in rows)


def _label(c):
    """The (position, velocity) names of the coordinate s = c . x: x3, x2-x1, or c's sum."""
    nz = [(i, v) for i, v in enumerate(c) if v != 0.0]
    if len(nz) == 1 and nz[0][1] == 1.0:
        return f"x{nz[0][0] + 1}", f"v{nz[0][0] + 1}"
    if len(nz) == 2 and sorted(v for _, v in nz) == [-1.0, 1.0]:
        (i, _), (j, _) = sorted(nz, key=lambda t: t[1])
        return f"x{j + 1}-x{i + 1}", f"v{j + 1}-v{i + 1}"
    terms = "+".join(f"{v:g}*x{i + 1}" for i, v in nz).replace("+-", "-")
    return f"({terms})", f"({terms})'"


def _sym(A):
    """A symmetrised (a congruence T^-T A T^-1 of a symmetric A, to rounding)."""
    return 0.5 * (A + A.T)


_MP_CACHE = {}


def _flow_mp(model, digits):
    return _memo(_MP_CACHE, (model, digits), lambda: LinearFlow(model, backend(digits)), size=64)


def modal_form(bk, M, K, C, A, damped):
    """(omega_j, lambda, W, W^-1, NIL) of z' = A z, A = [[0, I], [-M^-1 K, -M^-1 C]] (the
    module docstring): Phi(t) = Re(W e^{Lambda t} W^-1) + t NIL; NIL is None without free
    modes (K positive definite, or its null directions all damped by C).  The one
    construction of the modal form, for any (M, K, C) in backend ``bk``."""
    nz = null_dim(np.asarray(K, dtype=float))     # modes on no spring (float64 decides)
    if nz:
        return _free_modal(bk, M, K, C, A, damped, nz)
    # undamped modes: natural frequencies (resonance, 1 - cos) and, if C = 0, the basis
    omegas, psi = bk.eigh_pair(K, M)
    if not damped:
        Om = omegas
        i = 1j if bk is FLOAT64 else mpmath.mpc(0, 1)
        lam = np.concatenate([i * Om, -i * Om])
        W = np.block([[psi, psi], [i * psi * Om, -i * psi * Om]])
        PM = psi.T @ M
        half = 0.5 if bk is FLOAT64 else mpmath.mpf(1) / 2
        Oi = (1 / Om)[:, None]
        Winv = half * np.block([[PM, -i * Oi * PM], [PM, i * Oi * PM]])
    else:
        lam, W, Winv = _eig_modal(bk, A)
    return omegas, lam, W, Winv, None


def _free_modal(bk, M, K, C, A, damped, nz):
    """The modal form when K has ``nz`` null directions (masses on no spring).

    Rigid modes phi (K phi = 0 and C phi = 0, M-orthonormal, the columns of Pr) move as
    x = Pr (q + p t): A has the Jordan block A (0, phi) = (phi, 0) for lambda = 0 on
    span{(phi, 0), (0, phi)}, so e^{At} = Re(W e^{Lambda t} W^-1) + t NIL with
    NIL = W N_J W^-1 = A P0 = [[0, Pr Pr^T M], [0, 0]] (P0 the spectral projector of
    lambda = 0; NIL^2 = 0).  The M-orthogonal complement E (E^T M E = I) decouples:
    s'' + E^T C E s' + E^T K E s = 0 (E^T M Pr = 0, C Pr = K Pr = 0), taken in modal
    form as in :func:`modal_form` (closed form if C = 0, else eig); a null direction of K
    that C damps is a simple lambda = 0 there, diagonalisable.  The rigid columns are
    (phi, 0), (0, phi) with rows (phi^T M, 0), (0, phi^T M)."""
    n = M.shape[0]
    with np.errstate(invalid="ignore"):      # sqrt of a rounding-sized negative
        om, psi = bk.eigh_pair(K, M)
    omegas = np.concatenate([bk.arr(np.zeros(nz)), om[nz:]])
    Q0 = psi[:, :nz]                           # an M-orthonormal basis of ker K
    nr = nz
    if damped:                                 # rigid: ker K within ker C
        C0 = Q0.T @ C @ Q0
        mu = np.linalg.eigvalsh(np.asarray(C0, dtype=float))
        top = np.abs(np.linalg.eigvalsh(np.asarray(psi.T @ C @ psi, dtype=float))).max()
        nr = int(np.sum(mu <= 64 * n * EPS64 * top))
        if nr < nz:                            # the damped ones: simple lambda = 0
            with np.errstate(invalid="ignore"):
                _, S = bk.eigh_pair(C0, bk.arr(np.eye(nz)))   # ascending: rigid first
            Q0 = Q0 @ S
    if nr == 0:                                # no Jordan block: the damped path
        zn = bk.arr(np.zeros((n, nz)))
        return (omegas,) + _eig_modal(bk, A, np.block([[Q0], [zn]])) + (None,)
    i = 1j if bk is FLOAT64 else mpmath.mpc(0, 1)
    Pr = Q0[:, :nr]
    PrM = Pr.T @ M
    Z = bk.arr(np.zeros((n, n)))
    NIL = np.block([[Z, Pr @ PrM], [Z, Z]])
    zr = bk.arr(np.zeros((n, nr)))
    Wr = np.block([[Pr, zr], [zr, Pr]])                 # (phi, 0), (0, phi)
    Wir = np.block([[PrM, zr.T], [zr.T, PrM]])
    lam_r = 0 * i * bk.arr(np.zeros(2 * nr))
    if not damped:                             # the closed form of the elastic modes
        Om, pe = om[nz:], psi[:, nz:]
        lam_e = np.concatenate([i * Om, -i * Om])
        We = np.block([[pe, pe], [i * pe * Om, -i * pe * Om]])
        PM = pe.T @ M
        half = 0.5 if bk is FLOAT64 else mpmath.mpf(1) / 2
        Oi = (1 / Om)[:, None]
        Wie = half * np.block([[PM, -i * Oi * PM], [PM, i * Oi * PM]])
    else:                                      # eig of the decoupled complement
        E = np.concatenate([psi[:, nz:], Q0[:, nr:]], axis=1)
        ne = n - nr
        Ke, Ce = E.T @ K @ E, E.T @ C @ E
        # K E_i = 0 for the damped null directions: exact zeros there (rounding-sized
        # entries misguide eig's balancing: residuals of 1e-8 seen)
        Ke[ne - nz + nr:, :] = Ke[:, ne - nz + nr:] = 0
        Ae = np.block([[bk.arr(np.zeros((ne, ne))), bk.arr(np.eye(ne))], [-Ke, -Ce]])
        # the damped null directions of K are the last nz - nr of E: (e_i, 0) there
        lam_e, We, Wie = _eig_modal(bk, Ae, bk.arr(np.eye(2 * ne)[:, ne - nz + nr:ne]))
        ze = bk.arr(np.zeros((n, ne)))
        EM = E.T @ M
        We = np.block([[E, ze], [ze, E]]) @ We
        Wie = Wie @ np.block([[EM, ze.T], [ze.T, EM]])
    return (omegas, np.concatenate([lam_r, lam_e]), np.concatenate([Wr, We], axis=1),
            np.concatenate([Wir, Wie], axis=0), NIL)


def _eig_modal(bk, A, null=None):
    """(lambda, W, W^-1) of A by its eigenvectors, refused when they are nearly dependent.

    ``null``: k known real eigenvectors of lambda = 0 (columns; a null direction of K that
    C damps: a simple, semisimple eigenvalue), put in exactly for the k eigenvalues of
    least modulus (eig's own are inexact there, and mpmath's may be dependent)."""
    lam, W = bk.eig(A)
    if null is not None and null.shape[1]:
        idx = np.argsort([float(abs(x)) for x in lam])[:null.shape[1]]
        lam, W = lam.copy(), W.copy()
        for q, j in enumerate(idx):
            lam[j] = 0 * lam[j]
            W[:, j] = null[:, q]
    cond = bk.cond(W)
    if not cond < EIGVEC_COND_MAX:
        raise SingularCaseError(
            "defective-flow", f"the eigenvectors of the state matrix are nearly "
            f"dependent (condition {cond:.3g}): a mode is (close to) critically damped "
            "and the modal form of the flow would lose all accuracy")
    return lam, W, bk.inv(W)


#: the flows of contact phases per (model, active set): :meth:`LinearFlow.contact`
_PHASES = {}


def contact_matrices(model, active):
    """(K_S, C_S, f_S) in mass order: K + sum k_i c_i c_i^T, C + sum c_si c_i c_i^T and
    f_S = sum k_i g_i c_i over the elastic constraints i in ``active``
    (:mod:`symvi.flow.contact`, the contact law)."""
    K, C = model.stiffness, model.damping
    if not active:
        return K, C, None
    K, C = np.array(K, dtype=float), np.array(C, dtype=float)
    f = np.zeros(model.n)
    for i in active:
        con = model.constraints[i]
        c = np.array(con.normal, dtype=float)
        K = K + con.stiffness * np.outer(c, c)
        if con.damping:
            C = C + con.damping * np.outer(c, c)
        f = f + con.stiffness * con.gap * c
    return K, C, f


def contact_tangent(model, active, tangent):
    """(dK_S, dC_S, df_S) in mass order: the derivative of :func:`contact_matrices` along a
    :class:`symvi.model.parameters.Tangent`, dK + dk c c^T, dC + dc c c^T and
    (dk g + k db) c for the constraint in ``active`` whose stiffness (dk), damping (dc) or
    gap (db) moves (the tangent's stop)."""
    dK, dC = np.array(tangent.dK, dtype=float), np.array(tangent.dC, dtype=float)
    df = np.zeros(model.n)
    for i in active:
        if i != tangent.stop:
            continue
        con = model.constraints[i]
        c = np.array(con.normal, dtype=float)
        dK = dK + tangent.dk * np.outer(c, c)
        dC = dC + tangent.dc * np.outer(c, c)
        df = df + (tangent.dk * con.gap + con.stiffness * tangent.db) * c
    return dK, dC, df


def _memo(cache, key, compute, size=256):
    """cache[key], computed once; the cache is emptied past ``size`` entries."""
    hit = cache.get(key)
    if hit is None:
        if len(cache) > size:
            cache.clear()
        hit = cache[key] = compute()
    return hit


def _resonance(model, w, flow=None):
    """(relative distance to forcing resonance, index of the nearest undamped mode) of the
    model's free flow or of ``flow`` (a contact phase: its own K_S, C_S)."""
    damped = model.damped if flow is None else bool(np.any(flow.C))
    flow = _flow_float(model) if flow is None else flow
    j = int(np.argmin(np.abs(flow.omegas - w)))
    if not damped:                    # sigma_min(K~ - w^2 I) = min_j |omega_j^2 - w^2|
        return float(np.min(np.abs(flow.omegas ** 2 - w * w))) / (2 * w * w), j
    Kt, Ct = flow.mass_scaled
    smin = np.linalg.svd(Kt - w * w * np.eye(flow.n) + 1j * w * Ct, compute_uv=False)[-1]
    return smin / (2 * w * w), j


def check_range(omega, name="omega"):
    """omega as a float, finite and in OMEGA_RANGE, else a one-line ParameterError naming
    ``name``: the whole check of a nonlinear model's omega (a forcing resonance of its
    linear part is no singularity of its numerical flow), the first of a linear one's
    (:meth:`LinearFlow.check_omega`)."""
    try:
        w = float(omega)
    except (TypeError, ValueError):
        raise ParameterError(name, omega, "a finite real number > 0") from None
    lo, hi = OMEGA_RANGE
    if not (math.isfinite(w) and lo <= w <= hi):
        raise ParameterError(name, omega, f"{lo:g} <= {name} <= {hi:g}")
    return w


@dataclass(frozen=True)
class FirstImpact:
    """The first contact with the stop: status, time and state z (stop-first order)."""

    status: str
    t: object
    state: np.ndarray
    steps: int


class Motion:
    """z(t) = Re(W (c * e^{lambda t})) + t NIL w + zp(t) for one flight (w = z0 - zp(0);
    the drift t NIL w of the free modes moves positions only: NIL = [[0, G], [0, 0]])."""

    def __init__(self, flow, forcing, tau, c, nw=None):
        self.flow, self.forcing, self.tau, self.c, self.nw = flow, forcing, tau, c, nw
        bk = flow.bk
        n, g = flow.n, flow.guard
        # s(t) = guard . x(t) = Re sum d_j e^{lambda_j t} + guard . x_p (x_k for a stop on k)
        self.d = (g @ flow.W[:n]) * c
        self.dv = (g @ flow.W[n:]) * c            # s'(t), likewise
        self._U0, self._V0 = g @ forcing.U, g @ forcing.V
        # s(t) gains delta t (free modes); s'(t) = guard . v(t) (dv: W's velocity rows) is
        # exact as it is (the drift moves positions only), and s'' and M2 do not change
        self.delta = 0 if nw is None else g @ nw[:n]
        if flow.bk is FLOAT64:           # scalar Python is faster than numpy at this size
            self._terms = [(complex(l), complex(a), complex(b))
                           for l, a, b in zip(flow.lam, self.d, self.dv)]
            self._U0, self._V0 = float(self._U0), float(self._V0)
            self.delta = float(self.delta)
        self.Xk = bk.sqrt(self._U0 ** 2 + self._V0 ** 2)
        ad = bk.vabs(self.d)
        al = bk.vabs(flow.lam)
        self.amp = sum(ad)
        self.M2 = sum(ad * al * al) + self.Xk * forcing.omega ** 2

    def state(self, t):
        """z(t), a real 2N vector."""
        f, bk = self.flow, self.flow.bk
        hom = bk.vreal(f.W @ (self.c * bk.vexp(f.lam * t)))
        if self.nw is not None:
            hom = hom + t * self.nw
        return hom + self.forcing.zp(self.forcing.omega * t + self.tau, f.bk)

    def h(self, t):
        """(h, h') at t, h = guard . x - level (x_k - b for a stop on mass k)."""
        f = self.flow
        om = self.forcing.omega
        ph = om * t + self.tau
        s, c = f.bk.sin(ph), f.bk.cos(ph)
        if f.bk is FLOAT64:
            hh = hv = 0j
            for lam, a, b in self._terms:
                e = cmath.exp(lam * t)
                hh += a * e
                hv += b * e
            if self.nw is not None:         # h' = guard . v is exact already: v has no drift
                hh += self.delta * t
            return (hh.real + self._U0 * s + self._V0 * c - f.level,
                    hv.real + om * (self._U0 * c - self._V0 * s))
        e = f.bk.vexp(f.lam * t)
        h = (self.d @ e).real + self._U0 * s + self._V0 * c - f.level
        hd = (self.dv @ e).real + om * (self._U0 * c - self._V0 * s)
        if self.nw is not None:
            h = h + self.delta * t
        return h, hd

    def first_impact(self, t_max=None, max_steps=100000):
        """First t > 0 with h(t) = 0 (x_k(t) = b) for a flight that leaves the stop (h' < 0)."""
        f, bk = self.flow, self.flow.bk
        om = self.forcing.omega
        if t_max is None:
            t_max = 2000 * bk.pi / om                 # 1000 forcing periods
        M2 = self.M2
        L = self.amp + self.Xk + bk.fabs(f.level)
        eps_h = CONTACT_ULPS * bk.eps * L
        v_graze = GRAZING_SPEED_FACTOR * bk.sqrt(2 * M2 * eps_h)
        t0 = 0 * t_max
        _, hd = self.h(t0)
        if not hd < 0:
            return FirstImpact(GRAZING, t0, self.state(t0), 0)
        if not M2 > 0:                  # h linear (a free mass, unforced): never back
            return FirstImpact(NO_IMPACT, t_max, self.state(t_max), 0)
        t = -hd / M2                    # vertex of the bound: h(t) <= -hd^2 / (2 M2) < 0
        for n in range(1, max_steps + 1):
            h, hd = self.h(t)
            if h >= -eps_h:
                if hd <= v_graze:
                    return FirstImpact(GRAZING, t, self.state(t), n)
                for _ in range(3):    # Newton polish of a transversal root
                    dt = -h / hd
                    t += dt
                    h, hd = self.h(t)
                    if bk.fabs(dt) <= CONTACT_TIME_ULPS * bk.eps * t:
                        break
                return FirstImpact(IMPACT, t, self.state(t), n)
            if t > t_max:
                return FirstImpact(NO_IMPACT, t, self.state(t), n)
            # safe step: first positive root of h + hd s + M2 s^2/2 = 0 (stable form)
            t += -2 * h / (hd + bk.sqrt(hd * hd - 2 * M2 * h))
        return FirstImpact(NO_IMPACT, t, self.state(t), max_steps)
