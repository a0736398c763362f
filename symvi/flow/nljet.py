"""Jets of a nonlinear flight and of its impact map, to any order (issue 28).

The flight of :mod:`symvi.flow.nonlinear`, M x'' + C x' + K x + f(x, v) = P sin(omega t +
tau), is integrated on truncated power series (:mod:`symvi.flow.tps`) in the variables
delta: the start's free coordinates, the phase tau, and optionally omega and one named
parameter p.  The integrator is the trajectories' Taylor method with series for numbers
(:mod:`symvi.flow.jet_taylor`: the forces' tape on series of series, Jorba & Zou's order
and step over every coefficient).  The result is the flow's jet z(T; delta) at a fixed
time T to order K.

The impact (eqs. (28)-(30) of the paper, generalised).  At the end the flight's Taylor
coefficients there are its series in the time shift s, Z(T + s; delta) = sum_k z_k(delta)
s^k, exact to order K in (delta, s).  The impact time T + S(delta) solves
h(Z(S(delta); delta)) = 0 for the guard h = g . x - level of the constraint the flight
ends on, by K + 1 Newton iterations on series (each gains an order; dh/ds at delta = 0 is
the approach speed, nonzero off grazing).  Then z-(delta) = Z(S(delta); delta), the reset
v+ = R v-, and the section point on that constraint (the coordinates in its section's
layout, the phase tau + omega (T + S)).  Guards, levels, resets and layouts are the
linear part's flow's, in its (flow) order (:class:`FlowView`).  Its series are the jet of
the impact map P to order K: raw derivative tensors by
:meth:`symvi.flow.tps.Algebra.tensor`, as the generated jets of the linear flow give them
(:mod:`symvi.codegen.jets`).

Parameters.  omega enters the phase omega t + tau; a named force parameter is a variable of
the force program; a parameter of the linear part moves M, K, C, P (linearly: M(p) = M +
p dM, ...; M(p)^-1 as a series by K fixed-point sweeps w = M^-1 (e - p dM w)); in a
contact phase of an elastic stop (:mod:`symvi.flow.nlcontact`) K_S, C_S and the contact
force f_S move too, with the stop's stiffness, damping and gap (the phase's ``rates``:
-f_S is a slot of the force program, moved as a force's parameter).  A rigid stop's
gap b or restitution r moves no flight, only its ends (an elastic stop's gap moves its
ends in the same way) (as on the linear path, eqs.
(36)-(38) generalised): the gap the start's fixed coordinate x_a = b on its section (a
flight that starts on that stop starts from x_a = b + p) and the guard's level sign b (one
that ends on it); the restitution, and the masses for an impulse along M^-1 c, the reset
R(p) = I - (1 + r(p)) q(p) c^T / (c^T q(p)), q(p) = M(p)^-1 c (the law of
:meth:`symvi.model.Constraint.reset_matrix` on series).
"""
import numba as nb
import numpy as np

from .. import _numba_cache  # noqa: F401  (one cache key for all kernels)
from ..errors import ParameterError, SingularCaseError
from ..model.parameters import StopParameter
from . import jet_taylor, taylor, tps

#: how far (relative) the flight's end may lie from the impact the series solve for (the
#: shift's series, cut at order K in s, is exact near 0 only), and how often it is moved
TIME_TOL = 1e-12
TIME_TRIES = 4


# --------------------------------------------------------------------------- the impact
@nb.njit(cache=True)
def _horner(Z, S, out, tmp, MI, MJ, OFF):
    """out(delta) = sum_k Z[k](delta) S(delta)^k: a series in the time shift s, Z (K + 1,
    L), at s = S(delta) (Horner in s)."""
    L = out.shape[0]
    K = Z.shape[0] - 1
    for j in range(L):
        out[j] = Z[K, j]
    for k in range(K - 1, -1, -1):
        tps.mul(out, S, tmp, MI, MJ, OFF)
        for j in range(L):
            out[j] = tmp[j] + Z[k, j]


@nb.njit(cache=True)
def _impact_time(H, speed, St, hs, tmp, MI, MJ, OFF):
    """St(delta): the root of H(S(delta); delta) = 0, H a series in the time shift s,
    by K + 1 Newton iterations on series with the slope at delta = 0, the approach speed
    (each gains an order)."""
    L = St.shape[0]
    for j in range(L):
        St[j] = 0.0
    for _ in range(H.shape[0]):
        _horner(H, St, hs, tmp, MI, MJ, OFF)
        for j in range(L):
            St[j] -= hs[j] / speed


# --------------------------------------------------------------------------- Python side
class _Flight:
    """One series flight: its algebra, its state's series Y at its end T, the field and
    scratch of :mod:`symvi.flow.jet_taylor` (sy, tj), the series of omega and tau."""

    __slots__ = ("alg", "Y", "T", "sy", "tj", "omega", "tau")

    def __init__(self, alg, Y, T, sy, tj, omega, tau):
        self.alg, self.Y, self.T, self.sy, self.tj = alg, Y, T, sy, tj
        self.omega, self.tau = omega, tau

    def expansion(self):
        """(dim, K + 1, L): Z(T + s; delta) = sum_k out[:, k] s^k, exact to order K in (delta,
        s): the Taylor coefficients at the flight's end (:func:`jet_taylor.expansion`)."""
        return jet_taylor.expansion(self.sy, self.tj, self.T, self.Y, self.alg.K)


def _series(alg, value, var=None):
    a = np.zeros(alg.L)
    a[0] = value
    if var is not None:
        a[1 + var] = 1.0
    return a


def flight_series(flow, omega, z0, tau, T, order, B, *, omega_var=False, param=None,
                  dz0=None):
    """The flight's series z(T; delta) (mass order, rows; :class:`_Flight`) from z0 + B
    delta_state at phase tau, by the Taylor method on series (:mod:`symvi.flow.jet_taylor`).

    Variables, in order: the columns of ``B`` (dim x m: how the start moves with each),
    the phase, then omega if ``omega_var``, then ``param`` (a
    :class:`symvi.model.parameters.Parameter` other than omega) if given; ``dz0`` (mass
    order) how the start moves with ``param`` (a stop's gap moves it on its section: the
    caller knows which section).  How the field moves with ``param`` is
    :func:`_field_rates`'s (none for a rigid stop's gap or restitution)."""
    if not float(T) >= 0:                    # the Taylor steps run forward only
        raise SingularCaseError("flight", f"a series flight over t = {float(T):.6g} < 0: "
                                "the series flights run forward only")
    B = np.asarray(B, dtype=float)
    m = B.shape[1]
    d = m + 1 + bool(omega_var) + (param is not None)
    alg = tps.algebra(d, order)
    dim = 2 * flow.n
    Y = np.zeros((dim, alg.L))
    Y[:, 0] = z0
    Y[:, 1:1 + m] = B
    itau = m
    iw = itau + 1 if omega_var else None
    ip = d - 1 if param is not None else None
    tau_s = _series(alg, tau, itau)
    om_s = _series(alg, omega, iw)
    tangent, dpars, pvar = None, None, None
    if param is not None:
        pvar = _series(alg, 0.0, ip)
        tangent, dpars = _field_rates(flow, param)
        if dz0 is not None:
            Y[:, 1 + ip] = dz0
    sy, tj = jet_taylor.system(flow, alg, om_s, tau_s, pvar, tangent, dpars,
                               wvar=bool(omega_var))
    steps = jet_taylor.integrate(sy, tj, Y, float(T), flow.hmax(omega, taylor.STEP_CAP))
    if steps < 0 or not np.all(np.isfinite(Y)):
        raise SingularCaseError("flight", f"the series flight over t = {T:.6g} did not "
                                "finish (a non-finite state or the step limit)")
    return _Flight(alg, Y, float(T), sy, tj, om_s, tau_s)


#: the parameters the series take (:func:`check_parameter`)
TAKEN = ("omega, a parameter of the forces, an entry of M, K, C, P, a rigid stop's gap or "
         "restitution, or an elastic stop's gap, stiffness or damping")


def check_parameter(model, param):
    """``param`` (a :class:`symvi.model.parameters.Parameter`) when the series of a flight
    of ``model`` (nonlinear forces) take it as a variable, else the one-line
    ParameterError naming "param": the one owner of what they take (a curve's front end
    asks before it computes, :func:`symvi.curves.curve_params`; the shooting system of
    :class:`symvi.orbits.periodic.Problem` asks at its entry).  They take :data:`TAKEN`:
    omega, a force's parameter (a variable of the forces' program), and any parameter
    whose tangent moves M, K, C, P, a stop's gap, restitution, stiffness or damping, each
    linearly (:class:`symvi.model.parameters.Tangent`): the field of a free flight or of a
    contact phase (K_S, C_S, f_S: :meth:`symvi.flow.nlcontact.NonlinearPhase.rates`), the
    start's section, the guard's level and the reset (:func:`impact_series`)."""
    if param.is_forcing_frequency or _force_slot(model, param) is not None:
        return param
    try:
        if isinstance(param, StopParameter):
            param.stop_of(model)             # the model has that stop, and that number
        param.tangent(model)                 # a force's parameter of another model: none
    except ParameterError:
        raise ParameterError("param", param.name, TAKEN) from None
    return param


def _field_rates(flow, param):
    """(tangent, dpars): how the field of a series flight of ``flow`` (a
    :class:`symvi.flow.nonlinear.NonlinearFlow` or a contact phase,
    :class:`symvi.flow.nlcontact.NonlinearPhase`) moves along ``param``: the tangent of
    the M, K, C, P it reads (a phase's K_S, C_S: its ``rates``) and the rate of each
    parameter slot of the forces' program (a force's parameter; a phase's -f_S)."""
    model = getattr(flow, "source", flow.model)      # a phase's Model
    slot = _force_slot(model, param)
    if slot is not None:
        dpars = np.zeros(len(flow.pars))
        dpars[slot] = 1.0
        return None, dpars
    tan = check_parameter(model, param).tangent(model)
    rates = getattr(flow, "rates", None)
    return rates(tan) if rates is not None else (tan, None)


def _stop_tangent(model, param):
    """The tangent of ``param`` when it moves a stop's gap or restitution (the flight's
    ends; an elastic stop's gap moves its phases' field too, :func:`_field_rates`), else
    None."""
    if param is None or param.is_forcing_frequency or _force_slot(model, param) is not None:
        return None
    tan = param.tangent(model)
    return tan if (tan.db or tan.dr) else None


def _reset_moves(model, k, param):
    """Whether ``param`` moves constraint k's reset: its restitution, or the masses for an
    impulse along M^-1 c (:meth:`symvi.model.Constraint.reset_matrix`); an elastic
    constraint has none (the identity)."""
    if param is None or param.is_forcing_frequency or _force_slot(model, param) is not None:
        return False
    tan = param.tangent(model)
    con = model.constraints[k]
    if con.kind == "elastic":
        return False
    return bool((tan.dr and tan.stop == k) or
                (con.impulse is None and np.any(np.asarray(tan.dM) != 0)))


def _reset_series(view, fl, k, param, vm):
    """v+ = R(p) v- on series (flow order in and out) for constraint k: the law of
    :meth:`symvi.model.Constraint.reset_matrix`, R = I - (1 + r) q c^T / (c^T q), with r(p)
    = r + p dr and q(p) = M(p)^-1 c (the flight's M(p)^-1 series) or the fixed impulse."""
    alg, n = fl.alg, view.n
    L, K = alg.L, alg.K
    MI, MJ, OFF = alg.mul
    model = view.model
    con = model.constraints[k]
    tan = param.tangent(model)
    v = view.S[n:, n:] @ vm                   # mass order
    c = np.asarray(con.normal, dtype=float)
    # the flight's field (jet_taylor.system): M^-1, and M(p)^-1 as series W when M moves
    Minv, _, _, _, _, _, _, _, W, _, _, _, _, _, mass_moves, _ = fl.sy
    q = np.zeros((n, L))
    if con.impulse is not None:
        q[:, 0] = con.impulse
    elif mass_moves:
        q = np.tensordot(W, c, axes=([1], [0]))
    else:
        q[:, 0] = Minv @ c
    inv, u, tmp, cs = np.zeros(L), np.zeros(L), np.zeros(L), np.zeros(K + 1)
    tps.apply(tps.RECIP, c @ q, inv, u, tmp, cs, K, MI, MJ, OFF)      # 1 / (c^T q)
    one_r = _series(alg, 1.0 + con.restitution)
    if tan.dr and tan.stop == k:
        one_r[alg.d] += tan.dr                # the parameter: the last variable
    a, coef = np.zeros(L), np.zeros(L)
    tps.mul(c @ v, inv, a, MI, MJ, OFF)
    tps.mul(a, one_r, coef, MI, MJ, OFF)      # (1 + r) (c^T v) / (c^T q)
    vp = v.copy()
    for i in range(n):
        tps.mul(q[i], coef, a, MI, MJ, OFF)
        vp[i] -= a
    return view.Sinv[n:, n:] @ vp


def _force_slot(model, param):
    """The index of a named force parameter among the forces' parameters, else None."""
    names = () if model._nl is None else model._nl.names
    return list(names).index(param.name) if param.name in names else None


def flight_first(flow, omega, z0, tau, T, *, omega_var=False, param=None):
    """(z, dz/dz0, dz/dtau, dz/dt, dz/dp) of the flight from z0 (mass order) over T: the
    first-order series (the variational equations); dz/dp along omega or ``param`` (None
    when neither is asked for)."""
    dim = 2 * flow.n
    Y = flight_series(flow, omega, z0, tau, T, 1, np.eye(dim), omega_var=omega_var,
                      param=param).Y
    z = Y[:, 0].copy()
    Phi = Y[:, 1:1 + dim].copy()
    dzt = Y[:, 1 + dim].copy()
    dzp = Y[:, 2 + dim].copy() if (omega_var or param is not None) else None
    dzdt = flow.rhs(omega, tau, T, z)
    return z, Phi, dzt, dzdt, dzp


def impact_series(view, omega, y, T, order, start, end, *, omega_var=False, param=None):
    """(alg, P, te, speed): the series of the impact map's section point after the flight
    from section point ``y`` of constraint ``start`` (its layout, last the phase) that ends
    on constraint ``end`` near time T (its exact time is solved here: the flight is
    integrated again to the impact when it lies farther than TIME_TOL T, at most
    TIME_TRIES times), in the variables (y, [omega], [p]); ``speed`` the approach speed
    at the impact.  ``view`` a :class:`FlowView`: the constraints' guards, resets and
    section layouts are its flow order's."""
    T = float(T)
    for _ in range(TIME_TRIES):
        out = _impact_series(view, omega, y, T, order, start, end, omega_var, param)
        if abs(out[2] - T) <= TIME_TOL * max(T, 1.0):
            return out[:4]
        T = out[2]
    raise ParameterError("te", T, "the flight's impact time (the guard is not 0 there: "
                         f"the impact is {out[2] - T:.3g} away)")


def _impact_series(view, omega, y, T, order, start, end, omega_var, param):
    flow = view.nl
    n, dim = flow.n, 2 * flow.n
    rows = view.rows
    pa, fa = view.positions[start], view.frames[start]
    # the start in flow order: x_pa on its section, the other coordinates the point's
    w0 = np.zeros(dim)
    w0[pa] = rows[start][1]
    w0[fa] = y[:-1]
    E = np.zeros((dim, dim - 1))
    E[fa, np.arange(dim - 1)] = 1.0
    S = view.S
    # a stop's gap or restitution (its tangent, else None): the flight's ends move
    model = view.model
    stan = _stop_tangent(model, param)
    dz0 = None
    if stan is not None and stan.db and stan.stop == start:
        dz0 = np.zeros(dim)
        dz0[pa] = stan.db                     # the start's section x_a = b
        dz0 = S @ dz0
    fl = flight_series(flow, omega, S @ w0, float(y[-1]), T, order, S @ E,
                       omega_var=omega_var, param=param, dz0=dz0)
    alg = fl.alg
    K, L = alg.K, alg.L
    # Z(T + s; delta) = sum_k Z[:, k] s^k in flow order
    Z = (view.Sinv @ fl.expansion().reshape(dim, -1)).reshape(dim, K + 1, L)
    # the impact time: h(Z(S(delta); delta)) = 0, h = guard . x - level
    row = rows[end]
    guard, level = row[3:3 + n], row[2]
    H = np.tensordot(guard, Z[:n], axes=1)
    H[0, 0] -= level
    if stan is not None and stan.db and stan.stop == end:
        # the level sign b moves (the parameter is the last variable: monomial d), -sign b
        # on an exit's guard -h
        flip = -1.0 if end in view.exits else 1.0
        H[0, alg.d] -= flip * model.constraints[end].sign * stan.db
    speed = float(H[1, 0])
    if not speed > 0:
        raise SingularCaseError("grazing", f"the approach speed at the impact is {speed:.3g}: "
                                "the impact time is not a smooth function of the start "
                                "(grazing, eq. (30))")
    St, hs, tmp = np.zeros(L), np.zeros(L), np.zeros(L)
    MI, MJ, OFF = alg.mul
    _impact_time(H, speed, St, hs, tmp, MI, MJ, OFF)
    ze = np.zeros((dim, L))
    for i in range(dim):
        _horner(Z[i], St, ze[i], tmp, MI, MJ, OFF)
    # the reset v+ = R(p) v- and the section point on constraint ``end``
    if _reset_moves(model, end, param):
        ze[n:] = _reset_series(view, fl, end, param, ze[n:])
    else:
        ze[n:] = row[3 + n:].reshape(n, n) @ ze[n:]
    out = np.zeros((dim, L))
    out[:dim - 1] = ze[view.frames[end]]
    phase = fl.tau.copy()
    tser = St.copy()
    tser[0] += T
    tps.mul_add(fl.omega, tser, phase, MI, MJ, OFF)
    out[dim - 1] = phase
    return alg, out, float(T + St[0]), speed


def map_jet(view, omega, y, T, order, start=0, end=0, *, param=None):
    """The jet of the impact map as :func:`symvi.codegen.jets.flight_jet` gives it: a dict
    with "P" (the image, phase not reduced), "J", "d2".."d<order>" (raw tensors over the
    section point), "te", "speed"; with ``param`` (a Parameter, omega included) also
    "dpP" = dP/dp and "dpJ" = dJ/dp at fixed y."""
    w = param is not None and param.is_forcing_frequency
    alg, P, te, speed = impact_series(view, omega, y, T, order, start, end, omega_var=w,
                                      param=None if (param is None or w) else param)
    m = len(y)
    ax = tuple(range(m))
    out = {"P": P[:, 0].copy(), "te": te, "speed": speed,
           "J": alg.tensor(P, 1, ax)}
    for k in range(2, order + 1):
        out[f"d{k}"] = alg.tensor(P, k, ax)
    if param is not None:
        out["dpP"] = P[:, 1 + m].copy()
        if order >= 2:
            both = alg.tensor(P, 2)
            out["dpJ"] = both[:, :m, m]
    return out


# --------------------------------------------------------------------------- the view
_VIEWS = {}


class NonlinearForcing:
    """The forcing of a nonlinear flow at omega: the frequency alone (no steady state)."""

    __slots__ = ("omega",)

    def __init__(self, omega):
        self.omega = omega


class FlowView:
    """The nonlinear flow as the shooting system of :mod:`symvi.orbits.periodic` reads a
    flow: in the linear flow's (stop-first) order, with its constraint data (guards,
    resets, levels, section frames: geometry, the same for the linear part), and the
    flights of the series (:func:`flight_first`).  Only the names in :data:`GEOMETRY`
    are taken from the linear part's flow; every flight comes from the nonlinear one."""

    GEOMETRY = frozenset(("reset", "guard", "level", "constraint_rows", "constraint64",
                          "constraint", "position", "perm", "framed", "to_mass", "to_flow",
                          "approach", "section_approach", "bk", "n", "b", "r", "_unit_guard",
                          "_constrain", "_reset_data", "_framed_reset", "_mass_key"))
    offset = None
    free = False
    #: the constraints whose guard is an exit's, -h (a contact phase's, :mod:`.nlcontact`)
    exits = frozenset()

    def __init__(self, model):
        from .compiled import section_index
        from .linear import LinearFlow
        from .nonlinear import NonlinearFlow
        self.model = model
        lin = self.lin = LinearFlow.of(model.linear_part)
        self.nl = NonlinearFlow(model)
        dim = 2 * model.n
        #: z_mass = S z_flow (a permutation, or T^-1 on positions and on velocities)
        self.S = np.array([lin.to_mass(e) for e in np.eye(dim)]).T
        self.Sinv = np.array([lin.to_flow(e) for e in np.eye(dim)]).T
        #: per constraint: (position, gap, level, guard, reset) in flow order, its position
        #: and the flow-order index of each section coordinate
        self.rows = [np.asarray(r, dtype=float) for r in lin.constraint_rows()]
        self.positions = tuple(int(r[0]) for r in self.rows)
        self.frames = tuple(section_index(model.n, q) for q in self.positions)

    @classmethod
    def of(cls, model):
        """The view of ``model``, built once (its flows and tables; cached like
        :meth:`LinearFlow.of`)."""
        from .linear import _memo
        return _memo(_VIEWS, model, lambda: cls(model), size=64)

    def __getattr__(self, name):
        if name in type(self).GEOMETRY:
            return getattr(self.lin, name)
        raise AttributeError(name)

    def check_omega(self, omega, name="omega", warn=True):
        from .linear import check_range
        return check_range(omega, name)

    def forcing(self, omega):
        return NonlinearForcing(float(omega))

    def flight(self, forcing, z0, tau, t, param=None):
        """(z, dz/dz0, dz/dtau, dz/dt) at t of the flight from z0 (flow order) at phase
        tau, :meth:`symvi.flow.linear.LinearFlow.flight`'s layout; with ``param`` (a
        Parameter) the derivative along it is appended."""
        S, Si = self.S, self.Sinv
        w = param is not None and param.is_forcing_frequency
        z, Phi, dzt, dzdt, dzp = flight_first(
            self.nl, forcing.omega, S @ z0, float(tau), float(t), omega_var=w,
            param=None if (param is None or w) else param)
        out = (Si @ z, Si @ Phi @ S, Si @ dzt, Si @ dzdt)
        return out if param is None else out + (Si @ dzp,)

    def motion(self, forcing, z0, tau):
        """The first contact of the flight from z0 (flow order), as
        :class:`symvi.flow.linear.Motion` gives it (``first_impact(t_max)``)."""
        return _Motion(self, forcing.omega, self.S @ z0, float(tau))

    def step(self, forcing, y, k=0):
        """(status, t, y', constraint met) of the impact map from section point y of
        constraint k, in the flow order's section layouts (:attr:`frames`)."""
        n, dim = self.n, 2 * self.n
        w = np.empty(dim)
        w[self.positions[k]] = self.rows[k][1]
        w[self.frames[k]] = y[:-1]
        st, te, c, ze = self.nl.first_impact(forcing.omega, self.S @ w, float(y[-1]),
                                             just_hit=k)
        if st != "impact":
            return st, te, None, c
        z = self.Sinv @ ze
        z[n:] = self.rows[c][3 + n:].reshape(n, n) @ z[n:]
        z[self.positions[c]] = self.rows[c][1]
        y1 = np.append(z[self.frames[c]], float(y[-1]) + forcing.omega * te)
        return st, te, y1, c


class _Motion:
    def __init__(self, view, omega, z0, tau):
        self.view, self.omega, self.z0, self.tau = view, omega, z0, tau

    def state(self, t):
        """z(t) (flow order), the constraints ignored (:meth:`NonlinearFlow.state`)."""
        return self.view.Sinv @ self.view.nl.state(self.omega, self.z0, self.tau, float(t))

    def h(self, t):
        """(h(t),): the first constraint's guard along the flight, as
        :meth:`symvi.flow.linear.Motion.h` gives it (value only)."""
        row, n = self.view.rows[0], self.view.n
        return (float(row[3:3 + n] @ self.state(t)[:n] - row[2]),)

    def first_impact(self, t_max=None, max_steps=None):
        from .linear import GRAZING, IMPACT, NO_IMPACT, FirstImpact
        view, nl = self.view, self.view.nl
        zf, k = view.Sinv @ self.z0, -1
        for c, row in enumerate(view.rows):        # the constraint z0 lies on, if any
            if abs(zf[view.positions[c]] - row[1]) <= 1e-12 * max(1.0, abs(row[1])):
                k = c
        st, te, c, ze = nl.first_impact(self.omega, self.z0, self.tau, t_max=t_max,
                                        just_hit=k)
        status = {"impact": IMPACT, "grazing": GRAZING}.get(st, NO_IMPACT)
        if status == NO_IMPACT and t_max is not None:
            te = max(te, t_max * (1 + 1e-9))   # ran to t_max: decided
        hit = FirstImpact(status, te, self.view.Sinv @ ze, 0)
        object.__setattr__(hit, "constraint", c)
        return hit
