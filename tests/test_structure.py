"""One owner per concept, checked on the source (issue 24, item 5): one compiled run loop
of the impact map, one attractor classifier, one period detector in symvi/.  (On the
tree before that item the scans find two of each: flow/compiled._run_into and
plane/kernel._run; plane/kernel._classify_one and simulations/diagnostics.classify;
plane/kernel._period and simulations/diagnostics.period_of.)  One precision backend
(item 6): only symvi/numerics/backend.py defines backend classes (before that item the
scan finds six: _backend._Float and _Mp, flow/linear._NumpyLA and _MpLA,
normal_forms/normal_form._NumpyBackend and _MpBackend)."""
import ast
import re
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
    """Compiled functions with a loop whose body applies the map P (a *step* or *flight*
    kernel)."""
    found = []
    for rel, fn, decos in _functions():
        if not _compiled(decos):
            continue
        for loop in (n for n in ast.walk(fn) if isinstance(n, (ast.For, ast.While))):
            if any("step" in name or "flight" in name for name in _called(loop)):
                found.append(f"{rel}:{fn.name}")
                break
    return found


def _decides_a_class(fn):
    """Returns the code CHAOS, uses the circle test's threshold, or returns a
    Classification spelled with a literal "chaos": the marks of a classifier."""
    names = {n.id for n in ast.walk(fn) if isinstance(n, ast.Name)}
    names |= {n.attr for n in ast.walk(fn) if isinstance(n, ast.Attribute)}
    for r in (n for n in ast.walk(fn) if isinstance(n, ast.Return) and n.value is not None):
        inner = list(ast.walk(r.value))
        if any(isinstance(x, ast.Name) and x.id == "CHAOS" for x in inner):
            return True
        if any(isinstance(x, ast.Constant) and x.value == "chaos" for x in inner):
            return True
    return "RATIO_CIRCLE" in names


def classifiers():
    """Functions that decide an attractor class (:func:`_decides_a_class`)."""
    return [f"{rel}:{fn.name}" for rel, fn, _ in _functions() if _decides_a_class(fn)]


def period_detectors():
    """Functions that compare points q impacts apart to find a period: they call a
    distance of section points in a loop over a candidate period, named *period*."""
    return [f"{rel}:{fn.name}" for rel, fn, decos in _functions()
            if "period" in fn.name.lower() and fn.name not in ("fixed_point",)
            and any(isinstance(n, (ast.For, ast.While)) for n in ast.walk(fn))
            and ("_dist" in _called(fn) or "_unwrapped" in _called(fn))]


#: what a precision backend defines (scalar functions, linear algebra): a class that defines
#: two of them is one
BACKEND_OPS = {"sin", "cos", "atan2", "acos", "eig", "ceig", "eigh_pair", "solve", "csolve",
               "inv", "cinv", "svd"}


def backend_classes():
    """Classes defining (as methods or class attributes) two or more of BACKEND_OPS."""
    found = []
    for path in sorted(PKG.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text("utf-8"))):
            if not isinstance(node, ast.ClassDef):
                continue
            names = {b.name for b in node.body if isinstance(b, ast.FunctionDef)}
            names |= {t.id for b in node.body if isinstance(b, ast.Assign)
                      for t in b.targets if isinstance(t, ast.Name)}
            if len(names & BACKEND_OPS) >= 2:
                found.append(f"{path.relative_to(PKG)}:{node.name}")
    return found


def test_one_precision_backend():
    assert backend_classes() == ["numerics/backend.py:_Float64", "numerics/backend.py:_Mp"]


def test_one_run_loop():
    """One run loop for the exact linear flow; the nonlinear flow's (issue 28: simulation
    only; its Taylor or DOP853 flight by a flag) is the one other."""
    assert run_loops() == ["flow/compiled.py:_run_into", "flow/nonlinear.py:_run"]


def test_one_classifier():
    assert classifiers() == ["simulations/classifier.py:_judge"]


def test_one_period_detector():
    assert period_detectors() == ["simulations/classifier.py:_period"]


def test_the_scans_can_fail(tmp_path):
    """The scans see a second loop, classifier, detector or backend (here: the old plane
    kernel's loop, the old diagnostics' period detector, the old flow's and scalar backends)."""
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
class _NumpyLA:
    def solve(A, b):
        return np.linalg.solve(A, b)
    def inv(A):
        return np.linalg.inv(A)
class _Float:
    sin = staticmethod(math.sin)
    cos = staticmethod(math.cos)
'''
    global PKG
    old = PKG
    (tmp_path / "extra.py").write_text(src)
    PKG = tmp_path
    try:
        assert run_loops() == ["extra.py:_run"]
        assert classifiers() == ["extra.py:classify"]
        assert period_detectors() == ["extra.py:period_of"]
        assert backend_classes() == ["extra.py:_NumpyLA", "extra.py:_Float"]
    finally:
        PKG = old


def test_every_kernel_file_shares_the_cache_key():
    """The files that define numba kernels are exactly symvi._numba_cache.KERNEL_FILES, and
    each imports that module (its stamp joins them all: a kernel whose callee's file
    changed is recompiled, not loaded stale)."""
    from symvi import _numba_cache
    root = PKG
    defining = {str(p.relative_to(root)) for p in root.rglob("*.py")
                if re.search(r"^\s*@nb\.njit|^\s*@numba\.njit|nb\.njit\(cache",
                             p.read_text(), re.M)}
    assert defining == set(_numba_cache.KERNEL_FILES)
    for name in _numba_cache.KERNEL_FILES:
        assert "import _numba_cache" in (root / name).read_text(), name


def test_a_kernel_is_stamped_with_every_kernel_file(monkeypatch):
    """A kernel's cache stamp holds the digest of all kernel files: another digest (a
    changed callee file) is another stamp, so numba's index no longer matches."""
    from symvi import _numba_cache
    from symvi.flow import compiled as cf
    from symvi.simulations import classifier
    assert _numba_cache.installed()
    for kernel in (cf._run_into, classifier._classify_one):
        locator = kernel._cache._impl.locator
        assert isinstance(locator, _numba_cache._Joint)
        stamp = locator.get_source_stamp()
        assert stamp[1] == _numba_cache.DIGEST
        monkeypatch.setattr(_numba_cache, "DIGEST", b"another")
        assert locator.get_source_stamp() != stamp
        monkeypatch.undo()
