"""symvi: symbolic-numeric bifurcation analysis of vibro-impact systems."""
from .errors import NearSingularWarning as NearSingularWarning
from .errors import ParameterError as ParameterError
from .errors import SingularCaseError as SingularCaseError
from .errors import SymviError as SymviError
from .orbit import Orbit as Orbit
from .orbit import period1_orbits as period1_orbits
from .params import Params as Params
from .params import modal as modal
from .poincare import poincare_map as poincare_map

__version__ = "0.1.0"
