"""What a two-parameter curve is made of: its points and codimension-two points, and the two
numbers every part of :mod:`symvi.curves` evaluates at a point (the monodromy matrix, l1)."""
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..continuation.result import Located, Result
from ..errors import NearSingularWarning, SymviError
from ..normal_forms.normal_form import kuznetsov_resolved
from ..orbits.periodic import PeriodicOrbit

NORMALISATION = ("||q||_2 = 1, <p,q> = conj(p)^T q = 1; l1 = Re(e^{-i theta} c1) (l1 < 0: "
                 "supercritical, a stable invariant circle)")


@dataclass(frozen=True)
class CurvePoint:
    """One point of a curve: both parameter values, the orbit, and the curve's numbers
    there (theta, l1 for NS; c for flip; a for fold), ``ns`` False on a neutral-saddle
    stretch of an NS curve (a real pair with product 1, no bifurcation)."""

    params: dict
    orbit: PeriodicOrbit = field(repr=False)
    kappa: float = None
    theta: float = None
    l1: float = None
    coefficient: float = None
    ns: bool = True
    l1_noise: float = None      # rounding bound of l1: |l1| below it decides nothing

    @property
    def admissible(self):
        return self.orbit.admissible

    def as_dict(self):
        out = {"params": dict(self.params), "theta": self.theta, "l1": self.l1,
               "admissible": bool(self.orbit.admissible)}
        if self.l1_noise is not None:
            out["l1_noise"] = self.l1_noise
        if self.coefficient is not None:
            out["coefficient"] = self.coefficient
        out.update({"kappa": self.kappa, "neimark_sacker": bool(self.ns),
                    "multipliers": [[z.real, z.imag] for z in self.orbit.multipliers]})
        return out


@dataclass(frozen=True)
class Codim2Point(Located):
    """A located codimension-two point: ``kind`` CH, R1..R4, LPNS, PDNS, NSNS, LPPD, CP,
    GPD, or an end of the admissible curve (grazing), of the one vocabulary
    :data:`symvi.continuation.result.EVENT_KINDS`; it lies between the curve's points
    ``index`` and ``index + 1``."""

    kind: str
    params: dict
    orbit: PeriodicOrbit = field(repr=False)
    coefficients: dict
    detail: str
    index: int = 0

    def as_dict(self):
        return {"kind": self.kind, "params": dict(self.params),
                "coefficients": {k: _plain(v) for k, v in self.coefficients.items()},
                "detail": self.detail, "admissible": bool(self.orbit.admissible),
                "y": [float(v) for v in self.orbit.y],
                "multipliers": [[z.real, z.imag] for z in self.orbit.multipliers]}


@dataclass(frozen=True)
class TwoParameter(Result):
    """What every continued curve in two parameters ``names`` is (fold, flip, NS:
    :class:`symvi.curves.curve.Curve`; grazing: :class:`symvi.curves.grazing.GrazingCurve`):
    its points and located codimension-two points, why it ended on each side (its
    ``stop_reasons``), its box and the model's fixed values."""

    kind: str
    names: tuple
    n: int
    p: int
    points: tuple
    special: tuple
    ends: tuple                 # why it ended on each side (first, last)
    bounds: dict
    fixed: dict
    notes: tuple = ()
    states: tuple = field(repr=False, default=())
    model: object = field(repr=False, default=None)

    @property
    def stop_reasons(self):
        return tuple(self.ends)

    def values(self, name):
        return np.array([pt.params[name] for pt in self.points])


def _plain(v):
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        return float(v)
    if isinstance(v, complex):
        return [v.real, v.imag]
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    return v


def mono(system, X):
    """The monodromy matrix at a curve point X = (u, a, b)."""
    return system.orbit_data(X)[3]


def first_lyapunov(orbit, lam):
    """(l1, noise) of the pair of multiplier ``lam`` of the orbit; (None, None) at a strong
    resonance (no cubic normal form).  ``noise`` bounds l1's rounding error
    (:func:`symvi.normal_forms.normal_form.kuznetsov_resolved`; near grazing the jets blow up)."""
    A, d2, d3 = orbit.jet(3)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NearSingularWarning)
            # kuznetsov takes the pair with Im > 0 nearest the unit circle: lam's on an
            # NS curve (|lam| = 1); checked, so that a second pair never stands in
            _, l1, noise, lam1 = kuznetsov_resolved(A, d2, d3)
            if abs(lam1 - lam) > 1e-6 * (1 + abs(lam)):
                return None, None
    except SymviError:
        return None, None
    return l1, noise
