"""The package layout shows the layers (issue 11): a module imports only modules of its
own layer or of the layers below it, and the old top-level names of moved modules stay
importable as the very same module objects."""
import importlib
import os

import symvi
from symvi.reporting import scenes as sc

#: lowest first; a module belongs to the layer of its longest matching prefix
LAYERS = [
    ("base", ("errors", "_io", "_backend", "progress", "_compiled")),
    ("model", ("params", "model")),
    ("flow and maps", ("flow", "maps")),
    ("codegen", ("codegen", "_paper_eval")),
    ("orbits, normal forms, the paper's view and its modal oracles",
     ("orbits", "normal_forms", "orbit", "jets", "poincare", "paper", "paper.modal_orbit",
      "paper.modal_map")),
    ("continuation", ("continuation",)),
    ("analysis", ("analysis",)),
    ("simulations", ("simulations",)),
    ("curves and planes", ("curves", "plane")),
    ("studies and the paper's audit", ("studies", "paper.audit", "paper.audit_orbit")),
    ("reporting", ("reporting",)),
    ("cli", ("cli", "__main__")),
]
#: old top-level names kept for users: each is its new module, aliased
MOVED = {"normal_form": "normal_forms.normal_form", "codim2": "normal_forms.codim2",
         "hopf": "analysis.hopf", "precision": "analysis.precision",
         "simulation": "simulations.simulation", "diagnostics": "simulations.diagnostics",
         "mpcheck": "studies.mpcheck", "codim2_check": "studies.codim2_check",
         "circle_check": "studies.circle_check", "report": "reporting.report",
         "figures": "reporting.figures", "scenes": "reporting.scenes"}


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
                if rel != "__init__" and rel not in MOVED:
                    yield rel


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
            if t in MOVED:
                bad.append(f"{m} imports the old name symvi.{t}, not symvi.{MOVED[t]}")
                continue
            lt = _layer(t)
            if lt is None or lt > lm:
                bad.append(f"{m} ({LAYERS[lm][0]}) imports {t} "
                           f"({'no layer' if lt is None else LAYERS[lt][0]})")
    assert not bad, "\n".join(bad)


def test_old_module_names_are_the_moved_modules():
    for old, new in MOVED.items():
        assert importlib.import_module(f"symvi.{old}") is importlib.import_module(f"symvi.{new}")
    assert callable(symvi.simulate) and callable(symvi.hopf_points)
