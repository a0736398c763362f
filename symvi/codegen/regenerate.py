"""Writing and checking the generated jets (``symvi regenerate``): which derivation writes
which orders of which structures into which folder.

Two derivations write generated/: the paper's map (``order<K>.py``,
derivations/poincare_jets.py) and the N-mass structures (``impact_n<N>_order<K>.py``,
derivations/impact_jets.py).  The shipped set is orders 1-3 of the paper's map and of
N = 1..4, and orders 4-5 of N = 1, 2 (the state derivatives for l2, issue 13).  A model's
structure goes where the loader looks for it (:func:`symvi.codegen.layout.module`):
generated/ when shipped, else the per-user cache, which is created private and checked
(:mod:`symvi.codegen._usercache`); there a check runs the derivation again and compares
each module's text with it, never trusting the manifest in that folder.
"""
import time
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class Job:
    """One derivation's orders into one folder: ``name`` "paper" (the paper's map) or
    "impact" (the N-mass structures ``ns``); ``user``: the folder is the per-user cache."""

    name: str
    folder: Path
    orders: tuple
    ns: tuple = None
    user: bool = False
    #: also the structures' variants from each coordinate's section (issue 25)
    starts: bool = False

    def _derivation(self):
        from .._derivations import impact_jets, poincare_jets
        return poincare_jets if self.name == "paper" else impact_jets

    def _kw(self):
        if self.ns is None:
            return {"orders": self.orders}
        return {"ns": self.ns, "orders": self.orders, **({"starts": True} if self.starts else {})}

    def stale(self):
        """Why the folder's modules are not what the derivation writes ([] when fresh)."""
        if self.user:
            from ._usercache import stale_text
            (n,) = self.ns
            return stale_text(self.folder, n, self.orders)
        return self._derivation().check(self.folder, **self._kw())

    def generate(self, force=False):
        """(written, manifest) of the derivation into the folder (nothing written when its
        input hash is unchanged, unless ``force``)."""
        if self.user:
            from ._usercache import generate
            (n,) = self.ns
            return generate(self.folder, n, self.orders, force=force)
        return self._derivation().generate(self.folder, force=force, **self._kw())


@dataclass(frozen=True)
class Generated:
    """What :func:`generate` did for one :class:`Job`: the modules ``written`` (empty when
    up to date), the ``manifest`` and the ``seconds`` it took."""

    job: Job
    written: list
    manifest: dict
    seconds: float


def shipped_dir():
    """The folder of the shipped generated code (``symvi._generated``)."""
    import symvi._generated as g
    return Path(g.__file__).parent


def jobs(*, order=None, model=None, out=None):
    """The jobs of a regeneration up to ``order`` (default: the shipped set; with
    ``model``, 3): the shipped set into ``out`` (default generated/), or, with ``model``
    (a model file), that model's structure, each order where the loader looks for it
    (generated/ when shipped, else the per-user cache) unless ``out`` is given."""
    from .._derivations import impact_jets as ij
    top = order or (3 if model else max(ij.HIGH_ORDERS))
    low = tuple(K for K in ij.ORDERS if K <= top)
    high = tuple(K for K in ij.HIGH_ORDERS if K <= top)
    if model:
        from ..model import load_model
        from .layout import _user_dir
        n = load_model(model).n
        groups = {}
        for K in low + high:
            o = Path(out) if out else (shipped_dir() if ij.shipped(n, K) else _user_dir())
            groups.setdefault(o, []).append(K)
        return [Job("impact", o, tuple(ks), (n,), user=o == _user_dir() and not out)
                for o, ks in groups.items()]
    o = Path(out) if out else shipped_dir()
    todo = [Job("paper", o, low), Job("impact", o, low, ij.NS_SHIPPED, starts=True)]
    if high:
        todo.append(Job("impact", o, high, ij.NS_HIGH, starts=True))
    return todo


def stale(todo):
    """Why the jobs' folders are stale, every job's reasons in order ([] when fresh)."""
    return [why for job in todo for why in job.stale()]


def generate(todo, *, force=False):
    """Run each job's derivation (:meth:`Job.generate`), in order: a :class:`Generated`
    per job."""
    out = []
    for job in todo:
        t0 = time.perf_counter()
        written, manifest = job.generate(force=force)
        out.append(Generated(job, written, manifest, time.perf_counter() - t0))
    return out
