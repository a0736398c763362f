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
