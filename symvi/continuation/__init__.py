"""Continuation of n-p orbits in any named parameter, with their special points located:
one pseudo-arclength engine (:mod:`symvi.continuation.engine`), one result family and one
event vocabulary (:mod:`symvi.continuation.result`).

The vocabulary loads at once (every result checks its events against it, the NS scan's
too); the engine and the branches load at first use (PEP 562), so that a client that only
names events does not pay for them.
"""
import importlib

from .result import EVENT_KINDS as EVENT_KINDS
from .result import Result as Result

_LAZY = {"Branch": "points", "BranchPoint": "points", "SpecialPoint": "points",
         "continue_branch": "branch", "switch_at_flip": "branch",
         "period1_branches": "start", "same_branch": "branch",
         "diagram_branches": "start", "continue_orbits": "start",
         "switch_at_branch_point": "branch", "attractor_orbit": "start",
         "ns_scan": "start", "continue_sticking": "sticking"}
__all__ = ["EVENT_KINDS", "Result", *_LAZY]


def __getattr__(name):
    if name in _LAZY:
        value = getattr(importlib.import_module(f"{__name__}.{_LAZY[name]}"), name)
        globals()[name] = value
        return value
    if not name.startswith("__"):
        try:                                     # a submodule read as an attribute
            return importlib.import_module(f"{__name__}.{name}")
        except ModuleNotFoundError:
            pass
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
