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


def _zero_level(w):
    """Eigenvalues of a symmetric matrix (``w`` all of them) at most this in size are zero
    to rounding: 64 N ulps of the largest."""
    return 64 * len(w) * 2.0 ** -52 * max(abs(w).max(), 1e-300)


def null_dim(a):
    """Dimension of the null space of a symmetric positive semi-definite ``a`` (its
    eigenvalues zero to rounding, :func:`_zero_level`): for the stiffness, the number of
    modes on no spring (a free mass, a rigid-body mode)."""
    w = np.linalg.eigvalsh(np.asarray(a, dtype=float))
    return int(np.sum(np.abs(w) <= _zero_level(w)))


def _definite(field, a, semi, singular=False):
    """Refuse a matrix that is not positive (semi-)definite, or whose condition number
    exceeds 1 / DEF_TOL: say which (an ill-conditioned positive definite matrix is not
    "not positive definite").  ``singular`` (the stiffness): a matrix singular to rounding
    is accepted too (a mass on no spring: a free mode), one nearly singular is not."""
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
    if singular:
        zero = _zero_level(w)
        valid = (f"a positive semi-definite matrix: positive definite (condition number "
                 f"<= {1 / DEF_TOL:.0e}) or singular (a free mass)")
        if w.min() < -zero:
            raise ParameterError(field, _shown(a.tolist()), valid,
                                 f"indefinite: smallest eigenvalue {w.min():.3g} "
                                 "(an unstable mode)")
        pos = w[np.abs(w) > zero]
        if pos.size == 0 or pos.min() > DEF_TOL * top:
            return
        raise ParameterError(field, _shown(a.tolist()), valid,
                             f"nearly singular: eigenvalue {pos.min():.3g} of largest "
                             f"{top:.3g} is neither zero (a free mass) nor well separated")
    valid = f"a positive definite matrix with condition number <= {1 / DEF_TOL:.0e}"
    if w.min() > 64 * a.shape[0] * 2.0 ** -52 * top:
        raise ParameterError(field, _shown(a.tolist()), valid,
                             f"positive definite but ill-conditioned: condition number "
                             f"{top / w.min():.3g}, limit {1 / DEF_TOL:.0e}")
    if w.min() > 0:
        raise ParameterError(field, _shown(a.tolist()), valid,
                             f"singular to rounding: smallest eigenvalue {w.min():.3g} of "
                             f"largest {top:.3g}")
    raise ParameterError(field, _shown(a.tolist()), valid,
                         f"not positive definite: smallest eigenvalue {w.min():.3g}")


def _coordinate_name(idx):
    return f"x{idx[0] + 1}" if len(idx) == 1 else f"x{idx[1] + 1} - x{idx[0] + 1}"


def _check_stops(stops, n, named):
    """Mass indices within 1..n; at most one upper and one lower stop per coordinate, the
    lower one below the upper one (else there is no free space between them).  ``named``:
    errors name ``stop[k].field`` (``stops=``), else ``stop.field`` (``stop=``)."""
    def field(k, f):
        return f"stop[{k}].{f}" if named else f"stop.{f}"
    seen = {}
    for k, s in enumerate(stops, 1):
        if s.mass is not None and s.mass > n:
            raise ParameterError(field(k, "mass"), s.mass, f"a mass index from 1 to {n}")
        if s.between is not None and max(s.between) > n:
            raise ParameterError(field(k, "between"), list(s.between),
                                 f"two different mass indices from 1 to {n}")
        idx, sign = s.coordinate()
        # in terms of the coordinate s' = x_max - x_min (or x_k): an upper stop at g on
        # -s' is a lower stop at -g on s'
        upper = (s.side == "upper") == (sign > 0)
        g = sign * s.gap
        if (idx, upper) in seen:
            raise ParameterError(field(k, "side"), s.side,
                                 f"at most one upper and one lower stop on a coordinate "
                                 f"(stop[{seen[idx, upper][0]}] is on the same side of it)")
        seen[idx, upper] = (k, g)
        other = seen.get((idx, not upper))
        if other is not None:
            lo, hi = (other[1], g) if upper else (g, other[1])
            if not lo < hi:
                raise ParameterError(field(k, "gap"), s.gap,
                                     f"a gap that leaves free space between the lower and "
                                     f"the upper stop on one coordinate (stop[{other[0]}])",
                                     f"lower at {lo!r}, upper at {hi!r} in terms of "
                                     f"{_coordinate_name(idx)}")
