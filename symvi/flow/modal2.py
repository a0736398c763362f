"""Deprecated: moved to :mod:`symvi.paper.modal_flow` (the paper's oracle flow sits with the
paper); this path warns and is removed in the next release (issue 24)."""
from .._deprecated import moved as _moved

__getattr__, __dir__ = _moved(__name__, "symvi.paper.modal_flow")
