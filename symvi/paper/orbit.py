"""Period-1 one-impact orbits of the paper's model (``Params``), eqs. (10)–(18).

Since issue 11 the paper's model is solved by the chain of every model,
:func:`symvi.orbits.period1_orbits` on ``Model.luo_xie`` (the state-space closed form;
multipliers from the monodromy of eq. (30)).  This module only presents its orbits
in the paper's terms: :class:`Orbit` with (x1dot+, x20, x20dot, tau0) and the modal
integration constants a_j, b_j of eqs. (13)–(15).  The paper's own modal derivation
stays as the independent oracle, :mod:`symvi.paper.modal_orbit`.
"""
import functools
from dataclasses import dataclass, field, fields, replace

import mpmath

from ..numerics.backend import backend
from ..orbits.period1 import Orbit as _AnyOrbit
from .params import check_omega


@dataclass(frozen=True)
class Orbit(_AnyOrbit):
    """A period-1 one-impact orbit of the paper's model at forcing frequency omega, eqs. (17)–(18).

    An :class:`symvi.orbits.Orbit` (the fixed point ``y`` of P, its multipliers, its
    admissibility) seen in the paper's terms: ``y`` = (x1dot+, x20, x20dot, tau0) is the
    section order of ``Model.luo_xie``, named here ``v1_plus``, ``x20``, ``x20_dot``,
    ``tau0``, with the modal constants ``a``, ``b`` of eqs. (13)–(15).  Numbers are float,
    or mpf when computed with ``digits``.

    Attributes
    ----------
    params : Params
        The paper's parameters of the orbit.
    v1_plus, x20, x20_dot, tau0 : float
        ``y`` by the paper's names, eq. (9).
    a, b : tuple
        The modal integration constants a_j (eq. (15)) and b_j (eqs. (13)–(14)).
    """

    params: object = field(default=None, repr=False, compare=False)

    @classmethod
    def of(cls, params, orbit):
        """The paper's view of an orbit of ``Model.luo_xie`` (same section order)."""
        return cls(**{f.name: getattr(orbit, f.name) for f in fields(_AnyOrbit)}, params=params)

    @property
    def v1_plus(self):
        return self.y[0]

    @property
    def x20(self):
        return self.y[1]

    @property
    def x20_dot(self):
        return self.y[2]

    @functools.cached_property
    def _constants(self):
        """(a, b): the modal constants of xi_j = a_j cos w_j t + b_j sin w_j t + A_j sin(omega t + tau)."""
        from .modal_flow import motion_from
        from .params import modal
        lib = backend(self.digits)
        with lib.context():
            mot = motion_from(modal(self.params, lib), self.omega, (lib.num(self.params.b),
                              self.x20), (self.v1_plus, self.x20_dot), self.tau0, lib)
        return mot.a, mot.b

    @property
    def a(self):
        """Integration constants a_j of eq. (15)."""
        return self._constants[0]

    @property
    def b(self):
        """Integration constants b_j of eqs. (13)–(14)."""
        return self._constants[1]

    def as_dict(self):
        """The JSON shape of issue 2: floats, multipliers as [re, im] pairs."""
        return {"branch": self.branch, "v1_plus": float(self.v1_plus), "x20": float(self.x20),
                "x20_dot": float(self.x20_dot), "tau0": float(self.tau0),
                "impact_velocity": float(self.impact_velocity),
                "admissible": bool(self.admissible), "reason": self.reason,
                "multipliers": [[float(complex(l).real), float(complex(l).imag)]
                                for l in self.multipliers],
                "stable": bool(self.stable)}


def period1_orbits(params, omega, *, digits=None, multipliers=True):
    """Every period-1 one-impact orbit at omega (both branches), conditions (10).

    Returns a list of :class:`Orbit` (empty when the discriminant of eq. (16) is
    negative: no orbit exists).  Inadmissible orbits are returned with
    ``admissible=False`` and a reason, never silently analysed.  ``digits``
    selects mpmath at that precision.  ``multipliers=False`` skips the Jacobian.
    A :class:`symvi.Model` gets the any-model :class:`symvi.orbits.Orbit`.
    The orbits come from the closed form of :func:`symvi.orbits.period1_orbits`
    (eqs. (10)–(18) generalised), the multipliers from the monodromy of eq. (30), and
    admissibility from a run of the first-impact finder over the period.

    Parameters
    ----------
    params : Params or Model
        The paper's parameters (the orbits in the paper's terms: ``v1_plus``, ``x20``,
        ``x20_dot``, ``tau0``, the modal constants ``a``, ``b``), or any
        :class:`symvi.Model` with one rigid upper stop on one mass.
    omega : float
        Forcing frequency, 1e-4 <= omega <= 1e4, not at the natural frequency of an
        undamped mode (warned about within 1e-4, relative).  With ``digits`` an
        mpmath ``mpf`` keeps all its digits.
    digits : int, optional
        Compute with mpmath at this many significant digits, 16 to 10000.  Default
        None: float64 (the compiled kernel).
    multipliers : bool, optional
        Compute the multipliers and the stability (default True); False leaves
        ``multipliers`` empty and ``stable`` False.

    Returns
    -------
    list of Orbit
        Two orbits, branch "+" then "-" (tau0 = phi +- arccos(alpha b / rho), eq. (16)),
        admissible or not; an empty list when no period-1 orbit exists at omega.

    Raises
    ------
    ParameterError
        ``omega`` not a number or out of range, ``digits`` not an integer from 16 to
        10000, or a model with several stops, a lower, elastic or between-masses stop
        (no period-1 closed form: :func:`symvi.continuation.attractor_orbit`).
    SingularCaseError
        ``"forcing-resonance"`` (omega at an undamped natural frequency: the forcing of
        eq. (7) is infinite), ``"one-minus-cos"`` (omega_j / omega an integer for an
        undamped mode: the orbit is not isolated, eq. (15)),
        ``"degenerate-orbit-conditions"`` or ``"degenerate-forcing"`` (conditions (10)
        do not fix the orbit or its impact phase).

    Warns
    -----
    NearSingularWarning
        Omega near a natural frequency or the stop's mass near an anti-resonance:
        digits are lost.

    Examples
    --------
    >>> import math, symvi
    >>> p = symvi.Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    >>> orbits = symvi.period1_orbits(p, 0.72)
    >>> [(o.branch, o.admissible, o.stable) for o in orbits]
    [('+', True, True), ('-', False, False)]
    >>> o = orbits[0]
    >>> round(o.v1_plus, 6), round(o.tau0, 6)
    (-1.495139, 1.498021)
    >>> abs(math.prod(o.multipliers) - p.r ** 2) < 1e-12     # det DP = r^2 (C = 0)
    True
    >>> orbits[1].reason
    'impact velocity v1- = ... <= 0: the mass does not arrive moving towards the stop ...'
    """
    from ..model import Model
    from ..orbits import period1_orbits as any_model
    if isinstance(params, Model):
        return any_model(params, omega, digits=digits, multipliers=multipliers)
    omega_f = check_omega(params, omega)      # the paper's ranges and messages first
    if digits is not None and isinstance(omega, (mpmath.mpf, str)):
        omega_f = omega                       # a 50-digit omega must not be rounded
    return [Orbit.of(params, o) for o in any_model(Model.of(params), omega_f, digits=digits,
                                                  multipliers=multipliers)]


def auto_orbits(params, omega):
    """Every period-1 orbit at omega with its precision estimate, recomputed with mpmath
    where float64 gives too few digits (:func:`symvi.analysis.precision.auto_model_orbits`;
    ``symvi orbit``), omega checked first: of a :class:`symvi.Model`, or of the paper's
    Params in the paper's terms (its check of omega, each orbit its :class:`Orbit`)."""
    from ..analysis.precision import auto_model_orbits
    from ..flow import check_omega as check
    from ..model import Model
    model = Model.of(params)
    if model is params:
        return auto_model_orbits(model, check(model, omega))
    autos = auto_model_orbits(model, check_omega(params, omega))
    return [replace(a, orbit=Orbit.of(params, a.orbit)) for a in autos]


def admissible_orbits(params, omega, *, digits=None, multipliers=True):
    """The admissible period-1 orbits at omega, branch "+" first (empty when none).

    Raises SingularCaseError where conditions (10) are singular.
    """
    orbits = period1_orbits(params, omega, digits=digits, multipliers=multipliers)
    return sorted((o for o in orbits if o.admissible), key=lambda o: o.branch != "+")


def multiplier_path(params, omegas):
    """Multipliers of the admissible orbit along omega (figs. 4, 10), eq. (36); see
    :func:`symvi.orbits.multiplier_path`."""
    from ..model import Model
    from ..orbits.period1 import multiplier_path as path
    return path(Model.of(params), omegas)


def existence_ratio(params, omega):
    """The orbit exists iff |ratio| <= 1 (eq. 16, corrected; for any model
    :func:`symvi.orbits.existence_ratio`)."""
    from ..model import Model
    from ..orbits import existence_ratio as any_model
    omega = check_omega(params, omega, warn=False)
    return any_model(Model.of(params), omega)
