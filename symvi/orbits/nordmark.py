"""Nordmark's discontinuity map at a grazing periodic orbit (issue 27, item 3).

A periodic orbit of a model with rigid stops grazes when it touches a stop with zero
normal velocity: h = g . x - level = 0 and sigma = h' = g . v = 0 at a point X* of the
extended state X = (z, phi) (z the flow-order state of :mod:`symvi.flow.linear`,
phi = omega t + tau the forcing phase), with acceleration a = h'' = g . v' < 0 there
(a maximum of h: the orbit comes up to the stop and turns back).

**The section.**  Pi = {sigma = g . v = 0} near X*, transversal to the flow because
d sigma / dt = a != 0.  Its coordinates (:attr:`DiscontinuityMap.names`) are

    xi = (h, the other positions, the other velocities, phi)

in the flow's order: the normal velocity (zero on Pi) is left out and the stop's
position is replaced by h, measured from the stop (h > 0: past it).  On Pi the point
of a flight is its apex, so h(xi) is the flight's largest value of h: in the notation of
[dBBCK08, ch. 4], h = -h_min, and h_min >= 0 means no contact.

**The map** [Nordmark 1991, eq. (13); dBBCK08, eqs. (4.40)-(4.41)], for x = xi - xi*
and mu the distance past grazing (below):

    P_N(x) = N x + mu m                     h(x) <= 0 (no new impact)
    P_N(x) = N x + E sqrt(h(x)) + mu m      h(x) > 0 (a new low-velocity impact)

with O(|x|^2 + |x| mu + h) dropped, where

* N is the Jacobian of the smooth return map to Pi, the flow that ignores the grazing
  contact (the orbit's other impacts through their saltation matrices
  S = J + (f+ - J f-) grad(h)^T / (grad(h) . f-) [dBBCK08, eq. (2.49)]), projected on
  Pi along the flow: (I - f* grad(sigma)^T / a).  Its eigenvalues are the orbit's
  multipliers (for a touch inside a flight; for an impact of zero velocity those of
  the orbit without that impact);
* E = N E0, with E0 the leading coefficient of the discontinuity map on Pi (the PDM),
  applied at Pi before the smooth return.  Derived here from the model: a flight whose
  apex on Pi lies at depth h > 0 hits the stop at approach speed
  v- = sqrt(2 |a| h) (to O(h)); the reset changes the velocities by
  (R - I) v = -(1 + r) q (c . v) / (c . q) (the rigid impulse along q = M^-1 c, c . v the
  normal velocity); the post-impact flight, carried along the flow back to Pi
  (a time -(1 + r) v- / |a|), gives

      E0 = sqrt(2 |a|) D [ (0, w) + (1 + r) f* / a ],   w = (R - I) u, g . u = 1,

  D the map to xi coordinates and f* the vector field at X*.  The normal velocity's
  component cancels by construction, h's vanishes (h' = 0 at X*); for one mass on one
  spring only the phase moves: E0 = (0, -(1 + r) omega sqrt(2 / |a|)), the impact's time
  shift.  [dBBCK08]'s printed PDM has the same leading term; it is written with
  H_min = -h and its own section's coordinates.
* m = dP/dlambda at xi* for the branch parameter lambda, by central differences of the
  smooth return map (step 1e-6 relative), and delta' = e_h . (I - N)^-1 m the rate at
  which the smooth orbit's apex moves into the stop: mu = sign(delta') (lambda - lambda*)
  is the distance *past* grazing (mu > 0: the smooth orbit penetrates, a new impact).

**The scenario past grazing** (:func:`scenario`): from the leading multiplier lambda1
of N, in the one-dimensional reduction of [Chin et al. 1994] (the square-root map
h -> lambda1 h + (1 - lambda1) delta + gamma sqrt(h), gamma = l . E with l the left
eigenvector of lambda1 scaled so that l . r = 1, e_h . r = 1; valid when lambda1 is real,
0 < lambda1 < 1, the other multipliers are small next to it, and gamma < 0, the impact
throwing the next iterate away from the stop):

* 0 < lambda1 < 1/4: a period-adding cascade of stable periodic orbits with one impact
  each, their period -> infinity as mu -> 0+ [Chin et al. 1994, Sec. III];
* 1/4 < lambda1 < 2/3: period-adding with chaotic windows between the periodic ones;
* 2/3 < lambda1 < 1: immediate chaos, a chaotic attractor of size O(mu) at once.

The overdamped 1-DOF of ``tests/studies/test_nordmark_check.py`` shows each regime in
simulation (lambda1 = 0.05, 0.30, 0.55, 0.74).
Otherwise (|lambda1| >= 1: the grazing orbit is unstable, no local attractor; complex,
negative or not dominant lambda1; gamma >= 0) the scenario says so and does not guess.

**The square-root law.**  A flight that follows the smooth orbit past grazing first hits
the stop at v1 = sqrt(2 |a| delta) = c_first sqrt(mu) (1 + O(sqrt(mu))) with
c_first = sqrt(2 |a| |delta'|).  In the 1-D reduction every impact on the attractor
lies at depth h in (0, (1 - lambda1) delta], so its velocity is below
c_attractor sqrt(mu), c_attractor = c_first sqrt(1 - lambda1) (attained in the chaotic
case).  The impacting *period-1* orbit near grazing obeys another law: its fixed point
on the impacting side has sqrt(h) = s with s^2 - c s - delta = 0, c = e_h . (I - N)^-1 E,
so it exists past grazing only for c < 0, with h ~ (delta / c)^2 and an impact velocity
*linear* in mu, sqrt(2 |a|) delta' mu / |c|; it is unstable for small mu (a multiplier
~ e_h . E / (2 s) -> infinity unless e_h . E = 0) [Nordmark 1991, Sec. 4].

References
----------
[Nordmark 1991] A. B. Nordmark, Non-periodic motion caused by grazing incidence in an
    impact oscillator, J. Sound Vib. 145 (1991) 279-297.
[Chin et al. 1994] W. Chin, E. Ott, H. E. Nusse, C. Grebogi, Grazing bifurcations in
    impact oscillators, Phys. Rev. E 50 (1994) 4427-4444.
[dBBCK08] M. di Bernardo, C. J. Budd, A. R. Champneys, P. Kowalczyk, Piecewise-smooth
    Dynamical Systems, Springer 2008, ch. 4 (discontinuity mappings of impacting systems).
"""
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ParameterError, SingularCaseError
from ..flow.compiled import table as _table

#: |h| and |sigma| at the tangency, relative to the orbit's scale, above which the orbit
#: is refused as not grazing
GRAZING_TOL = 1e-6
#: |a| relative to the vector field's scale below which the grazing is degenerate
DEGENERATE_TOL = 1e-8
#: relative step of the central differences in the branch parameter (m)
PARAM_STEP = 1e-6
#: a leading multiplier is "dominant" for the 1-D reduction when the next one is at most
#: this fraction of it in modulus
DOMINANT_RATIO = 0.5


@dataclass(frozen=True)
class DiscontinuityMap:
    """Nordmark's map at a grazing orbit (normalisation: :mod:`symvi.orbits.nordmark`).

    Attributes
    ----------
    model : Model
        The orbit's model.
    omega : float
        The forcing frequency.
    param, value : str, float
        The branch parameter lambda and its value lambda* at grazing.
    kind : str
        "flight" (a touch inside a flight) or "impact" (an impact of zero velocity).
    stop : int
        The stop touched (0-based).
    names : tuple of str
        The coordinates xi on the section Pi = {g . v = 0}: ("h", positions, velocities,
        "phase"), h measured from the stop (> 0 past it).
    point : ndarray
        xi* of the grazing orbit on Pi.
    state : ndarray
        The flow-order state z* at the tangency (h = 0, g . v = 0).
    phase : float
        The forcing phase phi* = omega t + tau at the tangency, in [0, 2 pi).
    acceleration : float
        a = h'' at the tangency (< 0).
    restitution : float
        r of the stop touched.
    N : ndarray
        The smooth part (the Jacobian of the smooth return map on Pi).
    E0 : ndarray
        The discontinuity map's square-root coefficient on Pi (before the return).
    E : ndarray
        N E0: the square-root coefficient of P_N.
    m : ndarray or None
        dP/dlambda at xi* (per unit of the branch parameter), None without a parameter.
    delta_rate : float or None
        delta' = e_h . (I - N)^-1 m: the smooth orbit's depth per unit of lambda.
    multipliers : tuple of complex
        The eigenvalues of N, largest modulus first.
    gamma : float or None
        l . E of the 1-D reduction (None where it does not apply).
    c_fixed : float
        e_h . (I - N)^-1 E (the impacting period-1 orbit's coefficient).
    scenario : str
        The predicted local scenario past grazing, in words.
    legs, n_periods : tuple, int
        One period from the tangency: (duration, constraint hit at its end or None for
        the return to Pi) per leg; the forcing periods n.
    """

    model: object = field(repr=False)
    omega: float
    param: str
    value: float
    kind: str
    stop: int
    names: tuple
    point: np.ndarray
    state: np.ndarray
    phase: float
    acceleration: float
    restitution: float
    N: np.ndarray
    E0: np.ndarray
    E: np.ndarray
    m: object
    delta_rate: object
    multipliers: tuple
    gamma: object
    c_fixed: float
    scenario: str
    legs: tuple = field(repr=False, default=())
    n_periods: int = 1

    @property
    def past_direction(self):
        """+1 or -1: the sign of lambda - lambda* past grazing (None without a parameter)."""
        if self.delta_rate is None or not math.isfinite(self.delta_rate) or \
                self.delta_rate == 0:
            return None
        return 1.0 if self.delta_rate > 0 else -1.0

    @property
    def c_first(self):
        """c of v1 = c sqrt(mu): the first new impact of a flight on the smooth orbit."""
        if self.delta_rate is None:
            return None
        return math.sqrt(2 * abs(self.acceleration) * abs(self.delta_rate))

    @property
    def c_attractor(self):
        """The 1-D reduction's bound c of v <= c sqrt(mu) for the impacts on the attractor
        (None outside the reduction)."""
        lam1 = self.multipliers[0]
        if self.gamma is None or self.c_first is None:
            return None
        return self.c_first * math.sqrt(1.0 - lam1.real)

    def as_dict(self):
        f = lambda a: [float(v) for v in a]            # noqa: E731
        return {"omega": self.omega, "param": self.param, "value": self.value,
                "kind": self.kind, "stop": self.stop + 1, "names": list(self.names),
                "point": f(self.point), "phase": self.phase,
                "acceleration": self.acceleration, "restitution": self.restitution,
                "N": [f(row) for row in self.N], "E0": f(self.E0), "E": f(self.E),
                "m": None if self.m is None else f(self.m),
                "delta_rate": self.delta_rate,
                "multipliers": [[z.real, z.imag] for z in self.multipliers],
                "gamma": self.gamma, "c_fixed": self.c_fixed,
                "c_first": self.c_first, "c_attractor": self.c_attractor,
                "past_direction": self.past_direction, "scenario": self.scenario,
                "normalisation": NORMALISATION}


NORMALISATION = ("section Pi = {h' = 0} (zero normal velocity) at the tangency; xi = (h, other "
                 "positions, other "
                 "velocities, phase), h = g . x - level (> 0 past the stop, = -h_min); "
                 "P_N(x) = N x + E sqrt(h) + mu m for h > 0, N x + mu m else; E = N E0; "
                 "mu = sign(delta') (lambda - lambda*) > 0 past grazing")


# --------------------------------------------------------------------------- entry
def discontinuity_map(orbit, where, *, param="omega"):
    """Nordmark's map at a grazing periodic orbit, eqs. in :mod:`symvi.orbits.nordmark`.

    Parameters
    ----------
    orbit : PeriodicOrbit
        The grazing orbit (a grazing :class:`symvi.continuation.SpecialPoint`'s
        ``orbit``) of a model with rigid stops.
    where : dict or SpecialPoint
        Where it grazes: the point's ``coefficients``, ``{"impact": j}`` (impact j,
        1-based, arrives with zero velocity) or ``{"flight": i, "t": t}`` (flight i,
        1-based, touches a stop at time t of it; ``"stop"``, 1-based, names the stop
        when there are several); a SpecialPoint is read for its coefficients.
    param : str, optional
        The branch parameter lambda (any name of :meth:`symvi.Model.parameter`), for m
        and the distance past grazing; default "omega".

    Returns
    -------
    DiscontinuityMap
        N, E0, E = N E0, m, the multipliers, the scenario and the square-root
        coefficients, in the normalisation of the module docstring (``as_dict()``).

    Raises
    ------
    ParameterError
        ``where`` names no grazing, the orbit is not at grazing (``abs(h)`` or
        ``abs(g . v)`` above 1e-6 of its scale at the named place), or the model has an
        elastic stop.
    SingularCaseError
        ``"degenerate-grazing"``: the acceleration at the tangency is ~0 (``abs(a)`` below
        1e-8 of the vector field); ``"not-grazing"``: a > 0, the stop would hold the
        mass (sticking, not a grazing).

    Examples
    --------
    >>> import symvi
    >>> from symvi.continuation import continue_orbits
    >>> model = symvi.Model.luo_xie(2, 5, 0, 1.5, 0.8)
    >>> br = continue_orbits(model, "omega", 0.5, 1.0)[0]
    >>> g = next(s for s in br.special if s.kind == "grazing")
    >>> nm = symvi.discontinuity_map(g.orbit, g)
    >>> nm.names
    ('h', 'x2', 'v2', 'phase')
    >>> print(nm.acceleration < 0, nm.past_direction)
    True 1.0
    """
    coef = getattr(where, "coefficients", where)
    if not isinstance(coef, dict) or not ("impact" in coef or "flight" in coef):
        raise ParameterError("where", where, "a grazing point's coefficients: {'impact': j} "
                             "or {'flight': i, 't': t}")
    model = orbit.model
    if model.elastic:
        raise ParameterError("model", "elastic stop", "a model of rigid stops (an elastic "
                             "stop has no impact map: no Nordmark map)")
    par = model.parameter(param)
    G = _Grazing(orbit, coef)
    N, fX = G.smooth_jacobian()
    E0 = G.pdm(fX)
    E = N @ E0
    lam = orbit.omega if par.is_forcing_frequency else float(par.get(model, orbit.omega))
    m = G.dparam(par, lam)
    I = np.eye(len(E0))
    try:
        sol = np.linalg.solve(I - N, np.column_stack([m, E]))
        rate, cfix = float(sol[0, 0]), float(sol[0, 1])
    except np.linalg.LinAlgError:
        rate = cfix = math.nan
    mults = tuple(sorted((complex(z) for z in np.linalg.eigvals(N)),
                         key=lambda z: (-abs(z), -z.imag)))
    gamma, text = scenario(N, E, mults)
    return DiscontinuityMap(model, float(orbit.omega), par.name, float(lam), G.kind, G.k,
                            G.names, G.xi, G.z, float(G.phi % (2 * math.pi)), G.a, G.r, N,
                            E0, E, m, rate, mults, gamma, cfix, text, G.legs, G.n_periods)


def scenario(N, E, multipliers):
    """(gamma, words): the local scenario past grazing predicted from the leading
    multiplier of N (the criterion of the module docstring, [Chin et al. 1994]);
    gamma = l . E of the 1-D reduction, None where it does not apply."""
    lam1 = multipliers[0]
    if abs(lam1) >= 1:
        return None, (f"the grazing orbit is unstable (|lambda1| = {abs(lam1):.4g} >= 1): no "
                      "local attractor is born at grazing; the 1-D reduction does not apply")
    if abs(lam1.imag) > 1e-9 * max(1.0, abs(lam1)):
        return None, (f"leading multipliers complex (|lambda1| = {abs(lam1):.4g}, arg "
                      f"{math.degrees(math.atan2(lam1.imag, lam1.real)):.1f} deg): outside the "
                      "classical 1-D reduction of Nordmark's map; not classified")
    if lam1.real <= 0:
        return None, (f"leading multiplier lambda1 = {lam1.real:.4g} <= 0: outside the "
                      "classical 1-D reduction (0 < lambda1 < 1); not classified")
    ratio = abs(multipliers[1]) / abs(lam1) if len(multipliers) > 1 else 0.0
    if ratio > DOMINANT_RATIO:
        return None, (f"lambda1 = {lam1.real:.4g} is not dominant (|lambda2| / lambda1 = "
                      f"{ratio:.3g} > {DOMINANT_RATIO}): the 1-D reduction does not apply; "
                      "not classified")
    w, V = np.linalg.eig(N)
    j = int(np.argmin(np.abs(w - lam1)))
    r = V[:, j].real
    wl, U = np.linalg.eig(N.T)
    l = U[:, int(np.argmin(np.abs(wl - lam1)))].real
    if abs(r[0]) < 1e-12 or abs(l @ r) < 1e-12:
        return None, "the leading eigenvector does not move h: the 1-D reduction does not apply"
    r = r / r[0]                       # e_h . r = 1: the slow coordinate is h itself
    l = l / (l @ r)
    gamma = float(l @ E)
    lam = lam1.real
    if gamma >= 0:
        return gamma, (f"lambda1 = {lam:.4g} real and dominant but gamma = l . E = {gamma:.4g} "
                       ">= 0 (the impact does not throw the orbit off the stop): outside "
                       "Nordmark's classical case; not classified")
    if lam < 0.25:
        what = ("period-adding cascade: stable periodic orbits with one low-velocity impact "
                "each, their period growing without bound as mu -> 0+ (0 < lambda1 < 1/4)")
    elif lam < 2.0 / 3.0:
        what = ("period-adding cascade with chaotic windows between the periodic orbits "
                "(1/4 < lambda1 < 2/3)")
    else:
        what = "immediate chaos: a chaotic attractor of size O(mu) (2/3 < lambda1 < 1)"
    return gamma, f"{what}; lambda1 = {lam:.4g}, gamma = {gamma:.4g} [Chin et al. 1994]"


# --------------------------------------------------------------------------- the orbit
class _Grazing:
    """The grazing orbit read from a PeriodicOrbit: the tangency X* = (z*, phi*), the
    legs of one period from it, the section's coordinates (module docstring)."""

    def __init__(self, orbit, coef):
        from .periodic import Problem
        model = orbit.model
        self.model, self.omega = model, float(orbit.omega)
        pr = Problem(model, orbit.n, orbit.p, omega=self.omega, signature=orbit.signature)
        self.problem = pr
        fl, (_, flow, F) = pr.flights(np.asarray(orbit.u, dtype=float), None)
        self.flow, self.F = flow, F
        T = pr.split(np.asarray(orbit.u, dtype=float))[1]
        p, N = pr.p, pr.N
        self.N = N
        sig = [int(s) for s in pr.sig]
        # legs: (duration, constraint hit at its end or None for the return to Pi)
        if "impact" in coef:
            j = int(coef["impact"])
            if not 1 <= j <= p:
                raise ParameterError("where", coef, f"an impact 1..{p}")
            i = j - 1                          # flight i ends at the grazing impact
            k = sig[(i + 1) % p]
            z0, tau = fl[i][0], fl[i][1]
            t0 = float(T[i])
            self.kind = "impact"
            legs = [(float(T[q % p]), sig[(q + 1) % p]) for q in range(i + 1, i + p)]
            legs.append((float(T[i]), None))
        else:
            i = int(coef["flight"]) - 1
            if not 0 <= i < p:
                raise ParameterError("where", coef, f"a flight 1..{p}")
            t0 = float(coef.get("t", math.nan))
            if not 0 <= t0 <= float(T[i]):
                raise ParameterError("where", coef, f"a time t in [0, {float(T[i]):.6g}] of "
                                     f"flight {i + 1}")
            k = int(coef.get("stop", 1)) - 1
            z0, tau = fl[i][0], fl[i][1]
            self.kind = "flight"
            legs = [(float(T[i]) - t0, sig[(i + 1) % p])]
            legs += [(float(T[q % p]), sig[(q + 1) % p]) for q in range(i + 1, i + p)]
            legs.append((t0, None))
        self.k = k
        self.n_periods = int(orbit.n)
        if model.constraints[k].kind != "rigid":
            raise ParameterError("model", "elastic stop", "a rigid stop at the tangency")
        self.rows = _table(flow)
        self.g, self.level, self.R = self._row(self.rows, k)
        z0 = np.asarray(z0, dtype=float)
        z, _, _, f = flow.flight(F, z0, float(tau), t0)
        self.pg = int(np.flatnonzero(self.g)[0])
        self.sg = float(self.g[self.pg])
        if np.count_nonzero(self.g) != 1 or abs(abs(self.sg) - 1) > 1e-12:
            raise ParameterError("where", coef, "a stop on one coordinate of the flow's frame")
        self.r = float(model.constraints[k].restitution)
        h = float(self.g @ z[:N] - self.level)
        sigma = float(self.g @ z[N:])
        scale = 1.0 + float(np.max(np.abs(z)))
        if abs(h) > GRAZING_TOL * scale or abs(sigma) > GRAZING_TOL * scale:
            raise ParameterError("orbit", f"h = {h:.3g}, h' = {sigma:.3g}",
                                 f"an orbit at grazing (|h|, |h'| <= {GRAZING_TOL:g} of its "
                                 "scale at the named place)")
        check_acceleration(float(self.g @ f[N:]), float(np.max(np.abs(f))))
        # onto Pi exactly: a located touch time is a maximum of h, good to ~sqrt(eps) only
        z, phi, t1 = self._leg(flow, F, self.rows, z0, float(tau), t0, None)[:3]
        self.z, self.phi = z, phi % (2 * math.pi)
        self.a = float(self.g @ self.field(flow, F, self.z, self.phi)[N:2 * N])
        legs[-1] = (t1, None)
        if self.kind == "flight":
            legs[0] = (legs[0][0] + t0 - t1, legs[0][1])
        self.legs = tuple(legs)
        self.names = self._names()
        self.xi = self.coords(self.z, self.phi, self.level)

    # ---- coordinates on Pi ----------------------------------------------------------
    def _row(self, rows, k):
        N = self.N
        row = rows[k]
        return row[3:3 + N].copy(), float(row[2]), row[3 + N:].reshape(N, N).copy()

    def _names(self):
        flow, N = self.flow, self.N
        labels = getattr(flow, "lin", flow).labels     # FlowView: its linear part's frame
        if labels is not None:
            pos = [labels[j][0] for j in range(N)]
            vel = [labels[j][1] for j in range(N)]
        else:
            pos = [f"x{flow.perm[j] + 1}" for j in range(N)]
            vel = [f"v{flow.perm[j] + 1}" for j in range(N)]
        keep = [j for j in range(N) if j != self.pg]
        return ("h",) + tuple(pos[j] for j in keep) + tuple(vel[j] for j in keep) + ("phase",)

    def coords(self, z, phi, level):
        """xi of the state (z, phi): (h, the other positions and velocities, phi)."""
        N, pg = self.N, self.pg
        keep = [j for j in range(N) if j != pg]
        return np.concatenate(([self.sg * z[pg] - level], z[keep], z[[N + j for j in keep]],
                               [phi]))

    def state(self, xi, level):
        """(z, phi) on Pi of xi (the normal velocity 0)."""
        N, pg = self.N, self.pg
        keep = [j for j in range(N) if j != pg]
        z = np.zeros(2 * N)
        z[pg] = self.sg * (xi[0] + level)
        z[keep] = xi[1:N]
        z[[N + j for j in keep]] = xi[N:2 * N - 1]
        return z, float(xi[-1])

    def _D(self):
        """d xi / d X (2N x 2N + 1) and its right inverse on Pi, d X / d xi."""
        d = 2 * self.N
        D = np.zeros((d, d + 1))
        C = np.zeros((d + 1, d))
        e = np.eye(d + 1)
        N, pg = self.N, self.pg
        keep = [j for j in range(N) if j != pg]
        rows = [self.sg * e[pg]] + [e[j] for j in keep] + [e[N + j] for j in keep] + [e[d]]
        for q, row in enumerate(rows):
            D[q] = row
            C[:, q] = row * (self.sg if q == 0 else 1.0)
        return D, C

    def field(self, flow, F, z, phi):
        """The extended vector field (z', omega) at (z, phi)."""
        return np.append(flow.flight(F, z, phi, 0.0)[3], F.omega)

    # ---- the smooth return map and its Jacobian ---------------------------------------
    def smooth_jacobian(self):
        """(N, f*): the Jacobian of the smooth return map on Pi (saltation matrices at the
        orbit's impacts, the projection along the flow at the end) and the field at X*."""
        flow, F, N, d = self.flow, self.F, self.N, 2 * self.N
        z, phi = self.z.copy(), self.phi
        Mx = np.eye(d + 1)
        for t_leg, k in self.legs:
            z1, phi1, t, Phi, dzt, f = self._leg(flow, F, self.rows, z, phi, t_leg, k)
            Dl = np.eye(d + 1)
            Dl[:d, :d], Dl[:d, d] = Phi, dzt
            Mx = Dl @ Mx
            if k is not None:                  # S = J + (f+ - J f-) grad(h)^T / grad(h).f-
                g, _, R = self._row(self.rows, k)
                J = np.eye(d + 1)
                J[N:d, N:d] = R
                fm = np.append(f, F.omega)
                fp = self.field(flow, F, z1, phi1)
                gh = np.zeros(d + 1)
                gh[:N] = g
                S = J + np.outer(fp - J @ fm, gh) / (gh @ fm)
                Mx = S @ Mx
            z, phi = z1, phi1
        fX = self.field(flow, F, self.z, self.phi)
        gs = np.zeros(d + 1)
        gs[N:d] = self.g
        P = np.eye(d + 1) - np.outer(fX, gs) / (gs @ fX)
        D, C = self._D()
        return D @ P @ Mx @ C, fX

    def _leg(self, flow, F, rows, z, phi, t_nom, k):
        """One leg from (z, phi): to the impact on constraint k near t_nom (reset applied)
        or, k None, to Pi near t_nom.  (z1, phi1, t, Phi, dz/dtau, z'(t-)) ."""
        N = self.N
        if k is None:
            g = self.g
            ev = lambda zt, f: (g @ zt[N:], g @ f[N:])          # noqa: E731
        else:
            g, lv, _ = self._row(rows, k)
            ev = lambda zt, f: (g @ zt[:N] - lv, g @ f[:N])     # noqa: E731
        t = float(t_nom)
        for _ in range(40):
            zt, Phi, dzt, f = flow.flight(F, z, phi, t)
            val, der = ev(zt, f)
            dt = -val / der
            t += dt
            if abs(dt) <= 1e-15 * (1.0 + abs(t)):
                break
        zt, Phi, dzt, f = flow.flight(F, z, phi, t)
        if k is not None:
            R = self._row(rows, k)[2]
            zt = np.concatenate([zt[:N], R @ zt[N:]])
        return zt, phi + F.omega * t, t, Phi, dzt, f

    def smooth_return(self, xi, model=None, omega=None):
        """xi' = P(xi): the smooth return map on Pi (the grazing contact ignored, the
        orbit's impacts located near their times), at ``model`` and ``omega`` (default the
        orbit's)."""
        model = self.model if model is None else model
        omega = self.omega if omega is None else float(omega)
        flow = self.flow if model is self.model else _free_flow(model)
        F = flow.forcing(omega)
        rows = self.rows if model is self.model else _table(flow)
        level = self._row(rows, self.k)[1]
        z, phi = self.state(np.asarray(xi, dtype=float), level)
        for t_leg, k in self.legs:
            z, phi = self._leg(flow, F, rows, z, phi, t_leg, k)[:2]
        return self.coords(z, phi - 2 * math.pi * self.n_periods, level)

    def pdm(self, fX):
        """E0 on Pi (module docstring): sqrt(2|a|) D [(0, w) + (1 + r) f* / a]."""
        N, d = self.N, 2 * self.N
        u = self.g / (self.g @ self.g)
        w = (self.R - np.eye(N)) @ u
        dz = np.zeros(d + 1)
        dz[N:d] = w
        D, _ = self._D()
        return math.sqrt(2 * abs(self.a)) * (D @ (dz - fX * (self.g @ w) / self.a))

    def dparam(self, par, lam):
        """m = dP/dlambda at xi*, central differences of the smooth return map."""
        eps = PARAM_STEP * max(1.0, abs(lam))
        out = []
        for s in (1.0, -1.0):
            if par.is_forcing_frequency:
                out.append(self.smooth_return(self.xi, omega=lam + s * eps))
            else:
                out.append(self.smooth_return(self.xi, model=par.apply(self.model, lam + s * eps)))
        return (out[0] - out[1]) / (2 * eps)


def check_acceleration(a, scale):
    """The tangency's acceleration a = h'': refused when ~0 (degenerate grazing) or > 0
    (the stop would hold the mass: sticking, not a grazing)."""
    if not abs(a) > DEGENERATE_TOL * (1.0 + scale):
        raise SingularCaseError("degenerate-grazing",
                                f"the acceleration at the tangency is ~0 (h'' = {a:.3g}): a "
                                "degenerate grazing, the square-root map does not apply")
    if a > 0:
        raise SingularCaseError("not-grazing",
                                f"h'' = {a:.3g} > 0 at the contact: the stop would hold the "
                                "mass (sticking), not a grazing")


# --------------------------------------------------------------------------- past grazing
def smooth_orbit(nm, mu, *, tol=1e-13, maxit=50):
    """(xi, model, omega): the smooth orbit's point on Pi at distance ``mu`` past grazing
    (lambda = lambda* + sign(delta') mu), by the chord iteration
    xi <- xi + (I - N)^-1 (P(xi) - xi) from xi* + (I - N)^-1 m (lambda - lambda*)."""
    G = _grazing_of(nm)
    par = nm.model.parameter(nm.param)
    lam = nm.value + nm.past_direction * mu
    model, omega = (nm.model, lam) if par.is_forcing_frequency else \
        (par.apply(nm.model, lam), nm.omega)
    A = np.eye(len(nm.point)) - nm.N
    xi = nm.point + np.linalg.solve(A, nm.m * (lam - nm.value))
    for _ in range(maxit):
        step = np.linalg.solve(A, G.smooth_return(xi, model, omega) - xi)
        xi = xi + step
        if np.max(np.abs(step)) <= tol * (1.0 + np.max(np.abs(xi))):
            return xi, model, omega
    raise SingularCaseError("no-smooth-orbit", f"the smooth orbit at mu = {mu:g} past grazing "
                            "did not converge (mu too large for the local map?)")


def descent_point(nm, xi, model, omega):
    """(z, phi): where the smooth orbit through xi (apex at depth h > 0 on Pi) comes back
    out of the stop: h = 0 with h' < 0, at time ~ sqrt(2 h / |a|) after Pi."""
    G = _grazing_of(nm)
    flow = _free_flow(model)
    F = flow.forcing(omega)
    level = G._row(_table(flow), G.k)[1]
    z0, phi0 = G.state(xi, level)
    t = math.sqrt(2 * max(xi[0], 0.0) / abs(nm.acceleration))
    N = G.N
    for _ in range(40):
        zt, _, _, f = flow.flight(F, z0, phi0, t)
        dt = -(G.g @ zt[:N] - level) / (G.g @ f[:N])
        t += dt
        if abs(dt) <= 1e-15 * (1.0 + t):
            break
    zt = flow.flight(F, z0, phi0, t)[0]
    return zt, phi0 + F.omega * t


def other_speeds(nm):
    """The approach speeds of the grazing orbit's other impacts, in the order of the legs
    from the tangency (the speeds of the impacts the new one joins)."""
    G = _grazing_of(nm)
    z, phi, out = G.z, G.phi, []
    for t_leg, k in nm.legs[:-1]:
        g = G._row(G.rows, k)[0]
        z, phi, _, _, _, f = G._leg(G.flow, G.F, G.rows, z, phi, t_leg, k)
        out.append(float(g @ f[:G.N]))
    return out


_GRAZINGS = {}


def _free_flow(model):
    """The flow the shooting system reads (:func:`symvi.orbits.periodic.free_flow`: the
    exact linear one, or the nonlinear forces' series view)."""
    from .periodic import free_flow
    return free_flow(model)


def _grazing_of(nm):
    """The _Grazing behind a DiscontinuityMap (rebuilt from its legs and tangency)."""
    G = _GRAZINGS.get(id(nm))
    if G is None or G[0] is not nm:
        g = _Grazing.__new__(_Grazing)
        model = nm.model
        flow = _free_flow(model)
        g.model, g.omega, g.flow, g.F = model, nm.omega, flow, flow.forcing(nm.omega)
        g.N = model.n
        g.rows = _table(flow)
        g.k = nm.stop
        g.g, g.level, g.R = g._row(g.rows, g.k)
        g.pg = int(np.flatnonzero(g.g)[0])
        g.sg = float(g.g[g.pg])
        g.legs = nm.legs
        g.n_periods = nm.n_periods
        g.z, g.phi, g.a, g.r = nm.state, nm.phase, nm.acceleration, nm.restitution
        g.xi = nm.point
        if len(_GRAZINGS) > 32:
            _GRAZINGS.clear()
        G = _GRAZINGS[id(nm)] = (nm, g)
    return G[1]


__all__ = ["DiscontinuityMap", "discontinuity_map", "scenario", "smooth_orbit",
           "descent_point", "other_speeds", "check_acceleration", "NORMALISATION"]
