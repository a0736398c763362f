"""Scalar arithmetic backends: float64 (``math``) and mpmath at a chosen precision.

The exact flow, the period-1 orbit and the numeric map are written once against
this small interface, so the float64 and the high-precision chains share no
duplicated logic.
"""
import math

import mpmath

from .numerics.tolerances import EPS64


class _Float:
    name = "float64"
    sin = staticmethod(math.sin)
    cos = staticmethod(math.cos)
    sqrt = staticmethod(math.sqrt)
    atan2 = staticmethod(math.atan2)
    acos = staticmethod(math.acos)
    fabs = staticmethod(math.fabs)
    pi = math.pi
    eps = EPS64
    dps = 15

    @staticmethod
    def num(x):
        return float(x)

    @staticmethod
    def isfinite(x):
        return math.isfinite(x)


FLOAT = _Float()


class _Mp:
    """mpmath backend; the caller must hold ``mpmath.mp.workdps(dps)``."""

    name = "mpmath"
    sin = staticmethod(mpmath.sin)
    cos = staticmethod(mpmath.cos)
    sqrt = staticmethod(mpmath.sqrt)
    atan2 = staticmethod(mpmath.atan2)
    acos = staticmethod(mpmath.acos)
    fabs = staticmethod(mpmath.fabs)

    @property
    def pi(self):
        return +mpmath.pi

    @property
    def eps(self):
        return mpmath.mp.eps

    @property
    def dps(self):
        return mpmath.mp.dps

    @staticmethod
    def num(x):
        return mpmath.mpf(x) if not isinstance(x, mpmath.mpf) else +x

    @staticmethod
    def isfinite(x):
        return mpmath.isfinite(x)


MP = _Mp()


def lib_for(digits):
    """Return the backend for ``digits`` (``None`` means float64)."""
    return FLOAT if digits is None else MP
