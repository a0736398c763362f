"""The flow layer: exact motion between impacts and the first-impact finder.

* :mod:`symvi.flow.linear` -- any model (N masses, damping, stop on any mass):
  the state-space flow in modal form and the provably safe first-impact finder;
* :mod:`symvi.flow.compiled` -- its numba twin: the map P and long runs;
* :mod:`symvi.flow.nonlinear` -- a model with nonlinear forces (issue 28): a numerical
  flow (a Taylor method, events on the solution's polynomial) and its runs, for
  ``simulate``;
* :mod:`symvi.flow.taylor` -- that Taylor method (the forces' program on series);
* :mod:`symvi.flow.nlsticking` -- its runs through complete chatter and sticking;
* :mod:`symvi.flow.nlcontact` -- its contact phases at elastic stops;
* :mod:`symvi.flow.nljet` -- the jets of its impact maps (series flights).

The paper's 2-DOF undamped modal form, eqs. (7)–(8), is the oracle of the paper
(:mod:`symvi.paper.modal_flow`); its names here (``first_impact``, ``motion_from``, ...)
warn and are removed in the next release.
"""
from .._deprecated import moved_names as _moved_names

__getattr__ = _moved_names(__name__, "symvi.paper.modal_flow", (
    "GRAZING", "IMPACT", "NO_IMPACT", "FirstImpact", "Motion", "first_impact",
    "forcing_amplitudes", "motion_from"))


def check_omega(system, omega, name="omega", warn=True):
    """A valid forcing frequency for ``system`` (a Model, or what :meth:`symvi.Model.of`
    takes): :meth:`symvi.flow.linear.LinearFlow.check_omega` of its free flight (with
    elastic stops :meth:`~symvi.flow.linear.LinearFlow.contact`'s free phase)."""
    from ..model import Model
    from .linear import LinearFlow
    model = Model.of(system)
    if model.nonlinear is not None:           # its range; no steady state to resonate
        from .linear import check_range
        return check_range(omega, name)
    return LinearFlow.free(model).check_omega(omega, name, warn=warn)


def check_value(system, param, value, shown, *, resonance=True):
    """``value`` of ``param`` (a name or a :class:`symvi.model.parameters.Parameter`)
    valid for ``system`` (a Model), else a
    one-line ParameterError naming ``shown`` (what the user typed: a flag, a keyword) and
    the range: omega in OMEGA_RANGE and, with ``resonance``, not at a forcing resonance;
    another parameter where the system it makes is valid (restitution in (0, 1], a
    positive definite mass, ...).  The valid values of one parameter form an interval (the
    positive definite matrices are a convex cone), so both ends of a range being valid
    makes all of it valid."""
    import math

    from ..errors import ParameterError, SingularCaseError
    from ..model import Model
    from ..numerics.tolerances import OMEGA_RANGE
    model = Model.of(system)
    try:
        par = model.parameter(param)
    except ParameterError as exc:
        raise ParameterError(shown, value, exc.valid, f"the value of {param}") from None
    if par.is_forcing_frequency:
        lo, hi = OMEGA_RANGE
        if not (math.isfinite(value) and lo <= value <= hi):
            raise ParameterError(shown, value, f"a forcing frequency {lo:g} <= omega <= {hi:g}")
        try:
            check_omega(model, value, name=shown, warn=False)
        except SingularCaseError:
            if resonance:
                raise
        return value
    if not math.isfinite(value):
        raise ParameterError(shown, value, f"a finite value of {par.name}")
    try:
        par.apply(model, value)
    except ParameterError as exc:
        raise ParameterError(shown, value, exc.valid, f"the value of {par.name}") from None
    return value
