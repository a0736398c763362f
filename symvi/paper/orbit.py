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
