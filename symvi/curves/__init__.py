"""Two-parameter curves of fold, flip and Neimark–Sacker points with their codimension-two
points (issue 13): :func:`continue_curve`, :func:`curve_from_interval`."""
from .curve import Codim2Point, Curve, CurvePoint, continue_curve  # noqa: F401
from .start import curve_from_interval, start_points  # noqa: F401
