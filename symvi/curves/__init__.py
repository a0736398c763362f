"""Two-parameter curves of fold, flip and Neimark–Sacker points with their codimension-two
points (issue 13): :func:`continue_curve`, :func:`curve_from_interval`; grazing curves
(issue 27): :func:`continue_grazing`."""
from .curve import Curve, continue_curve  # noqa: F401
from .grazing import GrazingCurve, GrazingPoint, continue_grazing  # noqa: F401
from .points import Codim2Point, CurvePoint  # noqa: F401
from .start import (curve_from_interval, curve_params, curves_in_box,  # noqa: F401
                    curves_of_plane, parse_params, start_points)
