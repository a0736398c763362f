"""Period-1 one-impact orbits of any model, in closed form (eqs. (10)–(18) generalised).

With T = 2 pi / omega, Phi = e^{A T} and the steady-state response
zp(0) = cos(tau) P_c + sin(tau) P_s (P_c = (V, omega U), P_s = (U, -omega V)),
write the state just after the impact as z0 = w + zp(0).  The flight returns
after exactly one period, z(T) = Phi w + zp(0), and the impact law is
z0 = E z(T), E = diag(1, ..., 1, -r, 1, ..., 1) (-r on v_k).  With x_k(0) = b::

    (I - E Phi) w + (I - E) (c P_c + s P_s) = 0,     e_k^T w + c P_c[k] + s P_s[k] = b,

2N + 1 linear equations in the 2N + 2 unknowns (w, c, s).  Their solutions form a
line (w, c, s) = X_p + mu n (n spans the kernel); c^2 + s^2 = 1 cuts it in at
most two points: the two branches.  This is the paper's rho cos(tau - phi) =
alpha b of eq. (16) for any N, damping and stop; unlike eliminating w first it
stays regular at r = 1 (where I - E Phi is singular).

Branches: the line is nu . (c, s) = rho with nu the unit normal pointing *against*
the gradient of x_k(0) in (cos tau, sin tau) on the fixed-point set, so that
tau = arg(nu) +- arccos(rho): "+" and "-" as the paper's tau0 = phi +- arccos(alpha b / rho)
(its alpha = (1 - r) w1 w2 D is negative in its sign convention, D < 0).  At r = 1
with no damping alpha = 0: b no longer moves the line and that gradient's sign is
rounding noise, so the orientation is the limit r -> 1- (taken at r - 1e-6), which
keeps the names continuous in omega and equal to the paper's.

In float64 all of this, and the multipliers (the eigenvalues of the monodromy of
the shooting problem with u = (y, T), eq. (30)), come from one compiled call
(:mod:`symvi.orbits._period1`); admissibility is :func:`check_flight` with the
compiled first-impact finder.  ``COMPILED = False`` selects the numpy reference
(:class:`_Line`, :meth:`Motion.first_impact`, the generated order-1 jets), which
gives the same results to rounding; mpmath (``digits``) always runs the reference.
"""
import math
import warnings
from dataclasses import dataclass, field

import mpmath
import numpy as np

from ..errors import NearSingularWarning, ParameterError, SingularCaseError
from ..flow.linear import LinearFlow
from ..numerics.backend import FLOAT64
from ..maps.section import Section
#: |1 - e^{lambda_j T}| below which the period-1 orbit is refused as not isolated / warned about
from ..numerics.tolerances import EPS64, ISOLATION_REFUSE, ISOLATION_WARN
from . import _period1
from ._shooting import CompiledFinder
from .admissibility import END_TOL, check_flight, neutral, stable_of
#: |nu . p1| (relative) below which the branch orientation is taken from r - ORIENT_DR
ORIENT_NOISE = 1e-12
ORIENT_DR = 1e-6
#: float64 orbits from the compiled kernel (False: the numpy reference, same results)
COMPILED = True
#: the stop mass's steady amplitude |X_k|, relative to the largest |X_i|, below which it
#: is compared with the rounding level of the steady-state solve (and warned about)
STOP_FORCING_WARN = 1e-6


@dataclass(frozen=True)
class Orbit:
    """A period-1 one-impact orbit of a model at omega: the fixed point y of P.

    ``y`` follows :class:`symvi.maps.Section` (names in ``names``).  Numbers
    are float, or mpf when computed with ``digits``.  What :func:`symvi.period1_orbits`
    returns for a :class:`symvi.Model` (for the paper's :class:`symvi.Params`, a
    subclass with the paper's names); immutable.

    Attributes
    ----------
    model : Model
        The model of the orbit.
    omega : float
        The forcing frequency.
    branch : str
        "+" or "-": tau0 = phi +- arccos(alpha b / rho), the paper's two solutions of
        eq. (16).
    y : tuple
        The fixed point of the impact map P just after the impact, 2N numbers:
        (v_k+, x_j for j != k, v_j for j != k, tau) with k the stop's mass, tau the
        forcing phase in [0, 2 pi) (eq. (9) for the paper's model).
    names : tuple of str
        The names of the components of ``y``, e.g. ``("v1+", "x2", "v2", "tau")``.
    impact_velocity : float
        The stop mass's velocity just before the impact, v_k- at t = 2 pi / omega;
        > 0 on the physical branch.
    admissible : bool
        Whether the orbit is physical: it arrives moving towards the stop and meets no
        stop during the flight (the first-impact finder over (0, 2 pi / omega)).
    reason : str
        Why it is not admissible ("" when it is).
    multipliers : tuple of complex
        Eigenvalues of DP at y, eq. (36), sorted by modulus, largest first; empty when
        computed with ``multipliers=False``.
    stable : bool
        Admissible and every multiplier inside the unit circle (never, for a conservative
        model: its map preserves volume).
    neutral : bool
        A conservative model's orbit with every multiplier on the unit circle (elliptic).
    digits : int or None
        The mpmath precision the orbit was computed at (None: float64).
    tau0 : float
        The impact phase, ``y[-1]``.

    Examples
    --------
    >>> from symvi import Model, period1_orbits
    >>> m = Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    >>> o = period1_orbits(m, 0.72)[0]
    >>> o.names
    ('v1+', 'x2', 'v2', 'tau')
    >>> o.branch, o.admissible, round(float(o.impact_velocity), 6)
    ('+', True, 1.868924)
    >>> max(abs(z) for z in o.multipliers) < 1
    True
    """

    model: object = field(repr=False)
    omega: object
    branch: str
    y: tuple
    names: tuple
    impact_velocity: object   # v_k- at t = T, > 0 on the physical branch
    admissible: bool
    reason: str
    multipliers: tuple = ()
    stable: bool = False
    digits: object = None

    @property
    def tau0(self):
        return self.y[-1]

    @property
    def neutral(self):
        return neutral(self.multipliers, self.model)

    def as_dict(self):
        return {"branch": self.branch, "y": [float(v) for v in self.y],
                "names": list(self.names), "impact_velocity": float(self.impact_velocity),
                "admissible": bool(self.admissible), "reason": self.reason,
                "multipliers": [[float(complex(z).real), float(complex(z).imag)]
                                for z in self.multipliers],
                "stable": bool(self.stable), "neutral": self.neutral}


class _Line:
    """The solution line of the period-1 conditions at one omega."""

    def __init__(self, flow, omega, restitution=None):
        bk = flow.bk
        n2 = 2 * flow.n
        self.flow, self.omega = flow, omega
        T = 2 * bk.pi / omega
        F = self.forcing = flow.forcing(omega)
        self.Phi = flow.phi(T)
        self.Pc = np.concatenate([F.V, omega * F.U])
        self.Ps = np.concatenate([F.U, -omega * F.V])
        one = 1 if bk is FLOAT64 else mpmath.mpf(1)
        E = _state_reset(flow, restitution)
        I = bk.arr(np.eye(n2))
        IE = I - E
        G = np.zeros((n2 + 1, n2 + 2), dtype=object if bk is not FLOAT64 else float)
        G[:n2, :n2] = I - E @ self.Phi
        G[:n2, n2] = IE @ self.Pc
        G[:n2, n2 + 1] = IE @ self.Ps
        g = flow.guard                             # the impact condition g . x(0) = level
        G[n2, :flow.n] = g
        G[n2, n2] = g @ self.Pc[:flow.n]
        G[n2, n2 + 1] = g @ self.Ps[:flow.n]
        if bk is not FLOAT64:
            G[G == 0] = mpmath.mpf(0)
        # equilibrate the columns: near forcing resonance (U, V) ~ 1 / |omega_j - omega|
        # dwarfs the I - E Phi block, and the rank test must not read that as degeneracy
        if bk is FLOAT64:
            D = np.linalg.norm(G, axis=0)
        else:
            D = np.array([bk.sqrt(sum(x * x for x in G[:, j])) for j in range(n2 + 2)],
                         dtype=object)
        # a zero (or underflowing) column stays as it is: the rank tests below see it
        D = np.array([x if x > 0 else one for x in D], dtype=D.dtype)
        U, s, Vt = bk.svd(G / D)
        self.sigma = s
        self.null = Vt[-1] / D
        # share of the (unit, equilibrated) kernel vector in the (cos, sin) directions
        self.phase_share = Vt[-1][n2] ** 2 + Vt[-1][n2 + 1] ** 2
        self.rank_gap = s[-1] / s[0]
        r = n2 + 1

        def solve(rhs):
            return (Vt[:r].T @ ((U.T @ rhs)[:r] / s[:r])) / D

        e = np.zeros(n2 + 1, dtype=G.dtype)
        if bk is not FLOAT64:
            e[:] = mpmath.mpf(0)
        e[-1] = one
        self.Xp = solve(e * flow.level)
        p1 = solve(e)
        nc, ns = self.null[n2], self.null[n2 + 1]
        self.a = nc * nc + ns * ns
        nrm = bk.sqrt(self.a)
        nu = (ns / nrm, -nc / nrm)                 # along the gradient of x_k(0)
        side = nu[0] * p1[n2] + nu[1] * p1[n2 + 1]
        if restitution is None and not bk.fabs(side) > ORIENT_NOISE * (bk.fabs(p1[n2]) + bk.fabs(p1[n2 + 1])):
            # r = 1 with no damping: b no longer moves the line (the paper's alpha = (1 - r)
            # w1 w2 D = 0) and the sign above is rounding noise; orient as the limit r -> 1-
            ref = _Line(flow, omega, flow.r - bk.num(ORIENT_DR)).nu
            side = -(nu[0] * ref[0] + nu[1] * ref[1])
        if side < 0:
            nu = (-nu[0], -nu[1])
        self.nu = (-nu[0], -nu[1])                 # the paper's orientation (see module doc)
        self.ratio = self.nu[0] * self.Xp[n2] + self.nu[1] * self.Xp[n2 + 1]
        self.phase = bk.atan2(self.nu[1], self.nu[0])

    def point(self, tau):
        """(z0, w) on the line at phase tau."""
        bk = self.flow.bk
        n2 = 2 * self.flow.n
        c, s = bk.cos(tau), bk.sin(tau)
        mu = ((c - self.Xp[n2]) * self.null[n2] + (s - self.Xp[n2 + 1]) * self.null[n2 + 1]) / self.a
        w = self.Xp[:n2] + mu * self.null[:n2]
        return w + c * self.Pc + s * self.Ps, w


def _state_reset(flow, restitution=None):
    """E = diag(I, R) (2N x 2N, the flow's backend): the state just after an impact is E z
    of the state z just before it, R the constraint's reset (E = diag(1, .., -r, .., 1) for
    the stop); ``restitution`` overrides r (the orientation's limit r -> 1-)."""
    n, bk = flow.n, flow.bk
    R = flow.reset if restitution is None else flow.reset_at(restitution)
    E = np.zeros((2 * n, 2 * n), dtype=object if bk is not FLOAT64 else float)
    if bk is not FLOAT64:
        E[:] = mpmath.mpf(0)
    E[:n, :n] = bk.arr(np.eye(n))
    E[n:, n:] = R
    return E


def _line(model, omega, digits):
    """(flow, the solution line), or (flow, the reason) where no orbit exists because the
    stop mass gets no (or too little) steady forcing (:func:`_stop_forcing`,
    :func:`_out_of_reach`)."""
    flow = LinearFlow.of(model, digits)
    d, j = flow.one_minus_exp(omega)
    _check_isolated(flow, omega, d, j)
    F = flow.forcing(omega)
    why = _stop_forcing(flow, F, omega)
    if why:
        return flow, why
    L = _Line(flow, omega)
    try:
        _check_fixed(flow.bk, L.rank_gap, L.phase_share)
    except SingularCaseError:
        why = _out_of_reach(flow, F, omega)
        if not why:
            raise
        return flow, why
    return flow, L


def _out_of_reach(flow, F, omega):
    """The reason no orbit exists where the stop mass's steady amplitude A = |X_k| is too
    small to reach the gap, else "".  Any period-1 orbit has (module docstring)
    (I - E Phi) w = (E - I) zp(0), whose only nonzero entry is -(1 + r) v_k,p(0), so
    |x_k(0)| <= |w| + A <= A (1 + (1 + r) omega / sigma_min(I - E Phi)); a gap beyond
    twice that bound leaves no orbit.  Used where the period-1 conditions look
    degenerate (e.g. a forcing of 1e-300, whose squares underflow)."""
    A = math.hypot(float(F.U[0]), float(F.V[0]))
    _, s = _period_matrix(flow, omega)
    if not s[-1] > 0:
        return ""
    reach = _reach(flow, A, omega, s[-1])
    b = abs(float(flow.b))
    if not b > 2 * reach:
        return ""
    return (f"mass {flow.perm[0] + 1}'s steady forcing amplitude {A:.3g} is too small to "
            f"reach the stop: a period-1 orbit would have |x_{flow.perm[0] + 1}(0)| <= "
            f"{reach:.3g}, below the gap |b| = {b:g}")


def _stop_forcing(flow, F, omega):
    """The reason no period-1 one-impact orbit exists where the stop mass k gets no
    steady-state forcing, else "" (then the line of the module docstring is regular).

    With X_k = U_k + i V_k = 0 the phase columns of the period-1 conditions vanish:
    they become (I - E Phi) w = 0, e_k^T w = b, whose only solution for an invertible
    I - E Phi is w = 0, i.e. x_k(0) = 0 != b.  Three causes: no forcing at all, forcing
    only on masses decoupled from k, or an anti-resonance of mass k at this omega.
    |X_k| at the rounding level of the solve, delta = 64 eps cond(D) max_i |X_i|
    (D = K - omega^2 M + i omega C), counts as 0 when the bound
    |x_k(0)| <= delta (1 + (1 + r) omega ||(I - E Phi)^-1||) (which any period-1 orbit
    with |X_k| <= delta meets) excludes b (delta = 0 where X_k = 0 by structure: no
    forcing, or none coupled to k); SingularCaseError where it does not.  Where
    I - E Phi is singular (r = 1 without damping) an exact X_k = 0 leaves no orbit if b
    is out of the range of the stacked conditions, else a solution at every phase (not
    isolated: SingularCaseError).  A small |X_k| above delta warns
    (:func:`_warn_stop_forcing`)."""
    if _stop_forced(F):
        return ""
    U, V = np.asarray(F.U, dtype=float), np.asarray(F.V, dtype=float)
    xk, top = math.hypot(U[0], V[0]), float(np.hypot(U, V).max())   # hypot: no underflow
    w = float(omega)
    k, n = flow.perm[0] + 1, flow.n
    P = np.array([float(x) for x in flow.P])
    structural = not np.any(P) or not _reaches(flow)
    if structural:
        delta = 0.0                        # X_k = 0 exactly, whatever the rounding
    else:
        M, K, C = (np.asarray(a, dtype=float) for a in (flow.M, flow.K, flow.C))
        cond = float(np.linalg.cond(K - w * w * M + 1j * w * C))
        delta = 64 * float(flow.bk.eps) * cond * top
        if xk > delta:
            return ""                      # small but resolved: _warn_stop_forcing
    if not np.any(P):
        cause = "the model has no forcing (every forcing[i] = 0)"
    elif structural:
        cause = (f"the forcing acts only on masses not coupled to mass {k}, so mass {k} "
                 "gets no steady forcing")
    else:
        cause = (f"mass {k}'s steady forcing amplitude is 0 at omega = {w!r}, an "
                 f"anti-resonance (computed |X_{k}| = {xk:.3g})")
    H, s = _period_matrix(flow, omega)
    b = float(flow.b)
    none = f"{cause}; no period-1 one-impact orbit: the period-1 conditions reduce to "
    if s[-1] > 64 * EPS64 * s[0]:
        reach = _reach(flow, delta, omega, s[-1])
        if abs(b) > 2 * reach:
            return none + (f"(I - E Phi(T)) w = 0, whose only solution w = 0 is the steady "
                           f"state x_{k} = 0, which has no impact at the gap b = {b:g}")
        raise SingularCaseError(
            "degenerate-forcing",
            f"{cause}, and the gap |b| = {abs(b):.3g} is within its rounding level "
            f"{reach:.3g}: a period-1 orbit here, if any, has an impact velocity at rounding "
            "level (grazing) and cannot be resolved in float64")
    # I - E Phi singular (e.g. r = 1 without damping): solvable only if b is in the range
    # of the stacked system; solvable means a solution for every phase (not isolated)
    Ha = np.vstack([H, np.eye(2 * n)[:1]])
    rhs = np.zeros(2 * n + 1)
    rhs[-1] = b
    sol = np.linalg.lstsq(Ha, rhs, rcond=1e-10)[0]
    if structural and b != 0 and np.linalg.norm(Ha @ sol - rhs) > 1e-8 * abs(b):
        return none + (f"(I - E Phi(T)) w = 0 with x_{k}(0) = b, which has no solution: "
                       f"I - E Phi(T) is singular at omega = {w!r}, but its kernel does not "
                       f"reach the gap b = {b:g}")
    raise SingularCaseError(
        "degenerate-forcing",
        f"{cause}, and I - E Phi(T) is singular at omega = {w!r}: the period-1 conditions "
        "do not fix the impact phase (a solution, if any, exists for every phase), so no "
        "period-1 orbit is isolated")


def _period_matrix(flow, omega):
    """(H, its singular values): H = I - E Phi(T) in float64, E = diag(1, .., -r, ..) at the
    stop's velocity, the left side of the period-1 conditions (module docstring)."""
    n, T = flow.n, 2 * math.pi / float(omega)
    Phi = np.asarray(flow.phi(T) if flow.bk is FLOAT64 else
                     LinearFlow.of(flow.model).phi(T), dtype=float)
    E = np.asarray(_state_reset(flow), dtype=float)
    H = np.eye(2 * n) - E @ Phi
    return H, np.linalg.svd(H, compute_uv=False)


def _reach(flow, amplitude, omega, smin):
    """The bound |x_k(0)| <= A (1 + (1 + r) omega / sigma_min(I - E Phi)) of any period-1
    orbit whose stop mass has steady amplitude A (:func:`_out_of_reach`)."""
    return amplitude * (1 + (1 + float(flow.r)) * float(omega) / smin)


def _stop_forced(F):
    """The fast test: the stop mass's steady amplitude is not small (relative)."""
    u, v = F.U.tolist(), F.V.tolist()      # Python floats (or mpf): faster than numpy at N <= 8
    xk = float(u[0] * u[0] + v[0] * v[0])
    top = float(max([x * x + y * y for x, y in zip(u, v)]))
    return top > 0 and xk >= STOP_FORCING_WARN ** 2 * top


def _reaches(flow):
    """Whether the forcing reaches the stop's mass (index 0) through the coupling of
    M, K and C (a path of nonzero off-diagonal entries to a forced mass)."""
    n = flow.n
    link = np.zeros((n, n), dtype=bool)
    for a in (flow.M, flow.K, flow.C):
        link |= np.asarray(a, dtype=float) != 0
    forced = np.array([float(x) != 0 for x in flow.P])
    seen, todo = {0}, [0]
    while todo:
        i = todo.pop()
        for j in np.flatnonzero(link[i]):
            if int(j) not in seen:
                seen.add(int(j))
                todo.append(int(j))
    return bool(forced[sorted(seen)].any())


def _warn_stop_forcing(F, digits):
    """NearSingularWarning where the stop mass's steady amplitude |X_k| is small relative
    to the largest |X_i|: the impact phase of the orbits found loses that many digits."""
    if digits is not None:
        return
    amp = np.hypot(np.asarray(F.U, dtype=float), np.asarray(F.V, dtype=float))
    rel = float(amp[0] / amp.max())
    if rel < STOP_FORCING_WARN:
        warnings.warn(f"the stop mass's steady forcing amplitude is {rel:.1e} of the largest "
                      f"(near an anti-resonance): the impact phase loses about "
                      f"{-math.log10(rel):.0f} digits", NearSingularWarning, stacklevel=5)


def no_orbit_reason(model, omega):
    """Why ``model`` has no period-1 one-impact orbit at omega: a sentence, or "" when
    the period-1 conditions have solutions (admissible or not).  SingularCaseError
    where the case is singular (as :func:`period1_orbits`)."""
    model.require_one_rigid_stop()
    flow = LinearFlow.of(model)
    omega = flow.check_omega(omega, warn=False)
    flow, L = _line(model, omega, None)
    if isinstance(L, str):
        return L
    if abs(L.ratio) > 1:
        return (f"the period-1 conditions have no solution on the unit circle "
                f"(|rho| = {abs(float(L.ratio)):.6g} > 1)")
    return ""


def _check_isolated(flow, omega, d, j):
    """SingularCaseError where min_j |1 - e^{lambda_j T}| = d (mode j) says the orbit
    is not isolated; a warning where it is ill-conditioned (float64)."""
    bk = flow.bk
    if d < ISOLATION_REFUSE:
        ratio = float(flow.omegas[j]) / float(omega)
        raise SingularCaseError(
            "one-minus-cos",
            f"1 - cos(2 pi omega_{j + 1} / omega) = {float(d) ** 2 / 2:.3e} at omega = "
            f"{float(omega):.12g}: omega_{j + 1} / omega = {ratio:.6g} is (close to) the "
            f"integer {round(ratio)} for an undamped mode, so the period-1 orbit is not "
            f"isolated. Move omega away from omega_{j + 1} / n"
            + (" (a natural frequency near 0 is a nearly rigid mode: no omega helps)."
               if round(ratio) == 0 else "."))
    if bk is FLOAT64 and d < ISOLATION_WARN:
        warnings.warn(f"1 - cos(2 pi omega_{j + 1}/omega) = {d * d / 2:.2e} is small: the "
                      "period-1 conditions are ill-conditioned", NearSingularWarning, stacklevel=5)


def _check_fixed(bk, rank_gap, phase_share):
    """SingularCaseError where the period-1 conditions do not fix the orbit or its phase."""
    scale = 64 * bk.eps
    if not rank_gap > scale:
        raise SingularCaseError("degenerate-orbit-conditions",
                                "the period-1 conditions do not fix the orbit (their matrix "
                                f"has a second zero singular value, {float(rank_gap):.2e} "
                                "relative)")
    if not phase_share > scale:
        raise SingularCaseError("degenerate-forcing",
                                "the forcing does not move the stop's mass: the impact phase "
                                "is not fixed by the period-1 conditions")


def _admissibility(flow, forcing, omega, z0, tau, vimp):
    bk = flow.bk
    tol = END_TOL if flow.bk is FLOAT64 else bk.eps ** 0.5
    return check_flight(flow.motion(forcing, z0, tau).first_impact, 2 * bk.pi / omega,
                        flow.approach(z0), vimp, mass=flow.perm[0] + 1, tol=tol,
                        require_return=True)


def period1_orbits(model, omega, *, digits=None, multipliers=True):
    """Every period-1 one-impact orbit of ``model`` at omega (both branches).

    An empty list when the line misses the unit circle (no orbit exists).
    Inadmissible orbits come with ``admissible=False`` and the reason, never
    silently analysed.  ``digits`` selects mpmath at that precision.
    """
    model.require_one_rigid_stop()
    flow = LinearFlow.of(model)
    omega_f = flow.check_omega(omega)
    if digits is None:
        return _orbits(model, omega_f, None, multipliers)
    if not isinstance(digits, int) or isinstance(digits, bool) or not 16 <= digits <= 10000:
        raise ParameterError("digits", digits, "an integer from 16 to 10000")
    with mpmath.mp.workdps(digits):
        w = mpmath.mpf(omega) if isinstance(omega, (mpmath.mpf, str)) else mpmath.mpf(omega_f)
        return _orbits(model, w, digits, multipliers)


def _orbits(model, omega, digits, want_multipliers):
    if digits is None and COMPILED:
        return _orbits_compiled(model, omega, want_multipliers)
    flow, L = _line(model, omega, digits)
    if isinstance(L, str):
        return []
    bk = flow.bk
    if bk.fabs(L.ratio) > 1:
        return []
    _warn_stop_forcing(L.forcing, digits)
    ac = bk.acos(L.ratio)
    sec = Section(flow.n, flow.perm)
    T = 2 * bk.pi / omega
    out = []
    for branch, tau in (("+", L.phase + ac), ("-", L.phase - ac)):
        tau = tau % (2 * bk.pi)
        z0, w = L.point(tau)
        z0[0] = flow.b                              # exact by construction; remove rounding
        zT = L.Phi @ w + (z0 - w)
        vimp = flow.approach(zT)
        y = sec.point(z0, tau)                      # z0 is already after the impact
        ok, why = _admissibility(flow, L.forcing, omega, z0, tau, vimp)
        orb = Orbit(model, omega, branch, y, sec.names, vimp, ok, why, digits=digits)
        if want_multipliers:
            from ..codegen.jets import multipliers_of
            lam = multipliers_of(flow, L.forcing, y, T)
            orb = _with(orb, multipliers=lam, stable=stable_of(lam, ok, model))
        out.append(orb)
    return out


def _orbits_compiled(model, omega, want_multipliers):
    """:func:`_orbits` in float64 by the kernel of :mod:`symvi.orbits._period1`."""
    flow = LinearFlow.of(model)
    F = flow.forcing(omega)
    lam, W, Winv, A = flow.modal64
    forced = _stop_forced(F)
    if not forced:                          # checked before the kernel meets zero columns
        _check_isolated(flow, omega, *flow.one_minus_exp(omega))
        if _stop_forcing(flow, F, omega):
            return []
    st, d, j, gap, share, Y, vimp, M, has_M = _period1.period1(
        lam, W, Winv, A, F.U, F.V, omega, flow.constraint64,
        flow.reset_at(flow.r - ORIENT_DR).ravel(), ISOLATION_REFUSE,
        ORIENT_NOISE, bool(want_multipliers))
    _check_isolated(flow, omega, d, j)
    if st in (_period1.DEGENERATE, _period1.NO_PHASE) and _out_of_reach(flow, F, omega):
        return []
    _check_fixed(flow.bk, gap, share)
    if st == _period1.NO_ORBIT:
        return []
    if not forced:                          # forced: |X_k| is not small, nothing to warn
        _warn_stop_forcing(F, None)
    sec = Section.of(model)
    T = 2 * math.pi / omega
    finder = CompiledFinder(flow)
    mass = flow.perm[0] + 1
    if want_multipliers:
        from ..codegen.jets import eigenvalues, multipliers_of
    out = []
    for i, branch in enumerate(("+", "-")):
        y = tuple(Y[i].tolist())
        motion = finder.motion_from(F, Y[i])
        ok, why = check_flight(motion.first_impact, T, flow.section_approach(y), vimp[i],
                               mass=mass,
                               tol=END_TOL, require_return=True)
        lam_i, stable = (), False
        if want_multipliers:
            # no monodromy where the impact velocity is exactly 0: the reference's value
            lam_i = eigenvalues(M[i]) if has_M[i] else multipliers_of(flow, F, y, T)
            stable = stable_of(lam_i, ok, model)
        out.append(Orbit(model, omega, branch, y, sec.names, vimp[i], ok, why, lam_i,
                         stable))
    return out


def admissible_orbits(model, omega, *, digits=None, multipliers=True):
    """The admissible period-1 orbits at omega, branch "+" first (empty when none)."""
    orbits = period1_orbits(model, omega, digits=digits, multipliers=multipliers)
    return sorted((o for o in orbits if o.admissible), key=lambda o: o.branch != "+")


def select_orbit(model, omega, branch=None, digits=None, multipliers=False):
    """The admissible period-1 orbit at omega (``branch`` picks one when both are); a
    SingularCaseError saying why when there is none, or two and no ``branch``."""
    if branch is not None and branch not in ("+", "-"):
        raise ParameterError("branch", branch, "'+' or '-'")
    orbits = period1_orbits(model, omega, digits=digits, multipliers=multipliers)
    cands = [o for o in orbits if o.admissible and (branch is None or o.branch == branch)]
    if not cands:
        why = "; ".join(f"branch {o.branch}: {o.reason}" for o in orbits) or \
            "conditions (10) have no solution (eq. 16)"
        raise SingularCaseError("no-admissible-orbit",
                                f"no admissible period-1 orbit at omega = {float(omega):.12g} ({why})")
    if len(cands) > 1:
        raise SingularCaseError("two-admissible-orbits",
                                f"both branches are admissible at omega = {float(omega):.12g}; "
                                "pass branch='+' or '-'")
    return cands[0]


def multiplier_path(admissible, omegas, dim=None):
    """Multipliers of the admissible orbit along omega (figs. 4, 10 of the paper).

    ``admissible`` is a Model (its admissible period-1 orbits are used) or a function
    omega -> admissible orbits (branch "+" first).  Returns (lam, labels, skipped):
    lam is (n, dim) complex, |.| descending, NaN where no admissible orbit exists;
    labels name the branch used ("" where none); skipped counts the frequencies
    without an orbit, by reason.
    """
    if not callable(admissible):
        model = admissible
        dim = model.dim

        def admissible(w):
            return admissible_orbits(model, w)
    lam = np.full((len(omegas), dim), np.nan + 1j * np.nan)
    labels, skipped = [], {}
    for i, w in enumerate(omegas):
        try:
            ok = admissible(float(w))
        except SingularCaseError as exc:
            ok, why = [], exc.kind
        else:
            why = "no admissible orbit"
        if not ok:
            skipped[why] = skipped.get(why, 0) + 1
            labels.append("")
            continue
        lam[i] = [complex(z) for z in ok[0].multipliers]
        labels.append(ok[0].branch + ("" if len(ok) == 1 else "(2 admissible)"))
    return lam, labels, skipped


def existence_ratio(model, omega):
    """rho of nu . (cos tau, sin tau) = rho: the orbit exists iff |rho| <= 1 (eq. 16 generalised)."""
    flow = LinearFlow.of(model.require_one_rigid_stop())
    L = _line(model, flow.check_omega(omega, warn=False), None)[1]
    return math.inf if isinstance(L, str) else float(L.ratio)


def _with(obj, **kw):
    import dataclasses
    return dataclasses.replace(obj, **kw)
