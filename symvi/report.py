"""Moved to :mod:`symvi.reporting.report` (the layered layout of issue 11); this import
path stays and is the same module object."""
import sys

from .reporting import report as _module

sys.modules[__name__] = _module
