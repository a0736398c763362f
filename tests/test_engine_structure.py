"""One continuation engine (issue 24, item 4), checked on the source: one pseudo-arclength
loop, one corrector, one locator, one Tracker, one turning-angle limit, one result family
and one event vocabulary in ``symvi/``.  An AST scan (no execution) plus a few imports."""
import ast
import pathlib
from collections import defaultdict

import symvi
from symvi.continuation.result import EVENT_KINDS, Located, Result

PKG = pathlib.Path(symvi.__file__).parent
TREES = {p.relative_to(PKG.parent).as_posix(): ast.parse(p.read_text("utf-8"))
         for p in sorted(PKG.rglob("*.py"))}


def _called(node):
    """Names of the functions called anywhere inside ``node`` (f(...) and x.f(...))."""
    out = set()
    for n in ast.walk(node):
        if isinstance(n, ast.Call):
            f = n.func
            out.add(f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute)
                    else "")
    return out


def _functions():
    for rel, tree in TREES.items():
        for n in ast.walk(tree):
            if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)):
                yield rel, n


def test_one_pseudo_arclength_loop():
    """A predictor-corrector loop is a loop that both corrects a point (correct or chord)
    and takes the new tangent: exactly one function of symvi/ has one."""
    loops = []
    for rel, fn in _functions():
        for n in ast.walk(fn):
            if isinstance(n, (ast.While, ast.For)):
                calls = _called(n)
                if "tangent" in calls and calls & {"correct", "chord"}:
                    loops.append(f"{rel}:{fn.name}")
                    break
    assert loops == ["symvi/continuation/engine.py:run"], loops


def test_one_corrector_locator_and_tracker():
    defs = defaultdict(list)
    for rel, tree in TREES.items():
        for n in tree.body:                      # module level (Model.tangent is a method)
            if isinstance(n, (ast.FunctionDef, ast.ClassDef)) and n.name in (
                    "correct", "chord", "tangent", "root_on_arc", "sign_change", "Tracker",
                    "_to_bound", "_chord", "_factor", "_sign_change", "interpolated_root",
                    "_interpolated_root"):
                defs[n.name].append(rel)
    expected = {name: ["symvi/continuation/engine.py"] for name in
                ("correct", "chord", "tangent", "root_on_arc", "sign_change", "Tracker",
                 "_to_bound", "_factor", "interpolated_root")}
    assert dict(defs) == expected
    # every other tracker is a client of the one Tracker
    trackers = [(rel, n) for rel, tree in TREES.items() for n in ast.walk(tree)
                if isinstance(n, ast.ClassDef) and n.name.endswith("Tracker")
                and n.name != "Tracker"]
    assert trackers
    for rel, n in trackers:
        assert any((isinstance(b, ast.Name) and b.id == "Tracker") or
                   (isinstance(b, ast.Attribute) and b.attr == "Tracker") for b in n.bases), \
            (rel, n.name)


def test_one_turning_angle_limit():
    """MIN_COS (the step control's largest turn of the tangent) is defined once."""
    found = []
    for rel, tree in TREES.items():
        for stmt in tree.body:
            if isinstance(stmt, ast.Assign):
                for t in stmt.targets:
                    if isinstance(t, ast.Name) and t.id.endswith("MIN_COS"):
                        found.append(f"{rel}:{t.id}")
    assert found == ["symvi/continuation/engine.py:MIN_COS"]


def test_one_result_family():
    from symvi.analysis.hopf import HopfResult
    from symvi.continuation import Branch, SpecialPoint
    from symvi.curves import Codim2Point, Curve
    assert issubclass(Branch, Result) and issubclass(Curve, Result)
    assert issubclass(SpecialPoint, Located) and issubclass(Codim2Point, Located)
    assert not issubclass(HopfResult, Result)          # hopf_points stays a client


def test_every_event_kind_written_in_symvi_is_in_the_vocabulary():
    """The literal kinds given to SpecialPoint, Codim2Point and hopf's Event, and the kinds
    the trackers test for (TESTS of symvi.curves.special), are all in EVENT_KINDS."""
    from symvi.curves.special import TESTS
    seen = set()
    for rel, tree in TREES.items():
        for n in ast.walk(tree):
            if isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and \
                    n.func.id in ("SpecialPoint", "Codim2Point", "Event") and n.args and \
                    isinstance(n.args[0], ast.Constant) and isinstance(n.args[0].value, str):
                seen.add((rel, n.args[0].value))
    assert len(seen) > 8
    bad = sorted(s for s in seen if s[1] not in EVENT_KINDS)
    assert not bad, bad
    assert all(k in EVENT_KINDS for ks in TESTS.values() for k in ks)


def test_old_names_warn_and_name_the_new_ones():
    import importlib

    import pytest
    for old, name, new in (("symvi.continuation.branch", "MIN_COS", "continuation.engine"),
                           ("symvi.curves.curve", "CURVE_MIN_COS", "engine as MIN_COS"),
                           ("symvi.continuation.special", "Tracker", "as Codim1Tracker"),
                           ("symvi.curves.special", "Tracker", "as Codim2Tracker")):
        with pytest.warns(DeprecationWarning, match=new.replace(".", r"\.")):
            getattr(importlib.import_module(old), name)
    from symvi.continuation import engine
    from symvi.curves.special import Codim2Tracker
    with pytest.warns(DeprecationWarning):
        from symvi.curves.curve import CURVE_MIN_COS
    with pytest.warns(DeprecationWarning):
        from symvi.curves.special import Tracker
    assert CURVE_MIN_COS == engine.MIN_COS and Tracker is Codim2Tracker


def test_a_kind_outside_the_vocabulary_is_refused():
    import pytest

    from symvi.analysis.hopf import Event
    with pytest.raises(ValueError, match="EVENT_KINDS"):
        Event("hopf", 1.0, "a")
    assert Event("multiplier-1", 1.0, "a").kind == "multiplier-1"
