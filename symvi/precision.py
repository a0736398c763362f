"""Moved to :mod:`symvi.analysis.precision` (the layered layout of issue 11); this import
path stays and is the same module object."""
import sys

from .analysis import precision as _module

sys.modules[__name__] = _module
