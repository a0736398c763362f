"""The Neimark–Sacker scan of the paper's model in the paper's terms.

:func:`symvi.analysis.hopf.hopf_points` runs on ``Model.luo_xie`` (the chain of every
model); this view adds what only the paper has: its names of the section variables
(eq. (9)), its orbits' fields (:class:`symvi.paper.orbit.Orbit`) and its own f1 of eq. (60),
as printed and corrected (:mod:`symvi.paper.reduction`), in its normalisation
(||r1||_2 = 1, f1 > 0 attracting; f1_wan = -l1/4).
"""
import contextlib
import math
from dataclasses import dataclass, fields, replace

import mpmath

from ..analysis.hopf import HopfPoint, HopfResult
from ..analysis.hopf import hopf_points as _hopf_points
from .orbit import Orbit
from .params import Params

#: the paper's names of the section variables, eq. (9)
STATE_NAMES = ("x1dot+", "x20", "x20dot", "tau")


@dataclass(frozen=True)
class PaperHopfPoint(HopfPoint):
    """A :class:`symvi.analysis.hopf.HopfPoint` of the paper's model with eq. (60)'s f1:
    ``f1_paper`` as printed, ``f1_wan`` corrected (= -l1/4), ``wan_a`` (= l1/4), in the
    paper's normalisation (||r1||_2 = 1, f1 > 0 attracting)."""

    f1_paper: float = None
    f1_wan: float = None
    wan_a: float = None

    def as_dict(self):
        d = super().as_dict()
        d["f1_paper"], d["f1_wan"] = float(self.f1_paper), float(self.f1_wan)
        return d


@dataclass(frozen=True)
class PaperHopfResult(HopfResult):
    """A :class:`symvi.analysis.hopf.HopfResult` of the paper's model: ``params`` is the
    :class:`symvi.Params`, the points are :class:`PaperHopfPoint`."""

    def as_dict(self):
        d = super().as_dict()
        d.pop("model", None)
        return {"params": self.params.as_dict(), **d}


def hopf_points(params, omega_min, omega_max):
    """Every Neimark–Sacker point of an admissible period-1 orbit in [omega_min, omega_max].

    :func:`symvi.analysis.hopf.hopf_points` of a Model, or of the paper's Params in the
    paper's terms (a :class:`PaperHopfResult`: one HopfResult, with the paper's fields).
    Both orbit branches of eqs. (10)–(16) are scanned with order-1 code (orbit and
    multipliers); every crossing of a complex pair through the unit circle, (H1)–(H3),
    is located to 1e-12 in omega, and the order-3 jet and the normal form are evaluated
    there (Sec. 3).  The scan certifies each segment it accepts, so no crossing is
    missed there; the spans it could not certify are listed (``uncertified``; empty:
    ``complete``).  A natural frequency of an undamped mode strictly inside the interval
    cuts the branches and is reported as a ``forcing-resonance`` event.  A conservative
    model (r = 1, no damping) has no Neimark–Sacker point: ``conservative`` is set and
    only the other events are reported.

    Parameters
    ----------
    params : Params or Model
        The paper's parameters (points with the paper's f1 of eq. (60), printed and
        corrected), or a :class:`symvi.Model` with one rigid upper stop on one mass.
    omega_min : float
        Lower end of the interval scanned, 1e-4 <= omega_min < omega_max; not at the
        natural frequency of an undamped mode.
    omega_max : float
        Upper end, at most 1e4; not at the natural frequency of an undamped mode.

    Returns
    -------
    HopfResult
        ``points`` (each a :class:`symvi.analysis.hopf.HopfPoint`: ``omega_c``,
        ``branch``, ``multiplier``, (H1)–(H3), Kuznetsov's ``c1`` and ``l1``, ``kind``
        "supercritical" for l1 < 0, the orbit and the predicted circle; with Params a
        ``PaperHopfPoint`` adding ``f1_paper`` and ``f1_wan``) sorted by omega;
        ``events`` (real multipliers through +1 or -1, admissibility changes, orbits
        appearing or vanishing, cuts at natural frequencies); ``uncertified`` and
        ``complete``; ``conservative``.  Iterating the result gives its points.

    Raises
    ------
    ParameterError
        An end not a number or outside 1e-4..1e4, ``omega_max <= omega_min``, a
        ``params`` that is neither a Model nor Params, or a model with several stops or
        a lower, elastic or between-masses stop (:func:`symvi.continuation.ns_scan`
        scans those).
    SingularCaseError
        ``"forcing-resonance"``: an end at an undamped natural frequency.

    Examples
    --------
    >>> import symvi
    >>> p = symvi.Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    >>> res = symvi.hopf_points(p, 0.72, 0.75)
    >>> len(res), res.complete
    (1, True)
    >>> pt = res.points[0]
    >>> round(pt.omega_c, 6), pt.branch, pt.kind
    (0.736877, '+', 'supercritical')
    """
    if not isinstance(params, Params):
        return _hopf_points(params, omega_min, omega_max)     # checks what it is given
    res = _hopf_points(params.as_model(), omega_min, omega_max)
    base = {f.name: getattr(res, f.name) for f in fields(HopfResult)}
    base.update(params=params, points=tuple(paper_point(params, pt) for pt in res.points))
    return PaperHopfResult(**base)


def paper_point(params, point):
    """``point`` (of ``params.as_model()``) in the paper's terms: its orbit as the paper's
    Orbit, the circle's variables with the paper's names, and f1 of eq. (60) from the
    paper's reduction of the order-3 jet at the point's orbit."""
    from ..codegen.jets import jet_of_orbit
    from .reduction import normal_form
    j = jet_of_orbit(params.as_model(), point.orbit, 3)
    digits = point.orbit.digits
    with mpmath.workdps(digits) if digits else contextlib.nullcontext():
        nf = normal_form(j.jacobian, j.d2, j.d3, j.dA, names=STATE_NAMES, digits=digits)
    circle = point.circle if point.circle is None else replace(point.circle, names=STATE_NAMES)
    base = {f.name: getattr(point, f.name) for f in fields(HopfPoint)}
    base.update(orbit=Orbit.of(params, point.orbit), circle=circle, normal_form=nf,
                f1_paper=_float(nf.f1_printed), f1_wan=_float(nf.f1_wan),
                wan_a=_float(nf.wan_a))
    return PaperHopfPoint(**base)


def _float(x):
    return math.nan if x is None else float(x)
