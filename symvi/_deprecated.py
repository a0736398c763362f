"""Old module paths kept for one release as warning shims (issue 24, item 8).

The SciPy way (``scipy/integrate/odepack.py``): the old module stays a small module of its
own, whose module-level ``__getattr__`` warns with a ``DeprecationWarning`` that names the
new path and returns the new module's attribute.  Importing the old path does not warn and
imports nothing heavy; the first attribute read does both.  The objects are the new
module's very objects, but the old module is not the new one: setting an attribute on it
(``monkeypatch.setattr("symvi.hopf.x", ...)``) does not reach the new module, so code and
tests use the new paths.

Each shim is two lines::

    from ._deprecated import moved as _moved
    __getattr__, __dir__ = _moved(__name__, "symvi.analysis.hopf")
"""
import importlib
import warnings

__all__ = ["moved", "moved_names", "moved_call"]


def moved(old, new):
    """The module-level ``(__getattr__, __dir__)`` of the old module ``old``, now ``new``."""
    message = (f"{old} is deprecated; import {new} instead; "
               f"the old path will be removed in the next release")

    def __getattr__(name):
        if name.startswith("__") and name.endswith("__") and name != "__all__":
            # probes of module machinery (__path__, __wrapped__, ...): no forwarding
            raise AttributeError(f"module {old!r} has no attribute {name!r}")
        target = importlib.import_module(new)
        if name == "__all__":            # `from old import *` imports what `new` exports
            value = getattr(target, "__all__",
                            [n for n in vars(target) if not n.startswith("_")])
        else:
            try:
                value = getattr(target, name)
            except AttributeError:
                raise AttributeError(f"module {new!r} has no attribute {name!r} "
                                     f"(and {message})") from None
        warnings.warn(message, DeprecationWarning, stacklevel=2)
        return value

    def __dir__():
        return sorted(dir(importlib.import_module(new)))

    return __getattr__, __dir__


def moved_names(old, new, names):
    """The module-level ``__getattr__`` of a module that stays, for the ``names`` that moved
    from it to ``new``: each warns (DeprecationWarning naming ``new``) and is ``new``'s.
    ``names`` may map an old name to its new name in ``new`` (a renamed object)."""
    renamed = dict(names) if isinstance(names, dict) else {n: n for n in names}

    def __getattr__(name):
        if name not in renamed:
            raise AttributeError(f"module {old!r} has no attribute {name!r}")
        target = renamed[name]
        warnings.warn(f"{old}.{name} is deprecated; import it from {new}"
                      + (f" as {target}" if target != name else "")
                      + "; the old name will be removed in the next release",
                      DeprecationWarning, stacklevel=2)
        return getattr(importlib.import_module(new), target)
    return __getattr__


def moved_call(what, new, name):
    """``new.name``, after a DeprecationWarning saying that ``what`` is now that function
    (a keyword or a use that moved to a module of a higher layer, for one release)."""
    warnings.warn(f"{what} is deprecated; call {new}.{name}; the old form will be removed in "
                  "the next release", DeprecationWarning, stacklevel=3)
    return getattr(importlib.import_module(new), name)
