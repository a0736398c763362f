"""One owner per concept, checked on the source (issue 24, item 5): one compiled run loop
of the impact map, one attractor classifier, one period detector in symvi/."""
import ast
from pathlib import Path

PKG = Path(__file__).resolve().parents[1] / "symvi"


def _functions():
    """(relative path, FunctionDef, decorator names) of every function in symvi/."""
    for path in sorted(PKG.rglob("*.py")):
        tree = ast.parse(path.read_text("utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef):
                decos = {ast.unparse(d).split("(")[0] for d in node.decorator_list}
                yield str(path.relative_to(PKG)), node, decos


def _called(node):
    """Names of the functions called in ``node`` (a.b(...) gives b)."""
    out = set()
    for n in ast.walk(node):
        if isinstance(n, ast.Call):
            f = n.func
            out.add(f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", ""))
    return out


def _compiled(decos):
    return any(d.endswith("njit") or d.endswith("jit") for d in decos)


def run_loops():
    """Compiled functions with a loop whose body applies the map P (a *step* kernel)."""
    found = []
    for rel, fn, decos in _functions():
        if not _compiled(decos):
            continue
        for loop in (n for n in ast.walk(fn) if isinstance(n, (ast.For, ast.While))):
            if any("step" in name for name in _called(loop)):
                found.append(f"{rel}:{fn.name}")
                break
    return found


def classifiers():
    """Functions that assign an attractor class: they return the code CHAOS (the one
    class only a classifier can decide) or compare a loop length with RATIO_CIRCLE."""
    found = []
    for rel, fn, _ in _functions():
        names = {n.id for n in ast.walk(fn) if isinstance(n, ast.Name)}
        names |= {n.attr for n in ast.walk(fn) if isinstance(n, ast.Attribute)}
        strings = {n.value for n in ast.walk(fn)
                   if isinstance(n, ast.Constant) and isinstance(n.value, str)}
        if "RATIO_CIRCLE" in names or any(
                isinstance(r, ast.Return) and r.value is not None
                and "CHAOS" in {getattr(x, "id", None) for x in ast.walk(r.value)}
                for r in ast.walk(fn)) or "chaos" in strings and "Classification" in names \
                and "classifier" not in str(rel) and "_judge" not in _called(fn) \
                and "classify_section" not in _called(fn):
            found.append(f"{rel}:{fn.name}")
    return found


def period_detectors():
    """Functions that compare points q impacts apart to find a period: they call a
    distance of section points in a loop over a candidate period, named *period*."""
    return [f"{rel}:{fn.name}" for rel, fn, decos in _functions()
            if "period" in fn.name.lower() and fn.name not in ("fixed_point",)
            and any(isinstance(n, (ast.For, ast.While)) for n in ast.walk(fn))
            and ("_dist" in _called(fn) or "_unwrapped" in _called(fn))]


def test_one_run_loop():
    assert run_loops() == ["flow/compiled.py:_run_into"]


def test_one_classifier():
    assert classifiers() == ["simulations/classifier.py:_judge"]


def test_one_period_detector():
    assert period_detectors() == ["simulations/classifier.py:_period"]


def test_the_scans_can_fail(tmp_path):
    """The scans see a second loop, classifier or detector (here: the old plane kernel's
    loop, and the old diagnostics' period detector)."""
    src = '''
import numba as nb
@nb.njit(cache=True)
def _run(c, y, n):
    for k in range(n):
        st = _step_tangent_into(c, y)
def classify(sim):
    if chaos:
        return Classification("chaos", None, None, None, None)
def period_of(section):
    for k in range(1, 10):
        D = _unwrapped(section[k:], 0)
'''
    global PKG
    old = PKG
    (tmp_path / "extra.py").write_text(src)
    PKG = tmp_path
    try:
        assert run_loops() == ["extra.py:_run"]
        assert classifiers() == ["extra.py:classify"]
        assert period_detectors() == ["extra.py:period_of"]
    finally:
        PKG = old
