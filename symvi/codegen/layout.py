"""The one input layout of the generated impact-map jets (``generated/impact_n<N>_order<K>``).

The generated functions take, in the order of the module's ``INPUTS``
(:func:`derivations.impact_jets.inputs`):

    E_k = Phi(t_e) A^k (k = 0..K, row-major), U, V, [dU, dV, pE_0, pE_1, pU, pV],
    omega, g0, level, R_i0 (N), [plevel, pR_i0 (N)], y (2N), t_e

(bracketed groups for K = 2, 3 only; orders 4, 5 hold state derivatives alone,
for l2): the flow matrices of :mod:`symvi.flow.linear`,
the steady-state response and its omega-derivative, and the derivative of all
of these along one named parameter p (``pX = dX/dp``), exact: the Fréchet
derivative of the matrix exponential (eigen-decomposition form), the
derivative of the steady-state solve, and the model's :class:`symvi.model.Tangent`.

The constraint enters as its guard h = g0 x_0 - level and the column 0 of its reset
v+ = R v- (:func:`jet_constraint`), with their derivatives along p
(:func:`reset_tangent`): one generated structure per N and order serves every
single rigid constraint the flow's section supports (a stop on any mass, either
side, an impulse along M^-1 c for a non-diagonal M).
"""
import importlib
from dataclasses import replace

import mpmath
import numpy as np

from ..errors import ParameterError
from ..flow.linear import contact_tangent
from ..numerics.backend import FLOAT64
from ._assemble import assemble64

_LOADED = {}
#: orders whose modules take the parameter groups (derivations.impact_jets.has_parameters)
PARAMETER_ORDERS = (2, 3)


def _user_dir():
    """The per-user cache of generated code (:func:`symvi.codegen._usercache.cache_dir`)."""
    from ._usercache import cache_dir
    return cache_dir()


def module(n, order, start=None):
    """The generated module of structure n, order K: shipped in ``symvi._generated``
    (orders 1-3 of N = 1..4, orders 4-5 of N = 1, 2), else generated on first use
    into the per-user cache.  ``start`` s: the variant whose flight starts on the section
    of coordinate s (another constraint's), shipped for the same N and orders."""
    key = (n, order, start)
    if key not in _LOADED:
        name = f"impact_n{n}_order{order}" if start is None else \
            f"impact_n{n}_s{start}_order{order}"
        try:
            mod = importlib.import_module(f"symvi._generated.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"symvi._generated.{name}":
                raise
            mod = _user_module(n, order, name, start)
        _LOADED[key] = (mod, {k: np.asarray(v) for k, v in mod.LAYOUT.items()})
    return _LOADED[key]


def _user_module(n, order, name, start=None):
    # generated on first use, run only after the checks of symvi.codegen._usercache
    from ._usercache import load
    return load(n, order, start)


def frechet_kernel(lt, ex, t):
    """G_ij = t (e^{lt_i} - e^{lt_j}) / (lt_i - lt_j), t e^{lt_j} where lt_i = lt_j, in
    float64 (``ex`` = e^{lt}): the kernel of the Fréchet derivative of e^{At} in modal
    form.  The larger exponential is factored out, so expm1 never overflows (a stiff mode:
    Re(l_i - l_j) t > 709 gave inf * 0 = NaN): (e^a - e^b)/(a - b) with Re a > Re b is
    e^a (1 - e^{b-a})/(a - b)."""
    diff = lt[:, None] - lt[None, :]
    safe = np.where(diff == 0, 1, diff)
    pos = diff.real > 0
    arg = np.where(pos, -diff, diff)
    scale = np.where(pos, -ex[:, None], ex[None, :])
    return np.where(diff == 0, ex[None, :], np.expm1(arg) / safe * scale) * t


def frechet_exp(flow, t, dA):
    """d/de e^{(A + e dA) t} at e = 0, by the eigen-decomposition of A:
    W (G o (W^-1 dA W)) W^-1, G_ij = t (e^{l_i t} - e^{l_j t}) / ((l_i - l_j) t).
    With a mass on no spring A has a Jordan block and no eigenbasis: then the upper right
    block of exp([[A, dA], [0, A]] t) [Van Loan, IEEE Trans. Autom. Control 23 (1978)
    395-404; Higham, Functions of Matrices, SIAM 2008, eq. (3.16)]."""
    bk = flow.bk
    if flow.free:
        return _frechet_block(flow, t, dA)
    lt = flow.lam * t
    ex = bk.vexp(lt)
    m = len(lt)
    if bk is FLOAT64:
        G = frechet_kernel(lt, ex, t)
    else:
        G = np.empty((m, m), dtype=object)
        for i in range(m):
            for j in range(m):
                d = lt[i] - lt[j]
                G[i, j] = t * ex[j] * (mpmath.expm1(d) / d if d != 0 else 1)
    return bk.vreal(flow.W @ (G * (flow.Winv @ dA @ flow.W)) @ flow.Winv)


def _frechet_block(flow, t, dA):
    """The Frechet derivative of e^{At} in the direction dA as the upper right block of
    e^{[[A, dA], [0, A]] t} (:func:`frechet_exp`): scipy's expm in float64, mpmath's at
    the flow's precision."""
    bk, d = flow.bk, 2 * flow.n
    Z = np.zeros((d, d), dtype=object if bk is not FLOAT64 else float)
    B = np.block([[np.asarray(flow.A), np.asarray(dA)], [Z, np.asarray(flow.A)]])
    if bk is FLOAT64:
        from scipy.linalg import expm
        return expm(B * float(t))[:d, d:]
    E = mpmath.expm(mpmath.matrix(B.tolist()) * t)
    return np.array([[E[i, d + j] for j in range(d)] for i in range(d)], dtype=object)


def tangent_data(flow, forcing, te, tangent):
    """(pE_0, pE_1, pU, pV, pr, pb) along a :class:`symvi.model.Tangent` (stop-first order);
    the generated jets take the constraint's part through :func:`reset_tangent`."""
    bk, n = flow.bk, flow.n
    moves_A = any(np.any(np.asarray(a)) for a in (tangent.dM, tangent.dK, tangent.dC))
    dM, dK, dC, dP = (bk.arr(flow.framed(a)) for a in
                      (tangent.dM, tangent.dK, tangent.dC, tangent.dP))
    Minv = flow.Minv
    dMinv = -(Minv @ dM @ Minv)
    Z = bk.arr(np.zeros((n, n)))
    dA = np.block([[Z, Z], [-(dMinv @ flow.K + Minv @ dK), -(dMinv @ flow.C + Minv @ dC)]])
    # a gap, a restitution or a forcing amplitude leaves A (and e^{At}) alone
    dPhi = frechet_exp(flow, te, dA) if moves_A else bk.arr(np.zeros((2 * n, 2 * n)))
    Phi = flow.phi(te)
    pE0 = dPhi
    pE1 = dPhi @ flow.A + Phi @ dA
    w = forcing.omega
    i = 1j if bk is FLOAT64 else mpmath.mpc(0, 1)
    D = flow.K - w * w * flow.M + i * w * flow.C
    X = forcing.U + i * forcing.V
    dX = bk.solve(D, dP - (dK - w * w * dM + i * w * dC) @ X)
    return pE0, pE1, bk.vreal(dX), bk.vreal(-i * dX), tangent.dr, tangent.db


def phase_tangent(flow, tangent):
    """(the tangent of a contact phase's matrices, d zs) along a :class:`Tangent`, for the
    flow of a contact phase (:meth:`symvi.flow.linear.LinearFlow.contact`): dK_S = dK +
    dk c c^T and dC_S = dC + dc c c^T for the constraint in contact whose stiffness (dk)
    or damping (dc) moves, and, from zs = (K_S^-1 f_S, 0) with f_S = sum k_i g_i c_i,
    d xs = K_S^-1 (df_S - dK_S xs) (flow order); the contact law's derivative is
    :func:`symvi.flow.linear.contact_tangent`'s."""
    n = flow.n
    dK, dC, df = contact_tangent(flow.model, flow.active, tangent)
    xs = np.asarray(flow.offset[:n], dtype=float)
    dxs = np.linalg.solve(np.asarray(flow.K, dtype=float),
                          flow.framed(df) - flow.framed(dK) @ xs)
    return replace(tangent, dK=dK, dC=dC), np.concatenate([dxs, np.zeros(n)])


def jet_constraint(flow):
    """(g0, level, R[:, 0]) of the flow's constraint as the generated structures take them
    (:meth:`symvi.flow.linear.LinearFlow._constrain`, flow order): the guard
    h = g0 x_0 - level and the column 0 of the reset v+ = R v- (R is the identity but
    for that column: a rigid reset is I - (1 + r) q c^T / (c^T q) and c = +-e_0 in the
    section's frame).  Anything else is refused by name, never given wrong jets."""
    flow.model.require_one_rigid_stop()
    g, R = flow.guard, np.asarray(flow.reset)
    n = flow.n
    if not (g[0] != 0 and all(x == 0 for x in g[1:])):
        raise ParameterError("constraint.normal", flow.constraint.normal,
                             "a normal along the section's first coordinate (a stop on one "
                             "mass; other normals: the several-constraint jets, "
                             "flight_jet)")
    if not all(R[i, j] == (1 if i == j else 0) for i in range(n) for j in range(1, n)):
        raise ParameterError("constraint.impulse", flow.constraint.impulse,
                             "a reset along the guard's normal (R = I - (1 + r) q c^T / c^T q)")
    return g[0], flow.level, R[:, 0]


def _constraint_of(flow):
    """:func:`jet_constraint`, checked once per guard and reset of a flow: kept on the flow
    beside the very arrays it read (``_constrain`` puts new ones, or the shared ones of an
    equal constraint, on a flow for a new gap or restitution), so it never goes stale; the
    check costs ~7 us, a jet of order 1 ~15 us.  The level is read each time."""
    c = getattr(flow, "_jet_constraint", None)
    if c is None or c[0] is not flow.reset or c[1] is not flow.guard:
        g0, _, R0 = jet_constraint(flow)
        c = flow._jet_constraint = (flow.reset, flow.guard, g0, R0)
    return c[2], flow.level, c[3]


def reset_derivative(flow, con, dr, dM):
    """dR/dp of ``con``'s reset in the flow's order, for a restitution rate ``dr`` and a mass
    tangent ``dM`` (mass order): the one owner of the law's derivative (:func:`reset_tangent`
    takes its column 0, the shooting system all of it).

    R = (I - Q) - r Q gives dR = -dr Q - (1 + r) dQ; Q = q c^T / (c^T q) moves only with a
    rigid impulse q = M^-1 c along a mass tangent: dq = -M^-1 dM q,
    dQ = dq c^T / (c^T q) - Q (c^T dq) / (c^T q)."""
    bk = flow.bk
    if con.kind == "elastic":              # an entry or an exit: no jump, nothing moves
        return bk.arr(np.zeros((flow.n, flow.n)))
    Minv = None
    if con.impulse is None:
        Minv = bk.inv(bk.arr(np.asarray(flow.model.mass)))
    c = bk.arr(np.asarray(con.normal, dtype=float))
    q = con.direction(Minv)
    cq = c @ q
    Q = np.outer(q, c) / cq
    dR = -bk.num(dr) * Q
    dM = np.asarray(dM, dtype=float)
    if con.impulse is None and np.any(dM != 0):
        dq = -(Minv @ bk.arr(dM) @ q)
        dQ = np.outer(dq, c) / cq - Q * ((c @ dq) / cq)
        dR = dR - (1 + (flow.r if con is flow.constraint else bk.num(con.restitution))) * dQ
    return flow.framed_velocity(dR)


def reset_tangent(flow, tangent, con=None, order=None):
    """(d level/dp, dR[:, 0]/dp) along a :class:`symvi.model.Tangent` (flow order), of the
    flow's constraint or of ``con`` in the order ``order`` (positions of the flow's order,
    its coordinate first): level = sign b, so d level = sign db; dR by
    :func:`reset_derivative`."""
    con = flow.constraint if con is None else con
    dR = reset_derivative(flow, con, tangent.dr, tangent.dM)
    q = list(range(flow.n)) if order is None else list(order)
    return con.sign * flow.bk.num(tangent.db), dR[np.ix_(q, q)][:, 0]


def assemble(flow, forcing, y, te, order, tangent=None):
    """The input tuple of ``impact_n<N>_order<K>`` at section point y with flight time te."""
    bk = flow.bk
    g0, level, R0 = _constraint_of(flow)
    if bk is FLOAT64 and (tangent is None or tangent.zero) and not flow.free:
        lam, W, Winv, A = flow.modal64
        F = forcing
        # constraint64 = (b, level, guard, R row-major): the compiled kernels' layout
        return tuple(assemble64(lam, W, Winv, A, F.U, F.V, F.dU, F.dV, float(F.omega),
                                flow.constraint64, np.asarray(y, dtype=float),
                                float(te), order, order in PARAMETER_ORDERS).tolist())
    parts = [E.ravel() for E in flow.phis(te, order)]
    parts += [forcing.U, forcing.V]
    scal_p = []
    if tangent is not None and not tangent.zero and order not in PARAMETER_ORDERS:
        raise ParameterError("order", order, "2 or 3 with a parameter tangent")
    if order in PARAMETER_ORDERS:
        parts += [forcing.dU, forcing.dV]
        if tangent is None or tangent.zero:
            z = bk.arr(np.zeros((2 * flow.n) ** 2))
            zn = bk.arr(np.zeros(flow.n))
            parts += [z, z, zn, zn]
            scal_p = [bk.num(0)] * (1 + flow.n)
        else:
            pE0, pE1, pU, pV, _, _ = tangent_data(flow, forcing, te, tangent)
            parts += [pE0.ravel(), pE1.ravel(), pU, pV]
            plevel, pR = reset_tangent(flow, tangent)
            scal_p = [plevel] + list(np.asarray(pR).ravel())
    head = np.concatenate(parts) if bk is FLOAT64 else list(np.concatenate(parts))
    tail = [forcing.omega, g0, level] + list(R0) + scal_p + list(y) + [bk.num(te)]
    if bk is FLOAT64:
        return tuple(head.tolist()) + tuple(float(v) for v in tail)
    return tuple(head) + tuple(tail)


def flight_frame(flow, rows, ka, kb):
    """(I, s, pi) of a flight from constraint ka's section to constraint kb's
    (``rows``: :meth:`LinearFlow.constraint_rows`): I the state order of kb's frame
    (its coordinate first, then the flow's order), s the position of ka's coordinate in
    it, and pi with y_var = y[pi]: the start point in the layout of the generated
    variant ``impact_n<N>_s<s>`` (v_s, x_j and v_j for j != s in kb's frame, tau) from
    the layout of ka's section (:func:`symvi.flow.compiled.section_index`)."""
    from ..flow.compiled import section_index
    n = flow.n
    pa, pb = int(rows[ka][0]), int(rows[kb][0])
    Qb = [pb] + [j for j in range(n) if j != pb]
    s = Qb.index(pa)
    ia = list(section_index(n, pa))
    others = [Qb[j] for j in range(n) if j != s]
    want = [n + pa] + others + [n + j for j in others]
    pi = np.array([ia.index(k) for k in want] + [2 * n - 1])
    return np.array(Qb + [n + j for j in Qb]), s, pi


def assemble_flight(flow, forcing, y, te, order, ka, kb, tangent=None):
    """The input tuple of ``impact_n<N>_s<s>_order<K>`` for the flight from point y of
    constraint ka's section (its layout) that ends on constraint kb: the flow's matrices
    and the forcing in kb's frame, kb's guard and reset, ka's level b0, and y in the
    variant's layout (float64).  Returns (inputs, s, pi, dzs) (:func:`flight_frame`; dzs
    the motion of a contact phase's offset along ``tangent``, :func:`phase_tangent`, which
    the outputs need too, else None)."""
    from ..flow.compiled import table
    rows = table(flow)
    n = flow.n
    I, s, pi = flight_frame(flow, rows, ka, kb)
    Qb = I[:n]
    ix = np.ix_(I, I)
    parts = [E[ix].ravel() for E in flow.phis(te, order)]
    parts += [np.asarray(forcing.U)[Qb], np.asarray(forcing.V)[Qb]]
    con_a, con_b = flow.model.constraints[ka], flow.model.constraints[kb]
    rb = rows[kb]
    g0, level = rb[3 + int(rb[0])], rb[2]
    R = rb[3 + n:].reshape(n, n)[np.ix_(Qb, Qb)]
    if not all(R[i, j] == (1 if i == j else 0) for i in range(n) for j in range(1, n)):
        raise ParameterError("constraint.impulse", con_b.impulse,
                             "a reset along the guard's normal (R = I - (1 + r) q c^T / c^T q)")
    b0 = con_a.gap
    yv = np.asarray(y, dtype=float)
    if flow.offset is not None:
        # a contact phase: in z - zs its flow has no constant force, and a translation
        # leaves every derivative of the map as it is (LinearFlow.contact)
        from ..flow.compiled import section_index
        zs = np.asarray(flow.offset, dtype=float)
        pa = int(rows[ka][0])
        level, b0 = level - g0 * zs[int(rb[0])], b0 - zs[pa]
        yv = yv.copy()
        yv[:-1] = yv[:-1] - zs[np.asarray(section_index(n, pa))]
    scal = [float(forcing.omega), g0, level] + list(R[:, 0]) + [b0]
    dzs = None
    if order in PARAMETER_ORDERS:
        parts += [np.asarray(forcing.dU)[Qb], np.asarray(forcing.dV)[Qb]]
        d2 = (2 * n) ** 2
        if tangent is None or tangent.zero:
            parts += [np.zeros(d2), np.zeros(d2), np.zeros(n), np.zeros(n)]
            scal += [0.0] * (n + 2)
        else:
            tan, dzs = (tangent, None) if flow.offset is None else phase_tangent(flow, tangent)
            pE0, pE1, pU, pV, _, db = tangent_data(flow, forcing, te, tan)
            parts += [pE0[ix].ravel(), pE1[ix].ravel(), np.asarray(pU)[Qb], np.asarray(pV)[Qb]]
            # the gap and restitution of the tangent's stop move kb's guard and reset only
            # if it is kb (a mass tangent moves every rigid reset, q = M^-1 c)
            tb = tangent if tangent.stop == kb else replace(tangent, db=0.0, dr=0.0)
            plevel, pR = reset_tangent(flow, tb, con_b, list(Qb))
            pb0 = db if tangent.stop == ka else 0.0
            if dzs is not None:                  # the shifted levels move with zs
                plevel, pb0 = plevel - g0 * dzs[int(rb[0])], pb0 - dzs[int(rows[ka][0])]
            scal += [plevel] + list(np.asarray(pR, dtype=float))
            scal += [pb0]
    elif tangent is not None and not tangent.zero:
        raise ParameterError("order", order, "2 or 3 with a parameter tangent")
    yv = yv[pi]
    head = np.concatenate(parts)
    return tuple(head.tolist()) + tuple(float(v) for v in scal) + tuple(yv.tolist()) + (
        float(te),), s, pi, dzs
