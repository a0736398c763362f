"""What a branch is made of (points, special points, the branch); its points are computed
by the pseudo-arclength engine of :mod:`symvi.continuation.engine`."""
from dataclasses import dataclass, field

import numpy as np

from ..orbits.periodic import PeriodicOrbit, Problem
# the corrector and the locator, where they were defined before the one engine
from .engine import CORR_MAXIT as CORR_MAXIT  # noqa: F401
from .engine import CORR_TOL as CORR_TOL  # noqa: F401
from .engine import correct as correct  # noqa: F401
from .engine import root_on_arc as root_on_arc  # noqa: F401
from .engine import tangent as tangent  # noqa: F401
from .result import Located, Result


@dataclass(frozen=True)
class BranchPoint:
    """One point of a branch: the parameter value and the orbit there."""

    value: float
    orbit: PeriodicOrbit = field(repr=False)

    @property
    def y(self):
        return self.orbit.y

    @property
    def multipliers(self):
        return self.orbit.multipliers

    @property
    def stable(self):
        return self.orbit.stable

    @property
    def admissible(self):
        return self.orbit.admissible

    def as_dict(self):
        return {"value": self.value, "signature": self.orbit.signature_names,
                "y": [float(v) for v in self.orbit.y],
                "multipliers": [[z.real, z.imag] for z in self.orbit.multipliers],
                "stable": bool(self.orbit.stable), "admissible": bool(self.orbit.admissible),
                **_symmetry(self.orbit)}


def _symmetry(orbit):
    """{"symmetric": ...} where the model and the n-p have the mirror symmetry, else {}."""
    return {} if orbit.symmetric is None else {"symmetric": bool(orbit.symmetric)}


@dataclass(frozen=True)
class SpecialPoint(Located):
    """A located special point: ``kind`` is fold, flip, ns, branch-point, grazing,
    admissibility, unlocated, or R3/R4 (strong resonance), of the one vocabulary
    :data:`symvi.continuation.result.EVENT_KINDS`; ``coefficients`` its normal-form numbers."""

    kind: str
    value: float
    orbit: PeriodicOrbit = field(repr=False)
    coefficients: dict
    detail: str
    index: int = 0              # the branch point after which it lies

    def as_dict(self):
        co = {k: (float(v) if isinstance(v, (int, float, np.floating)) else v)
              for k, v in self.coefficients.items()}
        if "separation" in co:
            # the distance to the nearest other multiplier was "gap" (the stop's gap's name
            # too) until 0.1: kept under that key for one release (issue 26, naming)
            co["gap"] = co["separation"]
        return {"kind": self.kind, "value": self.value,
                "signature": self.orbit.signature_names, **_symmetry(self.orbit),
                "admissible": bool(self.orbit.admissible),
                "y": [float(v) for v in self.orbit.y],
                "multipliers": [[z.real, z.imag] for z in self.orbit.multipliers],
                "coefficients": co, "detail": self.detail}


@dataclass(frozen=True)
class Branch(Result):
    """A continued branch of n-p orbits: points in arclength order, special points
    located on it, and why it ended (a :class:`symvi.continuation.result.Result`)."""

    param: str
    n: int
    p: int
    points: tuple
    special: tuple
    end: str
    notes: tuple = ()
    problem: Problem = field(repr=False, default=None)
    states: tuple = field(repr=False, default=())      # X = (u, lam) of each point
    bounds: tuple = (None, None)

    @property
    def stop_reasons(self):
        return (self.end,)

    @property
    def values(self):
        return np.array([pt.value for pt in self.points])

    def curve(self, component=0):
        """Plain data for a figure: values, the section coordinate ``component`` of each
        impact point (points x p), stability, admissibility and the special points."""
        return {"values": [pt.value for pt in self.points],
                "Y": [[y[component] for y in pt.orbit.points] for pt in self.points],
                "stable": [bool(pt.stable) for pt in self.points],
                "admissible": [bool(pt.admissible) for pt in self.points],
                "special": [(sp.kind, sp.value, [y[component] for y in sp.orbit.points])
                            for sp in self.special]}

    def as_dict(self):
        return {"param": self.param, "orbit": f"{self.n}-{self.p}",
                "signature": self.points[0].orbit.signature_names if self.points else [],
                "points": [pt.as_dict() for pt in self.points],
                "special": [s.as_dict() for s in self.special],
                "end": self.end, "notes": list(self.notes)}
