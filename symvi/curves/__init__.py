"""Two-parameter curves of fold, flip and Neimark–Sacker points with their codimension-two
points (issue 13): :func:`continue_curve`, :func:`curve_from_interval`."""
from .curve import Curve, continue_curve  # noqa: F401
from .points import Codim2Point, CurvePoint  # noqa: F401
from .start import curve_from_interval, curves_in_box, parse_params, start_points  # noqa: F401
