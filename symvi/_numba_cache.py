"""One cache key for all of symvi's numba kernels.

numba keeps a kernel's machine code on disk (``cache=True``) and recompiles it when the
kernel's own source file changes.  But a kernel's machine code also holds the kernels it
calls, which may live in other files: the classifier's holds the run loop of
``flow/compiled.py``, ``period1`` holds the shooting of ``orbits/_shooting.py``.  After a
change to a callee's file only (a ``git pull`` into an editable install, a constants layout
that moved), numba would load the caller's stale code and compute with the old layout:
silently wrong numbers.  Here every symvi kernel is stamped with the content hash of all
of :data:`KERNEL_FILES` besides its own file's, so a change to any of them recompiles
them all.  Each kernel module imports this module before its first decorator.

The locator classes are numba's own (in-tree ``__pycache__``, ``NUMBA_CACHE_DIR``,
the user-wide cache), subclassed for files inside this package only; ``install`` puts
them first in numba's list, once.  Should a future numba change that private list, the
kernels keep numba's per-file stamp and :func:`installed` says so (a test checks it).
"""
import hashlib
import os

_HERE = os.path.dirname(os.path.abspath(__file__))

#: the package's files that define numba kernels (tests/test_structure.py checks the list)
KERNEL_FILES = ("_compiled.py", "codegen/_assemble.py", "flow/_hull.py", "flow/_program.py",
                "flow/_steady.py", "flow/compiled.py", "flow/jet_taylor.py", "flow/nljet.py",
                "flow/nlsticking.py", "flow/nonlinear.py", "flow/sticking.py", "flow/taylor.py",
                "flow/tps.py", "orbits/_period1.py", "orbits/_shooting.py",
                "simulations/classifier.py", "simulations/diagnostics.py")


def _digest():
    h = hashlib.sha256()
    for name in KERNEL_FILES:
        with open(os.path.join(_HERE, name), "rb") as fh:
            h.update(name.encode() + b"\0" + fh.read())
    return h.digest()


#: the joint stamp of the kernel files, as they are when the package is imported
DIGEST = _digest()


class _Joint:
    """A numba locator's stamp joined with :data:`DIGEST` (mixed into numba's locators)."""

    def get_source_stamp(self):
        return super().get_source_stamp(), DIGEST

    @classmethod
    def from_function(cls, py_func, py_file):
        if not os.path.abspath(py_file).startswith(_HERE + os.sep):
            return None                     # not a symvi file: numba's own locators
        return super().from_function(py_func, py_file)


def _impl():
    from numba.core import caching
    return getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl")


def install():
    """Put the joint locators first in numba's list (idempotent)."""
    try:
        from numba.core import caching
        impl = _impl()
        if any(issubclass(c, _Joint) for c in impl._locator_classes):
            return
        bases = [getattr(caching, n) for n in ("UserProvidedCacheLocator",
                                               "InTreeCacheLocator", "UserWideCacheLocator")]
        joint = [type("Joint" + b.__name__, (_Joint, b), {}) for b in bases]
        impl._locator_classes = joint + list(impl._locator_classes)
    except (ImportError, AttributeError):   # a numba without this private interface
        pass


def installed():
    """Whether numba uses the joint stamp for symvi's kernels."""
    try:
        return any(issubclass(c, _Joint) for c in _impl()._locator_classes)
    except (ImportError, AttributeError):
        return False


install()
