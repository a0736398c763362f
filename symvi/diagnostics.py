"""Moved to :mod:`symvi.simulations.diagnostics` (the layered layout of issue 11); this import
path stays and is the same module object."""
import sys

from .simulations import diagnostics as _module

sys.modules[__name__] = _module
