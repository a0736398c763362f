"""Deprecated: moved to :mod:`symvi.paper.orbit` (the paper sits on top of the package); this path
warns and is removed in the next release (issue 24)."""
from ._deprecated import moved as _moved

__getattr__, __dir__ = _moved(__name__, "symvi.paper.orbit")
