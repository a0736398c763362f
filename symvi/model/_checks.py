"""Checks of the model's numbers, shared by the constructor (:mod:`symvi.model._model`)
and the parameter objects (:mod:`symvi.model.parameters`): one-line ParameterErrors naming
the field and its valid range."""
import math

import numpy as np

from ..errors import ParameterError

#: smallest eigenvalue of M and K, relative to the largest, accepted as definite
DEF_TOL = 1e-12


def _short(value, limit=40):
    """repr of ``value`` cut to ``limit`` characters (a message stays one short line)."""
    def plain(v):                          # numpy scalars as Python numbers: no np.float64(...)
        if isinstance(v, (np.ndarray, np.generic)):
            return v.tolist()
        return type(v)(plain(x) for x in v) if isinstance(v, (list, tuple)) else v
    try:
        text = repr(plain(value))
    except ValueError:                     # an int beyond the 4300-digit str limit
        text = f"<an integer of {int(value.bit_length() * 0.30103) + 1} digits>"
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _shown(value):
    """``value`` itself where its repr is short, else :func:`_short` (for ParameterError)."""
    text = _short(value)
    return text if text.endswith(("...", "digits>")) else value


def _number(value):
    """float(value) for a real number; None for anything else (bool and str included:
    ``true`` and ``"1.0"`` in a model file are not numbers)."""
    if isinstance(value, (bool, np.bool_, str, bytes, list, tuple, dict, np.ndarray)):
        return None
    try:
        return float(value)
    except (TypeError, ValueError, OverflowError):
        return None


def _toml(x):
    """How a value reads in a model file (true, "1.0", ...), for messages."""
    return ("true" if x else "false") if isinstance(x, (bool, np.bool_)) else _short(x, 20)


def _finite(name, value, valid="a finite real number"):
    v = _number(value)
    if v is None:
        raise ParameterError(name, _shown(value), valid, f"not a number: {_toml(value)}")
    if not math.isfinite(v):
        raise ParameterError(name, v, valid)
    return v


def _definite(field, a, semi):
    """Refuse a matrix that is not positive (semi-)definite, or whose condition number
    exceeds 1 / DEF_TOL: say which (an ill-conditioned positive definite matrix is not
    "not positive definite")."""
    w = np.linalg.eigvalsh(a)
    top = max(abs(w).max(), 1e-300)
    if semi:
        if w.min() < -DEF_TOL * top:
            raise ParameterError(field, _shown(a.tolist()), "a positive semi-definite matrix",
                                 f"smallest eigenvalue {w.min():.3g}: not positive "
                                 "semi-definite")
        return
    if w.min() > DEF_TOL * top:
        return
    valid = f"a positive definite matrix with condition number <= {1 / DEF_TOL:.0e}"
    if w.min() > 64 * a.shape[0] * 2.0 ** -52 * top:
        raise ParameterError(field, _shown(a.tolist()), valid,
                             f"positive definite but ill-conditioned: condition number "
                             f"{top / w.min():.3g}, limit {1 / DEF_TOL:.0e}")
    what = ("; every free-flight mode must oscillate: a rigid-body or unstable mode is not "
            "supported" if field == "stiffness" else "")
    if w.min() > 0:
        raise ParameterError(field, _shown(a.tolist()), valid,
                             f"singular to rounding: smallest eigenvalue {w.min():.3g} of "
                             f"largest {top:.3g}{what}")
    raise ParameterError(field, _shown(a.tolist()), valid,
                         f"not positive definite: smallest eigenvalue {w.min():.3g}{what}")
