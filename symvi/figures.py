"""Moved to :mod:`symvi.reporting.figures` (the layered layout of issue 11); this import
path stays and is the same module object."""
import sys

from .reporting import figures as _module

sys.modules[__name__] = _module
