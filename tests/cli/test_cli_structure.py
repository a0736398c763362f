"""The command line parses and prints only (issue 24, item 7), checked on the source:

* no command module imports numpy, scipy, mpmath, sympy or numba: the numerics are the
  library's; ``symvi/cli/__init__.py`` alone writes .npz files (``save_npz``, ``data_key``);
* no loop in ``symvi/cli`` calls a function of the library (a name a cli module imports
  from a package module outside ``cli``, ``errors`` and ``_io``, or a function of a module
  it imports so): a loop over library calls (a starting guess per point, a check per grid
  point, a second run per output) is something a Python user needs too, so it lives in the
  library as one function the command calls.

(On the tree before item 7 the scans find numpy in ``cli/curve.py`` (parameter tangents
compared), ``cli/simulate.py`` and ``cli/sweep.py``, and library calls in the loops of
``cli/sweep.py`` (a check per grid point, a figure drawn per output), ``cli/hopf.py`` (a
check per point), ``cli/orbit.py`` (the paper's view per orbit) and ``cli/regenerate.py``
(which folder each order goes to).)"""
import ast
from pathlib import Path

CLI = Path(__file__).resolve().parents[2] / "symvi" / "cli"
#: numerical packages: the library's, never a command's
NUMERIC = {"numpy", "scipy", "mpmath", "sympy", "numba"}
#: modules of the package a command may call in a loop: the command line itself, the
#: error types and the checked outputs
PRESENTATION = {"cli", "errors", "_io"}


def _imported(tree):
    """{bound name: top-level module} of every import in ``tree`` (module or function
    level); a relative import from ``symvi.cli`` resolves against ``symvi``."""
    out = {}
    for n in ast.walk(tree):
        if isinstance(n, ast.Import):
            for a in n.names:
                out[(a.asname or a.name).split(".")[0]] = a.name.split(".")[0]
        elif isinstance(n, ast.ImportFrom):
            if n.level == 1:                         # from . import x: the cli itself
                top = "cli"
            elif n.level >= 2:                       # from ..x.y import z / from .. import x
                top = (n.module or "").split(".")[0]
            else:
                top = (n.module or "").split(".")[0]
                top = (n.module.split(".") + [""])[1] if top == "symvi" else top
            for a in n.names:
                name = a.asname or a.name
                out[name] = top or name              # from .. import figures: the module
    return out


def numeric_imports(source):
    """The numerical packages ``source`` imports."""
    return sorted({mod for mod in _imported(ast.parse(source)).values() if mod in NUMERIC})


def _library(imported):
    """The names bound to the library: imported from a package module outside
    :data:`PRESENTATION` (relative imports of ``symvi.cli``)."""
    return {name for name, top in imported.items()
            if top not in PRESENTATION and top not in NUMERIC and not _stdlib(top)}


def _stdlib(top):
    import sys
    return top in sys.stdlib_module_names or top == "argparse"


def _repeated(node):
    """The parts of a loop evaluated once per iteration: a for's body, a while's test and
    body, a comprehension's element, its conditions and its inner iterables."""
    if isinstance(node, (ast.For, ast.AsyncFor)):
        return node.body + node.orelse
    if isinstance(node, ast.While):
        return [node.test] + node.body + node.orelse
    gens = node.generators
    elts = [node.key, node.value] if isinstance(node, ast.DictComp) else [node.elt]
    return elts + [c for g in gens for c in g.ifs] + [g.iter for g in gens[1:]]


_LOOPS = (ast.For, ast.AsyncFor, ast.While, ast.ListComp, ast.SetComp, ast.DictComp,
          ast.GeneratorExp)


def library_calls_in_loops(source):
    """"line: call" of each call of a library function inside a loop of ``source``."""
    tree = ast.parse(source)
    lib = _library(_imported(tree))
    found = []
    for loop in (n for n in ast.walk(tree) if isinstance(n, _LOOPS)):
        for part in _repeated(loop):
            for c in (n for n in ast.walk(part) if isinstance(n, ast.Call)):
                f = c.func
                if isinstance(f, ast.Name) and f.id in lib or (
                        isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name)
                        and f.value.id in lib):
                    found.append(f"{c.lineno}: {ast.unparse(f)}")
    return sorted(set(found))


def _modules():
    return sorted(CLI.glob("*.py"))


def test_no_command_imports_numerics():
    bad = {p.name: numeric_imports(p.read_text("utf-8")) for p in _modules()
           if p.name != "__init__.py"}
    assert not any(bad.values()), bad
    # the one place that writes data imports numpy (and the scan sees it)
    assert numeric_imports((CLI / "__init__.py").read_text("utf-8")) == ["numpy"]


def test_no_loop_calls_the_library():
    bad = {p.name: library_calls_in_loops(p.read_text("utf-8")) for p in _modules()}
    assert not any(bad.values()), bad


def test_the_scans_can_fail():
    """Each scan finds what it looks for (here: the command code of before item 7)."""
    grid = '''
def run(args):
    import numpy as np
    from ..flow import check_omega
    from ..reporting import figures
    omegas = np.linspace(args.a, args.b, args.steps)
    for w in omegas[1:-1]:
        check_omega(args.params, float(w), "omega", warn=False)
    for path in args.figs:
        figures.save(figures.bifurcation_diagram(omegas), path)
'''
    hopf = '''
def run(args):
    from ..studies.mpcheck import check_point
    from . import print_json
    checks = [check_point(p, pt) for pt in points(args)]
    print_json({k: str(v) for k, v in checks})
'''
    assert numeric_imports(grid) == ["numpy"]
    assert library_calls_in_loops(grid) == ["10: figures.bifurcation_diagram",
                                            "10: figures.save", "8: check_omega"]
    assert library_calls_in_loops(hopf) == ["5: check_point"]
