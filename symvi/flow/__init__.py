"""The flow layer: exact motion between impacts and the first-impact finder.

* :mod:`symvi.flow.linear` -- any model (N masses, damping, stop on any mass):
  the state-space flow in modal form and the provably safe first-impact finder;
* :mod:`symvi.flow.modal2` -- the paper's 2-DOF undamped modal form, eqs. (7)–(8),
  kept as the independent oracle (the paper's modal map :mod:`symvi.paper.modal_map`, the
  closed form :mod:`symvi.paper.modal_orbit`); ``Params`` itself runs on ``linear``.
"""
from .modal2 import GRAZING as GRAZING
from .modal2 import IMPACT as IMPACT
from .modal2 import NO_IMPACT as NO_IMPACT
from .modal2 import FirstImpact as FirstImpact
from .modal2 import Motion as Motion
from .modal2 import first_impact as first_impact
from .modal2 import forcing_amplitudes as forcing_amplitudes
from .modal2 import motion_from as motion_from


def check_omega(system, omega, name="omega", warn=True):
    """A valid forcing frequency for the paper's ``Params`` (:func:`symvi.params.check_omega`)
    or any ``Model`` (:meth:`symvi.flow.linear.LinearFlow.check_omega`)."""
    from ..model import Model
    if isinstance(system, Model):
        from .linear import LinearFlow
        return LinearFlow.of(system).check_omega(omega, name, warn=warn)
    from ..params import check_omega as paper_check
    return paper_check(system, omega, name, warn=warn)


def check_value(system, param, value, shown, *, resonance=True):
    """``value`` of ``param`` valid for ``system`` (``Params`` or ``Model``), else a
    one-line ParameterError naming ``shown`` (what the user typed: a flag, a keyword) and
    the range: omega in OMEGA_RANGE and, with ``resonance``, not at a forcing resonance;
    another parameter where the system it makes is valid (restitution in (0, 1], a
    positive definite mass, ...).  The valid values of one parameter form an interval (the
    positive definite matrices are a convex cone), so both ends of a range being valid
    makes all of it valid."""
    import math

    from ..errors import ParameterError, SingularCaseError
    from ..numerics.tolerances import OMEGA_RANGE
    if param == "omega":
        lo, hi = OMEGA_RANGE
        if not (math.isfinite(value) and lo <= value <= hi):
            raise ParameterError(shown, value, f"a forcing frequency {lo:g} <= omega <= {hi:g}")
        try:
            check_omega(system, value, name=shown, warn=False)
        except SingularCaseError:
            if resonance:
                raise
        return value
    if not math.isfinite(value):
        raise ParameterError(shown, value, f"a finite value of {param}")
    try:
        system.with_(**{param: value})
    except ParameterError as exc:
        raise ParameterError(shown, value, exc.valid, f"the value of {param}") from None
    return value
