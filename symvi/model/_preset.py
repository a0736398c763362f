"""The two-mass family of eq. (4) as a model preset: its five named parameters and their
valid ranges, checked in one place (numbers by the model's own
:func:`symvi.model._checks._finite`) for ``Model.luo_xie`` and the paper's ``Params``
(:mod:`symvi.paper.params`, which sits on top and builds on this)."""
from ..errors import ParameterError
from ..numerics.tolerances import ABS_MAX
from ._checks import _finite as finite

#: the preset's parameters, in the order of eq. (4)
NAMES = ("mu_m", "mu_k", "f2", "b", "r")
#: valid mass and stiffness ratios; outside them float64 over- or underflows in eqs. (4)-(16)
MU_RANGE = (1e-6, 1e6)


def values(mu_m, mu_k, f2, b, r):
    """The preset's parameters as floats, validated: mu_m, mu_k in MU_RANGE, |b|, |f2| at
    most ABS_MAX, 0 < r <= 1; else a one-line ParameterError naming the parameter."""
    out = {name: finite(name, v) for name, v in zip(NAMES, (mu_m, mu_k, f2, b, r))}
    lo, hi = MU_RANGE
    for name in ("mu_m", "mu_k"):
        v = out[name]
        if not v > 0:
            raise ParameterError(name, v, f"{name} > 0 (and {lo:g} <= {name} <= {hi:g})")
        if not lo <= v <= hi:
            raise ParameterError(name, v, f"{lo:g} <= {name} <= {hi:g}")
    for name in ("b", "f2"):
        if not abs(out[name]) <= ABS_MAX:
            raise ParameterError(name, out[name], f"|{name}| <= {ABS_MAX:g}")
    if not 0 < out["r"] <= 1:
        raise ParameterError("r", out["r"], "0 < r <= 1")
    return out
