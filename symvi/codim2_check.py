"""Moved to :mod:`symvi.studies.codim2_check` (the layered layout of issue 11); this import
path stays and is the same module object."""
import sys

from .studies import codim2_check as _module

sys.modules[__name__] = _module
