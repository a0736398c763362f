"""Derive the Taylor jets of the impact map of any N-mass model and write generated/.

One *structure* per N serves every model with N masses: the numbers are inputs,
and the masses are renumbered so that the stop's mass comes first
(:class:`symvi.maps.Section`).  Run through ``symvi regenerate``.

Method.  Between impacts z' = A z + B sin(omega t + tau) (state z = (x, v)), so
z(t) = Phi(t) (z0 - zp(0)) + zp(t) with Phi(t) = e^{A t} and the steady-state
response zp (x_p = U sin + V cos).  About a base section point y with flight
time t_e, the flight of the perturbed point ends at t' = (omega t_e + theta) /
(omega + domega), the implicit theta as in eq. (26); with dt = t' - t_e = O(theta, domega),

    Phi(t') = Phi(t_e) e^{A dt} = sum_{k <= K} (Phi(t_e) A^k) dt^k / k!  + O(order K + 1),

exactly to the order K of the jet.  The matrices E_k = Phi(t_e) A^k are
*inputs* (computed from the eigen-decomposition of A, :mod:`symvi.flow.linear`),
so no matrix exponential or eigenproblem is ever symbolic, damping of any kind
included, and the expressions stay polynomial in the E_k.

1. Build f~ (the section point after the impact, eq. (26) generalised) and the
   guard h = g . x(t') - level (eq. (27) generalised) directly as truncated power
   series in the variables (dy, domega, dp, theta); dp is a *generic* named
   parameter whose direction enters through the inputs pE_k = d(E_k)/dp, pU, pV,
   plevel, pR.
2. Abstract their coefficients (the primitive partials) into symbols.
3. The implicit function theorem order by order, theta_k = -[g(z, theta_<k)]_k / g_theta
   (eq. (37) generalised), then f = f~(z, theta(z)) (eq. (38) generalised).
4. CSE, and print one body that takes sin, cos and the rationals as arguments,
   so the float64 and mpmath backends run the very same expressions.

The constraint is an input (issue 24, item 3; :mod:`symvi.model._constraint`,
:func:`symvi.codegen.layout.jet_constraint`), written in the section's frame, whose
first coordinate is the constrained one (s = c^T x; x_0 = b on the section):

* the guard h = g0 x_0 - level (g0 = +-1 for the upper / lower side, level = g0 b),
  with d level/dp;
* the reset v+ = R v-.  Every rigid reset of the interface is R = I - (1 + r) Q with
  Q = q c^T / (c^T q) of rank one along the guard's normal, so in this frame R is
  the identity but for its column 0: the inputs are R_i0 (i = 0..N-1) and dR_i0/dp.

So one structure per N and order serves any single rigid constraint the section
supports: a stop on any mass, either side, any impulse direction q (M^-1 c for a
non-diagonal M).  A normal that is not a coordinate vector needs a section frame
(issue 25): the flow's inputs change, this structure does not.

Why R as inputs and not applied afterwards.  The reset is linear, so applying it to
each output tensor in codegen would be exact too; but that costs one tensor
contraction per output and order in numpy on every evaluation (microseconds each
against a 16-80 us jet), the pre-impact state for the dR/dp . h term, and a second
output layout.  As inputs, R_i0 adds one product per primitive of a velocity output
inside the one straight-line function (the composition of eq. (38) works on the
abstracted primitives and does not grow), the layout of the outputs is unchanged,
and regeneration stays at seconds.  A general guard normal and a full R as inputs
(tried first) cost up to 1.6x at N = 4, order 1, for entries that are zero in the
section's frame by construction.

Variables: states to degree K; domega or dp once, with at most one state (K = 2, 3).
Module ``impact_n<N>_order<K>`` holds everything up to order K: a multiplier-only
job imports ``order1`` alone.

Orders 4 and 5 (issue 13: the second Lyapunov coefficient l2 at Chenciner
points) hold the state derivatives J, d2..d5 alone, without the domega and dp
slots (:func:`has_parameters`: fewer inputs, a smaller module); they are shipped
for N = 1, 2 (``NS_HIGH``), any other N goes to the per-user cache on demand.
Only :mod:`symvi.codegen.high` imports them.  The same series method suffices
(N = 2, orders 4-5 in seconds, mostly CSE; benchmarks/bench_regen_high.py).
"""
import hashlib
import itertools
import json
import math
import os
from pathlib import Path

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

NS_SHIPPED = (1, 2, 3, 4)
ORDERS = (1, 2, 3)
#: orders 4, 5 (issue 13: l2 at Chenciner points) are shipped for these N only;
#: any other N is generated on demand into the per-user cache
NS_HIGH = (1, 2)
HIGH_ORDERS = (4, 5)
EQUATIONS = "eqs. (19)-(31), (33)-(38) generalised to N masses"
SCRIPT = "derivations/impact_jets.py"
MANIFEST = "impact_manifest.json"


def module_name(n, K, start=None):
    """impact_n<N>_order<K>, or impact_n<N>_s<s>_order<K> for a flight that starts on the
    section of coordinate s (:func:`model`)."""
    return f"impact_n{n}_order{K}" if start is None else f"impact_n{n}_s{start}_order{K}"


def has_parameters(K):
    """Whether order K carries the domega and dp slots: orders 2 and 3 only, since
    orders 4, 5 serve the state derivatives of l2 alone (smaller modules)."""
    return K in (2, 3)


def shipped(n, K):
    """Whether impact_n<n>_order<K> belongs in generated/ (else the per-user cache)."""
    return n in (NS_SHIPPED if K in ORDERS else NS_HIGH if K in HIGH_ORDERS else ())


# --------------------------------------------------------------------------- inputs
def inputs(n, K, start=None):
    """Input names, in order, of the generated functions of structure n, order K (with a
    ``start`` coordinate: the start section's level b0 too, and its d b0/dp)."""
    d = 2 * n
    names = [f"E{k}_{i}_{j}" for k in range(K + 1) for i in range(d) for j in range(d)]
    names += [f"U{i}" for i in range(n)] + [f"V{i}" for i in range(n)]
    if has_parameters(K):
        names += [f"dU{i}" for i in range(n)] + [f"dV{i}" for i in range(n)]
        names += [f"pE{k}_{i}_{j}" for k in range(2) for i in range(d) for j in range(d)]
        names += [f"pU{i}" for i in range(n)] + [f"pV{i}" for i in range(n)]
    # the constraint (symvi.codegen.layout.jet_constraint), in the section's frame: the
    # guard h = g0 x_0 - level and the reset's column R_i0 (v+ = R v-, R = I off column 0)
    reset = [f"R{i}_0" for i in range(n)]
    names += ["omega", "g0", "level"] + reset + ([] if start is None else ["b0"])
    if has_parameters(K):
        names += ["plevel"] + ["p" + x for x in reset] + ([] if start is None else ["pb0"])
    names += [f"y{i}" for i in range(d)] + ["te"]
    return names


# --------------------------------------------------------------------------- series
class Vars:
    """Variable slots: dy_0..dy_{2N-1} (dy_{2N-1} = dtau), domega, dp, theta."""

    def __init__(self, n, K):
        self.n, self.K = n, K
        self.d = 2 * n
        self.w, self.p, self.th = self.d, self.d + 1, self.d + 2
        self.nv = self.d + 3

    def allowed(self, e):
        state = sum(e[:self.d]) + e[self.th]
        np_ = e[self.w] + e[self.p]
        tot = state + np_
        if tot > self.K:
            return False
        return np_ == 0 or (np_ == 1 and has_parameters(self.K) and tot <= 2)

    def unit(self, i):
        e = [0] * self.nv
        e[i] = 1
        return tuple(e)

    @property
    def zero(self):
        return (0,) * self.nv

    def var(self, i):
        return {self.unit(i): sp.Integer(1)}

    def const(self, c):
        return {self.zero: c} if c != 0 else {}

    def add(self, *terms):
        out = {}
        for a in terms:
            for e, c in a.items():
                out[e] = out.get(e, 0) + c
        return {e: c for e, c in out.items() if c != 0}

    def scale(self, a, k):
        return {e: c * k for e, c in a.items()} if k != 0 else {}

    def mul(self, a, b):
        out = {}
        for ea, ca in a.items():
            for eb, cb in b.items():
                e = tuple(x + y for x, y in zip(ea, eb))
                if self.allowed(e):
                    out[e] = out.get(e, 0) + ca * cb
        return out

    def power(self, a, k):
        out = self.const(sp.Integer(1))
        for _ in range(k):
            out = self.mul(out, a)
        return out

    def trig(self, s0, c0, u):
        """(sin, cos) of (x0 + u) as series, sin x0 = s0, cos x0 = c0, u without constant."""
        derivs = [(s0, c0), (c0, -s0), (-s0, -c0), (-c0, s0)]
        S, C, uk = {}, {}, self.const(sp.Integer(1))
        for k in range(self.K + 1):
            ds, dc = derivs[k % 4]
            f = sp.Rational(1, math.factorial(k))
            S = self.add(S, self.scale(uk, ds * f))
            C = self.add(C, self.scale(uk, dc * f))
            uk = self.mul(uk, u)
        return S, C


def model(n, K, start=None):
    """g (eq. 27) and f~ (eq. 26) as truncated series in (dy, domega, dp, theta).

    ``start`` None: the flight starts and ends on the section x_0 = level / g0.  A
    coordinate s: it starts on the section x_s = b0 (another constraint's: a two-sided
    stop, a stop on another mass) and ends on x_0 = level / g0; y is then the point of
    the start section, (v_s+, x_j and v_j for j != s in order, tau) (issue 25)."""
    V_ = Vars(n, K)
    d = V_.d
    sym = {s: sp.Symbol(s, real=True) for s in inputs(n, K, start)}
    E = [[[sym[f"E{k}_{i}_{j}"] for j in range(d)] for i in range(d)] for k in range(K + 1)]
    has_p = has_parameters(K)
    pE = ([[[sym[f"pE{k}_{i}_{j}"] for j in range(d)] for i in range(d)] for k in range(2)]
          if has_p else None)
    omega, te = sym["omega"], sym["te"]
    g0 = sym["g0"]
    y = [sym[f"y{i}"] for i in range(d)]
    dw, dp, th = V_.var(V_.w), V_.var(V_.p), V_.var(V_.th)
    # parameter-dependent inputs: X + pX dp (+ dX domega for the forcing amplitudes)
    U = [V_.add(V_.const(sym[f"U{i}"]),
                V_.scale(dw, sym[f"dU{i}"]) if has_p else {},
                V_.scale(dp, sym[f"pU{i}"]) if has_p else {}) for i in range(n)]
    Vv = [V_.add(V_.const(sym[f"V{i}"]),
                 V_.scale(dw, sym[f"dV{i}"]) if has_p else {},
                 V_.scale(dp, sym[f"pV{i}"]) if has_p else {}) for i in range(n)]
    level = V_.add(V_.const(sym["level"]), V_.scale(dp, sym["plevel"]) if has_p else {})
    RS = [V_.add(V_.const(sym[f"R{i}_0"]), V_.scale(dp, sym[f"pR{i}_0"]) if has_p else {})
          for i in range(n)]
    W = V_.add(V_.const(omega), dw)
    invW = V_.add(V_.const(1 / omega), V_.scale(dw, -1 / omega ** 2))
    dt = V_.mul(V_.add(th, V_.scale(dw, -te)), invW)
    tau = y[d - 1]
    dtau = V_.var(d - 1)

    def zp(s, c):
        xs = [V_.add(V_.mul(U[i], s), V_.mul(Vv[i], c)) for i in range(n)]
        vs = [V_.mul(W, V_.add(V_.mul(U[i], c), V_.scale(V_.mul(Vv[i], s), -1)))
              for i in range(n)]
        return xs + vs

    s0, c0 = V_.trig(sp.sin(tau), sp.cos(tau), dtau)
    zp0 = zp(s0, c0)
    # z0 from the section point, stop-first order: (x_0, x_j; v_0+, v_j), x_0 on the
    # guard: x_0 = level / g0 (b: g0 = +-1, level = +-b)
    x0 = V_.scale(level, 1 / g0)
    if start is None:
        z0 = [x0] + [V_.add(V_.const(y[i]), V_.var(i)) for i in range(1, n)]
        z0 += [V_.add(V_.const(y[0]), V_.var(0))]
        z0 += [V_.add(V_.const(y[n + i - 1]), V_.var(n + i - 1)) for i in range(1, n)]
    else:
        # x_s = b0 on the start section; the others at their slots (y[0] is v_s)
        b0 = V_.add(V_.const(sym["b0"]), V_.scale(dp, sym["pb0"]) if has_p else {})
        z0 = [None] * d
        z0[start] = b0
        z0[n + start] = V_.add(V_.const(y[0]), V_.var(0))
        for q, j in enumerate((j for j in range(n) if j != start), start=1):
            z0[j] = V_.add(V_.const(y[q]), V_.var(q))
            z0[n + j] = V_.add(V_.const(y[n - 1 + q]), V_.var(n - 1 + q))
    w = [V_.add(z0[i], V_.scale(zp0[i], -1)) for i in range(d)]
    hom = [{} for _ in range(d)]
    dtk = V_.const(sp.Integer(1))
    for k in range(K + 1):
        fk = sp.Rational(1, math.factorial(k))
        for i in range(d):
            row = {}
            for j in range(d):
                row = V_.add(row, V_.scale(w[j], E[k][i][j]))
                if has_p and k <= 1:
                    row = V_.add(row, V_.mul(V_.scale(dp, pE[k][i][j]), w[j]))
            hom[i] = V_.add(hom[i], V_.scale(V_.mul(row, dtk), fk))
        dtk = V_.mul(dtk, dt)
    phe = omega * te + tau
    se, ce = V_.trig(sp.sin(phe), sp.cos(phe), V_.add(th, dtau))
    zpe = zp(se, ce)
    ze = [V_.add(hom[i], zpe[i]) for i in range(d)]
    # the guard h = g0 x_0(t') - level (eq. (27) generalised), as h / g0 = x_0(t') - level / g0:
    # theta does not see the factor, g_theta gets it back (build); and the reset v+ = R v-:
    # v_0+ = R_00 v_0-, v_i+ = v_i- + R_i0 v_0- (i > 0)
    g = V_.add(ze[0], V_.scale(x0, -1))
    vp = [V_.mul(RS[0], ze[n])] + [V_.add(ze[n + i], V_.mul(RS[i], ze[n])) for i in range(1, n)]
    ft = [vp[0]] + [ze[i] for i in range(1, n)] + vp[1:] + [V_.add(dtau, th)]
    # only derivatives are output: drop the constant terms
    g = {e: c for e, c in g.items() if e != V_.zero}
    ft = [{e: c for e, c in f.items() if e != V_.zero} for f in ft]
    return V_, g, ft


# --------------------------------------------------------------------------- composition
def zmonomials(V_):
    """Monomials in the z-variables (no theta) kept at order K, ordered by degree."""
    out = []
    zv = [i for i in range(V_.nv) if i != V_.th]
    for deg in range(1, V_.K + 1):
        for combo in itertools.combinations_with_replacement(zv, deg):
            e = [0] * V_.nv
            for c in combo:
                e[c] += 1
            if V_.allowed(tuple(e)):
                out.append(tuple(e))
    return out


def build(n, K, start=None):
    """The straight-line program for structure n, order K: (defs, names, exprs)."""
    V_, g, ft = model(n, K, start)
    defs = []
    counter = itertools.count()

    def abstract(series, tag):
        res = {}
        for e in sorted(series, key=lambda e: (sum(e), e)):
            c = series[e]
            if c == 0:
                continue
            if c.is_Number:
                res[e] = c
                continue
            s = sp.Symbol(f"{tag}{next(counter)}")
            defs.append((s, c))
            res[e] = s
        return res

    gc = abstract(g, "pg")
    fcs = [abstract(f, f"pf{i}_") for i, f in enumerate(ft)]
    eth = V_.unit(V_.th)
    g_th = gc[eth]
    g_rest = {e: c for e, c in gc.items() if e != eth}

    def compose(series, theta):
        powers = {0: V_.const(sp.Integer(1))}
        out = {}
        for e, c in series.items():
            k = e[V_.th]
            ez = list(e)
            ez[V_.th] = 0
            for m in range(len(powers), k + 1):
                powers[m] = V_.mul(powers[m - 1], theta)
            out = V_.add(out, V_.mul({tuple(ez): c}, powers[k]))
        return out

    theta = {}
    mons = zmonomials(V_)
    for k in range(1, K + 1):
        S = compose(g_rest, theta)
        for e in mons:
            if sum(e) == k and e in S:
                theta[e] = -S[e] / g_th
    f = [compose(fc, theta) for fc in fcs]
    names, exprs = [], []
    for e in mons:
        fac = math.prod(math.factorial(x) for x in e)
        for i in range(V_.d):
            names.append(("f", i, e))
            exprs.append(f[i].get(e, 0) * fac)
    for i in range(V_.d):
        e = V_.unit(i)
        names.append(("theta", e))
        exprs.append(theta.get(e, 0))
    names.append(("g_theta",))
    exprs.append(g_th * sp.Symbol("g0", real=True))     # dh/dtheta, h = g0 (x_0 - level / g0)
    return V_, defs, names, exprs


def layout_of(V_, names):
    """Index maps from the flat output tuple to the tensors."""
    pos = {nm: i for i, nm in enumerate(names)}
    d, K = V_.d, V_.K

    def unit(*idx):
        e = [0] * V_.nv
        for j in idx:
            e[j] += 1
        return tuple(e)
    def tensor(m, idx=()):
        # d<m>[i, j1..jm]: every index tuple points at its one sorted monomial (symmetric)
        if len(idx) == m + 1:
            return pos[("f", idx[0], unit(*idx[1:]))]
        return [tensor(m, idx + (j,)) for j in range(d)]
    out = {"J": tensor(1),
           "theta1": [pos[("theta", unit(j))] for j in range(d)],
           "g_theta": pos[("g_theta",)]}
    if K >= 2:
        out["d2"] = tensor(2)
    if has_parameters(K):
        for tag, slot in (("w", V_.w), ("p", V_.p)):
            out[f"d{tag}J"] = [[pos[("f", i, unit(j, slot))] for j in range(d)]
                               for i in range(d)]
            out[f"d{tag}P"] = [pos[("f", i, unit(slot))] for i in range(d)]
    for m in range(3, K + 1):
        out[f"d{m}"] = tensor(m)
    return out


# --------------------------------------------------------------------------- printing
class _BackendFreePrinter(PythonCodePrinter):
    """sin/cos as bare names and each rational p/q as a constant ``q{p}_{q}``, so
    one function body serves float64 and mpmath (they are passed in)."""

    def __init__(self):
        super().__init__({"fully_qualified_modules": False})
        self.rationals = set()

    def _print_Rational(self, expr):
        self.rationals.add((int(expr.p), int(expr.q)))
        return f"q{expr.p}_{expr.q}".replace("-", "m")

    def _print_Half(self, expr):
        return self._print_Rational(expr)

    def _print_sin(self, expr):
        return f"sin({self._print(expr.args[0])})"

    def _print_cos(self, expr):
        return f"cos({self._print(expr.args[0])})"


def emit_body(input_names, defs, exprs):
    """One straight-line ``_jet(inp, sin, cos, Q)``: CSE of the primitives, then of
    the composition.  Returns (source, sorted rationals used)."""
    pr = _BackendFreePrinter()
    lines = ["    (" + ", ".join(input_names) + ",) = inp"]
    rep1, red1 = sp.cse([e for _, e in defs], symbols=sp.numbered_symbols("c"),
                        order="canonical")
    for s, e in rep1:
        lines.append(f"    {s} = {pr.doprint(e)}")
    for (s, _), e in zip(defs, red1):
        lines.append(f"    {s} = {pr.doprint(e)}")
    rep2, red2 = sp.cse(exprs, symbols=sp.numbered_symbols("k"), order="canonical")
    for s, e in rep2:
        lines.append(f"    {s} = {pr.doprint(e)}")
    lines.append("    return (" + ", ".join(pr.doprint(e) for e in red2) + ",)")
    rats = sorted(pr.rationals)
    head = ["def _jet(inp, sin, cos, Q):"]
    if rats:
        head.append("    " + ", ".join(f"q{p}_{q}".replace("-", "m") for p, q in rats) + ", = Q")
    return "\n".join(head + lines), rats


def input_hash():
    """Hash of what the output depends on: this script and the SymPy version."""
    h = hashlib.sha256()
    h.update(Path(__file__).read_bytes())
    h.update(sp.__version__.encode())
    return h.hexdigest()


def render(n, K, ihash, start=None):
    V_, defs, names, exprs = build(n, K, start)
    ins = inputs(n, K, start)
    where = "" if start is None else f", from the section of coordinate {start}"
    header = (f"# Generated by {SCRIPT} from {EQUATIONS}, N = {n}, order {K}{where}. "
              "DO NOT EDIT.\n"
              f"# input-hash: {ihash}\n"
              f"# sympy: {sp.__version__}\n")
    doc = (f'"""Jet of the impact map of any {n}-mass model up to order {K}{where}, '
           f'{EQUATIONS}.\n\n'
           "Machine-written; regenerate with ``symvi regenerate``.  ``f64(inp)`` and\n"
           "``mp(inp)`` evaluate the same expressions; ``inp`` is a tuple in the order of\n"
           "``INPUTS`` (assembled by :mod:`symvi.codegen.layout`); the flat result is\n"
           "indexed by ``LAYOUT``.\n\"\"\"\n")
    src, rats = emit_body(ins, defs, exprs)
    qf = "(" + "".join(f"{p} / {q}, " for p, q in rats) + ")"
    qm = "(" + "".join(f"mpmath.mpf({p}) / {q}, " for p, q in rats) + ")"
    body = [header, doc, "import math", "", "import mpmath", "",
            f"N = {n}", f"ORDER = {K}", f"INPUTS = {ins!r}",
            f"LAYOUT = {layout_of(V_, names)!r}",
            "#: the rationals Q of ``_jet`` in float64 (also used by compiled kernels)",
            f"Q_F64 = {qf}", "", "", src, "", "",
            "def f64(inp):",
            '    """float64 backend (``math``)."""',
            "    return _jet(inp, math.sin, math.cos, Q_F64)", "", "",
            "def mp(inp):",
            '    """mpmath backend at the current ``mpmath.mp.dps``."""',
            f"    return _jet(inp, mpmath.sin, mpmath.cos, {qm})", ""]
    return "\n".join(body)


def _write_atomic(path, text):
    tmp = path.with_name(path.name + ".new")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)


def file_hash(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _read_manifest(out_dir):
    p = Path(out_dir) / MANIFEST
    return json.loads(p.read_text()) if p.exists() else {}


def _modules(ns, orders, starts):
    """(n, K, start) of every module: the structures, and with ``starts`` their variants
    from the section of each coordinate s (flights between two constraints' sections,
    issue 25; orders 4-5 give l2 on such orbits)."""
    for n in ns:
        for K in orders:
            yield n, K, None
    if starts:
        for n in ns:
            for K in orders:
                for st in range(n):
                    yield n, K, st


def generate(out_dir, ns=NS_SHIPPED, orders=ORDERS, force=False, starts=False):
    """Write impact_n<N>_order<K>.py for the requested structures (with ``starts``, also
    impact_n<N>_s<s>_order<K>.py) and update the manifest.

    Skips a module whose manifest entry is fresh.  Returns (written: list, manifest).
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ihash = input_hash()
    man = _read_manifest(out_dir)
    files = dict(man.get("files", {})) if man.get("input_hash") == ihash else {}
    written = []
    for n, K, st in _modules(ns, orders, starts):
        f = f"{module_name(n, K, st)}.py"
        p = out_dir / f
        if not force and f in files and p.exists() and file_hash(p) == files[f]:
            continue
        _write_atomic(p, render(n, K, ihash, st))
        files[f] = file_hash(p)
        written.append(f)
    init = out_dir / "__init__.py"
    if not init.exists():
        _write_atomic(init, '"""Machine-written by derivations/; do not edit."""\n')
    man = {"script": SCRIPT, "equations": EQUATIONS, "sympy": sp.__version__,
           "input_hash": ihash, "files": dict(sorted(files.items()))}
    if written or not (out_dir / MANIFEST).exists():
        _write_atomic(out_dir / MANIFEST, json.dumps(man, indent=2, sort_keys=True) + "\n")
    return written, man


def check(out_dir, ns=NS_SHIPPED, orders=ORDERS, starts=False):
    """Reasons why out_dir is stale for the structures ``ns`` (empty when fresh)."""
    out_dir = Path(out_dir)
    man = _read_manifest(out_dir)
    if not man:
        return [f"{out_dir / MANIFEST} is missing"]
    why = []
    if man.get("input_hash") != input_hash():
        why.append("input hash differs: the derivation script or the SymPy version changed")
    for n, K, st in _modules(ns, orders, starts):
        f = f"{module_name(n, K, st)}.py"
        if f not in man.get("files", {}):
            why.append(f"{f} is not in the manifest")
        elif not (out_dir / f).exists():
            why.append(f"{f} is missing")
        elif file_hash(out_dir / f) != man["files"][f]:
            why.append(f"{f} was edited by hand (hash differs from the manifest)")
    return why


if __name__ == "__main__":
    import argparse
    ap = argparse.ArgumentParser()
    ap.add_argument("out_dir")
    ap.add_argument("--n", type=int, nargs="*", default=list(NS_SHIPPED))
    ap.add_argument("--orders", type=int, nargs="*", default=list(ORDERS))
    ap.add_argument("--force", action="store_true")
    ap.add_argument("--starts", action="store_true")
    a = ap.parse_args()
    w, _ = generate(a.out_dir, tuple(a.n), tuple(a.orders), force=a.force, starts=a.starts)
    print("written: " + ", ".join(w) if w else "up to date")
