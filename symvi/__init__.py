"""symvi: symbolic-numeric bifurcation analysis of vibro-impact systems.

Heavy parts (the Hopf scan with scipy, the numba simulator) are imported on
first use, so ``import symvi`` and ``symvi orbit`` stay fast.
"""
import importlib

from .errors import NearSingularWarning as NearSingularWarning
from .errors import ParameterError as ParameterError
from .errors import SingularCaseError as SingularCaseError
from .errors import SymviError as SymviError
from .model import Model as Model
from .model import Stop as Stop
from .model import load_model as load_model
from .paper.params import Params as Params
from .paper.params import modal as modal

__version__ = "0.1.0"

_LAZY = {"jet": "paper.jets", "Jet": "paper.jets", "hopf_points": "paper.hopf",
         "simulate": "simulations.simulation", "poincare_map": "maps.impact", "Orbit": "orbits", "period1_orbits": "paper.orbit",
         "discontinuity_map": "orbits.nordmark"}


def __getattr__(name):
    if name in _LAZY:
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module 'symvi' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + list(_LAZY))
