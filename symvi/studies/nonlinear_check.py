"""An independent 40-digit chain for the impact map of a model with nonlinear forces (issue 28).

Shares no numerical code with symvi's flows (no NonlinearFlow, no LinearFlow, no contact
phase of :mod:`symvi.flow.contact` or :mod:`symvi.flow.nlcontact`, no generated jets): it
reads the model's matrices, the SymPy expressions of its forces and their parameters'
values, its stops (normal, gap, side; a rigid stop's reset, an elastic stop's stiffness
k_s and damping c_s) and the layout of their sections (the flow coordinates of
:func:`symvi.flow.linear.frame_of`, in which each stop fixes one coordinate, and
:func:`symvi.flow.compiled.section_index`: the order of a section's coordinates, as
symvi's orbits give their points), and computes in mpmath at ``digits`` + GUARD_DIGITS.
Between events, with the set S of elastic stops in contact (S empty: a free flight)::

    M x'' + C_S x' + K_S x + f(x, v) = P sin(omega t + tau) + f_S,
    K_S = K + sum_{i in S} k_i c_i c_i^T,  C_S = C + sum_{i in S} c_si c_i c_i^T,
    f_S = sum_{i in S} k_i g_i c_i,

the contact law of :mod:`symvi.flow.contact` (the stop's force -(k_i (c_i . x - g_i) +
c_si c_i . x') c_i while it is penetrated), summed here at the chain's precision (symvi
sums K + k_i c c^T in float64: models whose sums round differ by ~1e-17 there).
Events: a rigid impact (the guard h_j = sign_j (c_j . x - g_j) of a stop j outside S
crosses 0 upward; v+ = R_j v-), an elastic entry (the same for an elastic j outside S; S
gains j) and an exit (-h_j crosses 0 upward for j in S: the stop is left when the mass
leaves it, as symvi's walk does, the contact force then being whatever the law gives,
an attractive damping part included; S loses j).  An elastic event has no jump.  A
section point lies on the section of the stop of its event, in the same layout for
every kind (the velocity kept at an entry or exit); P^p from it runs in the phase
``contact`` (:class:`symvi.model.Signature`'s: the stops in contact during the first
flight), and a fixed point of P^p returns to its section in the same phase.

Flight: a Taylor method.  The Taylor coefficients of the solution at each step come from
the recurrences of automatic differentiation applied to the forces' expressions (sums,
products, quotients, powers, exp, log, sin/cos, sinh/cosh, atan and what is built from
them) [Jorba & Zou 2005]; degree K = ceil(-ln(tol) / 2) + 1 and step h = rho / e^2, rho
the radius of convergence estimated from the last two coefficients (Jorba and Zou's rule:
the truncation of a step is ~ tol = 10^-(digits + GUARD_DIGITS) relative to max(1, |z|)),
and at most STEP_FRACTION of a forcing period (a contact phase's stiffer modes shrink rho
by themselves).  ``mpmath.odefun`` (also a Taylor method) was measured: one flight of the
Duffing oscillator of the tests (t_e = 4.19) takes it 18 s at 50 digits against 0.14 s
here (the two agree to 1e-51), and it gives no access to the step's polynomial, which the
contact search below needs.

Contact: on each step each stop's guard g(s) = sign (c . x(s) - b) (its negative for a
stop in contact) is the step's Taylor polynomial of degree K; the first event is the
earliest over the stops.  Its Bernstein coefficients on [0, h] bound it (convex hull);
de Casteljau halving finds the leftmost sub-interval whose coefficients end >= 0 with one
sign change (Descartes' rule for Bernstein forms: exactly one root there), where
``mpmath.findroot`` solves the polynomial.
Guarantee: no zero of the step's polynomial is stepped over; the polynomial differs from
the true guard by the step's truncation (~ tol), so a contact can be missed only if its
penetration is below that (~1e-50 at 40 digits). A hull that still touches 0 after
ROOT_DEPTH halvings with no such sub-interval (a tangency within 2^-ROOT_DEPTH h) is
refused as grazing. Just after an event the guard of its stop starts at 0 exactly and
the search looks at g(s) / s (after an entry, the exit's guard -h).

Jets: the derivatives of the map by central finite differences of the map with the phase
unwrapped (tau + omega t_e, so that nothing jumps at 2 pi), product stencils of accuracy
order ``acc`` = 4 (order <= 3) or 6 (orders 4, 5), one step delta = 10^-round(digits /
(acc + order)) on every coordinate.  Error of a derivative of order m: truncation
~ delta^acc max |d^(m + acc) P| (with 40 digits, order 3: delta = 1e-6, ~1e-24 times the
7th derivatives) plus rounding ~ 10^-digits W / delta^m (W <= 8 the stencil's weight sum for
orders <= 3: ~1e-21 for m = 3); so ~1e-15 relative holds while the map's derivatives up to order 7
(order 11 for jets of order 5) are within ~1e6 of the tensor's own size, which is what a
flight far from grazing gives (their growth near grazing is like 1/v_impact^k).  The
tests show 1e-12 against the exact linear jets (beta = 0).  With an elastic stop
(tests/studies/test_nonlinear_check_elastic.py) the events agree with symvi's walk to
2e-15 (nonlinear, and an elastic with a rigid stop) and with the exact linear phases to
5e-15 (float64 walk) and 1e-35 (closed form at 50 digits); at a flip of an elastic
Duffing oscillator's branch the chain's multiplier is -1 to 4e-16 and c agrees to 15
digits.

References
----------
[Jorba & Zou 2005] A. Jorba and M. Zou, A software package for the numerical integration
of ODEs by means of high-order Taylor methods, Experimental Mathematics 14 (2005) 99-117.
[Kuznetsov, Elements of Applied Bifurcation Theory] Yu. A. Kuznetsov, 3rd ed., Springer
2004, Sec. 5.4.
"""
import itertools
import math
from dataclasses import dataclass

import mpmath
import numpy as np

from ..errors import ConvergenceError, ParameterError, SingularCaseError
from ..flow.compiled import section_index
from ..flow.linear import frame_of
from ..maps.section import Section
from ..normal_forms.normal_form import flip_coefficient, kuznetsov

#: digits computed beyond the requested ones (the map is then good to ``digits``)
GUARD_DIGITS = 10
#: a Taylor step is at most this fraction of a forcing period (keeps the hull tight)
STEP_FRACTION = 0.25
#: halvings of a step in the contact search before a tangency is refused as grazing
ROOT_DEPTH = 64
#: the longest flight searched, in forcing periods
MAX_PERIODS = 1000

# the nodes of the forces' Taylor recurrences
_CONST, _XVAR, _VVAR, _ADD, _SCALE, _MUL, _DIV, _POW, _EXP, _LOG, _SIN, _SINH, _PAIR, \
    _ATAN = range(14)


class _Recurrences:
    """The Taylor coefficients of the forces f_1..f_N along a series of the state: each
    node of the expressions' DAG, in evaluation order, gets its k-th coefficient from the
    lower ones [Jorba & Zou 2005, Sec. 2]."""

    def __init__(self, exprs, symbols, values, n, dps):
        import sympy
        self._sympy = sympy
        self.n, self.dps = n, dps
        self.state = {symbols[f"x{i + 1}"]: (_XVAR, i) for i in range(n)}
        self.state.update({symbols[f"v{i + 1}"]: (_VVAR, i) for i in range(n)})
        self.values = {symbols[k]: sympy.Float(v, dps + 5) for k, v in values.items()}
        self.ops, self._memo = [], {}
        self.out = [self._node(sympy.sympify(e)) for e in exprs]

    def _add(self, *op):
        self.ops.append(op)
        return len(self.ops) - 1

    def _const(self, value):
        return self._add(_CONST, None, None, value)

    def _mpf(self, e):
        v = e.subs(self.values).evalf(self.dps + 5)
        if not v.is_real:
            raise ParameterError("nonlinear", str(e), "real forces", f"{v} is not real")
        return mpmath.mpf(self._sympy.Float(v, self.dps + 5))

    def _node(self, e):
        got = self._memo.get(e)
        if got is None:
            got = self._memo[e] = self._build(e)
        return got

    def _binary(self, kind, args):
        acc = args[0]
        for a in args[1:]:
            acc = self._add(kind, acc, a, None)
        return acc

    def _build(self, e):
        sp = self._sympy
        if e in self.state:
            kind, i = self.state[e]
            return self._add(kind, i, None, None)
        if not (e.free_symbols & set(self.state)):     # parameters and numbers only
            return self._const(self._mpf(e))
        if isinstance(e, sp.Add):
            return self._binary(_ADD, [self._node(a) for a in e.args])
        if isinstance(e, sp.Mul):
            const = [a for a in e.args if not (a.free_symbols & set(self.state))]
            rest = [self._node(a) for a in e.args if a.free_symbols & set(self.state)]
            node = self._binary(_MUL, rest)
            if const:                        # a constant factor scales (O(1), not O(k))
                node = self._add(_SCALE, node, None, self._mpf(sp.Mul(*const)))
            return node
        if isinstance(e, sp.Pow):
            base, ex = e.args
            if ex.free_symbols & set(self.state):
                return self._node(sp.exp(ex * sp.log(base)))
            if ex.is_Integer:
                m = int(ex)
                if m == 0:
                    return self._const(mpmath.mpf(1))
                pos = self._power(self._node(base), abs(m))
                return pos if m > 0 else self._add(_DIV, self._const(mpmath.mpf(1)), pos, None)
            return self._add(_POW, self._node(base), None, self._mpf(ex))
        if isinstance(e, sp.exp):
            return self._add(_EXP, self._node(e.args[0]), None, None)
        if isinstance(e, sp.log):
            return self._add(_LOG, self._node(e.args[0]), None, None)
        if isinstance(e, (sp.sin, sp.cos, sp.sinh, sp.cosh)):
            a = self._node(e.args[0])
            hyper = isinstance(e, (sp.sinh, sp.cosh))
            s = self._add(_SINH if hyper else _SIN, a, len(self.ops) + 1, None)
            c = self._add(_PAIR, a, s, None)
            self._memo[(sp.sinh if hyper else sp.sin)(e.args[0])] = s
            self._memo[(sp.cosh if hyper else sp.cos)(e.args[0])] = c
            return s if isinstance(e, (sp.sin, sp.sinh)) else c
        if isinstance(e, sp.tan):
            return self._node(sp.sin(e.args[0]) * sp.Pow(sp.cos(e.args[0]), -1, evaluate=False))
        if isinstance(e, sp.tanh):
            return self._node(sp.sinh(e.args[0]) * sp.Pow(sp.cosh(e.args[0]), -1,
                                                         evaluate=False))
        if isinstance(e, sp.atan):
            a = e.args[0]
            w = self._node(sp.Pow(1 + a * a, -1))        # atan' = 1 / (1 + a^2)
            return self._add(_ATAN, self._node(a), w, None)
        raise ParameterError("nonlinear", str(e), "a smooth elementary expression",
                             f"{type(e).__name__} has no Taylor recurrence here")

    def _power(self, a, m):
        """a^m (m >= 1) by products (exact at a = 0, where a^p's recurrence divides)."""
        if m == 1:
            return a
        half = self._power(a, m // 2)
        sq = self._add(_MUL, half, half, None)
        return sq if m % 2 == 0 else self._add(_MUL, sq, a, None)

    def start(self):
        self.c = [[] for _ in self.ops]

    def order(self, k, X, V):
        """Append the k-th coefficient of every node (X, V: the state's coefficients up
        to k); returns the forces' k-th coefficients."""
        c, fdot = self.c, mpmath.fdot
        for i, (kind, a, b, x) in enumerate(self.ops):
            if kind == _PAIR:                  # appended with its sin / sinh
                continue
            ca = c[a] if isinstance(a, int) and kind not in (_XVAR, _VVAR) else None
            if kind == _CONST:
                v = x if k == 0 else mpmath.mpf(0)
            elif kind == _XVAR:
                v = X[a][k]
            elif kind == _VVAR:
                v = V[a][k]
            elif kind == _ADD:
                v = ca[k] + c[b][k]
            elif kind == _SCALE:
                v = x * ca[k]
            elif kind == _MUL:
                v = fdot(ca[:k + 1], c[b][k::-1])
            elif kind == _DIV:                 # q = a / b: q_k = (a_k - sum q_j b_{k-j}) / b_0
                cb, q = c[b], c[i]
                v = (ca[k] - fdot(q[:k], cb[k:0:-1])) / cb[0] if k else ca[0] / cb[0]
            elif kind == _POW:                 # a^p: k a_0 q_k = sum (p (k - j) - j) a_{k-j} q_j
                q = c[i]
                v = (fdot([(x * (k - j) - j) * ca[k - j] for j in range(k)], q[:k])
                     / (k * ca[0]) if k else ca[0] ** x)
            elif kind == _EXP:                 # e' = a' e
                q = c[i]
                v = (fdot([j * ca[j] for j in range(1, k + 1)], q[k - 1::-1]) / k
                     if k else mpmath.exp(ca[0]))
            elif kind == _LOG:                 # a l' = a'
                q = c[i]
                v = ((ca[k] - fdot([j * q[j] for j in range(1, k)], ca[k - 1:0:-1]) / k)
                     / ca[0] if k else mpmath.log(ca[0]))
            elif kind == _ATAN:                # u' = a' w
                cw = c[b]
                v = (fdot([j * ca[j] for j in range(1, k + 1)], cw[k - 1::-1]) / k
                     if k else mpmath.atan(ca[0]))
            else:                              # s' = a' c, c' = -+ a' s
                s, co = c[i], c[b]
                if k == 0:
                    v, w = ((mpmath.sinh(ca[0]), mpmath.cosh(ca[0])) if kind == _SINH
                            else (mpmath.sin(ca[0]), mpmath.cos(ca[0])))
                else:
                    da = [j * ca[j] for j in range(1, k + 1)]
                    v = fdot(da, co[k - 1::-1]) / k
                    w = fdot(da, s[k - 1::-1]) / k
                    w = w if kind == _SINH else -w
                co.append(w)
            c[i].append(v)
        return [c[o][k] for o in self.out]


class NonlinearChain:
    """The impact map P (event to event) of ``model`` at forcing frequency ``omega``,
    independently, at ``digits`` digits (module docstring): :meth:`flight`, :meth:`map`,
    :meth:`map_n`, :meth:`jets`, :meth:`fixed_point`, :meth:`normal_form`.

    The model: rigid and elastic stops (on masses, upper or lower, or between masses),
    any number of masses, any smooth forces (or none).  A section point lies on the
    section of one stop (``on``, 0-based; the model's first by default), in the layout
    symvi's orbits use (one stop on mass k: :meth:`symvi.maps.Section.of`, y = (v_k+,
    x_j, v_j for j != k, tau)), its first flight in the phase ``contact`` (the elastic
    stops in contact, () by default); states z are in mass order (x, v).  Numbers come
    back as mpf at the precision of the call's context; compute with them under
    ``mpmath.workdps(digits)`` or more."""

    def __init__(self, model, omega, digits=40):
        cons = model.constraints
        if not cons:
            raise ParameterError("model", model, "a model with stops (the chain checks maps "
                                 "from a stop's section)")
        if not isinstance(digits, int) or isinstance(digits, bool) or not 16 <= digits <= 200:
            raise ParameterError("digits", digits, "an integer from 16 to 200")
        omega = float(omega)
        if not (math.isfinite(omega) and omega > 0):
            raise ParameterError("omega", omega, "a finite number > 0")
        self.model, self.digits, self.n = model, digits, model.n
        self.dps = digits + GUARD_DIGITS
        self.section = Section.of(model)
        n = self.n
        # the layout (not numerics): flow coordinates q = T x in which each constraint
        # fixes one coordinate (a permutation for stops on masses), and each section's
        # coordinates in that order, as symvi's orbits give their points
        perm, T, _ = frame_of(model)
        if T is None:
            T = np.zeros((n, n))
            for i, j in enumerate(perm):
                T[i, j] = 1.0
        self.positions = tuple(next(i for i, row in enumerate(T) if tuple(row) == c.normal)
                               for c in cons)
        self.frames = tuple(tuple(int(v) for v in section_index(n, q))
                            for q in self.positions)
        with mpmath.workdps(self.dps):
            mp = mpmath.mpf
            self.omega = mp(omega)
            self.T = mpmath.matrix([[mp(v) for v in row] for row in T])
            self.Tinv = self.T ** -1
            M = mpmath.matrix([[mp(v) for v in row] for row in model.mass])
            Minv = M ** -1
            self.Minv = [[Minv[i, j] for j in range(n)] for i in range(n)]
            self.K = [[mp(v) for v in row] for row in model.stiffness]
            self.C = [[mp(v) for v in row] for row in model.damping]
            self.P = [mp(v) for v in model.forcing]
            Mo = np.empty((n, n), dtype=object)
            Mo[:] = self.Minv
            # per constraint: its guard h = sign (c . x - gap), a rigid one's reset
            # v+ = R v- (mass order) at this precision, an elastic one's stiffness and
            # damping (its contact phase, :meth:`_phase`)
            self.normals = [[mp(v) for v in c.normal] for c in cons]
            self.gaps = [mp(c.gap) for c in cons]
            self.signs = [int(c.sign) for c in cons]
            self.elastic = tuple(c.kind == "elastic" for c in cons)
            self.resets = [None if el else c.reset_matrix(Mo, r=mp(c.restitution))
                           for c, el in zip(cons, self.elastic)]
            self.contact_law = [(mp(c.stiffness), mp(c.damping or 0)) if el else None
                                for c, el in zip(cons, self.elastic)]
            self._phases = {}
            self.tol = mp(10) ** -self.dps
            self.degree = math.ceil(self.dps * math.log(10) / 2) + 1
            forces = model._nl
            if forces is None:
                self.forces = None
            else:
                self.forces = _Recurrences(forces.exprs(n), forces.symbols(n),
                                           dict(forces.parameters), n, self.dps)
            self.hcap = STEP_FRACTION * 2 * mpmath.pi / self.omega
            self._bern = _bernstein_table(self.degree)
            self._bern1 = _bernstein_table(self.degree - 1)

    # --- one flight -------------------------------------------------------------------
    def _phase(self, S):
        """(K_S, C_S, f_S) of the contact phase S (the elastic constraints in contact, a
        sorted tuple), at this precision: K + sum k_i c_i c_i^T, C + sum c_si c_i c_i^T,
        sum k_i g_i c_i (module docstring); S = () is the free flight (f_S = 0)."""
        got = self._phases.get(S)
        if got is None:
            n = self.n
            K = [row[:] for row in self.K]
            C = [row[:] for row in self.C]
            f = [mpmath.mpf(0)] * n
            for i in S:
                (k, cs), c, g = self.contact_law[i], self.normals[i], self.gaps[i]
                for a in range(n):
                    f[a] += k * g * c[a]
                    for b in range(n):
                        K[a][b] += k * c[a] * c[b]
                        C[a][b] += cs * c[a] * c[b]
            got = self._phases[S] = (K, C, f)
        return got

    def _series(self, z, phi, S=()):
        """The Taylor coefficients (X, V), each N lists of degree + 1, of the solution
        through z at s = 0, the forcing's phase there phi, in the contact phase S."""
        n, K = self.n, self.degree
        Ks, Cs, fs = self._phase(S)
        X = [[z[i]] for i in range(n)]
        V = [[z[n + i]] for i in range(n)]
        if self.forces is not None:
            self.forces.start()
        s, c = mpmath.sin(phi), mpmath.cos(phi)
        cyc = (s, c, -s, -c)
        wk = mpmath.mpf(1)
        fdot = mpmath.fdot
        for k in range(K):
            f = self.forces.order(k, X, V) if self.forces is not None else None
            xs = [X[j][k] for j in range(n)]
            vs = [V[j][k] for j in range(n)]
            fk = wk * cyc[k % 4]                   # d^k/dt^k sin(omega t + phi) / k!
            rhs = [self.P[i] * fk - fdot(Cs[i], vs) - fdot(Ks[i], xs)
                   - (f[i] if f is not None else 0) + (fs[i] if k == 0 else 0)
                   for i in range(n)]
            for i in range(n):
                X[i].append(vs[i] / (k + 1))
                V[i].append(fdot(self.Minv[i], rhs) / (k + 1))
            wk = wk * self.omega / (k + 1)
        return X, V

    def _step_size(self, X, V, z):
        """h = rho / e^2 (Jorba and Zou), rho from the last two coefficients."""
        K = self.degree
        scale = max(1, max(abs(v) for v in z))
        rho = self.hcap * mpmath.e ** 2
        for j in (K - 1, K):
            top = max(max(abs(X[i][j]) for i in range(self.n)),
                      max(abs(V[i][j]) for i in range(self.n))) / scale
            if top:
                rho = min(rho, top ** (-mpmath.mpf(1) / j))
        return min(rho / mpmath.e ** 2, self.hcap)

    def flight(self, z0, tau, *, t_max=None, contact=()):
        """(t_e, z_e-): :meth:`first_contact` without the constraint's index."""
        t, z, _ = self.first_contact(z0, tau, t_max=t_max, contact=contact)
        return t, z

    def first_contact(self, z0, tau, *, t_max=None, on=None, contact=()):
        """(t_e, z_e-, j): the first event from the state z0 (mass order x, v) at time 0
        and phase tau (the forcing is P sin(omega t + tau)) in the contact phase
        ``contact`` (the elastic constraints in contact, () for a free flight), at
        ``digits`` digits, and the index j of the constraint met: a rigid impact or an
        elastic entry (h_j = 0 rising) for j outside ``contact``, an exit (h_j = 0
        falling) for j in it.  z0 may lie on a guard (h_j = 0 exactly, or the constraint
        ``on``: a start on its section, h_on = 0 up to the rounding of the frame), leaving
        it.  ``t_max``: longest flight searched (default MAX_PERIODS forcing periods);
        there is no guess to give, the search is exhaustive for each guard
        e_j = -+ sign_j (c_j . x - gap_j) (module docstring).

        Raises SingularCaseError "no-impact" (none before t_max: for a contact phase, a
        contact that is not left), "grazing" (a tangency the search cannot resolve, or a
        start on a guard that does not leave it); ParameterError for a start inside a stop
        not in ``contact`` (or outside one in it)."""
        with mpmath.workdps(self.dps):
            z = [mpmath.mpf(v) for v in z0]
            if len(z) != 2 * self.n:
                raise ParameterError("z0", z0, f"{2 * self.n} numbers (x, v in mass order)")
            S = self._check_contact(contact)
            tau = mpmath.mpf(tau)
            t_max = (MAX_PERIODS * 2 * mpmath.pi / self.omega if t_max is None
                     else mpmath.mpf(t_max))
            n, guards = self.n, range(len(self.gaps))
            # the guard of each constraint in this phase: h_j outside a contact, -h_j in it
            side = [-1 if j in S else 1 for j in guards]
            g0 = [side[j] * self._guard(j, z[:n]) for j in guards]
            if any(g > 0 and j != on for j, g in enumerate(g0)):
                raise ParameterError("z0", z0, "a state off every stop not in contact and "
                                     "inside every one in contact (sign (c . x - gap) <= 0, "
                                     ">= 0)")
            on_stop = [g == 0 or j == on for j, g in enumerate(g0)]
            t = mpmath.mpf(0)
            while t < t_max:
                X, V = self._series(z, tau + self.omega * t, S)
                h = self._step_size(X, V, z)
                first = None
                for j in guards:
                    sg, c = side[j] * self.signs[j], self.normals[j]
                    g = [sg * mpmath.fdot(c, [X[i][m] for i in range(n)])
                         for m in range(self.degree + 1)]
                    g[0] = side[j] * self._guard(j, [X[i][0] for i in range(n)])
                    s = self._contact(g, h, on_stop[j])
                    if s is not None and (first is None or s < first[0]):
                        first = (s, j)
                if first is not None:
                    s, j = first
                    return (t + s, [mpmath.polyval(row[::-1], s) for row in X + V], j)
                z = [mpmath.polyval(row[::-1], h) for row in X + V]
                t += h
                on_stop = [False] * len(on_stop)
            raise SingularCaseError("no-impact", f"no {'exit or ' if S else ''}contact "
                                    f"within t = {float(t_max):.6g}")

    def _guard(self, j, x):
        """h_j = sign_j (c_j . x - gap_j) at positions x (mass order)."""
        return self.signs[j] * (mpmath.fdot(self.normals[j], x) - self.gaps[j])

    def _contact(self, g, h, on_stop):
        """The first zero s in (0, h] of the guard's polynomial g (coefficients in s),
        or None (module docstring)."""
        p = [gj * h ** j for j, gj in enumerate(g)]     # in theta = s / h
        if on_stop:                                     # g(0) = 0: look at g / theta
            p, table = p[1:], self._bern1
            if not p[0] < 0:
                raise SingularCaseError("grazing", "the start on the guard does not leave it "
                                        "(speed towards it >= 0)")
        else:
            table = self._bern
            if p[0] + sum(abs(c) for c in p[1:]) < 0:   # |g - g(0)| cannot reach 0
                return None
        b = [mpmath.fdot(row, p[:len(row)]) for row in table]
        box = _leftmost(b, mpmath.mpf(0), mpmath.mpf(1), 0)
        if box is None:
            return None
        lo, hi = box[0] * h, box[1] * h
        poly = (g[1:] if on_stop else g)[::-1]         # its value at lo is < 0
        if mpmath.polyval(poly, hi) == 0:
            return hi
        s = mpmath.findroot(lambda x: mpmath.polyval(poly, x), (lo, hi), solver="anderson")
        if not lo <= s <= hi:
            s = mpmath.findroot(lambda x: mpmath.polyval(poly, x), (lo, hi),
                                solver="bisect")
        return s

    # --- the map ----------------------------------------------------------------------
    def _state(self, y, on=0):
        """(z0 in mass order, tau) of a point y on the section of constraint ``on``: the
        flow coordinate it fixes at its gap, the others y's (:attr:`frames`)."""
        n = self.n
        q = [None] * (2 * n)
        q[self.positions[on]] = self.gaps[on]            # q_p = c . x on the section
        for slot, idx in enumerate(self.frames[on]):
            q[idx] = y[slot]
        x = self.Tinv * mpmath.matrix(q[:n])
        v = self.Tinv * mpmath.matrix(q[n:])
        return [x[i] for i in range(n)] + [v[i] for i in range(n)], y[-1]

    def _point(self, z, j, tau):
        """The section point of constraint j of a state z (mass order) on it."""
        n = self.n
        x = self.T * mpmath.matrix(z[:n])
        v = self.T * mpmath.matrix(z[n:])
        q = [x[i] for i in range(n)] + [v[i] for i in range(n)]
        q[self.positions[j]] = self.gaps[j]               # exactly on the section
        return [q[i] for i in self.frames[j]] + [tau]

    def _map_u(self, y, p, on=0, contact=()):
        """P^p(y) from the section of constraint ``on`` with ``contact`` in contact during
        the first flight, the phase unwrapped (tau + omega sum t_e): (y', flight times,
        constraints met, the contact after the last event).  A rigid impact applies its
        reset; an elastic event (no jump) toggles its constraint's contact."""
        n = self.n
        y = [mpmath.mpf(v) for v in y]
        S = tuple(contact)
        times, hits = [], []
        for _ in range(p):
            z, tau = self._state(y, on)
            t, ze, j = self.first_contact(z, tau, on=on, contact=S)
            times.append(t)
            hits.append(j)
            if self.elastic[j]:                           # an entry or an exit
                S = tuple(sorted(set(S) ^ {j}))
                vplus = ze[n:]
            else:
                vplus = self.resets[j].dot(np.array(ze[n:], dtype=object))
            y = self._point(list(ze[:n]) + list(vplus), j, tau + self.omega * t)
            on = j
        return y, times, hits, S

    def _map_back(self, y, p, on, contact=()):
        """:meth:`_map_u`'s point, refused unless the p-th event is on constraint ``on``
        again, in the phase ``contact`` (else P^p maps between two different sections or
        phases)."""
        img, times, hits, S = self._map_u(y, p, on, contact)
        if hits[-1] != on or S != tuple(contact):
            raise SingularCaseError("signature", f"P^{p} from stop {on + 1} ends on stop "
                                    f"{hits[-1] + 1} (events on stops "
                                    f"{', '.join(str(j + 1) for j in hits)}"
                                    + (f"; in contact with {_stops(S) or 'none'}, from "
                                       f"{_stops(contact) or 'none'}" if any(self.elastic)
                                       else "") + ")")
        return img, times, hits

    def map(self, y, *, on=0, contact=()):
        """P(y): the section point after the next event (one flight, then a rigid reset
        v+ = R v-, or an elastic entry or exit, which keeps v), tau' = tau + omega t_e
        mod 2 pi; y on the section of constraint ``on``, the first flight in the phase
        ``contact`` (a :class:`symvi.model.Signature`'s: with the default (), a start on an
        elastic stop's section leaves it), the image on the section of the constraint met
        (with one stop: the layout of y)."""
        return self.map_n(y, 1, on=on, contact=contact)

    def map_n(self, y, p, *, on=0, contact=()):
        """P^p(y): p events from the section of constraint ``on`` (first flight in the
        phase ``contact``), tau mod 2 pi at the end, on the section of the last
        constraint met."""
        if not isinstance(p, int) or isinstance(p, bool) or p < 1:
            raise ParameterError("p", p, "an integer >= 1")
        self._check_on(on)
        contact = self._check_contact(contact)
        with mpmath.workdps(self.dps):
            y, _, _, _ = self._map_u(self.section.check(y), p, on, contact)
            y[-1] = y[-1] % (2 * mpmath.pi)
            return tuple(y)

    def _check_on(self, on):
        if not isinstance(on, int) or isinstance(on, bool) or not 0 <= on < len(self.gaps):
            raise ParameterError("on", on, f"a constraint index from 0 to {len(self.gaps) - 1}")

    def _check_contact(self, contact):
        """``contact`` as a sorted tuple of elastic constraint indices, or ParameterError."""
        try:
            S = tuple(sorted({int(i) for i in contact}))
            ok = all(0 <= i < len(self.gaps) and self.elastic[i] for i in S) and all(
                not isinstance(i, bool) and float(i) == int(i) for i in contact)
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ParameterError("contact", contact, "indices of elastic constraints (0-based)")
        return S

    # --- jets, fixed point, normal form -----------------------------------------------
    def jets(self, y, order=3, *, p=1, on=0, contact=()):
        """(J, d2, d3[, d4, d5]) of P^p at y: raw derivative tensors, d2[i, j, k] =
        d^2 P_i / dy_j dy_k (as :mod:`symvi.codegen.jets`), numpy object arrays of mpf,
        by central differences of the map at ``digits`` (error bound: module docstring).
        The phase row is the derivative of tau + omega sum t_e.  y lies on the section of
        constraint ``on`` (first flight in the phase ``contact``), and so must P^p(y)
        (in the same phase)."""
        if order not in (1, 2, 3, 4, 5):
            raise ParameterError("order", order, "1 to 5")
        self._check_on(on)
        contact = self._check_contact(contact)
        acc = 4 if order <= 3 else 6
        with mpmath.workdps(self.dps):
            y = [mpmath.mpf(v) for v in self.section.check(y)]
            delta = mpmath.mpf(10) ** -round(self.digits / (acc + order))
            return _differences(lambda u: self._map_back(u, p, on, contact)[0], y, order,
                                acc, delta)

    def fixed_point(self, y_guess, *, p=1, max_iter=30, on=0, contact=()):
        """Newton at ``digits`` digits on P^p(y) = y + (0, ..., 2 pi m), m the forcing
        periods of the guess's flights (finite-difference Jacobians, refreshed when a
        step contracts by less than 1e-6); :class:`ChainFixedPoint`.  y on the section of
        constraint ``on``, the first flight in the phase ``contact``."""
        self._check_on(on)
        contact = self._check_contact(contact)
        with mpmath.workdps(self.dps):
            y = [mpmath.mpf(v) for v in self.section.check(y_guess, "y_guess")]
            dim = len(y)
            twopi = 2 * mpmath.pi
            img, _, _ = self._map_back(y, p, on, contact)
            m = int(mpmath.nint((img[-1] - y[-1]) / twopi))

            def residual(u, img):
                r = [a - b for a, b in zip(img, u)]
                r[-1] -= twopi * m
                return r

            res = residual(y, img)
            norm = max(abs(v) for v in res)
            J, tol = None, mpmath.mpf(10) ** -self.digits
            for _ in range(max_iter):
                if norm <= tol * max(1, max(abs(v) for v in y)):
                    break
                if J is None:
                    J = self.jets(y, 1, p=p, on=on, contact=contact)[0]
                A = mpmath.matrix(dim, dim)
                for i in range(dim):
                    for j in range(dim):
                        A[i, j] = J[i, j] - (1 if i == j else 0)
                dy = mpmath.lu_solve(A, mpmath.matrix([-v for v in res]))
                y = [y[i] + dy[i] for i in range(dim)]
                img, _, _ = self._map_back(y, p, on, contact)
                new = residual(y, img)
                nn = max(abs(v) for v in new)
                if nn > norm * mpmath.mpf("1e-6"):
                    J = None                       # a slow step: a fresh Jacobian
                res, norm = new, nn
            else:
                raise ConvergenceError(f"Newton on P^{p}(y) = y did not converge in "
                                       f"{max_iter} steps", float(norm))
            J = self.jets(y, 1, p=p, on=on, contact=contact)[0]
            _, times, hits = self._map_back(y, p, on, contact)
            y[-1] = y[-1] % twopi
            return ChainFixedPoint(tuple(y), _eigenvalues(J), J, norm, tuple(times), m,
                                   tuple(hits))

    def normal_form(self, y, *, p=1, on=0, contact=()):
        """The flip coefficient and the Neimark-Sacker c1, l1 of P^p at the fixed point y
        (on the section of constraint ``on``, the first flight in the phase ``contact``),
        from the jets of order 3 (:class:`ChainNormalForm` says each normalisation)."""
        J, d2, d3 = self.jets(y, 3, p=p, on=on, contact=contact)
        with mpmath.workdps(self.dps):
            mults = _eigenvalues(J)
            flip = c1 = l1 = None
            near = min(mults, key=lambda z: abs(z + 1))
            if abs(mpmath.im(near)) <= 1e3 * mpmath.eps * max(1, abs(near)):
                f64 = [np.array(a.tolist(), dtype=float) for a in (J, d2, d3)]
                flip = flip_coefficient(*f64)[0]
            if any(mpmath.im(z) > 1e3 * mpmath.eps for z in mults):
                c1, l1 = kuznetsov(J, d2, d3, digits=self.digits)
            return ChainNormalForm(mults, flip, c1, l1)


@dataclass(frozen=True)
class ChainFixedPoint:
    """A fixed point of P^p found by :meth:`NonlinearChain.fixed_point`: ``y`` (tau in
    [0, 2 pi)), its ``multipliers`` (eigenvalues of ``jacobian``, |.| descending, to ~1e-30
    at 40 digits), the final ``residual`` (max norm), the flight ``times`` and ``periods``
    m (the flights last m forcing periods in all), the constraint each flight ends on
    (``hits``, 0-based)."""

    y: tuple
    multipliers: tuple
    jacobian: np.ndarray
    residual: object
    times: tuple
    periods: int
    hits: tuple = ()


@dataclass(frozen=True)
class ChainNormalForm:
    """Normal-form coefficients of P^p at a fixed point from the chain's jets.

    ``flip``: c of eta -> -eta + c eta^3 (:func:`symvi.normal_forms.normal_form.
    flip_coefficient`: q with ||q||_2 = 1, largest component > 0, <p, q> = 1; c > 0
    supercritical), in float64 from the 40-digit jets, when the multiplier nearest -1 is
    real; else None.  ``c1``, ``l1``: Kuznetsov's NS coefficients
    (:func:`symvi.normal_forms.normal_form.kuznetsov` at ``digits``: ||q||_2 = 1,
    <p, q> = 1, l1 = Re(e^{-i theta} c1), l1 < 0 supercritical) for the complex pair with
    modulus nearest 1, when there is one; else None."""

    multipliers: tuple
    flip: object
    c1: object
    l1: object


def _eigenvalues(J):
    """Eigenvalues of J (object array of mpf), |.| descending, then Im descending."""
    ev = mpmath.eig(mpmath.matrix(J.tolist()), left=False, right=False)
    # the moduli rounded well above the rounding: a conjugate pair ties, Im > 0 first
    return tuple(sorted(ev, key=lambda z: (-int(mpmath.nint(abs(z) * 10 ** 20)),
                                           -mpmath.im(z))))


def _bernstein_table(d):
    """Rows T[i] with b_i = sum_j T[i][j] p_j: Bernstein coefficients on [0, 1] of the
    polynomial sum p_j theta^j of degree d (b_i = sum_{j<=i} C(i, j) / C(d, j) p_j)."""
    return [[mpmath.mpf(math.comb(i, j)) / math.comb(d, j) for j in range(i + 1)]
            for i in range(d + 1)]


def _split(b):
    """de Casteljau at 1/2: the Bernstein coefficients of both halves."""
    left, right, cur = [b[0]], [b[-1]], b
    while len(cur) > 1:
        cur = [(cur[i] + cur[i + 1]) / 2 for i in range(len(cur) - 1)]
        left.append(cur[0])
        right.append(cur[-1])
    return left, right[::-1]


def _variations(b):
    signs = [c > 0 for c in b if c != 0]
    return sum(1 for u, v in zip(signs, signs[1:]) if u != v)


def _leftmost(b, lo, w, depth):
    """(lo, hi) in theta of the leftmost sub-interval holding exactly one zero of the
    polynomial with Bernstein coefficients b on [lo, lo + w] (its value at lo < 0), or None
    when its hull stays below 0."""
    if max(b) < 0:
        return None
    if b[-1] >= 0 and _variations(b) <= 1:
        return lo, lo + w
    if depth >= ROOT_DEPTH:
        raise SingularCaseError("grazing", f"the guard comes within {float(max(b)):.2e} of "
                                "the stop inside a step without crossing it: a tangency the "
                                "chain does not resolve")
    left, right = _split(b)
    half = w / 2
    return (_leftmost(left, lo, half, depth + 1)
            or _leftmost(right, lo + half, half, depth + 1))


def _weights(m, acc):
    """{offset: weight} of the central difference of derivative order m and accuracy acc
    (exact rationals as mpf; zero weights dropped)."""
    from sympy import Integer
    from sympy.calculus.finite_diff import finite_diff_weights
    s = (m + acc - 1) // 2
    offs = list(range(-s, s + 1))
    w = finite_diff_weights(m, [Integer(o) for o in offs], Integer(0))[m][-1]
    return {o: mpmath.mpf(int(c.p)) / int(c.q) for o, c in zip(offs, w) if c != 0}


def _differences(f, y, order, acc, delta):
    """(J, d2, ...) of f at y by product stencils of central differences (step delta)."""
    dim = len(y)
    cache = {}

    def at(offset):
        got = cache.get(offset)
        if got is None:
            got = cache[offset] = f([y[i] + offset[i] * delta for i in range(dim)])
        return got

    stencils = {m: _weights(m, acc) for m in range(1, order + 1)}
    out = []
    for m in range(1, order + 1):
        d = np.empty((dim,) * (m + 1), dtype=object)
        for idx in itertools.combinations_with_replacement(range(dim), m):
            alpha = [idx.count(i) for i in range(dim)]
            axes = [stencils[a].items() if a else [(0, mpmath.mpf(1))] for a in alpha]
            acc_v = [mpmath.mpf(0)] * dim
            for combo in itertools.product(*axes):
                w = mpmath.fprod(c for _, c in combo)
                val = at(tuple(o for o, _ in combo))
                for i in range(dim):
                    acc_v[i] += w * val[i]
            scale = delta ** m
            for perm in set(itertools.permutations(idx)):
                for i in range(dim):
                    d[(i,) + perm] = acc_v[i] / scale
        out.append(d)
    return tuple(out)


__all__ = ["NonlinearChain", "ChainFixedPoint", "ChainNormalForm"]


#: the special points :func:`check_special` re-derives (a grazing point has no map there)
CHECKED_KINDS = ("fold", "flip", "ns")


@dataclass(frozen=True)
class SpecialCheck:
    """A special point of a nonlinear model's branch re-derived by the chain at ``digits``
    (:func:`check_special`).

    ``residual``: the chain's fixed-point residual; ``distance``: max |y_chain - y| of
    the section points (how far symvi's float64 orbit lies from the chain's; at a fold,
    where Newton is singular, |P^p(y) - y| at symvi's point);
    ``multiplier``: the chain's critical one (nearest +1 for a fold, -1 for a flip, the
    complex one nearest the unit circle for NS), ``critical_error`` |mu - 1|, |mu + 1| or
    ||mu| - 1| (how well symvi located the point); ``coefficient`` its name (``c`` of a
    flip, ``l1`` of an NS point, each in symvi's normalisation; None for a fold: the chain
    has no quadratic coefficient), with the chain's and symvi's values; ``reason`` why a
    point was not checked ("" when it was)."""

    kind: str
    digits: int
    residual: float = math.nan
    distance: float = math.nan
    multiplier: complex = complex("nan")
    critical_error: float = math.nan
    coefficient: str = None
    chain: float = None
    symvi: float = None
    reason: str = ""

    @property
    def agreement(self):
        """Digits of agreement of the coefficient, -log10 of the relative difference
        (None without one; 17 where the two are equal in float64)."""
        if self.chain is None or self.symvi is None:
            return None
        d = abs(self.chain - self.symvi) / max(abs(self.chain), 1e-300)
        return 17.0 if d == 0 else round(-math.log10(d), 1)

    def as_dict(self):
        z = self.multiplier
        return {"kind": self.kind, "digits": self.digits, "residual": self.residual,
                "distance": self.distance, "multiplier": [z.real, z.imag],
                "critical_error": self.critical_error, "coefficient": self.coefficient,
                "chain": self.chain, "symvi": self.symvi, "agreement": self.agreement,
                "reason": self.reason}

    def text(self):
        if self.reason:
            return f"chain ({self.digits} digits): not checked ({self.reason})"
        z = self.multiplier
        mu = f"{z.real:.6g}" if z.imag == 0 else f"{z.real:.6g}{z.imag:+.6g}i"
        where = (f"|P(y) - y| = {self.distance:.1e} at symvi's orbit" if self.kind == "fold"
                 else f"orbit within {self.distance:.1e}")
        out = (f"chain ({self.digits} digits): {where}, critical multiplier {mu} (off by "
               f"{self.critical_error:.1e})")
        if self.coefficient is not None:
            out += (f", {self.coefficient} = {self.chain:.12g} ({self.agreement} digits of "
                    "agreement)")
        return out


def check_special(sp, digits=40):
    """Re-derive a special point ``sp`` of a branch of a nonlinear model (a
    :class:`symvi.continuation.SpecialPoint` of kind fold, flip or ns) with the chain at
    ``digits``: its orbit by Newton from symvi's, the critical multiplier and, for a flip
    or an NS point, the coefficient (:class:`SpecialCheck`).  With several stops the
    chain starts on the section of the orbit's first event (``signature[0]``), with
    elastic stops in the orbit's phase (``contact``: the stops in contact during its
    first flight), and its own search must meet the stops in the orbit's order.  A point
    the chain does not take (another kind, a start it refuses) comes back with its
    ``reason``."""
    o = sp.orbit
    if sp.kind not in CHECKED_KINDS:
        return SpecialCheck(sp.kind, digits, reason=f"no map at a {sp.kind} point")
    try:
        chain = NonlinearChain(o.model, o.omega, digits)
        sig = tuple(o.signature) if o.signature is not None else (0,) * o.p
        contact = tuple(getattr(o, "contact", ()) or ())
        if sp.kind == "fold":
            # Newton is singular at a fold (a double root): the chain's map and Jacobian
            # at symvi's point, its residual |P^p(y) - y| for the distance
            fp, nf = _at_point(chain, o.points[0], o.p, sig[0], contact), None
        else:
            fp = chain.fixed_point(o.points[0], p=o.p, on=sig[0], contact=contact)
            nf = chain.normal_form(fp.y, p=o.p, on=sig[0], contact=contact)
    except (ParameterError, SingularCaseError, ConvergenceError) as exc:
        return SpecialCheck(sp.kind, digits, reason=str(exc))
    if fp.hits != sig[1:] + sig[:1]:
        # the chain's own contact search met the stops in another order than symvi's
        return SpecialCheck(sp.kind, digits, reason="the chain's events hit stops "
                            f"{_stops(fp.hits[-1:] + fp.hits[:-1])}, symvi's orbit "
                            f"{_stops(sig)}")
    with mpmath.workdps(chain.dps):
        mults = [complex(z) for z in fp.multipliers]
        d = [float(a - b) for a, b in zip(fp.y[:-1], o.points[0][:-1])]
        dt = float((fp.y[-1] - o.points[0][-1] + mpmath.pi) % (2 * mpmath.pi) - mpmath.pi)
    distance = max(abs(v) for v in d + [dt]) if sp.kind != "fold" else float(fp.residual)
    if sp.kind == "fold":
        mu = min(mults, key=lambda z: abs(z - 1))
        err, name, mine, theirs = abs(mu - 1), None, None, None
    elif sp.kind == "flip":
        mu = min(mults, key=lambda z: abs(z + 1))
        err, name = abs(mu + 1), "c"
        mine, theirs = sp.coefficients.get("c"), nf.flip
    else:
        mu = min((z for z in mults if z.imag > 0), key=lambda z: abs(abs(z) - 1),
                 default=complex("nan"))
        err, name = abs(abs(mu) - 1), "l1"
        mine, theirs = sp.coefficients.get("l1"), None if nf.l1 is None else float(nf.l1)
    return SpecialCheck(sp.kind, digits, float(fp.residual), distance, mu, err, name,
                        None if theirs is None else float(theirs),
                        None if mine is None else float(mine))


def _stops(hits):
    return ", ".join(str(j + 1) for j in hits)


def check_branches(branches, digits=40):
    """:func:`check_special` of every special point of ``branches``: one tuple per branch,
    in the order of its ``special``."""
    return tuple(tuple(check_special(sp, digits) for sp in br.special) for br in branches)


def _at_point(chain, y, p, on=0, contact=()):
    """A :class:`ChainFixedPoint` at y itself (no Newton): the chain's Jacobian of P^p
    there, its multipliers, and the residual |P^p(y) - y - (0, .., 2 pi m)|."""
    contact = chain._check_contact(contact)
    with mpmath.workdps(chain.dps):
        u = [mpmath.mpf(v) for v in chain.section.check(y, "y")]
        img, times, hits = chain._map_back(u, p, on, contact)
        twopi = 2 * mpmath.pi
        m = int(mpmath.nint((img[-1] - u[-1]) / twopi))
        res = [a - b for a, b in zip(img, u)]
        res[-1] -= twopi * m
        J = chain.jets(u, 1, p=p, on=on, contact=contact)[0]
        return ChainFixedPoint(tuple(u), _eigenvalues(J), J, max(abs(v) for v in res),
                               tuple(times), m, tuple(hits))
