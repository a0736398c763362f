"""The old top-level module paths (issue 24, item 8): SciPy-style shims for one release.

``symvi.hopf`` and the eleven others are small modules of their own: importing one neither
warns nor loads its new module; reading an attribute warns with a DeprecationWarning that
names the new path and returns the new module's very object.  This file is the only place
that uses the old paths (tests/test_layers.py holds the rest of the repository to that).
"""
import ast
import importlib
import json
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

import symvi
from symvi.reporting import scenes as sc

from .test_layers import MOVED

OLD = sorted(MOVED)


def _public(module):
    return sorted(n for n in vars(module) if not n.startswith("_"))


def _message(old):
    return (f"symvi.{old} is deprecated; import symvi.{MOVED[old]} instead; "
            f"the old path will be removed in the next release")


@pytest.mark.parametrize("old", OLD)
def test_every_attribute_is_the_new_modules_object_with_a_warning(old):
    shim = importlib.import_module(f"symvi.{old}")
    new = importlib.import_module(f"symvi.{MOVED[old]}")
    assert shim is not new
    names = _public(new)
    assert names
    for name in names:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            got = getattr(shim, name)
        assert got is getattr(new, name), name
        assert [w.category for w in caught] == [DeprecationWarning], name
        assert str(caught[0].message) == _message(old)
        assert caught[0].filename == __file__          # points at the caller's line


@pytest.mark.parametrize("old", OLD)
def test_from_import_and_star_import_warn_and_give_the_same_objects(old):
    new = importlib.import_module(f"symvi.{MOVED[old]}")
    name = _public(new)[0]
    ns = {}
    with pytest.warns(DeprecationWarning, match=rf"import symvi\.{MOVED[old]} instead"):
        exec(f"from symvi.{old} import {name}", ns)
    assert ns[name] is getattr(new, name)
    star = {}
    with pytest.warns(DeprecationWarning, match=rf"symvi\.{old} is deprecated"):
        exec(f"from symvi.{old} import *", star)
    assert {k for k in star if not k.startswith("__")} == set(_public(new))
    assert all(star[k] is getattr(new, k) for k in _public(new))


@pytest.mark.parametrize("old", OLD)
def test_private_names_dir_and_missing_names(old):
    shim = importlib.import_module(f"symvi.{old}")
    new = importlib.import_module(f"symvi.{MOVED[old]}")
    assert dir(shim) == sorted(dir(new))
    private = sorted(n for n in vars(new) if n.startswith("_") and not n.startswith("__"))
    for name in private[:3]:                         # private names forward too, with the warning
        with pytest.warns(DeprecationWarning):
            assert getattr(shim, name) is getattr(new, name)
    with warnings.catch_warnings():
        warnings.simplefilter("error")               # module machinery probes do not warn
        assert not hasattr(shim, "__path__")
        assert not hasattr(shim, "__wrapped__")
    with pytest.raises(AttributeError, match=rf"symvi\.{MOVED[old]}' has no attribute 'no_such"):
        shim.no_such_name


def test_importing_the_old_paths_neither_warns_nor_loads_the_new_modules():
    """``import symvi.hopf`` is cheap and silent (SciPy: the warning comes on use); and
    ``import symvi`` imports no shim.  (``symvi.paper.params`` comes with ``import symvi``:
    ``symvi.Params`` is its class.)"""
    code = ("import json, sys, symvi;"
            "before = sorted(m for m in sys.modules if m.startswith('symvi'));"
            f"olds = {OLD!r}; news = {[MOVED[o] for o in OLD]!r};"
            "import importlib; [importlib.import_module('symvi.' + o) for o in olds];"
            "print(json.dumps([before, [n for n in news if 'symvi.' + n in sys.modules"
            " and 'symvi.' + n not in before]]))")
    out = subprocess.run([sys.executable, "-W", "error::DeprecationWarning", "-c", code],
                         capture_output=True, text=True, check=True)
    before, loaded = json.loads(out.stdout.strip().splitlines()[-1])
    assert not {f"symvi.{o}" for o in OLD} & set(before)
    assert loaded == []


def test_public_functions_survive_the_old_imports():
    """symvi.simulate and symvi.hopf_points stay the functions (``symvi.simulation`` and
    ``symvi.hopf`` are module attributes of their own names)."""
    code = ("import types, warnings, symvi;"
            f"[__import__('symvi.' + o) for o in {OLD!r}];"
            "warnings.simplefilter('ignore', DeprecationWarning);"
            "symvi.simulation.simulate; symvi.hopf.hopf_points;"
            "names = ['simulate', 'jet', 'hopf_points', 'period1_orbits', 'poincare_map'];"
            "print([n for n in names if isinstance(getattr(symvi, n), types.ModuleType)"
            " or not callable(getattr(symvi, n))])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_each_shim_is_the_two_line_form_and_there_are_no_others():
    """Every old path calls the one helper (symvi/_deprecated.py) with its own new path, and
    imports nothing else; the top-level modules that do so are exactly the old paths."""
    pkg = Path(symvi.__file__).parent
    shims = set()
    for f in sorted(pkg.rglob("*.py")):
        tree = ast.parse(f.read_text(encoding="utf-8"))
        calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call)
                 and getattr(n.func, "id", None) == "_moved"]
        if not calls:
            continue
        name = ".".join(f.relative_to(pkg).with_suffix("").parts)
        shims.add(name)
        assert name in MOVED, f.name
        assert sc.module_imports(name) == ("_deprecated",), f.name
        assert [ast.literal_eval(a) for a in calls[0].args[1:]] == [f"symvi.{MOVED[name]}"]
    assert shims == set(MOVED)


def test_split_module_symvi_poincare_warns_naming_each_names_home():
    """symvi.poincare's names went two ways (issue 24, item 1): the map of any model to
    symvi.maps.impact, the paper's modal oracle to symvi.paper.modal_map."""
    from symvi.maps import impact
    from symvi.paper import modal_map
    homes = {"poincare_map": impact, "step": modal_map, "MapStep": modal_map,
             "fd_jacobian": modal_map}
    shim = importlib.import_module("symvi.poincare")
    for name, home in homes.items():
        with pytest.warns(DeprecationWarning, match=rf"import {name} from {home.__name__}"):
            assert getattr(shim, name) is getattr(home, name)
    with pytest.raises(AttributeError):
        shim.nothing_here


def test_the_paper_oracle_names_of_symvi_flow_warn_and_forward():
    from symvi.paper import modal_flow
    import symvi.flow as flow
    for name in ("first_impact", "motion_from", "forcing_amplitudes", "GRAZING"):
        with pytest.warns(DeprecationWarning, match="symvi.paper.modal_flow"):
            assert getattr(flow, name) is getattr(modal_flow, name)


def test_the_papers_reduction_left_normal_form_with_a_warning():
    """Issue 24, item 1: normal_form(paper=True) and the reduction's names in
    symvi.normal_forms.normal_form still work for a release, warning and naming the new home;
    the default normal form carries general fields only."""
    import numpy as np

    from symvi.normal_forms import normal_form as nfm
    from symvi.paper import reduction
    th = 0.3
    A = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])    # |lambda| = 1
    d2, d3 = np.zeros((2, 2, 2)), np.zeros((2, 2, 2, 2))
    d3[0, 0, 0, 0] = d3[1, 1, 1, 1] = -1.0
    plain = nfm.normal_form(A, d2, d3)
    assert not hasattr(plain, "f1_printed") and not hasattr(plain, "paper")
    with pytest.warns(DeprecationWarning, match="symvi.paper.reduction.normal_form"):
        old = nfm.normal_form(A, d2, d3, paper=True)
    new = reduction.normal_form(A, d2, d3)
    assert type(old) is reduction.PaperNormalForm and old.f1_printed == new.f1_printed
    assert new.l1 == plain.l1 and new.f1_wan == pytest.approx(-plain.l1 / 4, rel=1e-12)
    for name in ("eigenmatrix", "appendix_printed", "f1_eq60", "wan_a", "PaperReduction"):
        with pytest.warns(DeprecationWarning, match="symvi.paper.reduction"):
            assert getattr(nfm, name) is getattr(reduction, name)
