"""Deprecated: the plane's classifier is the one classifier of symvi,
:mod:`symvi.simulations.classifier` (``classify`` is now ``classify_runs``); this path
warns and is removed in the next release (issue 24)."""
from .._deprecated import moved as _moved

_get, __dir__ = _moved(__name__, "symvi.simulations.classifier")


def __getattr__(name):
    return _get("classify_runs" if name == "classify" else name)
