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
    """One point of a branch: the parameter value and the orbit there.

    Attributes
    ----------
    value : float
        The continued parameter's value.
    orbit : PeriodicOrbit
        The n-p orbit at that value (:class:`symvi.orbits.periodic.PeriodicOrbit`:
        ``points``, ``times``, ``multipliers``, ``signature``, ...).
    y : tuple
        The orbit's first section point, ``orbit.y``.
    multipliers : tuple of complex
        The orbit's multipliers (of the monodromy of its p impacts), largest first.
    stable : bool
        Whether the orbit is stable (admissible, every multiplier inside the unit
        circle).
    admissible : bool
        Whether the orbit is physical (no stop crossed in flight, impacts towards the
        stop).
    """

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
    """A located special point of a branch, with its normal-form coefficients.

    ``kind`` is fold, flip, ns, branch-point, symmetry-breaking, grazing,
    admissibility, unlocated, or R3/R4 (strong resonance), of the one vocabulary
    :data:`symvi.continuation.result.EVENT_KINDS`; ``coefficients`` its normal-form numbers.

    Attributes
    ----------
    kind : str
        The kind of point, a key of :data:`EVENT_KINDS`.
    value : float
        The continued parameter's value at the point.
    orbit : PeriodicOrbit
        The orbit at the point.
    coefficients : dict
        Its normal-form numbers by name (e.g. ``"c"`` of a flip, ``"l1"`` of an NS
        point, ``"multiplier"``, ``"separation"``: the distance to the nearest other
        multiplier).
    detail : str
        What the point is, in words (super- or subcritical, ...).
    index : int
        The index of the first branch point past it: it lies between the branch's points
        ``index - 1`` and ``index``.
    """

    kind: str
    value: float
    orbit: PeriodicOrbit = field(repr=False)
    coefficients: dict
    detail: str
    index: int = 0              # the first branch point past it

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
    """A continued branch of n-p orbits (a :class:`symvi.continuation.result.Result`).

    Points in arclength order, special points located on it, and why it ended.  What
    :func:`continue_branch`, :func:`continue_orbits` and the branch switches return.

    Attributes
    ----------
    param : str
        The continued parameter's name.
    n : int
        Forcing periods of the branch's orbits.
    p : int
        Impacts per orbit.
    points : tuple of BranchPoint
        The points, in arclength order.
    special : tuple of SpecialPoint
        The special points located on it, in arclength order.
    end : str
        Why the branch ended (``"reached omega = 2.8"``, the orbit stops being
        admissible, the branch closes on itself, ``max_points`` reached, ...).
    notes : tuple of str
        Remarks on the whole branch (a start moved, a conservative model).
    problem : Problem
        The shooting problem continued (:class:`symvi.orbits.periodic.Problem`).
    states : tuple of ndarray
        X = (u, lam) of each point: shooting unknowns and parameter.
    bounds : tuple of float
        (lo, hi): the parameter interval the branch was kept in.
    values : ndarray
        The parameter value of each point.
    stop_reasons : tuple of str
        ``(end,)``.

    Examples
    --------
    >>> from symvi import Model, Stop
    >>> from symvi.continuation import continue_branch
    >>> m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
    ...           stop=Stop(mass=1, gap=0.0, restitution=0.8))
    >>> br = continue_branch(m, "omega", 2.5, 2.8)
    >>> br.param, br.n, br.p, br.bounds
    ('omega', 1, 1, (2.5, 2.8))
    >>> pt = br.points[0]                                 # a BranchPoint
    >>> pt.value, pt.admissible, pt.stable
    (2.5, True, True)
    >>> sp = br.special[0]                                # a SpecialPoint
    >>> sp.kind, round(sp.value, 6), round(sp.coefficients["c"], 4)
    ('flip', 2.656177, 4.0651)
    """

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
        """Plain data for a figure: the branch's values and one section coordinate.

        Values, the section coordinate ``component`` of each impact point (points x p),
        stability, admissibility and the special points.

        Parameters
        ----------
        component : int, optional
            0-based index into a section point (default 0: the stop mass's velocity
            after the impact).

        Returns
        -------
        dict
            ``"values"``: the parameter value of each point; ``"Y"``: per point, the
            coordinate at each of its p impacts; ``"stable"``, ``"admissible"``: a bool
            per point; ``"special"``: (kind, value, coordinates at its impacts) per
            special point.

        Examples
        --------
        >>> from symvi import Model, Stop
        >>> from symvi.continuation import continue_branch
        >>> m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
        ...           stop=Stop(mass=1, gap=0.0, restitution=0.8))
        >>> c = continue_branch(m, "omega", 2.5, 2.8).curve()
        >>> sorted(c)
        ['Y', 'admissible', 'special', 'stable', 'values']
        >>> len(c["Y"]) == len(c["values"]), c["special"][0][0]
        (True, 'flip')
        """
        return {"values": [pt.value for pt in self.points],
                "Y": [[y[component] for y in pt.orbit.points] for pt in self.points],
                "stable": [bool(pt.stable) for pt in self.points],
                "admissible": [bool(pt.admissible) for pt in self.points],
                "special": [(sp.kind, sp.value, [y[component] for y in sp.orbit.points])
                            for sp in self.special]}

    def as_dict(self):
        """The branch as plain data: dicts, lists, strings and numbers (JSON types).

        Returns
        -------
        dict
            ``"param"``, ``"orbit"`` (``"n-p"``), ``"signature"`` (the stop of each
            impact, ``"stop1"``, ...), ``"points"`` (each with ``"value"``, ``"y"``,
            ``"multipliers"`` as [re, im] pairs, ``"stable"``, ``"admissible"``),
            ``"special"`` (:meth:`SpecialPoint.as_dict`), ``"end"``, ``"notes"``.

        Examples
        --------
        >>> from symvi import Model, Stop
        >>> from symvi.continuation import continue_branch
        >>> m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
        ...           stop=Stop(mass=1, gap=0.0, restitution=0.8))
        >>> d = continue_branch(m, "omega", 2.5, 2.8).as_dict()
        >>> d["orbit"], d["signature"], d["end"], d["special"][0]["kind"]
        ('1-1', ['stop1'], 'reached omega = 2.8', 'flip')
        """
        return {"param": self.param, "orbit": f"{self.n}-{self.p}",
                "signature": self.points[0].orbit.signature_names if self.points else [],
                "points": [pt.as_dict() for pt in self.points],
                "special": [s.as_dict() for s in self.special],
                "end": self.end, "notes": list(self.notes)}
