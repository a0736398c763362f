"""Shared constants are defined in one place (issue 24, item 6): the tolerances live in
:mod:`symvi.numerics.tolerances`, and the modules that use one import it.  An AST scan
of ``symvi/`` (no imports, no execution): fast."""
import ast
import importlib
import math
import pathlib
import re
from collections import defaultdict

import symvi
from symvi.numerics import tolerances

PKG = pathlib.Path(symvi.__file__).parent
UPPER = re.compile(r"_?[A-Z][A-Z0-9_]*")


def _value(node):
    """The value of a constant expression (1e-6, 2.0 ** -52, (1e-4, 1e4), -1.5), else None."""
    if isinstance(node, ast.Constant):
        return node.value
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        v = _value(node.operand)
        return None if v is None else (-v if isinstance(node.op, ast.USub) else v)
    if isinstance(node, ast.BinOp):
        a, b = _value(node.left), _value(node.right)
        ops = {ast.Add: lambda x, y: x + y, ast.Sub: lambda x, y: x - y,
               ast.Mult: lambda x, y: x * y, ast.Div: lambda x, y: x / y,
               ast.Pow: lambda x, y: x ** y}
        if isinstance(a, (int, float)) and isinstance(b, (int, float)) and type(node.op) in ops:
            return ops[type(node.op)](a, b)
        return None
    if isinstance(node, ast.Tuple):
        vs = [_value(e) for e in node.elts]
        return None if any(v is None for v in vs) else tuple(vs)
    return None


def _is_float(v):
    """A float, or a tuple of numbers with a float in it (a range such as OMEGA_RANGE)."""
    if isinstance(v, float):
        return True
    return (isinstance(v, tuple) and v and any(isinstance(x, float) for x in v)
            and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v))


def _targets(stmt):
    """(name, value node or None) of each UPPER_CASE name a module-level statement binds."""
    if isinstance(stmt, ast.Assign):
        pairs = []
        for t in stmt.targets:
            if isinstance(t, ast.Name):
                pairs.append((t.id, stmt.value))
            elif isinstance(t, (ast.Tuple, ast.List)):
                pairs += [(e.id, None) for e in t.elts if isinstance(e, ast.Name)]
        return [(n, v) for n, v in pairs if UPPER.fullmatch(n)]
    if isinstance(stmt, ast.AnnAssign) and isinstance(stmt.target, ast.Name) and stmt.value:
        return [(stmt.target.id, stmt.value)] if UPPER.fullmatch(stmt.target.id) else []
    return []


def _modules():
    for path in sorted(PKG.rglob("*.py")):
        yield path.relative_to(PKG.parent).as_posix(), ast.parse(path.read_text("utf-8"))


MODULES = list(_modules())


def test_no_float_constant_defined_in_two_modules():
    """A module-level UPPER_CASE float (or float range) is written as a number in one
    module only; every other module imports it (an import is no definition)."""
    seen = defaultdict(list)
    for rel, tree in MODULES:
        for stmt in tree.body:
            for name, node in _targets(stmt):
                v = None if node is None else _value(node)
                if _is_float(v):
                    seen[name].append(f"{rel} ({v!r})")
    dup = {n: w for n, w in seen.items() if len(w) > 1}
    assert not dup, "defined in more than one module (import it from symvi.numerics):\n" + \
        "\n".join(f"{n}: {', '.join(w)}" for n, w in sorted(dup.items()))


def test_no_constant_bound_twice_in_one_module():
    """No module-level UPPER_CASE name is bound twice in one module (a second binding
    silently replaced plane.kernel's attractor code ESCAPE = 6 by the bound 1e6)."""
    bad = []
    for rel, tree in MODULES:
        count = defaultdict(int)
        for stmt in tree.body:
            for name, _ in _targets(stmt):
                count[name] += 1
        bad += [f"{rel}: {n}" for n, k in count.items() if k > 1]
    assert not bad, "\n".join(bad)


def test_each_tolerance_is_documented():
    """Every constant of symvi.numerics.tolerances has a ``#:`` comment just above it
    saying what it bounds and why its value."""
    path = PKG / "numerics" / "tolerances.py"
    lines = path.read_text("utf-8").splitlines()
    tree = ast.parse("\n".join(lines))
    names = []
    for stmt in tree.body:
        for name, _ in _targets(stmt):
            names.append(name)
            assert lines[stmt.lineno - 2].startswith("#: "), f"{name} has no #: comment"
    assert names and all(isinstance(getattr(tolerances, n), (int, float, tuple)) for n in names)


def test_old_names_are_the_shared_values():
    """The old module-level names stay importable, as the shared values."""
    t = tolerances
    same = {
        "symvi.paper.params": {"RESONANCE_REFUSE": t.FORCING_RESONANCE_REFUSE,
                         "RESONANCE_WARN": t.FORCING_RESONANCE_WARN,
                         "ABS_MAX": t.ABS_MAX, "OMEGA_RANGE": t.OMEGA_RANGE},
        "symvi.flow.linear": {"RESONANCE_REFUSE": t.FORCING_RESONANCE_REFUSE,
                              "RESONANCE_WARN": t.FORCING_RESONANCE_WARN,
                              "RESONANCE_CUT": t.FORCING_RESONANCE_CUT,
                              "OMEGA_RANGE": t.OMEGA_RANGE},
        "symvi.model._model": {"ABS_MAX": t.ABS_MAX},
        "symvi.analysis.hopf": {"RESONANCE_GAP": t.FORCING_RESONANCE_CUT},
        "symvi.normal_forms.normal_form": {"RESONANCE_REFUSE": t.STRONG_RESONANCE_REFUSE,
                                           "RESONANCE_WARN": t.STRONG_RESONANCE_WARN},
        "symvi.orbits.period1": {"ISOLATION_REFUSE": t.ISOLATION_REFUSE,
                                 "ISOLATION_WARN": t.ISOLATION_WARN, "END_TOL": t.END_TOL},
        "symvi.orbits.admissibility": {"END_TOL": t.END_TOL},
        "symvi.orbits.periodic": {"NEWTON_TOL": t.NEWTON_TOL},
        "symvi.analysis.precision": {"EPS64": t.EPS64},
        "symvi.simulations.diagnostics": {"MIN_CLASSIFY": t.MIN_CLASSIFY},
        "symvi.cli.simulate": {"MIN_CLASSIFY": t.MIN_CLASSIFY},
    }
    for mod, names in same.items():
        m = importlib.import_module(mod)
        for name, value in names.items():
            assert getattr(m, name) == value, f"{mod}.{name}"
    # the values the modules had before they were shared (unchanged by the move)
    assert (t.FORCING_RESONANCE_REFUSE, t.FORCING_RESONANCE_WARN, t.FORCING_RESONANCE_CUT) == \
        (1e-10, 1e-4, 1e-6)
    assert (t.STRONG_RESONANCE_REFUSE, t.STRONG_RESONANCE_WARN) == (1e-10, 1e-3)
    assert t.EPS64 == math.ulp(1.0)
    # the paper's |sin(pi w_j / omega)| is half the general |1 - e^{i w_j T}|: same bounds
    mo = importlib.import_module("symvi.paper.modal_orbit")
    assert (mo.KAPPA_REFUSE, mo.KAPPA_WARN) == (1e-9, 1e-4)


def test_plane_escape_code_is_not_the_escape_bound():
    """The classifier's (once plane.kernel's) attractor code ESCAPE indexes ATTRACTORS (it
    was replaced by the
    bound 1e6, so an escaping point got code 64 and no label)."""
    from symvi.simulations import classifier as kernel
    assert kernel.ATTRACTORS[kernel.ESCAPE] == "escape" and kernel.ESCAPE_MAX == 1e6
