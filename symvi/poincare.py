"""The Poincaré map P of the paper's model or of any model, eq. (31): one owner,
:mod:`symvi.maps.impact`; a :class:`symvi.Params` runs as ``Model.luo_xie``.

``step``, ``MapStep`` and ``fd_jacobian`` (the paper's modal map and its finite
differences) keep their import path here; they live in :mod:`symvi.paper.modal_map`,
the independent oracle.
"""
_ORACLE = ("MapStep", "fd_jacobian", "step")


def poincare_map(system, omega, y, *, digits=None):
    """P(y; omega), eq. (31), of a :class:`symvi.Params` or :class:`symvi.Model`, on float64
    or (``digits``) mpmath: :func:`symvi.maps.impact.poincare_map`.  Raises nothing for a
    flight that grazes or never returns; inspect ``MapStep.status``."""
    from .maps.impact import poincare_map as impact_map    # numba: not on import symvi
    from .model import Model
    return impact_map(Model.of(system), omega, y, digits=digits)


def __getattr__(name):
    # the oracle's published names, imported only when asked for (off the production path)
    if name in _ORACLE:
        from .paper import modal_map
        return getattr(modal_map, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
