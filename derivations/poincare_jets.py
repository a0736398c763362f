"""Derive the Taylor jets of the Poincaré map, eqs. (19)–(38), and write generated/.

The only writer of ``generated/``.  Run through ``symvi regenerate``.

Method (avoids expression swell):

1. Build f~ (eq. 26) and g (eq. 27) in SymPy about a base impact point: inputs
   are the modal data (psi, omega_j, modal forcing F_j), omega, r, b, the base
   section point y = (x1dot+, x20, x20dot, tau) and the base flight time t_e.
   Variables: dX = (dv, dx2, dx2dot, dtau), domega and the implicit dtheta, with
   t_e' = (omega t_e + dtheta) / (omega + domega), so tau' = tau + dtau + omega t_e + dtheta.
2. Take only the *primitive* partials of f~ and g at 0 (plain SymPy diff).
3. Compose with truncated power series over abstract symbols for those partials:
   the implicit function theorem order by order, dtheta_k = -[g(z, dtheta_<k)]_k / g_theta
   (eq. 37 generalised), then f = f~(z, dtheta(z)) (eq. 38 generalised).
4. CSE each order's straight-line program and print it once, as a body that
   takes sin, cos and the rational constants as arguments: ``f64`` passes
   ``math`` and floats, ``mp`` passes mpmath and mpf, so both backends run the
   very same expressions.

Order K's module holds everything up to order K, so a caller that needs only
the Jacobian imports ``order1`` alone.  domega enters at order >= 2 only:
the explicit d/domega of P and of its Jacobian, from which the evaluator forms
F11 of eq. (34) along the orbit branch.
"""
import hashlib
import itertools
import json
import math
import os
import sys
from pathlib import Path

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

#: input names of every generated function, in order
INPUTS = ["psi11", "psi12", "psi21", "psi22", "w1", "w2", "F1", "F2",
          "omega", "r", "b", "v1", "x20", "x20d", "tau", "te"]
NZ = 5          # z = (dv, dx2, dx2d, dtau, domega); index 4 is domega
NS = 4          # state variables
ORDERS = (1, 2, 3)
EQUATIONS = "eqs. (19)-(31), (33)-(38)"
SCRIPT = "derivations/poincare_jets.py"


def allowed(e, K):
    """Monomials z^e kept at order K: states to degree K; domega once, with at most one state."""
    deg = sum(e)
    if deg > K or deg == 0:
        return deg == 0
    w = e[4]
    return w == 0 or (K >= 2 and w == 1 and deg <= 2)


def monomials(K, nvars=NZ):
    out = []
    for deg in range(1, K + 1):
        for combo in itertools.combinations_with_replacement(range(nvars), deg):
            e = [0] * nvars
            for c in combo:
                e[c] += 1
            if allowed(tuple(e), K):
                out.append(tuple(e))
    return out


# --- truncated power series in z: dict {exponent tuple: sympy expr} ---------------

def s_mul(a, b, K):
    out = {}
    for ea, ca in a.items():
        for eb, cb in b.items():
            e = tuple(x + y for x, y in zip(ea, eb))
            if allowed(e, K):
                out[e] = out.get(e, 0) + ca * cb
    return out


def s_add(a, b):
    out = dict(a)
    for e, c in b.items():
        out[e] = out.get(e, 0) + c
    return out


def s_scale(a, k):
    return {e: c * k for e, c in a.items()}


def compose(coeffs, theta, K):
    """sum_alpha c_alpha z^alpha_z theta^alpha_th, truncated at order K.

    ``coeffs`` maps (z exponent, theta power) -> coefficient.
    """
    powers = {0: {(0,) * NZ: sp.Integer(1)}}
    out = {}
    for (ez, k), c in coeffs.items():
        for n in range(len(powers), k + 1):
            powers[n] = s_mul(powers[n - 1], theta, K)
        term = s_mul({ez: c}, powers[k], K)
        out = s_add(out, term)
    return out


def model():
    """f~ (eq. 26) and g (eq. 27) as SymPy expressions of the inputs and variables."""
    (psi11, psi12, psi21, psi22, w1, w2, F1, F2, omega, r, b,
     v1, x20, x20d, tau, te) = sp.symbols(INPUTS, real=True)
    dv, dx2, dx2d, dtau, dw, dth = sp.symbols("dv dx2 dx2d dtau dw dth", real=True)
    psi = sp.Matrix([[psi11, psi12], [psi21, psi22]])
    D = psi11 * psi22 - psi12 * psi21
    adj = sp.Matrix([[psi22, -psi12], [-psi21, psi11]])
    W = omega + dw
    ws, Fs = (w1, w2), (F1, F2)
    A = [Fs[j] / (ws[j] ** 2 - W ** 2) for j in range(2)]             # eq. (7)
    xi0 = adj * sp.Matrix([b, x20 + dx2]) / D                         # eqs. (21)-(22)
    xid0 = adj * sp.Matrix([v1 + dv, x20d + dx2d]) / D                # eqs. (23)-(24)
    ph0 = tau + dtau
    a = [xi0[j] - A[j] * sp.sin(ph0) for j in range(2)]
    bb = [(xid0[j] - A[j] * W * sp.cos(ph0)) / ws[j] for j in range(2)]
    t_e = (omega * te + dth) / W                                      # t_e of eq. (26)
    ph = omega * te + dth + ph0                                       # W t_e + tau + dtau
    xi = [a[j] * sp.cos(ws[j] * t_e) + bb[j] * sp.sin(ws[j] * t_e) + A[j] * sp.sin(ph)
          for j in range(2)]                                          # eq. (28)
    xid = [ws[j] * (-a[j] * sp.sin(ws[j] * t_e) + bb[j] * sp.cos(ws[j] * t_e))
           + A[j] * W * sp.cos(ph) for j in range(2)]                 # eq. (29)
    x1 = psi[0, 0] * xi[0] + psi[0, 1] * xi[1]
    g = x1 - b                                                        # eq. (27)
    ft = [-r * (psi[0, 0] * xid[0] + psi[0, 1] * xid[1]),            # eq. (26), absolute
          psi[1, 0] * xi[0] + psi[1, 1] * xi[1],
          psi[1, 0] * xid[0] + psi[1, 1] * xid[1],
          dtau + dth]
    return g, ft, (dv, dx2, dx2d, dtau, dw), dth


def primitive_partials(expr, zvars, dth, K):
    """{(z exponent, theta power): d^alpha expr / alpha!} at 0 for the monomials order K needs."""
    zero = {v: 0 for v in (*zvars, dth)}
    out = {}
    for deg in range(1, K + 1):
        for combo in itertools.combinations_with_replacement(range(NZ + 1), deg):
            e = [0] * (NZ + 1)
            for c in combo:
                e[c] += 1
            ez, k = tuple(e[:NZ]), e[NZ]
            # theta counts as order >= 1 in z; domega rule applies to its slot
            probe = list(ez)
            probe[0] += k
            if not allowed(tuple(probe), K):
                continue
            d = expr
            for idx, n in enumerate(e):
                if n:
                    d = sp.diff(d, (*zvars, dth)[idx], n)
            val = d.subs(zero)
            if val != 0:
                out[(ez, k)] = val / math.prod(math.factorial(n) for n in e)
    return out


def build_order(K):
    """The straight-line program for order K: (assignments, outputs, layout)."""
    g, ft, zvars, dth = model()
    defs = []                      # (abstract symbol, expression in inputs)
    counter = itertools.count()

    def abstract(partials, tag):
        res = {}
        for key in sorted(partials, key=lambda kk: (sum(kk[0]) + kk[1], kk)):
            s = sp.Symbol(f"{tag}{next(counter)}")
            defs.append((s, partials[key]))
            res[key] = s
        return res

    gc = abstract(primitive_partials(g, zvars, dth, K), "pg")
    fcs = []
    for i in range(NS):
        if i == 3:      # f~4 = dtau + dth exactly: no partials to evaluate
            fcs.append({((0, 0, 0, 1, 0), 0): sp.Integer(1), ((0,) * NZ, 1): sp.Integer(1)})
        else:
            fcs.append(abstract(primitive_partials(ft[i], zvars, dth, K), f"pf{i}_"))
    g_th = gc[((0,) * NZ, 1)]
    # implicit function theorem, order by order: eq. (37) generalised
    theta = {}
    g_rest = {key: c for key, c in gc.items() if key != ((0,) * NZ, 1)}
    for k in range(1, K + 1):
        S = compose(g_rest, theta, K)
        for e in monomials(K):
            if sum(e) == k and e in S:
                theta[e] = -S[e] / g_th
    f = [compose(fc, theta, K) for fc in fcs]                        # eq. (38) generalised
    # outputs: unique derivatives (coefficient * e!) in a fixed layout
    names, exprs = [], []
    for e in monomials(K):
        fac = math.prod(math.factorial(n) for n in e)
        for i in range(NS):
            names.append(("f", i, e))
            exprs.append(f[i].get(e, 0) * fac)
    for e in monomials(1):
        if e[4] == 0:
            names.append(("theta", e))
            exprs.append(theta.get(e, 0))
    names.append(("g_theta",))
    exprs.append(g_th)
    return defs, names, exprs


class _BackendFreePrinter(PythonCodePrinter):
    """Prints sin/cos as bare names and each rational p/q as a constant ``q{p}_{q}``,
    so one function body serves float64 and mpmath (they are passed in)."""

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


def emit_body(defs, exprs):
    """One straight-line function ``_jet(inp, sin, cos, Q)``: CSE of the primitives,
    then of the composition.  Returns (source, sorted rationals used)."""
    pr = _BackendFreePrinter()
    lines = ["    " + ", ".join(INPUTS) + " = inp"]
    prim_syms = [s for s, _ in defs]
    rep1, red1 = sp.cse([e for _, e in defs], symbols=sp.numbered_symbols("c"),
                        order="canonical")
    for s, e in rep1:
        lines.append(f"    {s} = {pr.doprint(e)}")
    for s, e in zip(prim_syms, red1):
        lines.append(f"    {s} = {pr.doprint(e)}")
    rep2, red2 = sp.cse(exprs, symbols=sp.numbered_symbols("k"), order="canonical")
    for s, e in rep2:
        lines.append(f"    {s} = {pr.doprint(e)}")
    outs = ", ".join(pr.doprint(e) for e in red2)
    lines.append(f"    return ({outs},)")
    rats = sorted(pr.rationals)
    names = [f"q{p}_{q}".replace("-", "m") for p, q in rats]
    head = ["def _jet(inp, sin, cos, Q):"]
    if names:
        head.append(f"    {', '.join(names)}, = Q")
    return "\n".join(head + lines), rats


def layout_of(names, K):
    """Index maps from the flat output tuple to the tensors (numpy index arrays as lists)."""
    pos = {n: i for i, n in enumerate(names)}
    out = {}

    def unit(*idx):
        e = [0] * NZ
        for j in idx:
            e[j] += 1
        return tuple(e)
    out["J"] = [[pos[("f", i, unit(j))] for j in range(NS)] for i in range(NS)]
    out["theta1"] = [pos[("theta", unit(j))] for j in range(NS)]
    out["g_theta"] = pos[("g_theta",)]
    if K >= 2:
        out["d2"] = [[[pos[("f", i, unit(j, k))] for k in range(NS)] for j in range(NS)]
                     for i in range(NS)]
        out["dwJ"] = [[pos[("f", i, unit(j, 4))] for j in range(NS)] for i in range(NS)]
        out["dwP"] = [pos[("f", i, unit(4))] for i in range(NS)]
    if K >= 3:
        out["d3"] = [[[[pos[("f", i, unit(j, k, l))] for l in range(NS)] for k in range(NS)]
                      for j in range(NS)] for i in range(NS)]
    return out


def input_hash():
    """Hash of what the output depends on: this script and the SymPy version."""
    h = hashlib.sha256()
    h.update(Path(__file__).read_bytes())
    h.update(sp.__version__.encode())
    return h.hexdigest()


def render(K, ihash):
    defs, names, exprs = build_order(K)
    header = (f"# Generated by {SCRIPT} from {EQUATIONS}, order {K}. DO NOT EDIT.\n"
              f"# input-hash: {ihash}\n"
              f"# sympy: {sp.__version__}\n")
    doc = (f'"""Jet of the Poincaré map up to order {K}, {EQUATIONS}.\n\n'
           "Machine-written; regenerate with ``symvi regenerate``.  ``f64(inp)`` and\n"
           "``mp(inp)`` evaluate the same expressions; ``inp`` is a tuple in the order of\n"
           "``INPUTS``; the flat result is indexed by ``LAYOUT``.\n\"\"\"\n")
    src, rats = emit_body(defs, exprs)
    qf = "(" + "".join(f"{p} / {q}, " for p, q in rats) + ")"
    qm = "(" + "".join(f"mpmath.mpf({p}) / {q}, " for p, q in rats) + ")"
    body = [header, doc, "import math", "", "import mpmath", "",
            f"INPUTS = {INPUTS!r}", f"ORDER = {K}", f"LAYOUT = {layout_of(names, K)!r}",
            "#: the rationals Q of ``_jet`` in float64 (also used by the compiled kernels)",
            f"Q_F64 = {qf}", "", "",
            src, "", "",
            "def f64(inp):",
            '    """float64 backend (``math``)."""',
            "    return _jet(inp, math.sin, math.cos, Q_F64)", "", "",
            "def mp(inp):",
            '    """mpmath backend at the current ``mpmath.mp.dps``; rationals exact to that precision."""',
            f"    return _jet(inp, mpmath.sin, mpmath.cos, {qm})", ""]
    return "\n".join(body)


def _write_atomic(path, text):
    tmp = path.with_name(path.name + ".new")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)


def file_hash(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def generate(out_dir, orders=ORDERS, force=False):
    """Write order<K>.py and manifest.json into out_dir; skip when the input hash is unchanged.

    Returns (written: bool, manifest: dict).
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ihash = input_hash()
    man_path = out_dir / "manifest.json"
    old = json.loads(man_path.read_text()) if man_path.exists() else {}
    if not force and not check(out_dir, orders):
        return False, old
    # keep entries of orders not regenerated now only if they are still fresh
    files = {}
    for K in sorted(set(old.get("orders", [])) - set(orders)):
        f = f"order{K}.py"
        if (old.get("input_hash") == ihash and (out_dir / f).exists()
                and file_hash(out_dir / f) == old["files"].get(f)):
            files[f] = old["files"][f]
    for K in orders:
        p = out_dir / f"order{K}.py"
        _write_atomic(p, render(K, ihash))
        files[p.name] = file_hash(p)
    init = out_dir / "__init__.py"
    if not init.exists():
        _write_atomic(init, f'"""Machine-written by {SCRIPT}; do not edit."""\n')
    man = {"script": SCRIPT, "equations": EQUATIONS, "sympy": sp.__version__,
           "orders": sorted(int(f[5:-3]) for f in files), "inputs": INPUTS,
           "input_hash": ihash, "files": files}
    _write_atomic(man_path, json.dumps(man, indent=2, sort_keys=True) + "\n")
    return True, man


def check(out_dir, orders=ORDERS):
    """List of reasons why out_dir is stale for ``orders`` (empty when fresh)."""
    out_dir = Path(out_dir)
    man_path = out_dir / "manifest.json"
    if not man_path.exists():
        return [f"{man_path} is missing"]
    man = json.loads(man_path.read_text())
    why = []
    if man.get("input_hash") != input_hash():
        why.append("input hash differs: the derivation script or the SymPy version changed")
    for K in orders:
        f = f"order{K}.py"
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
    ap.add_argument("--order", type=int, default=3)
    ap.add_argument("--force", action="store_true")
    a = ap.parse_args()
    wrote, _ = generate(a.out_dir, tuple(range(1, a.order + 1)), force=a.force)
    print("written" if wrote else "up to date")
