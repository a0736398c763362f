"""Compiled (numba) evaluators of the generated jets, eqs. (33)–(38).

A kernel is the machine-written ``f64`` of ``generated/order<K>.py`` compiled
as it is, with its ``_jet`` body compiled too: no second copy of the
expressions exists.  ``cache=True`` keeps the machine code on disk (beside
the generated module, or in numba's user cache when that is read-only); it is
invalidated when ``symvi regenerate`` rewrites the module.  Order K is
imported and compiled only when first asked for.  These serve the published
16-input evaluators of the paper's modal structure (:func:`symvi.jets.compiled`) and
any generated module (:func:`kernel_of`); the analysis itself runs on the compiled
kernels of :mod:`symvi.orbits._shooting` and :mod:`symvi.flow.compiled`.
"""
import importlib
import types

import numba as nb

from . import _numba_cache  # noqa: F401  (one cache key for all kernels)

_KERNELS = {}


def f64_kernel(order):
    """The numba-compiled ``f64(inp) -> flat tuple`` of generated order ``order``."""
    return kernel_of(importlib.import_module(f"symvi._generated.order{order}"))


def kernel_of(mod):
    """The numba-compiled ``f64`` of any generated module (``_jet`` compiled as it is)."""
    if mod.__name__ not in _KERNELS:
        # f64 calls _jet(inp, math.sin, math.cos, Q_F64); let it call the compiled body
        env = dict(vars(mod), _jet=nb.njit(cache=True)(mod._jet))
        f64 = types.FunctionType(mod.f64.__code__, env, "f64")
        _KERNELS[mod.__name__] = nb.njit(cache=True)(f64)
    return _KERNELS[mod.__name__]


# --------------------------------------------------------------------------- first run
# numba keeps what it compiles on disk (cache=True); the first command after an install
# (or after the sources change) compiles ~15-20 s of kernels.  What follows says so on
# stderr and compiles the kernels a command is known to need in parallel processes.

def _dispatcher(module, name):
    return getattr(importlib.import_module(module), name)


def _signature(sig):
    """The argument types of a signature string such as ``"(float64[::1], int64)"``."""
    from numba.core import sigutils
    args, _ = sigutils.normalize_signature(sig)
    return tuple(args)


def is_cached(module, name, sig):
    """Whether numba's disk cache holds kernel ``module.name`` for ``sig`` (an index lookup,
    no code loaded); None when this numba does not let us tell."""
    try:
        index = _dispatcher(module, name)._cache._cache_file._load_index()
    except Exception:       # a private numba interface: unknown rather than wrong
        return None
    want = _signature(sig)
    return any(key[0] == want for key in index)


def _fits(module, name, sig):
    try:
        return len(_signature(sig)) == _dispatcher(module, name).py_func.__code__.co_argcount
    except Exception:
        return False


def _compile_one(module, name, sig, worker=True):
    """Compile one kernel into the disk cache: seconds taken.  Its compile is reported as
    "compiled k/n", not by the listener (unregistered for good in a worker process)."""
    global _LISTENER
    listener = _LISTENER
    if listener is not None:
        from numba.core import event
        event.unregister("numba:compile", listener)
        if worker:
            _LISTENER = None
    try:
        return _compile_timed(module, name, sig)
    finally:
        if listener is not None and not worker:
            event.register("numba:compile", listener)


def _compile_timed(module, name, sig):
    import time
    t = time.perf_counter()
    # the argument types, not the string: numba's cache is keyed by what it is given
    _dispatcher(module, name).compile(_signature(sig))
    return time.perf_counter() - t


def _workers(n):
    import os
    try:
        cpus = len(os.sched_getaffinity(0))
    except AttributeError:
        cpus = os.cpu_count() or 1
    return max(1, min(n, cpus))


def warm_up(kernels, what, stream=None):
    """Compile the ``kernels`` ((module, name, signature, seconds) rows) missing from numba's
    disk cache, longest first, in parallel processes, saying so on ``stream`` (stderr):
    nothing is printed and nothing compiled when all are cached.  Returns how many were
    compiled.  A kernel that fails here is compiled again, and reported, where it is used."""
    import sys
    import time

    from .progress import shown
    stream = stream or sys.stderr
    # a row whose signature no longer fits its kernel is left to the run (and announced)
    todo = [k for k in kernels if _fits(*k[:3]) and is_cached(*k[:3]) is False]
    if not todo:
        return 0
    todo.sort(key=lambda k: -k[3])
    n, workers = len(todo), _workers(len(todo))
    say = stream.write if shown(stream) else (lambda text: None)
    where = f" in {workers} processes" if workers > 1 else ""
    say(f"symvi: first run after install: compiling {n} numba kernels for {what}{where}, "
        f"once (cached afterwards; about {sum(k[3] for k in todo):.0f} s of compiling)\n")
    stream.flush()
    t0 = time.perf_counter()
    done = 0

    def report(k, secs):
        nonlocal done
        done += 1
        how = f"in {secs:.1f} s" if secs == secs else "failed here (compiled where used)"
        say(f"symvi: compiled {done}/{n} {k[1]} ({k[0]}) {how}\n")
        stream.flush()
    left = list(todo)
    if workers > 1:
        import concurrent.futures as cf
        import multiprocessing as mp
        # fork (Linux): the workers start with numba and symvi imported, nothing compiled
        ctx = mp.get_context("fork" if sys.platform.startswith("linux") else "spawn")
        try:
            with cf.ProcessPoolExecutor(workers, mp_context=ctx) as pool:
                futures = {pool.submit(_compile_one, *k[:3]): k for k in todo}
                for f in cf.as_completed(futures):
                    try:
                        secs = f.result()
                    except cf.process.BrokenProcessPool:
                        raise
                    except Exception:
                        secs = float("nan")
                    left.remove(futures[f])
                    report(futures[f], secs)
        except (OSError, ImportError, cf.process.BrokenProcessPool):
            pass                   # no worker processes here: compile the rest in this one
    for k in left:
        try:
            secs = _compile_one(*k[:3], worker=False)
        except Exception:
            secs = float("nan")
        report(k, secs)
    say(f"symvi: compiled the kernels in {time.perf_counter() - t0:.1f} s\n")
    stream.flush()
    return n


class _Announce:
    """A numba compile listener: one line on stderr for each kernel compiled, so that a
    compile not covered by :func:`warm_up` is never silent."""

    def __init__(self, stream):
        self.stream = stream                  # None: sys.stderr at the time

    def on_start(self, event):
        import sys

        from .progress import shown
        stream = self.stream or sys.stderr
        d = event.data["dispatcher"].py_func
        if not d.__module__.startswith("symvi") or not shown(stream):
            return                        # numba's own helpers, compiled inside ours
        stream.write(f"symvi: compiling {d.__name__} ({d.__module__}), first use only "
                     "(cached afterwards)\n")
        stream.flush()

    def on_end(self, event):
        pass


_LISTENER = None


def announce_compiles(stream=None):
    """From now on, say on ``stream`` (stderr) what numba compiles (cache misses only)."""
    global _LISTENER
    from numba.core import event
    if _LISTENER is None:
        _LISTENER = type("Listener", (_Announce, event.Listener), {})(stream)
        event.register("numba:compile", _LISTENER)
    return _LISTENER
