"""A linear impact oscillator: N masses, damping, stops (one rigid stop on any mass today).

Between impacts::

    M x'' + C x' + K x = P sin(omega t + tau),   x_k < b;
    at x_k = b:  v_k+ = -r v_k-                    (Newton's impact law, eq. (2) generalised)

Each stop is one constraint of the model (:attr:`Model.constraints`, a
:class:`symvi.model.Constraint` built by :meth:`Stop.constraint`): its guard and
its reset are what the flow, the maps, the orbits and the compiled kernels read.
A model may hold several stops, stops between two masses (s = x_j - x_i), lower stops
(s >= g) and elastic ones (issue 25); the model layer reads, checks and writes them, and
the dynamics take one rigid upper stop on one mass for now
(:meth:`Model.require_one_rigid_stop`, called where a model enters them).

M symmetric positive definite, K symmetric positive semi-definite (singular for a
mass on no spring: a free mode, as in an impact damper), C symmetric positive
semi-definite (zero by default, as in the paper), P the forcing amplitudes; one stop
on mass k (1-based) with gap b and restitution 0 < r <= 1.  Luo & Xie's model, eq. (4), is
:meth:`Model.luo_xie`.

Named parameters
----------------
Every scalar that defines the model has a stable name (1-based indices):
``gap``, ``restitution`` (the first stop's), ``stop[k].gap``, ``stop[k].restitution``,
``stop[k].stiffness``, ``stop[k].damping``, ``mass[i]`` (= ``mass[i,i]``), ``mass[i,j]``,
``stiffness[i,j]``, ``damping[i,j]``, ``forcing[i]``; for the paper's preset
also ``mu_m``, ``mu_k``, ``f2``, ``b``, ``r``.  ``omega`` is the forcing
frequency and is not a field of the model.  Setting an off-diagonal entry sets
its mirror too (the matrices stay symmetric).  :meth:`Model.tangent` gives the
exact derivative of (M, C, K, P, b, r) with respect to any name: the data the
exact parameter derivatives of the map are built from.  :meth:`Model.parameter` parses a
name once into an object that reads, sets and differentiates it
(:mod:`symvi.model.parameters`); ``value``, ``with_`` and ``tangent`` are thin wrappers.
"""
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
#: |entry| and |gap| limits: beyond them float64 over- or underflows in the flow
from ..numerics.tolerances import ABS_MAX
from . import _preset
from ._checks import DEF_TOL, _number, _short, _toml  # noqa: F401 (re-exported)
from ._checks import _check_stops, _definite, _finite, _shown
from ._constraint import SIDES, Constraint
from ._forces import Forces
from .parameters import NamedParameter, PresetParameter, StopParameter
from .parameters import Tangent  # noqa: F401 (re-exported)
from .parameters import parse as _parse_parameter

#: number of masses supported
N_MAX = 8
#: relative asymmetry tolerated (and removed) in a matrix given by the user
SYM_TOL = 1e-12


@dataclass(frozen=True, repr=False)
class Stop:
    """One stop of a :class:`Model` (keyword fields; ``Stop(mass, gap, restitution)`` as before).

    The coordinate: exactly one of ``mass=k`` (s = x_k) or ``between=(i, j)``
    (s = x_j - x_i, an impact between two masses), 1-based, i != j.  ``gap`` g;
    ``side`` "upper" (s <= g, the default) or "lower" (s >= g).  The contact: rigid
    with ``restitution`` 0 < r <= 1 (Newton's law v+ = -r v-, eq. (2)), or elastic with
    ``stiffness`` > 0 and an optional ``damping`` >= 0 (:mod:`symvi.model._constraint`).
    Each field is checked here; the model checks the indices against N and the stops
    against each other.  Immutable and hashable.

    Parameters
    ----------
    mass : int, optional
        1-based index (1 to 8) of the mass that meets the stop: s = x_k.  Exactly one of
        ``mass`` and ``between``.
    gap : float
        The gap g (required): the stop is at s = g; finite, ``abs(gap) <= 1e6``.
    restitution : float, optional
        Coefficient of restitution r of a rigid stop, 0 < r <= 1 (1: elastic impact, no
        loss).  Required for a rigid stop, refused with ``stiffness``.
    between : tuple of int, optional
        ``(i, j)``: two different 1-based mass indices, s = x_j - x_i (an impact between
        two masses).  Exactly one of ``mass`` and ``between``.
    side : {"upper", "lower"}, optional
        "upper" (default): the motion keeps s <= g; "lower": s >= g.
    stiffness : float, optional
        Contact stiffness k_s of an elastic stop, 0 < k_s <= 1e6 (then no
        ``restitution``).  Default None: a rigid stop.
    damping : float, optional
        Contact damping c_s of an elastic stop, 0 <= c_s <= 1e6; only with
        ``stiffness``.  Default None (no contact damping).

    Raises
    ------
    ParameterError
        A field out of its range, naming it (``stop.mass``, ``stop.gap``,
        ``stop.restitution``, ...): neither or both of ``mass`` and ``between``, a mass
        index outside 1..8, a missing or non-finite gap, a side other than "upper" or
        "lower", a rigid stop without a restitution in (0, 1], ``restitution`` together
        with ``stiffness``, ``damping`` without ``stiffness``.

    Examples
    --------
    >>> from symvi import Stop
    >>> Stop(mass=1, gap=0.5, restitution=0.8)
    Stop(mass=1, gap=0.5, restitution=0.8)
    >>> s = Stop(between=(1, 2), gap=0.1, side="lower", stiffness=50.0)
    >>> s.kind
    'elastic'
    """

    mass: int = None
    gap: float = None
    restitution: float = None
    between: tuple = None
    side: str = "upper"
    stiffness: float = None
    damping: float = None

    def __post_init__(self):
        if (self.mass is None) == (self.between is None):
            raise ParameterError("stop.mass", _shown(self.mass),
                                 "exactly one of mass=k (a 1-based mass index) or "
                                 "between=(i, j) (two different mass indices)",
                                 "both given" if self.mass is not None else "neither given")
        if self.mass is not None:
            object.__setattr__(self, "mass", _index("stop.mass", self.mass))
        else:
            b = self.between
            if isinstance(b, (str, bytes)) or not isinstance(b, (list, tuple, np.ndarray)) \
                    or len(b) != 2:
                raise ParameterError("stop.between", _shown(b),
                                     "two different 1-based mass indices [i, j] (s = x_j - x_i)")
            i, j = (_index("stop.between", x) for x in b)
            if i == j:
                raise ParameterError("stop.between", [i, j],
                                     "two different 1-based mass indices [i, j] (s = x_j - x_i)")
            object.__setattr__(self, "between", (i, j))
        if self.gap is None:
            raise ParameterError("stop.gap", None, "a finite real number (required)")
        g = _finite("stop.gap", self.gap)
        if not abs(g) <= ABS_MAX:
            raise ParameterError("stop.gap", g, f"|gap| <= {ABS_MAX:g}")
        object.__setattr__(self, "gap", g)
        if self.side not in SIDES:
            raise ParameterError("stop.side", _shown(self.side), '"upper" or "lower"')
        if self.stiffness is None:
            if self.damping is not None:
                raise ParameterError("stop.damping", _shown(self.damping),
                                     "only with a stiffness > 0 (an elastic stop); a rigid "
                                     "stop has a restitution 0 < r <= 1 and no damping")
            if self.restitution is None:
                raise ParameterError("stop.restitution", None,
                                     "0 < restitution <= 1 (a rigid stop), or a stiffness > 0 "
                                     "(an elastic stop)")
            r = _finite("stop.restitution", self.restitution, "0 < restitution <= 1")
            if not 0 < r <= 1:
                raise ParameterError("stop.restitution", r, "0 < restitution <= 1")
            object.__setattr__(self, "restitution", r)
            return
        if self.restitution is not None:
            raise ParameterError("stop.stiffness", _shown(self.stiffness),
                                 "none for a rigid stop (it has a restitution); an elastic "
                                 "stop has a stiffness > 0 and no restitution")
        k = _finite("stop.stiffness", self.stiffness, "stiffness > 0")
        if not 0 < k <= ABS_MAX:
            raise ParameterError("stop.stiffness", k, f"0 < stiffness <= {ABS_MAX:g}")
        object.__setattr__(self, "stiffness", k)
        if self.damping is not None:
            c = _finite("stop.damping", self.damping, "damping >= 0")
            if not 0 <= c <= ABS_MAX:
                raise ParameterError("stop.damping", c, f"0 <= damping <= {ABS_MAX:g}")
            object.__setattr__(self, "damping", c)

    @property
    def kind(self):
        """"rigid" (a restitution) or "elastic" (a stiffness)."""
        return "rigid" if self.stiffness is None else "elastic"

    @property
    def plain(self):
        """True for today's stop: rigid, upper side, on one mass (the single ``[stop]``
        table of a model file says all of it)."""
        return self.mass is not None and self.side == "upper" and self.stiffness is None

    def fields(self, short=False):
        """The fields that are set, in the order of a model file's ``[[stop]]`` table
        (``short``: the side left out where it is the default, as in a ``[stop]`` table)."""
        d = {"mass": self.mass} if self.mass is not None else {"between": list(self.between)}
        d["gap"] = self.gap
        if not (short and self.plain):
            d["side"] = self.side
        if self.stiffness is None:
            d["restitution"] = self.restitution
        else:
            d["stiffness"] = self.stiffness
            if self.damping is not None:
                d["damping"] = self.damping
        return d

    def key(self):
        """Every number of the stop, for hashing (today's (mass, gap, r) for a plain stop)."""
        if self.plain:
            return (self.mass, self.gap, self.restitution)
        return (self.mass, self.between, self.side, self.gap, self.restitution,
                self.stiffness, self.damping)

    def __repr__(self):
        return "Stop(" + ", ".join(f"{k}={v!r}" for k, v in self.fields(True).items()) + ")"

    def replaced(self, **values):
        """This stop with some numbers (gap, restitution, stiffness, damping) replaced,
        each checked as the constructor does."""
        d = self.fields()
        d.pop("between", None)
        d.update(values)
        return Stop(between=self.between, **d)

    def coordinate(self):
        """(0-based mass indices of s, sign) with s = sign (x_j - x_i) or x_k, indices
        sorted: two stops on one coordinate have one key (for the model's checks)."""
        if self.mass is not None:
            return (self.mass - 1,), 1.0
        i, j = self.between
        return (min(i, j) - 1, max(i, j) - 1), (1.0 if i < j else -1.0)

    def constraint(self, n):
        """This stop as the :class:`symvi.model.Constraint` of a model of n masses: guard
        normal c = e_mass (or e_j - e_i), its side; rigid: the impulse along M^-1 c
        (impulse None), which is v_k+ = -r v_k- (eq. (2)) bit for bit where M is diagonal;
        elastic: stiffness and damping, no reset."""
        if self.mass is not None:
            c = tuple(1.0 if i == self.mass - 1 else 0.0 for i in range(n))
        else:
            i, j = self.between
            c = tuple(-1.0 if k == i - 1 else 1.0 if k == j - 1 else 0.0 for k in range(n))
        return Constraint(normal=c, gap=self.gap, restitution=self.restitution,
                          side=self.side, stiffness=self.stiffness, damping=self.damping)


def _index(field, k):
    """A 1-based mass index (an integer from 1 to N_MAX)."""
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
        raise ParameterError(field, _shown(k), "a 1-based mass index (integer >= 1)")
    if not 1 <= k <= N_MAX:
        raise ParameterError(field, _shown(k), f"a 1-based mass index (integer from 1 to {N_MAX})")
    return int(k)


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


def _tup(a):
    return tuple(tuple(float(x) for x in row) for row in np.asarray(a))


_PRESET = _preset.NAMES
#: what the dynamics take today (:meth:`Model.require_one_rigid_stop`)
_ONE_STOP = "one rigid stop on one mass (upper side)"
#: what the flow and the compiled run take today (:meth:`Model.require_rigid_stops`)
_RIGID_STOPS = "rigid stops, each on one mass or between two"


def _stop_list(stop, stops):
    """The model's stops as a tuple: ``stop=`` (one) or ``stops=`` (one or more)."""
    if (stop is None) == (stops is None):
        raise ParameterError("stop", _shown(stop if stops is None else stops),
                             "exactly one of stop=Stop(...) or stops=[Stop(...), ...]",
                             "both given" if stop is not None else "neither given")
    if stop is not None:
        if not isinstance(stop, Stop):
            raise ParameterError("stop", stop, "a symvi.Stop(mass=k, gap=b, restitution=r)")
        return (stop,)
    if isinstance(stops, Stop) or not isinstance(stops, (list, tuple)) or not stops:
        raise ParameterError("stops", _shown(stops), "a non-empty list of symvi.Stop")
    for k, s in enumerate(stops, 1):
        if not isinstance(s, Stop):
            raise ParameterError(f"stop[{k}]", _shown(s), "a symvi.Stop(mass=k, gap=b, ...)")
    return tuple(stops)


class Model:
    """A linear impact oscillator (see the module docstring); immutable, hashable.

    Between impacts ``M x'' + C x' + K x = P sin(omega t + tau)``; at a stop Newton's
    impact law (eq. (2) generalised), or a contact phase for an elastic stop.
    ``Model(mass=..., stiffness=..., forcing=..., damping=None, stop=Stop(...))``, or
    ``stops=[Stop(...), ...]`` for several stops (exactly one of ``stop`` and ``stops``);
    every argument is keyword-only and validated here; an error names the
    field and its valid range (``stop.gap`` for ``stop=``, ``stop[2].gap`` for ``stops=``).
    The forcing frequency omega is not a field of the model: every analysis takes it
    beside the model.  Luo & Xie's two-mass model, eq. (4), is :meth:`luo_xie`.

    Parameters
    ----------
    mass : array_like
        M: a list of N numbers (the diagonal) or an N x N matrix (a list of rows),
        1 <= N <= 8; symmetric positive definite with condition number <= 1e12, entries
        ``abs(m_ij) <= 1e6``.  An asymmetry of at most 1e-12 (relative) is removed.
    stiffness : array_like
        K: an N x N matrix, symmetric positive semi-definite: positive definite
        (condition number <= 1e12) or singular to rounding (a mass on no spring: a free
        mode); entries ``abs(k_ij) <= 1e6``.
    forcing : array_like
        P: the N forcing amplitudes, ``abs(P_i) <= 1e6``.
    stop : Stop, optional
        The one stop.  Exactly one of ``stop`` and ``stops``.
    stops : list of Stop, optional
        Several stops, in order (``stop[k]`` in parameter names is ``stops[k - 1]``); at
        most one upper and one lower stop per coordinate, with free space between them.
    damping : array_like, optional
        C: an N x N symmetric positive semi-definite matrix.  Default None: C = 0, as in
        the paper.
    nonlinear : list of str, optional
        Smooth nonlinear forces f_1..f_N added to the left-hand side (M x'' + C x' + K x +
        f(x, v) = P sin(omega t + tau), issue 28): one expression per mass in x1..xN,
        v1..vN and the named ``parameters`` (:mod:`symvi.model._forces`).  Default None:
        a linear model.  Only ``simulate`` runs such a model for now.
    parameters : dict, optional
        The named parameters of the forces, ``{"beta": 0.5}`` (finite values, names not
        clashing with a built-in one); only with ``nonlinear``.

    Raises
    ------
    ParameterError
        An argument out of its valid range, naming the field (``mass``, ``stiffness``,
        ``damping``, ``forcing``, ``stop.gap``, ``stop[2].mass``, ...): a wrong size or
        shape, a non-finite or non-numeric entry, an asymmetric or indefinite matrix, an
        ill-conditioned M, a mass index beyond N, two stops on one side of a coordinate.

    Examples
    --------
    >>> from symvi import Model, Stop
    >>> m = Model(mass=[1.0, 2.0], stiffness=[[2.0, -1.0], [-1.0, 1.0]],
    ...           forcing=[1.0, 0.0], damping=[[0.02, 0.0], [0.0, 0.02]],
    ...           stop=Stop(mass=1, gap=0.5, restitution=0.8))
    >>> m.n, m.dim
    (2, 4)
    >>> m.mass
    array([[1., 0.],
           [0., 2.]])
    """

    __slots__ = ("_M", "_K", "_C", "_P", "_stops", "_preset", "_arrays", "_hash", "_nl")

    def __init__(self, *, mass, stiffness, forcing, stop=None, stops=None, damping=None,
                 nonlinear=None, parameters=None, _preset=None):
        stops = _stop_list(stop, stops)
        M = _matrix("mass", mass, diag_ok=True)
        n = M.shape[0]
        K = _matrix("stiffness", stiffness, n)
        C = np.zeros((n, n)) if damping is None else _matrix("damping", damping, n)
        _definite("mass", M, semi=False)
        _definite("stiffness", K, semi=False, singular=True)
        _definite("damping", C, semi=True)
        P = _vector("forcing", forcing, n)
        if np.abs(P).max() > ABS_MAX:
            raise ParameterError("forcing", P.tolist(), f"|forcing[i]| <= {ABS_MAX:g}")
        _check_stops(stops, n, named=stop is None)
        if nonlinear is None and parameters:
            raise ParameterError("parameters", _shown(parameters), "named parameters of the "
                                 "nonlinear forces, only with nonlinear=[...]")
        forces = None if nonlinear is None else Forces.of(nonlinear, parameters, n)
        object.__setattr__(self, "_nl", forces)
        object.__setattr__(self, "_M", _tup(M))
        object.__setattr__(self, "_K", _tup(K))
        object.__setattr__(self, "_C", _tup(C))
        object.__setattr__(self, "_P", tuple(float(x) for x in P))
        object.__setattr__(self, "_stops", stops)
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
        """The first stop (the one stop of a one-stop model)."""
        return self._stops[0]

    @property
    def stops(self):
        """Every stop, in order (``stop[k]`` in parameter names is ``stops[k - 1]``)."""
        return self._stops

    @property
    def constraints(self):
        """The model's constraints (:class:`symvi.model.Constraint`), one per stop in order,
        indexed by a :class:`symvi.model.Signature`."""
        cs = self._arrays.get("constraints")
        if cs is None:
            cs = self._arrays["constraints"] = tuple(s.constraint(self.n) for s in self._stops)
        return cs

    def require_rigid_stops(self):
        """``self``, or the one-line ParameterError saying what the flow and the compiled run
        cannot handle yet: every stop rigid (on one mass or between two, either side;
        several stops allowed; a stop between masses is a coordinate of the flow's frame,
        :func:`symvi.flow.linear.frame_of`).  Called where a model enters the flow
        (:class:`LinearFlow`, the section); the analyses on the period-1 closed form ask
        :meth:`require_one_rigid_stop` too.  Elastic stops run in ``simulate`` through
        :mod:`symvi.flow.contact` and in the orbit analyses through
        :meth:`LinearFlow.contact`."""
        for k, s in enumerate(self._stops, start=1):
            if s.stiffness is not None:
                name = "stop" if len(self._stops) == 1 else f"stop[{k}]"
                raise ParameterError(name, s, _RIGID_STOPS, "an elastic stop is not supported "
                                     "by this analysis (simulate, orbit, continue, curve, "
                                     "hopf, sweep and plane run it)")
        return self

    @property
    def nonlinear(self):
        """The smooth nonlinear forces f_1..f_N (SymPy expressions in x1..xN, v1..vN and the
        named parameters), added to the left-hand side: M x'' + C x' + K x + f(x, v) =
        P sin(omega t + tau) (issue 28); None for a linear model."""
        return None if self._nl is None else self._nl.exprs(self.n)

    @property
    def linear_part(self):
        """The model without its nonlinear forces: its constraints, frames and section
        layouts are the linear part's (issue 28)."""
        if self._nl is None:
            return self
        from .parameters import _copy
        return _copy(self, preset=self._preset, _nl=None)

    def require_linear(self):
        """``self``, or the one-line ParameterError of an analysis that rests on the exact
        linear flow: a model with nonlinear forces runs in simulate, orbits, continuation and
        special points (the series of :mod:`symvi.flow.nljet`), not yet in the analyses that
        call this (issue 28).  Called where a model enters the linear flow
        (:class:`symvi.flow.linear.LinearFlow`)."""
        if self._nl is not None:
            raise ParameterError("model", "nonlinear", "a linear model: with nonlinear "
                                 "forces this analysis is a later step of issue 28 (simulate, "
                                 "orbit, continue, curve, hopf, sweep and plane run them)")
        return self

    @property
    def elastic(self):
        """Whether a stop is elastic (a contact phase: :mod:`symvi.flow.contact`)."""
        return any(s.stiffness is not None for s in self._stops)

    @property
    def one_rigid_stop(self):
        """Whether the orbit analyses take this model: one rigid upper stop on one mass."""
        return len(self._stops) == 1 and self._stops[0].plain

    def require_one_rigid_stop(self):
        """``self``, or the one-line ParameterError saying what the analyses built on the
        period-1 closed form cannot handle: they take one rigid upper stop on one mass.  Called where a model enters them (period-1 orbits and the certified
        Hopf scan, the Python map, the single-section jets, the mpmath simulation); the
        flow asks :meth:`require_rigid_stops`, and the n-p orbits, continuation, curves,
        Lyapunov exponents, the classifier and the planes take several rigid stops."""
        if self.one_rigid_stop:
            return self
        stops = self._stops
        if len(stops) > 1:
            raise ParameterError("stops", len(stops), _ONE_STOP, "several stops have no "
                                 "period-1 closed form, which this analysis rests on "
                                 "(orbit, continue, curve, hopf, simulate, sweep and plane "
                                 "take them)")
        s = stops[0]
        what = ("an elastic stop" if s.stiffness is not None else
                "a stop between two masses" if s.between is not None else "a lower stop")
        raise ParameterError("stop", s, _ONE_STOP,
                             f"{what} has no period-1 closed form, which this analysis rests "
                             "on (orbit, continue, curve, hopf, simulate, sweep and plane "
                             "take it)")

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
        """r = 1, no contact damping, C = 0 and no nonlinear force of a velocity: the
        impact map preserves volume (multipliers may sit on the unit circle over whole
        intervals, and (H3) has no meaning)."""
        return all(s.restitution == 1.0 if s.stiffness is None else not s.damping
                   for s in self._stops) and not self.damped and (
            self._nl is None or self._nl.velocity_free(self.n))

    @property
    def preset(self):
        """``{"name": "luo_xie", "mu_m": ..., ...}`` for the paper's model, else None."""
        return None if self._preset is None else dict(self._preset)

    def key(self):
        """A stable tuple of every number, for hashing and caching."""
        s = self._stops
        if len(s) == 1 and s[0].plain:
            key = (self._M, self._K, self._C, self._P) + s[0].key()
        else:
            key = (self._M, self._K, self._C, self._P, tuple(t.key() for t in s))
        return key if self._nl is None else key + ("nonlinear",) + self._nl.key(self.n)

    def __eq__(self, other):
        return isinstance(other, Model) and self.key() == other.key()

    def __hash__(self):
        return self._hash

    def __repr__(self):
        if self._preset is not None:
            p = self._preset
            return ("Model.luo_xie(" + ", ".join(f"{k}={p[k]!r}" for k in _PRESET) + ")")
        nl = "" if self._nl is None else (f", nonlinear={list(self._nl.texts)!r}, "
                                          f"parameters={dict(self._nl.parameters)!r}")
        return (f"Model(mass={[list(r) for r in self._M]}, stiffness={[list(r) for r in self._K]}, "
                f"damping={[list(r) for r in self._C]}, forcing={list(self._P)}, "
                + (f"stop={self._stops[0]!r}" if len(self._stops) == 1 else
                   f"stops={list(self._stops)!r}") + nl + ")")

    def as_dict(self):
        """The model as plain data (the ``[model]`` and ``[stop]`` tables of a model file):
        ``stop`` is one table for a one-stop model whose stop is today's (rigid, upper, on
        one mass), else a list of tables (``[[stop]]``)."""
        s = self._stops
        d = {"mass": [list(r) for r in self._M], "stiffness": [list(r) for r in self._K],
             "damping": [list(r) for r in self._C], "forcing": list(self._P),
             "stop": s[0].fields(True) if len(s) == 1 and s[0].plain else [t.fields() for t in s]}
        if self._preset is not None:
            d["preset"] = dict(self._preset)
        if self._nl is not None:
            d["nonlinear"] = list(self._nl.texts)
            d["parameters"] = dict(self._nl.parameters)
        return d

    # ---- the paper's preset ----------------------------------------------------
    @classmethod
    def luo_xie(cls, mu_m, mu_k, f2, b, r):
        """The two-mass model of Luo & Xie (1998), eq. (4).

        M = diag(1, mu_m), K = [[1, -1], [-1, 1 + mu_k]], P = (1 - f2, f2), stop on
        mass 1 at b.  No damping (C = 0); one rigid upper stop on mass 1.  The model
        remembers the five numbers (:attr:`preset`), so ``mu_m``, ``mu_k``, ``f2``,
        ``b``, ``r`` are named parameters of it too.  The paper's :class:`symvi.Params`
        gives the same model (:meth:`symvi.Params.as_model`).

        Parameters
        ----------
        mu_m : float
            Mass ratio m2 / m1, 1e-6 <= mu_m <= 1e6.
        mu_k : float
            Stiffness ratio k2 / k1 (k1 couples the masses, k2 holds mass 2 to the
            frame), 1e-6 <= mu_k <= 1e6.
        f2 : float
            Share of the forcing on mass 2 (mass 1 gets 1 - f2), ``abs(f2) <= 1e6``.
        b : float
            Gap between mass 1 at rest and the stop, ``abs(b) <= 1e6``.
        r : float
            Coefficient of restitution, 0 < r <= 1.

        Returns
        -------
        Model
            The two-mass model of eq. (4).

        Raises
        ------
        ParameterError
            A value out of its range, naming it (``mu_m``, ``mu_k``, ``f2``, ``b``,
            ``r``).

        Examples
        --------
        >>> from symvi import Model
        >>> m = Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
        >>> m.stiffness
        array([[ 1., -1.],
               [-1.,  6.]])
        >>> m.stop
        Stop(mass=1, gap=1.5, restitution=0.8)
        """
        p = _preset.values(mu_m, mu_k, f2, b, r)      # the preset's ranges and messages
        return cls(mass=[1.0, p["mu_m"]], stiffness=[[1.0, -1.0], [-1.0, 1.0 + p["mu_k"]]],
                   forcing=[1.0 - p["f2"], p["f2"]],
                   stop=Stop(mass=1, gap=p["b"], restitution=p["r"]),
                   _preset={"name": "luo_xie", **p})

    @classmethod
    def of(cls, system):
        """The Model of ``system``: a Model itself, or what its ``as_model()`` gives.

        ``system`` itself when it is a Model, else the Model it presents through its
        ``as_model()`` (the paper's :class:`symvi.Params` does: its ``Model.luo_xie``).  The
        layers below the paper take Models only; this is where a client's object becomes one.

        Parameters
        ----------
        system : Model or object
            A Model, or an object whose class has an ``as_model()`` method returning one.

        Returns
        -------
        Model

        Raises
        ------
        ParameterError
            ``model``: ``system`` is neither a Model nor has an ``as_model()`` that returns
            one.

        Examples
        --------
        >>> from symvi import Model, Params
        >>> p = Params(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
        >>> Model.of(p) == Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
        True
        """
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
        stops = self._stops
        names = ["gap"] + (["restitution"] if stops[0].stiffness is None else [])
        if len(stops) > 1 or not stops[0].plain:
            for k, s in enumerate(stops, 1):
                names += [f"stop[{k}].{f}" for f in
                          (("gap", "restitution") if s.stiffness is None else
                           ("gap", "stiffness", "damping"))]
        names += [f"mass[{i + 1},{j + 1}]" for i in range(n) for j in range(i, n)]
        names += [f"stiffness[{i + 1},{j + 1}]" for i in range(n) for j in range(i, n)]
        names += [f"damping[{i + 1},{j + 1}]" for i in range(n) for j in range(i, n)]
        names += [f"forcing[{i + 1}]" for i in range(n)]
        if self._preset is not None:
            names = list(_PRESET) + names
        if self._nl is not None:
            names += list(self._nl.names)
        return names

    def parameter(self, name):
        """The :class:`symvi.model.parameters.Parameter` called ``name`` (``omega`` included).

        Parsed once per model shape (the objects are cached), then it reads, sets and
        differentiates that parameter on any model of this shape.  A bad name raises the
        one-line ParameterError naming the valid names.

        Parameters
        ----------
        name : str or Parameter
            ``omega``; ``gap``, ``restitution`` (the first stop's); ``stop[k].gap``,
            ``stop[k].restitution``, ``stop[k].stiffness``, ``stop[k].damping``;
            ``mass[i]`` (= ``mass[i,i]``), ``mass[i,j]``, ``stiffness[i,j]``,
            ``damping[i,j]``, ``forcing[i]`` (1-based indices up to N); on the paper's
            preset also ``mu_m``, ``mu_k``, ``f2``, ``b``, ``r``.  A Parameter is
            returned as this model's.

        Returns
        -------
        Parameter
            A lens on the point (model, omega): ``get``, ``set``, ``apply``,
            ``tangent``, ``is_forcing_frequency``.

        Raises
        ------
        ParameterError
            ``parameter``: not a name of this model (the message lists the valid ones),
            or a ``stop[k]`` field the model's stop k does not have.

        Examples
        --------
        >>> from symvi import Model
        >>> m = Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
        >>> m.parameter("omega").is_forcing_frequency
        True
        >>> m.parameter("stiffness[2,2]").get(m)
        6.0
        """
        if self._nl is not None and str(name) in self._nl.names:
            return NamedParameter(str(name), "named", n=len(self._P))
        try:
            par = _parse_parameter(name, len(self._P), self._preset is not None)
        except ParameterError as exc:
            if self._nl is None or not self._nl.names:
                raise
            # the forces' named parameters are names of this model too
            raise ParameterError(exc.name, exc.value, f"{exc.valid}, or a parameter of the "
                                 f"forces: {', '.join(self._nl.names)}", exc.detail) from None
        if isinstance(par, StopParameter):
            par.stop_of(self)                     # the model has that stop, of that kind
        return par

    def value(self, name):
        """The value of a named parameter (not omega, which is not a field of the model).

        Parameters
        ----------
        name : str
            A parameter name of :meth:`parameter`, except ``omega``.

        Returns
        -------
        float

        Raises
        ------
        ParameterError
            A name that is not a parameter of this model, or ``omega``.

        Examples
        --------
        >>> from symvi import Model
        >>> m = Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
        >>> m.value("mu_k"), m.value("gap"), m.value("forcing[1]")
        (5.0, 1.5, 1.0)
        """
        par = self.parameter(name)
        if par.is_forcing_frequency:
            par.apply(self, None)                 # refuses: omega lives beside the model
        return par.get(self)

    def with_(self, **changes):
        """A copy with named parameters changed.

        E.g. ``model.with_(**{"forcing[1]": 0.3})`` or ``model.with_(mu_m=3)`` on the
        preset.  Validated like the constructor (one change: :meth:`Parameter.apply`,
        which checks only what the change can break).  Changing a preset number
        (``mu_m``, ...) rebuilds :meth:`luo_xie`; changing a matrix entry of a preset
        model gives a plain Model.

        Parameters
        ----------
        **changes : float
            New values by parameter name (see :meth:`parameter`; not ``omega``).
            Setting an off-diagonal entry sets its mirror too.  None: the model itself.

        Returns
        -------
        Model

        Raises
        ------
        ParameterError
            A name that is not a parameter of this model, ``omega``, or a value that
            leaves the model invalid (a non-finite number, an indefinite matrix, a
            restitution outside (0, 1], ...), naming it.

        Examples
        --------
        >>> from symvi import Model
        >>> m = Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
        >>> m.with_(b=1.2).value("gap")
        1.2
        >>> m.with_(**{"forcing[2]": 0.3}).forcing
        array([1. , 0.3])
        """
        if not changes:
            return self
        if len(changes) == 1:
            (name, v), = changes.items()
            return self.parameter(name).apply(self, v)
        pars = {name: self.parameter(name) for name in changes}
        named = {k: v for k, v in changes.items() if isinstance(pars[k], NamedParameter)}
        if named:                                 # the forces' parameters, set last
            new = self.with_(**{k: v for k, v in changes.items() if k not in named})
            for name, v in named.items():
                new = pars[name].apply(new, v)
            return new
        preset = dict(self._preset) if self._preset else None
        if changes and all(isinstance(p, StopParameter) for p in pars.values()):
            new = self
            for name, v in changes.items():
                new = pars[name].apply(new, v)
            return new
        pre = {k: v for k, v in changes.items() if isinstance(pars[k], PresetParameter)
               or (k in _PRESET and preset is not None)}
        if pre:
            vals = {k: preset[k] for k in _PRESET}
            vals.update(pre)
            base = Model.luo_xie(**vals)
            rest = {k: v for k, v in changes.items() if k not in pre}
            return base.with_(**rest) if rest else base
        M, K, C = (np.array(x) for x in (self._M, self._K, self._C))
        P = np.array(self._P)
        on_stops = {}
        for name, v in changes.items():
            par = pars[name]
            if par.is_forcing_frequency:
                par.apply(self, v)                # refuses: omega lives beside the model
            kind, i, j = par.kind, par.i, par.j
            v = _finite(name, v)
            if isinstance(par, StopParameter):
                on_stops[name] = v                # set on the new model, below
            elif kind == "forcing":
                P[i] = v
            else:
                A = {"mass": M, "stiffness": K, "damping": C}[kind]
                A[i, j] = A[j, i] = v
        nl = self._nl
        new = Model(mass=M, stiffness=K, damping=C, forcing=P, stops=self._stops,
                    **({} if nl is None else {"nonlinear": list(nl.texts),
                                              "parameters": dict(nl.parameters)}))
        for name, v in on_stops.items():
            new = pars[name].apply(new, v)
        return new

    def tangent(self, name):
        """d(M, C, K, P, b, r) / d(name): exact derivative of the model data, as a
        :class:`Tangent` (:meth:`Parameter.tangent`).  ``omega`` has the zero tangent here
        (it enters the map directly, not through the model)."""
        return self.parameter(name).tangent(self)
