"""Moved to :mod:`symvi.normal_forms.normal_form` (the layered layout of issue 11); this import
path stays and is the same module object."""
import sys

from .normal_forms import normal_form as _module

sys.modules[__name__] = _module
