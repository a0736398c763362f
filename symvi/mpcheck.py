"""Moved to :mod:`symvi.studies.mpcheck` (the layered layout of issue 11); this import
path stays and is the same module object."""
import sys

from .studies import mpcheck as _module

sys.modules[__name__] = _module
