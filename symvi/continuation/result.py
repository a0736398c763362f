"""One result family and one event vocabulary for every continuation run (issue 24, item 4).

A run of :mod:`symvi.continuation.engine` gives a :class:`Result`: its points in arclength
order, the events located on it (``special``, each a :class:`Located` with a ``kind`` of
:data:`EVENT_KINDS`) and why it ended (``stop_reasons``).  :class:`symvi.continuation.Branch`
(one parameter) and :class:`symvi.curves.Curve` (two) are its members; the certified scan
:func:`symvi.analysis.hopf.hopf_points` stays a client with its own result, whose events
take their kinds from the same vocabulary.
"""
from dataclasses import dataclass

#: every kind of event a continuation run or the NS scan reports, and what it is
EVENT_KINDS = {
    # codimension one, located on branches of orbits (symvi.continuation.special)
    "fold": "a multiplier through +1 where the branch turns (saddle-node)",
    "flip": "a multiplier through -1 (period doubling)",
    "ns": "a complex pair through |lambda| = 1 (Neimark-Sacker)",
    "branch-point": "a multiplier through +1 where the branch does not turn (branches cross)",
    "symmetry-breaking": "a symmetric orbit's half map has a multiplier through -1: a pair "
                         "of mirror-image asymmetric orbits branches off (pitchfork)",
    "grazing": "an impact with zero velocity, or a flight touching the stop",
    "admissibility": "the orbit's admissibility changes (not located further)",
    "unlocated": "a test function changed sign, but locating the event failed",
    # strong resonances: on a conservative branch (R3, R4) or on a curve (R1..R4)
    "R1": "strong resonance 1:1", "R2": "strong resonance 1:2",
    "R3": "strong resonance 1:3", "R4": "strong resonance 1:4",
    # codimension two, located on fold, flip and NS curves (symvi.curves.special)
    "CH": "Chenciner point (l1 = 0 on an NS curve)",
    "LPNS": "fold-Neimark-Sacker point", "PDNS": "flip-Neimark-Sacker point",
    "NSNS": "double Neimark-Sacker point", "LPPD": "fold-flip point",
    "CP": "cusp point (fold with a = 0)", "GPD": "generalised flip point (flip with c = 0)",
    # codimension two, located on grazing curves (symvi.curves.grazing)
    "grazing-fold": "the fold curve meets the grazing curve: a multiplier +1 of an orbit "
                    "smooth at its touch, or the regular fold test w det(M - I) = 0 at an "
                    "impact's zero velocity",
    "grazing-flip": "the flip curve meets the grazing curve: a multiplier -1 of an orbit "
                    "smooth at its touch, or the regular flip test w det(M + I) = 0 at an "
                    "impact's zero velocity",
    "grazing-NS": "a grazing orbit (smooth at its touch) with a complex pair on the unit "
                  "circle, or the regular test w det(M - e^{i theta} I) = 0 at an impact's "
                  "zero velocity: the Neimark-Sacker curve meets the grazing curve",
    "double-grazing": "a second impact of a grazing orbit arrives with zero velocity too",
    "RG": "resonant grazing: a fold and a flip curve of the impacting orbit both leave the "
          "grazing curve of an impact at zero velocity here, tangentially",
    "degenerate-grazing": "zero acceleration of the guard at the grazing: the tangency is "
                          "not quadratic",
    # what the certified scan of closed-form branches meets (symvi.analysis.hopf)
    "multiplier+1": "the scan's sign change of prod(mu - 1): located as a branch-point",
    "multiplier-1": "the scan's sign change of prod(mu + 1): located as a flip",
    "becomes-admissible": "the scanned orbit becomes admissible",
    "becomes-inadmissible": "the scanned orbit stops being admissible",
    "orbit-appears": "a closed-form branch begins", "orbit-vanishes": "a closed-form branch ends",
    "singular": "the closed form is singular here",
    "forcing-resonance": "omega at an undamped natural frequency",
    "conservative": "r = 1 without damping: no NS point is sought",
    "unresolved": "a span the scan could not certify",
    "ns-unanalysable": "a complex pair through |lambda| = 1 whose normal form failed",
}
#: a kind of the scan that names a located kind: what the locator calls it
LOCATED_AS = {"ns": "ns", "multiplier-1": "flip", "multiplier+1": "branch-point"}


def check_kind(kind):
    """``kind`` itself when it is in :data:`EVENT_KINDS`, else ValueError."""
    if kind not in EVENT_KINDS:
        raise ValueError(f"event kind {kind!r} is not in symvi.continuation.result.EVENT_KINDS")
    return kind


@dataclass(frozen=True)
class Located:
    """Base of a located event of a run (kind, orbit, coefficients, detail, index):
    :class:`symvi.continuation.SpecialPoint`, :class:`symvi.curves.Codim2Point`."""

    def __post_init__(self):
        check_kind(self.kind)


@dataclass(frozen=True)
class Result:
    """Base of a continuation run's result (one family for branches and curves).

    ``points`` in arclength order, ``special`` the located events (:class:`Located`),
    ``stop_reasons`` why each end of the run stopped.  Its members are
    :class:`symvi.continuation.Branch` (one parameter) and :class:`symvi.curves.Curve`
    (two); every event's kind is checked against :data:`EVENT_KINDS` when the result is
    made (ValueError otherwise).  ``len(result)`` is the number of points.

    Attributes
    ----------
    points : tuple
        The points of the run, in arclength order.
    special : tuple
        The located events, each with a ``kind`` of :data:`EVENT_KINDS`.
    events : tuple
        The same as ``special``.
    stop_reasons : tuple of str
        Why each end of the run stopped.

    Examples
    --------
    >>> from symvi import Model, Stop
    >>> from symvi.continuation import Result, continue_branch
    >>> m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
    ...           stop=Stop(mass=1, gap=0.0, restitution=0.8))
    >>> br = continue_branch(m, "omega", 2.5, 2.8)
    >>> isinstance(br, Result), len(br) == len(br.points), br.stop_reasons
    (True, True, ('reached omega = 2.8',))
    >>> [sp.kind for sp in br.events_of("flip")], br.events_of("fold")
    (['flip'], ())
    """

    def __post_init__(self):
        for sp in self.special:
            check_kind(sp.kind)

    def __len__(self):
        return len(self.points)

    @property
    def events(self):
        return self.special

    @property
    def stop_reasons(self):
        raise NotImplementedError                                 # pragma: no cover

    def events_of(self, kind):
        """The located events of one ``kind`` (of :data:`EVENT_KINDS`); ValueError for a
        kind not in it."""
        check_kind(kind)
        return tuple(sp for sp in self.special if sp.kind == kind)
