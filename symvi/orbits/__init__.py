"""Periodic-orbit problems of any model: period-1 one-impact orbits in closed form, and
orbits with a sticking phase on their release section (:mod:`symvi.orbits.sticking`)."""
from .period1 import Orbit as Orbit
from .period1 import admissible_orbits as admissible_orbits
from .period1 import existence_ratio as existence_ratio
from .period1 import multiplier_path as multiplier_path
from .period1 import period1_orbits as period1_orbits
from .period1 import select_orbit as select_orbit
from .sticking import StickingOrbit as StickingOrbit
from .sticking import StickingSignature as StickingSignature
from .sticking import sticking_orbit as sticking_orbit
