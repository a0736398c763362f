"""Deprecated: ``poincare_map`` is :func:`symvi.maps.impact.poincare_map` (also
``symvi.poincare_map``); ``step``, ``MapStep`` and ``fd_jacobian`` (the paper's modal map,
the oracle) are in :mod:`symvi.paper.modal_map`.  This path warns and is removed in the
next release (issue 24)."""
import importlib
import warnings

_HOME = {"poincare_map": "symvi.maps.impact", "step": "symvi.paper.modal_map",
         "MapStep": "symvi.paper.modal_map", "fd_jacobian": "symvi.paper.modal_map"}


def __getattr__(name):
    if name not in _HOME:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(f"symvi.poincare is deprecated; import {name} from {_HOME[name]}; the old "
                  "path will be removed in the next release", DeprecationWarning, stacklevel=2)
    return getattr(importlib.import_module(_HOME[name]), name)


def __dir__():
    return sorted(_HOME)
