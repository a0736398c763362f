"""A linear impact oscillator: N masses, damping, one rigid stop on any mass.

Between impacts::

    M x'' + C x' + K x = P sin(omega t + tau),   x_k < b;
    at x_k = b:  v_k+ = -r v_k-                    (Newton's impact law, eq. (2) generalised)

The stop is the model's one constraint (:attr:`Model.constraints`, a
:class:`symvi.model.Constraint` built by :meth:`Stop.constraint`): its guard and
its reset are what the flow, the maps, the orbits and the compiled kernels read.

M symmetric positive definite, K symmetric positive definite (every free-flight
mode oscillates), C symmetric positive semi-definite (zero by default, as in
the paper), P the forcing amplitudes; one stop on mass k (1-based) with gap b
and restitution 0 < r <= 1.  Luo & Xie's model, eq. (4), is
:meth:`Model.luo_xie`.

Named parameters
----------------
Every scalar that defines the model has a stable name (1-based indices):
``gap``, ``restitution``, ``mass[i]`` (= ``mass[i,i]``), ``mass[i,j]``,
``stiffness[i,j]``, ``damping[i,j]``, ``forcing[i]``; for the paper's preset
also ``mu_m``, ``mu_k``, ``f2``, ``b``, ``r``.  ``omega`` is the forcing
frequency and is not a field of the model.  Setting an off-diagonal entry sets
its mirror too (the matrices stay symmetric).  :meth:`Model.tangent` gives the
exact derivative of (M, C, K, P, b, r) with respect to any name: the data the
exact parameter derivatives of the map are built from.
"""
import functools
import math
import re
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
#: |entry| and |gap| limits: beyond them float64 over- or underflows in the flow
from ..numerics.tolerances import ABS_MAX
from . import _preset
from ._constraint import Constraint

#: number of masses supported
N_MAX = 8
#: relative asymmetry tolerated (and removed) in a matrix given by the user
SYM_TOL = 1e-12
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


@dataclass(frozen=True)
class Stop:
    """The rigid stop: on mass ``mass`` (1-based), at x_mass = ``gap``, restitution r."""

    mass: int
    gap: float
    restitution: float

    def __post_init__(self):
        if isinstance(self.mass, bool) or not isinstance(self.mass, (int, np.integer)):
            raise ParameterError("stop.mass", _shown(self.mass),
                                 "a 1-based mass index (integer >= 1)")
        object.__setattr__(self, "mass", int(self.mass))
        if not 1 <= self.mass <= N_MAX:
            raise ParameterError("stop.mass", _shown(self.mass),
                                 f"a 1-based mass index (integer from 1 to {N_MAX})")
        g = _finite("stop.gap", self.gap)
        if not abs(g) <= ABS_MAX:
            raise ParameterError("stop.gap", g, f"|gap| <= {ABS_MAX:g}")
        r = _finite("stop.restitution", self.restitution, "0 < restitution <= 1")
        if not 0 < r <= 1:
            raise ParameterError("stop.restitution", r, "0 < restitution <= 1")
        object.__setattr__(self, "gap", g)
        object.__setattr__(self, "restitution", r)

    def constraint(self, n):
        """This stop as the :class:`symvi.model.Constraint` of a model of n masses: guard
        normal c = e_mass, side "upper", impulse along e_mass (v_k+ = -r v_k-, eq. (2))."""
        e = tuple(1.0 if i == self.mass - 1 else 0.0 for i in range(n))
        return Constraint(normal=e, gap=self.gap, restitution=self.restitution,
                          side="upper", impulse=e)


def _size(field, value, n, valid):
    """len(value) for a list of at most N_MAX (or exactly n) items, checked before any
    array is built (a file's 30000-entry list must not become a 30000 x 30000 matrix)."""
    if isinstance(value, np.ndarray):
        if value.ndim == 0:
            raise ParameterError(field, _shown(value), valid)
        size = value.shape[0]
    elif isinstance(value, (list, tuple)):
        size = len(value)
    else:
        raise ParameterError(field, _shown(value), valid)
    if n is None and not 1 <= size <= N_MAX:
        raise ParameterError(field, f"{size} entries", valid, f"it has {size}")
    if n is not None and size != n:
        raise ParameterError(field, f"{size} entries", valid, f"it has {size}, not {n}")
    return size


def _entry(field, x, where):
    """One matrix or vector entry: a finite real number (not a bool or a string)."""
    v = _number(x)
    if v is None:
        raise ParameterError(field, _shown(x), "finite real numbers only (not booleans, "
                             "strings or nested lists)", f"entry {where} = {_toml(x)}")
    if not math.isfinite(v):
        raise ParameterError(field, v, "finite numbers only", f"entry {where}: NaN or infinity")
    return v


def _rows(value):
    """The items of a list, tuple or array (a 2-D array as its rows)."""
    return list(value) if not isinstance(value, np.ndarray) else [r for r in value]


def _vector(field, value, n=None, valid=None):
    """A float vector of n (or 1..N_MAX) finite numbers, checked entry by entry."""
    valid = valid or f"a list of {n or 'N'} finite numbers"
    size = _size(field, value, n, valid)
    return np.array([_entry(field, x, f"[{i + 1}]") for i, x in
                     enumerate(_rows(value))], dtype=float).reshape(size)


def _matrix(field, value, n=None, diag_ok=False):
    """A symmetric square float matrix from a list (the diagonal, when ``diag_ok``) or a
    list of rows.  Sizes, shapes and entry types are checked in Python first: nothing
    larger than N_MAX x N_MAX is allocated and no nesting is followed past two levels."""
    nn = n or "N"
    an = "an" if str(nn) in ("N", "8") else "a"
    valid = (f"a list of {nn} numbers (the diagonal) or {an} {nn}x{nn} matrix (list of rows)"
             if diag_ok else f"{an} {nn}x{nn} matrix (list of rows)")
    if n is None:
        valid += f", 1 <= N <= {N_MAX}"
    size = _size(field, value, n, valid)
    rows = _rows(value)
    flat = [not isinstance(r, (list, tuple, np.ndarray)) for r in rows]
    if all(flat) and diag_ok:
        a = np.diag([_entry(field, x, f"[{i + 1}]") for i, x in enumerate(rows)])
    elif any(flat):
        i = flat.index(True) if not all(flat) else 0
        raise ParameterError(field, _shown(value), valid,
                             f"row {i + 1} is {_short(rows[i], 20)}, not a list")
    else:
        for i, r in enumerate(rows):
            if len(r) != size:
                raise ParameterError(field, _shown(value), valid,
                                     f"row {i + 1} has {len(r)} entr{'y' if len(r) == 1 else 'ies'}"
                                     f", not {size}")
        a = np.array([[_entry(field, x, f"[{i + 1},{j + 1}]") for j, x in enumerate(_rows(r))]
                      for i, r in enumerate(rows)], dtype=float)
    if np.abs(a).max() > ABS_MAX:
        i, j = np.unravel_index(np.argmax(np.abs(a)), a.shape)
        raise ParameterError(field, _shown(a.tolist()), f"entries with |a_ij| <= {ABS_MAX:g}",
                             f"entry [{i + 1},{j + 1}] = {float(a[i, j])!r}")
    scale = np.abs(a).max()
    if np.abs(a - a.T).max() > SYM_TOL * max(scale, 1e-300):
        i, j = np.unravel_index(np.argmax(np.abs(a - a.T)), a.shape)
        raise ParameterError(field, _shown(a.tolist()), "a symmetric matrix",
                             f"entry [{i + 1},{j + 1}] = {float(a[i, j])!r} but [{j + 1},{i + 1}] = "
                             f"{float(a[j, i])!r}")
    return 0.5 * (a + a.T)


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


def _tup(a):
    return tuple(tuple(float(x) for x in row) for row in np.asarray(a))


_NAME = re.compile(r"^(mass|stiffness|damping|forcing)\[(\d+)(?:,\s*(\d+))?\]$")
_PRESET = _preset.NAMES


#: the names that change the stop only (a cheap copy of the model, no matrix validation)
_STOP_NAMES = frozenset(("gap", "restitution", "b", "r"))


class Model:
    """A linear impact oscillator (see the module docstring); immutable, hashable.

    ``Model(mass=..., stiffness=..., forcing=..., damping=None, stop=Stop(...))``;
    every argument is keyword-only and validated here; an error names the
    field and its valid range.
    """

    __slots__ = ("_M", "_K", "_C", "_P", "_stop", "_preset", "_arrays", "_hash")

    def __init__(self, *, mass, stiffness, forcing, stop, damping=None, _preset=None):
        if not isinstance(stop, Stop):
            raise ParameterError("stop", stop, "a symvi.Stop(mass=k, gap=b, restitution=r)")
        M = _matrix("mass", mass, diag_ok=True)
        n = M.shape[0]
        K = _matrix("stiffness", stiffness, n)
        C = np.zeros((n, n)) if damping is None else _matrix("damping", damping, n)
        _definite("mass", M, semi=False)
        _definite("stiffness", K, semi=False)
        _definite("damping", C, semi=True)
        P = _vector("forcing", forcing, n)
        if np.abs(P).max() > ABS_MAX:
            raise ParameterError("forcing", P.tolist(), f"|forcing[i]| <= {ABS_MAX:g}")
        if stop.mass > n:
            raise ParameterError("stop.mass", stop.mass, f"a mass index from 1 to {n}")
        object.__setattr__(self, "_M", _tup(M))
        object.__setattr__(self, "_K", _tup(K))
        object.__setattr__(self, "_C", _tup(C))
        object.__setattr__(self, "_P", tuple(float(x) for x in P))
        object.__setattr__(self, "_stop", stop)
        object.__setattr__(self, "_preset", _preset)
        object.__setattr__(self, "_arrays", {})
        object.__setattr__(self, "_hash", hash(self.key()))     # hashed on every cache lookup

    def __setattr__(self, name, value):
        raise AttributeError("symvi.Model is immutable; use model.with_(...)")

    # ---- fields --------------------------------------------------------------
    def _array(self, key, data):
        a = self._arrays.get(key)
        if a is None:
            a = np.array(data, dtype=float)
            a.flags.writeable = False
            self._arrays[key] = a
        return a

    @property
    def mass(self):
        """M, (N, N), read-only."""
        return self._array("M", self._M)

    @property
    def stiffness(self):
        return self._array("K", self._K)

    @property
    def damping(self):
        return self._array("C", self._C)

    @property
    def forcing(self):
        return self._array("P", self._P)

    @property
    def stop(self):
        return self._stop

    @property
    def constraints(self):
        """The model's constraints (:class:`symvi.model.Constraint`), indexed by a
        :class:`symvi.model.Signature`: today the one stop, ``(stop.constraint(N),)``."""
        cs = self._arrays.get("constraints")
        if cs is None:
            cs = self._arrays["constraints"] = (self._stop.constraint(self.n),)
        return cs

    @property
    def n(self):
        """Number of masses N."""
        return len(self._P)

    @property
    def dim(self):
        """Dimension of the section state y, 2N."""
        return 2 * self.n

    @property
    def damped(self):
        return any(x != 0.0 for row in self._C for x in row)

    @property
    def conservative(self):
        """r = 1 and C = 0: the impact map preserves volume (multipliers may sit on
        the unit circle over whole intervals, and (H3) has no meaning)."""
        return self._stop.restitution == 1.0 and not self.damped

    @property
    def preset(self):
        """``{"name": "luo_xie", "mu_m": ..., ...}`` for the paper's model, else None."""
        return None if self._preset is None else dict(self._preset)

    def key(self):
        """A stable tuple of every number, for hashing and caching."""
        s = self._stop
        return (self._M, self._K, self._C, self._P, s.mass, s.gap, s.restitution)

    def __eq__(self, other):
        return isinstance(other, Model) and self.key() == other.key()

    def __hash__(self):
        return self._hash

    def __repr__(self):
        if self._preset is not None:
            p = self._preset
            return ("Model.luo_xie(" + ", ".join(f"{k}={p[k]!r}" for k in _PRESET) + ")")
        return (f"Model(mass={[list(r) for r in self._M]}, stiffness={[list(r) for r in self._K]}, "
                f"damping={[list(r) for r in self._C]}, forcing={list(self._P)}, "
                f"stop={self._stop!r})")

    def as_dict(self):
        """The model as plain data (the ``[model]``/``[stop]`` tables of a model file)."""
        d = {"mass": [list(r) for r in self._M], "stiffness": [list(r) for r in self._K],
             "damping": [list(r) for r in self._C], "forcing": list(self._P),
             "stop": {"mass": self._stop.mass, "gap": self._stop.gap,
                      "restitution": self._stop.restitution}}
        if self._preset is not None:
            d["preset"] = dict(self._preset)
        return d

    # ---- the paper's preset ----------------------------------------------------
    @classmethod
    def luo_xie(cls, mu_m, mu_k, f2, b, r):
        """The model of Luo & Xie (1998), eq. (4): M = diag(1, mu_m),
        K = [[1, -1], [-1, 1 + mu_k]], P = (1 - f2, f2), stop on mass 1 at b."""
        p = _preset.values(mu_m, mu_k, f2, b, r)      # the preset's ranges and messages
        return cls(mass=[1.0, p["mu_m"]], stiffness=[[1.0, -1.0], [-1.0, 1.0 + p["mu_k"]]],
                   forcing=[1.0 - p["f2"], p["f2"]],
                   stop=Stop(mass=1, gap=p["b"], restitution=p["r"]),
                   _preset={"name": "luo_xie", **p})

    @classmethod
    def of(cls, system):
        """``system`` itself when it is a Model, else the Model it presents through its
        ``as_model()`` (the paper's :class:`symvi.Params` does: its ``Model.luo_xie``).  The
        layers below the paper take Models only; this is where a client's object becomes one."""
        if isinstance(system, cls):
            return system
        as_model = getattr(type(system), "as_model", None)
        model = as_model(system) if callable(as_model) else None
        if not isinstance(model, cls):
            raise ParameterError("model", type(system).__name__,
                                 "a symvi.Model or the paper's symvi.Params")
        return model

    # ---- named parameters ------------------------------------------------------
    def parameter_names(self):
        """Every named scalar of this model (``omega`` excluded), in a stable order."""
        n = self.n
        names = ["gap", "restitution"]
        names += [f"mass[{i + 1},{j + 1}]" for i in range(n) for j in range(i, n)]
        names += [f"stiffness[{i + 1},{j + 1}]" for i in range(n) for j in range(i, n)]
        names += [f"damping[{i + 1},{j + 1}]" for i in range(n) for j in range(i, n)]
        names += [f"forcing[{i + 1}]" for i in range(n)]
        if self._preset is not None:
            names = list(_PRESET) + names
        return names

    def _parse(self, name):
        """(kind, i, j) of a named parameter, 0-based; raise naming the valid names."""
        valid = ("omega, gap, restitution, mass[i], mass[i,j], stiffness[i,j], damping[i,j], "
                 f"forcing[i] with 1 <= i, j <= {self.n}"
                 + ("; for this preset also mu_m, mu_k, f2, b, r" if self._preset else ""))
        if name in ("gap", "restitution"):
            return name, None, None
        if name in _PRESET:
            if self._preset is None:
                raise ParameterError("parameter", name, valid,
                                     f"{name} belongs to the Luo-Xie preset only")
            return name, None, None
        m = _NAME.match(str(name).replace(" ", ""))
        if not m:
            raise ParameterError("parameter", name, valid)
        kind, i = m.group(1), int(m.group(2)) - 1
        j = None if m.group(3) is None else int(m.group(3)) - 1
        if kind == "forcing" and j is not None:
            raise ParameterError("parameter", name, valid)
        if kind == "mass" and j is None:
            j = i
        if kind in ("stiffness", "damping") and j is None:
            raise ParameterError("parameter", name, valid, f"{kind} needs two indices")
        if not 0 <= i < self.n or (j is not None and not 0 <= j < self.n):
            raise ParameterError("parameter", name, valid)
        return kind, i, j

    def value(self, name):
        """The value of a named parameter."""
        kind, i, j = self._parse(name)
        if kind == "gap":
            return self._stop.gap
        if kind == "restitution":
            return self._stop.restitution
        if kind in _PRESET:
            return self._preset[kind]
        if kind == "forcing":
            return self._P[i]
        return {"mass": self._M, "stiffness": self._K, "damping": self._C}[kind][i][j]

    def with_(self, **changes):
        """A copy with named parameters changed, e.g. ``model.with_(**{"forcing[1]": 0.3})``
        or ``model.with_(mu_m=3)`` on the preset.  Validated like the constructor."""
        preset = dict(self._preset) if self._preset else None
        if changes and set(changes) <= _STOP_NAMES:
            return self._with_stop(preset, changes)
        pre = {k: v for k, v in changes.items() if k in _PRESET}
        for k in pre:
            self._parse(k)                    # refuses preset names on a general model
        if pre:
            vals = {k: preset[k] for k in _PRESET}
            vals.update(pre)
            base = Model.luo_xie(**vals)
            rest = {k: v for k, v in changes.items() if k not in _PRESET}
            return base.with_(**rest) if rest else base
        M, K, C = (np.array(x) for x in (self._M, self._K, self._C))
        P = np.array(self._P)
        gap, r = self._stop.gap, self._stop.restitution
        for name, v in changes.items():
            kind, i, j = self._parse(name)
            v = _finite(name, v)
            if kind == "gap":
                gap = v
            elif kind == "restitution":
                r = v
            elif kind == "forcing":
                P[i] = v
            else:
                A = {"mass": M, "stiffness": K, "damping": C}[kind]
                A[i, j] = A[j, i] = v
        if preset is not None and set(changes) <= {"gap", "restitution"}:
            # only b or r changed: still the paper's model, keep the preset's names
            preset.update(b=gap, r=r)
            return Model.luo_xie(**{k: preset[k] for k in _PRESET})
        return Model(mass=M, stiffness=K, damping=C, forcing=P,
                     stop=Stop(mass=self._stop.mass, gap=gap, restitution=r))

    def _with_stop(self, preset, changes):
        """A copy with only the stop changed: the matrices are not validated again (a curve
        in b or r builds one model per corrector step)."""
        gap, r = self._stop.gap, self._stop.restitution
        for name, v in changes.items():
            kind = self._parse(name)[0]
            v = _finite(name, v)
            if kind in ("gap", "b"):
                gap = v
            else:
                r = v
        if preset is not None:
            preset.update(_preset.values(preset["mu_m"], preset["mu_k"], preset["f2"], gap,
                                         r))      # the preset's ranges and messages
        new = object.__new__(Model)
        for slot in ("_M", "_K", "_C", "_P"):
            object.__setattr__(new, slot, getattr(self, slot))
        stop = Stop(mass=self._stop.mass, gap=gap, restitution=r)
        object.__setattr__(new, "_stop", stop)
        object.__setattr__(new, "_preset", preset)
        cs = self._arrays.get("constraints")
        object.__setattr__(new, "_arrays", {} if cs is None else {
            "constraints": (cs[0].with_values(stop.gap, stop.restitution),)})
        object.__setattr__(new, "_hash", hash(new.key()))
        return new

    def tangent(self, name):
        """d(M, C, K, P, b, r) / d(name): exact derivative of the model data, as a
        :class:`Tangent`.  ``omega`` has the zero tangent here (it enters the map
        directly, not through the model)."""
        n = self.n
        z = np.zeros((n, n))
        dM, dK, dC, dP = z.copy(), z.copy(), z.copy(), np.zeros(n)
        db = dr = 0.0
        if name == "omega":
            return Tangent(dM, dK, dC, dP, db, dr)
        kind, i, j = self._parse(name)
        if kind in ("gap", "b"):
            db = 1.0
        elif kind in ("restitution", "r"):
            dr = 1.0
        elif kind == "mu_m":
            dM[1, 1] = 1.0
        elif kind == "mu_k":
            dK[1, 1] = 1.0
        elif kind == "f2":
            dP[:] = (-1.0, 1.0)
        elif kind == "forcing":
            dP[i] = 1.0
        else:
            A = {"mass": dM, "stiffness": dK, "damping": dC}[kind]
            A[i, j] = A[j, i] = 1.0
        return Tangent(dM, dK, dC, dP, db, dr)


@dataclass(frozen=True)
class Tangent:
    """Derivative of the model data with respect to one named parameter."""

    dM: np.ndarray
    dK: np.ndarray
    dC: np.ndarray
    dP: np.ndarray
    db: float
    dr: float

    @property
    def zero(self):
        return (self.db == 0 and self.dr == 0 and not np.any(self.dM) and not np.any(self.dK)
                and not np.any(self.dC) and not np.any(self.dP))
