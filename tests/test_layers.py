"""The package layout shows the layers (issue 11): a module imports only modules of its
own layer or of the layers below it.  The old top-level names of moved modules are
deprecated shims (issue 24; tests/test_deprecated_paths.py): nothing in symvi/, tests/,
benchmarks/ or the README's code imports them."""
import ast
import os
import re
from pathlib import Path

import symvi
from symvi.reporting import scenes as sc

#: lowest first; a module belongs to the layer of its longest matching prefix
LAYERS = [
    ("numerics: shared tolerances and the precision backend", ("numerics",)),
    ("base", ("errors", "_io", "progress", "_compiled", "_numba_cache", "_deprecated")),
    ("model", ("model",)),
    ("flow and maps", ("flow", "maps")),
    ("codegen", ("codegen",)),
    ("orbits and normal forms", ("orbits", "normal_forms")),
    ("simulations", ("simulations",)),
    ("continuation", ("continuation",)),
    ("analysis", ("analysis",)),
    ("curves and planes", ("curves", "plane")),
    ("studies and the paper (its preset, views, reduction, oracle and audit)",
     ("studies", "paper")),
    ("reporting", ("reporting",)),
    ("cli", ("cli", "__main__")),
]
#: old top-level names kept for one release: each warns and forwards to its new module
MOVED = {"normal_form": "normal_forms.normal_form", "codim2": "normal_forms.codim2",
         "hopf": "analysis.hopf", "precision": "analysis.precision",
         "simulation": "simulations.simulation", "diagnostics": "simulations.diagnostics",
         "mpcheck": "studies.mpcheck", "codim2_check": "studies.codim2_check",
         "circle_check": "studies.circle_check", "report": "reporting.report",
         "figures": "reporting.figures", "scenes": "reporting.scenes",
         "params": "paper.params", "orbit": "paper.orbit", "jets": "paper.jets",
         "flow.modal2": "paper.modal_flow"}
#: old modules whose names went to several new homes (each name warns, naming its home)
SPLIT = {"poincare": ("maps.impact", "paper.modal_map")}


def _layer(m):
    best = None
    for i, (_, prefixes) in enumerate(LAYERS):
        for p in prefixes:
            if (m == p or m.startswith(p + ".")) and (best is None or len(p) > best[1]):
                best = (i, len(p))
    return None if best is None else best[0]


def _modules():
    pkg = os.path.dirname(symvi.__file__)
    for root, _, files in os.walk(pkg):
        for f in files:
            if f.endswith(".py"):
                rel = os.path.relpath(os.path.join(root, f), pkg)[:-3].replace(os.sep, ".")
                rel = rel[:-len(".__init__")] if rel.endswith(".__init__") else rel
                if rel != "__init__" and rel not in MOVED and rel not in SPLIT:
                    yield rel


#: imports that still run up, each to be removed by the step of issue 24 named
PENDING = set()


def test_no_module_imports_a_layer_above_its_own():
    bad = []
    for m in _modules():
        lm = _layer(m)
        if lm is None:
            bad.append(f"{m}: in no layer")
            continue
        for t in sc.module_imports(m):
            if not t or m.startswith(t + "."):
                continue
            if t in MOVED or t in SPLIT:
                bad.append(f"{m} imports the old name symvi.{t}, not "
                           f"symvi.{MOVED.get(t) or ' / symvi.'.join(SPLIT[t])}")
                continue
            lt = _layer(t)
            if (lt is None or lt > lm) and (m, t) not in PENDING:
                bad.append(f"{m} ({LAYERS[lm][0]}) imports {t} "
                           f"({'no layer' if lt is None else LAYERS[lt][0]})")
    assert not bad, "\n".join(bad)


ROOT = Path(__file__).resolve().parents[1]
_OLD = re.compile(r"symvi\.(%s)(\.\w+)*" % "|".join([*MOVED, *SPLIT]))


def old_paths_used(source):
    """The old module paths ``source`` (Python) imports or names in a string: ``import
    symvi.hopf``, ``from symvi.hopf import x``, ``from symvi import hopf``, and strings
    such as ``importorskip("symvi.hopf")`` or ``monkeypatch.setattr("symvi.hopf.x", ...)``
    (which would patch the shim, not the module that uses it).  Docstrings are prose."""
    tree = ast.parse(source)
    docs = {id(n.value) for n in ast.walk(tree) if isinstance(n, ast.Expr)
            and isinstance(n.value, ast.Constant) and isinstance(n.value.value, str)}
    out = []
    for n in ast.walk(tree):
        if isinstance(n, ast.Import):
            out += [a.name for a in n.names if _OLD.fullmatch(a.name)]
        elif isinstance(n, ast.ImportFrom) and n.module and not n.level:
            if _OLD.fullmatch(n.module):
                out.append(n.module)
            elif n.module == "symvi":
                out += [f"symvi.{a.name}" for a in n.names if a.name in MOVED or a.name in SPLIT]
        elif (isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docs
              and _OLD.fullmatch(n.value)):
            out.append(n.value)
    return out


def test_no_test_benchmark_or_readme_block_uses_an_old_path():
    """Issue 24, item 8: tests, benchmarks and the README use the new names only (the
    deprecation test, which exercises the old names on purpose, aside)."""
    files = [p for p in sorted((ROOT / "tests").rglob("*.py")) + sorted(
        (ROOT / "benchmarks").rglob("*.py")) if p.name != "test_deprecated_paths.py"]
    bad = [f"{p.relative_to(ROOT)}: {u}" for p in files
           for u in old_paths_used(p.read_text(encoding="utf-8"))]
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    for k, block in enumerate(re.findall(r"^```python\s*\n(.*?)^```", readme, re.M | re.S)):
        bad += [f"README.md, python block {k + 1}: {u}" for u in old_paths_used(block)]
    assert not bad, "\n".join(bad)


def test_no_symvi_module_names_an_old_path():
    """Strings too: a lazy ``importlib.import_module("symvi.hopf")`` inside symvi/ is an
    import of the old path that the ast import graph above does not see."""
    bad = [f"symvi.{m}: {u}" for m in _modules()
           for u in old_paths_used(Path(sc._module_file(m)).read_text(encoding="utf-8"))]
    assert not bad, "\n".join(bad)


def test_the_old_path_scan_sees_every_form():
    src = ('"""symvi.hopf in a docstring is prose."""\n'
           "import symvi.hopf\nfrom symvi.precision import x\nfrom symvi import jets, scenes\n"
           "from symvi import hopf_points, simulate\nimport symvi.analysis.hopf\n"
           "m.setattr('symvi.simulation.simulate', 1)\nimportorskip('symvi.report')\n"
           "s = 'symvi.hopf_points'\nt = 'symvi.hopf was not found'\n")
    assert old_paths_used(src) == ["symvi." + p for p in (
        "hopf", "precision", "jets", "scenes", "simulation.simulate", "report")]


def test_the_paper_sits_on_top():
    """Issue 24, item 1: below the layer of the paper (and of the studies) no module imports
    the paper or asks whether an object is its ``Params``: the preset becomes a Model at the
    boundary (:meth:`symvi.Model.of`), and general results carry general fields only."""
    top = next(i for i, (name, _) in enumerate(LAYERS) if name.startswith("studies and the paper"))
    bad = []
    for m in _modules():
        lm = _layer(m)
        if lm is None or lm >= top:
            continue
        tree = ast.parse(Path(sc._module_file(m)).read_text(encoding="utf-8"))
        for n in ast.walk(tree):
            if (isinstance(n, ast.Call) and getattr(n.func, "id", None) == "isinstance"
                    and len(n.args) == 2 and "Params" in ast.unparse(n.args[1])):
                bad.append(f"{m}:{n.lineno}: {ast.unparse(n)}")
            if isinstance(n, ast.ImportFrom) and n.module and (
                    n.module == "paper" or n.module.startswith("paper.")
                    or n.module.startswith("symvi.paper")):
                bad.append(f"{m}:{n.lineno}: imports {n.module}")
            if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name) and \
                    n.target.id in ("f1_paper", "f1_wan", "wan_a", "f1_printed"):
                bad.append(f"{m}:{n.lineno}: a general result with the paper's field {n.target.id}")
    assert not bad, "\n".join(bad)


def test_test_folders_mirror_the_package_tree():
    """Issue 24, item 9: a test folder is named after the package it tests (``tests/orbits``
    for ``symvi/orbits``), so one area runs alone; ``fuzz`` and ``property`` are kinds of
    test that cross the packages, ``cli`` tests the command line (``symvi/cli``)."""
    pkg = Path(symvi.__file__).parent
    packages = {p.name for p in pkg.iterdir() if (p / "__init__.py").is_file()}
    folders = {p.name for p in (ROOT / "tests").iterdir()
               if p.is_dir() and (p / "__init__.py").is_file()}
    assert folders - packages <= {"fuzz", "property"}, sorted(folders - packages)
