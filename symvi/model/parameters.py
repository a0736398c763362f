"""Named parameters as objects: a name parsed once, then read, set and differentiated.

A :class:`Parameter` is a lens on the point (model, omega), as in BifurcationKit's
``@optic``/``Lens``: ``get`` reads the value, ``set`` returns the point with the value
changed, ``tangent`` is d(M, C, K, P, b, r)/d(value), the data the exact parameter
derivatives of the map, eqs. (36)-(38) generalised, are built from.

Names (1-based indices): ``omega``; ``gap``, ``restitution`` (the first stop's);
``stop[k].gap``, ``stop[k].restitution``, ``stop[k].stiffness``, ``stop[k].damping``
(stop k's, as its kind has them); ``mass[i]`` (=
``mass[i,i]``), ``mass[i,j]``, ``stiffness[i,j]``, ``damping[i,j]``, ``forcing[i]``;
for the paper's preset also ``mu_m``, ``mu_k``, ``f2``, ``b``, ``r``.  A name is parsed
by :meth:`symvi.model.Model.parameter` (once per model shape: the objects are cached),
so a corrector step that sets a parameter neither parses its name nor validates the
parts of the model the change cannot touch.

The point is the pair (model, omega)
------------------------------------
``omega`` is the forcing frequency: it is not a field of the :class:`Model` (a model's
flow, modes and jets do not depend on it; the forcing's particular solution does, and
the flow builds it per omega, :meth:`symvi.flow.linear.LinearFlow.forcing`).  So the
lenses act on the pair ``(model, omega)`` that every layer already carries (an orbit
problem's ``at``, a curve system, a simulation) rather than on a new state type:
``get(model, omega)`` and ``set(model, omega, value) -> (model, omega)``, with omega
one parameter among the others (:class:`Omega`).  Its valid range needs the flow (a
forcing resonance), so the model layer checks it finite only; the range and the
resonance are checked at the boundary by :func:`symvi.flow.check_value`.

Validation
----------
``set`` returns a valid model or raises the one-line :class:`ParameterError` of the
constructor: a gap within ABS_MAX, 0 < restitution <= 1, a matrix entry keeps the
matrix positive (semi-)definite (only that matrix is checked), the preset's ranges.
"""
import functools
import re

import numpy as np

from dataclasses import dataclass

from ..errors import ParameterError
from ..numerics.tolerances import ABS_MAX
from . import _preset
from ._checks import _check_stops, _definite, _finite, _shown

_NAME = re.compile(r"^(mass|stiffness|damping|forcing)\[(\d+)(?:,\s*(\d+))?\]$")
_STOP_NAME = re.compile(r"^stop\[(\d+)\]\.(gap|restitution|stiffness|damping)$")
#: the numbers of a stop that are parameters, by the stop's kind
_STOP_FIELDS = {"rigid": ("gap", "restitution"), "elastic": ("gap", "stiffness", "damping")}


class Parameter:
    """One named parameter of models of ``n`` masses (``preset``: the paper's preset).

    Frozen and hashable (equal when name, kind, indices and shape are); built by
    :meth:`symvi.model.Model.parameter`, never by hand."""

    __slots__ = ("name", "kind", "i", "j", "n", "preset", "_tangent")
    #: True for omega only: the forcing frequency, which lives beside the model
    is_forcing_frequency = False

    def __init__(self, name, kind, i=None, j=None, *, n, preset=False):
        for k, v in (("name", name), ("kind", kind), ("i", i), ("j", j), ("n", n),
                     ("preset", preset), ("_tangent", None)):
            object.__setattr__(self, k, v)

    def __setattr__(self, name, value):
        raise AttributeError("a symvi Parameter is immutable")

    def _key(self):
        return (type(self), self.name, self.kind, self.i, self.j, self.n, self.preset)

    def __eq__(self, other):
        return isinstance(other, Parameter) and self._key() == other._key()

    def __hash__(self):
        return hash(self._key())

    def __repr__(self):
        return f"Parameter({self.name!r})"

    def __reduce__(self):                   # unpickled through the parser's cache
        return parse, (self.name, self.n, self.preset)

    def __str__(self):
        return self.name

    # ---- the lens ----------------------------------------------------------------
    def get(self, model, omega=None):
        """The value at the point (model, omega)."""
        raise NotImplementedError

    def set(self, model, omega, value):
        """The point (model, omega) with this parameter at ``value``: (model', omega')."""
        return self.apply(model, value), omega

    def apply(self, model, value):
        """``model`` with this parameter at ``value`` (validated: see the module docstring)."""
        raise NotImplementedError

    def tangent(self, model=None):
        """d(M, C, K, P, b, r)/d(this parameter), exact: a :class:`Tangent` (read-only
        arrays, built once per parameter; it does not depend on the model's values)."""
        t = self._tangent
        if t is None:
            n = self.n
            dM, dK, dC, dP = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n)), np.zeros(n)
            vals = tuple(self._fill(dM, dK, dC, dP))
            db, dr, dk, dc = vals + (0.0,) * (4 - len(vals))
            for a in (dM, dK, dC, dP):
                a.flags.writeable = False
            t = Tangent(dM, dK, dC, dP, db, dr,
                        getattr(self, "i", 0) if (db or dr or dk or dc) else 0, dk, dc)
            object.__setattr__(self, "_tangent", t)
        return t

    def _fill(self, dM, dK, dC, dP):
        """Write this parameter's tangent into the zero arrays; return (db, dr)."""
        return 0.0, 0.0


class Omega(Parameter):
    """The forcing frequency omega: beside the model, not in it (see the module docstring)."""

    __slots__ = ()
    is_forcing_frequency = True

    def get(self, model, omega=None):
        if omega is None:
            raise ParameterError("omega", None, "a forcing frequency (the point has none)")
        return omega

    def set(self, model, omega, value):
        # omega's range and resonances are the flow's: checked at the boundary
        # (symvi.flow.check_value) and by the orbit problem's check_omega
        return model, value

    def apply(self, model, value):
        raise ParameterError("parameter", "omega", "a parameter of the model (omega is the "
                             "forcing frequency: it lives beside the model, set it on the "
                             "point (model, omega))")


class StopParameter(Parameter):
    """``gap`` / ``restitution`` (the preset's ``b`` / ``r``; the first stop's), and
    ``stop[k].gap``, ``.restitution``, ``.stiffness``, ``.damping`` (stop k = i + 1): the
    stops only, so a new model shares the validated matrices (a curve in b or r builds one
    per corrector step)."""

    __slots__ = ()

    def stop_of(self, model):
        """The stop this parameter names on ``model``, or ParameterError when the model has
        no such stop or the stop has no such number (a rigid stop's stiffness)."""
        stops = model._stops
        if self.i >= len(stops):
            raise ParameterError("parameter", self.name, f"stop[k] with 1 <= k <= {len(stops)} "
                                 f"(the model has {len(stops)} stop{'s' if len(stops) > 1 else ''})")
        s = stops[self.i]
        if self.kind not in _STOP_FIELDS[s.kind]:
            valid = ", ".join(f"stop[{self.i + 1}].{f}" for f in _STOP_FIELDS[s.kind])
            raise ParameterError("parameter", self.name, valid,
                                 f"stop {self.i + 1} is {s.kind}: it has no {self.kind}")
        return s

    def get(self, model, omega=None):
        return getattr(self.stop_of(model), self.kind)

    def apply(self, model, value):
        value = _finite(self.name, value)
        s = self.stop_of(model)
        preset = model._preset
        if preset is not None:                  # the preset's ranges and messages
            gap, r = (value, s.restitution) if self.kind == "gap" else (s.gap, value)
            preset = dict(preset)
            preset.update(_preset.values(preset["mu_m"], preset["mu_k"], preset["f2"], gap, r))
        stops = list(model._stops)
        try:
            stop = stops[self.i] = s.replaced(**{self.kind: value})
        except ParameterError as exc:           # named as the user named it: stop[2].gap
            if exc.name.startswith("stop.") and self.name.startswith("stop["):
                raise ParameterError(f"stop[{self.i + 1}].{exc.name[5:]}", exc.value,
                                     exc.valid, exc.detail) from None
            raise
        if len(stops) > 1 and self.kind == "gap":
            try:                                # the stops still leave free space
                _check_stops(stops, model.n, named=True)
            except ParameterError as exc:
                raise ParameterError(self.name, value, exc.valid, exc.detail) from None
        # the constraints carried over at the new numbers: the flow's caches of the guard
        # and reset stay valid (a curve in b or r sets the stop at every corrector step)
        cs = model._arrays.get("constraints")
        arrays = {}
        if cs is not None:
            cs = list(cs)
            cs[self.i] = cs[self.i].with_values(stop.gap, stop.restitution, stop.stiffness,
                                                stop.damping)
            arrays["constraints"] = tuple(cs)
        return _copy(model, _stops=tuple(stops), preset=preset, _arrays=arrays)

    def _fill(self, dM, dK, dC, dP):
        # (db, dr, dk, dc): the Tangent holds the stop's number that moves (Tangent.stop)
        return {"gap": (1.0, 0.0, 0.0, 0.0), "restitution": (0.0, 1.0, 0.0, 0.0),
                "stiffness": (0.0, 0.0, 1.0, 0.0), "damping": (0.0, 0.0, 0.0, 1.0)}[self.kind]


class EntryParameter(Parameter):
    """``mass[i,j]``, ``stiffness[i,j]``, ``damping[i,j]``: one entry and its mirror; the
    new matrix is checked definite (semi-definite for damping), the others are shared."""

    __slots__ = ()
    _SLOT = {"mass": "_M", "stiffness": "_K", "damping": "_C"}

    def get(self, model, omega=None):
        return getattr(model, self._SLOT[self.kind])[self.i][self.j]

    def apply(self, model, value):
        value = _finite(self.name, value)
        i, j, kind = self.i, self.j, self.kind
        A = np.array(getattr(model, self._SLOT[kind]))
        A[i, j] = A[j, i] = value
        if abs(value) > ABS_MAX:
            i0, j0 = sorted((i, j))
            raise ParameterError(kind, _shown(A.tolist()), f"entries with |a_ij| <= {ABS_MAX:g}",
                                 f"entry [{i0 + 1},{j0 + 1}] = {value!r}")
        _definite(kind, A, semi=kind == "damping", singular=kind == "stiffness")
        rows = tuple(tuple(float(x) for x in row) for row in A)
        # a changed matrix is no longer the paper's preset (as Model.with_ always did)
        return _copy(model, preset=None, **{self._SLOT[kind]: rows})

    def _fill(self, dM, dK, dC, dP):
        A = {"mass": dM, "stiffness": dK, "damping": dC}[self.kind]
        A[self.i, self.j] = A[self.j, self.i] = 1.0
        return 0.0, 0.0


class ForcingParameter(Parameter):
    """``forcing[i]``: one forcing amplitude."""

    __slots__ = ()

    def get(self, model, omega=None):
        return model._P[self.i]

    def apply(self, model, value):
        value = _finite(self.name, value)
        P = list(model._P)
        P[self.i] = value
        if abs(value) > ABS_MAX:
            raise ParameterError("forcing", P, f"|forcing[i]| <= {ABS_MAX:g}")
        return _copy(model, preset=None, _P=tuple(P))

    def _fill(self, dM, dK, dC, dP):
        dP[self.i] = 1.0
        return 0.0, 0.0


class PresetParameter(Parameter):
    """The paper's ``mu_m``, ``mu_k``, ``f2``: the preset rebuilt (eq. (4)) with its ranges."""

    __slots__ = ()

    def get(self, model, omega=None):
        return model._preset[self.kind]

    def apply(self, model, value):
        vals = {k: model._preset[k] for k in _preset.NAMES}
        vals[self.kind] = value
        return type(model).luo_xie(**vals)

    def _fill(self, dM, dK, dC, dP):
        if self.kind == "mu_m":
            dM[1, 1] = 1.0
        elif self.kind == "mu_k":
            dK[1, 1] = 1.0
        else:                                   # f2: P = (1 - f2, f2)
            dP[:] = (-1.0, 1.0)
        return 0.0, 0.0


class NamedParameter(Parameter):
    """A named parameter of the model's nonlinear forces (``beta`` of ``beta*x1**3``,
    issue 28): read and set like the others; its tangent waits for the nonlinear jets."""

    __slots__ = ()

    def __reduce__(self):
        return _named, (self.name, self.n)

    def get(self, model, omega=None):
        return model._nl.value(self.name)

    def apply(self, model, value):
        return _copy(model, preset=model._preset, _nl=model._nl.with_value(self.name, value))

    def tangent(self, model=None):
        raise ParameterError("parameter", self.name, "a parameter of the linear model: a "
                             "nonlinear force's parameter has no tangent yet (issue 28)")


def _named(name, n):
    return NamedParameter(name, "named", n=n)


def _copy(model, *, preset, **slots):
    """A copy of ``model`` with some fields (slot names: ``_M``, ``_stops``, ...) replaced,
    already validated by the caller."""
    assert set(slots) <= {"_M", "_K", "_C", "_P", "_stops", "_arrays", "_nl"}, slots
    new = object.__new__(type(model))
    for slot in ("_M", "_K", "_C", "_P", "_stops", "_nl"):
        object.__setattr__(new, slot, slots.get(slot, getattr(model, slot)))
    object.__setattr__(new, "_preset", preset)
    object.__setattr__(new, "_arrays", slots.get("_arrays", {}))
    object.__setattr__(new, "_hash", hash(new.key()))
    return new


@dataclass(frozen=True)
class Tangent:
    """Derivative of the model data with respect to one named parameter."""

    dM: np.ndarray
    dK: np.ndarray
    dC: np.ndarray
    dP: np.ndarray
    db: float
    dr: float
    #: the stop whose gap (db), restitution (dr), contact stiffness (dk) or contact
    #: damping (dc) moves (0-based; 0 when none does)
    stop: int = 0
    #: an elastic stop's stiffness and damping rates (:mod:`symvi.flow.contact`'s K_S, C_S)
    dk: float = 0.0
    dc: float = 0.0

    @property
    def zero(self):
        return (self.db == 0 and self.dr == 0 and self.dk == 0 and self.dc == 0
                and not np.any(self.dM) and not np.any(self.dK)
                and not np.any(self.dC) and not np.any(self.dP))




#: how many names have been parsed (a test counts that a corrector loop parses none)
PARSES = [0]


def valid_names(n, preset):
    """The valid names, in words, for ParameterError."""
    return ("omega, gap, restitution, stop[k].gap, stop[k].restitution, stop[k].stiffness, "
            "stop[k].damping, mass[i], mass[i,j], stiffness[i,j], damping[i,j], "
            f"forcing[i] with 1 <= i, j <= {n}"
            + ("; for this preset also mu_m, mu_k, f2, b, r" if preset else ""))


@functools.lru_cache(maxsize=1024)
def _parse(name, n, preset):
    PARSES[0] += 1
    valid = valid_names(n, preset)
    if name == "omega":
        return Omega(name, "omega", n=n)
    if name in ("gap", "restitution", "b", "r"):
        if name in ("b", "r") and not preset:
            raise ParameterError("parameter", name, valid,
                                 f"{name} belongs to the Luo-Xie preset only")
        return StopParameter(name, "gap" if name in ("gap", "b") else "restitution", 0, n=n,
                             preset=name in ("b", "r"))
    m = _STOP_NAME.match(name.replace(" ", ""))
    if m:
        k = int(m.group(1))
        if not 1 <= k <= 64:
            raise ParameterError("parameter", name, valid, "stop[k] with k >= 1")
        return StopParameter(name, m.group(2), k - 1, n=n)
    if name in _preset.NAMES:
        if not preset:
            raise ParameterError("parameter", name, valid,
                                 f"{name} belongs to the Luo-Xie preset only")
        return PresetParameter(name, name, n=n, preset=True)
    m = _NAME.match(name.replace(" ", ""))
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
    if not 0 <= i < n or (j is not None and not 0 <= j < n):
        raise ParameterError("parameter", name, valid)
    if kind == "forcing":
        return ForcingParameter(name, kind, i, n=n)
    return EntryParameter(name, kind, i, j, n=n)


def parse(name, n, preset):
    """The :class:`Parameter` called ``name`` for models of n masses (``preset``: the
    paper's); a Parameter is returned as it is when it fits.  A bad name raises the
    one-line ParameterError naming the valid names."""
    if isinstance(name, Parameter):
        if name.n == n and preset >= name.preset:
            return name
        name = name.name
    if not isinstance(name, str):
        raise ParameterError("parameter", name, valid_names(n, preset))
    return _parse(name, n, bool(preset))
