"""Numerics shared by every layer: the tolerances of :mod:`symvi.numerics.tolerances` and
the one precision backend (float64 / mpmath) of :mod:`symvi.numerics.backend`.

The lowest layer of the package (``tests/test_layers.py``): it imports nothing from
symvi, so any module may import it.  Each shared tolerance is defined once here;
the modules that use one import it (their old module-level names, such as
``symvi.flow.linear.RESONANCE_REFUSE``, are those imports).
"""
from . import tolerances as tolerances
