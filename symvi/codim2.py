"""Moved to :mod:`symvi.normal_forms.codim2` (the layered layout of issue 11); this import
path stays and is the same module object."""
import sys

from .normal_forms import codim2 as _module

sys.modules[__name__] = _module
