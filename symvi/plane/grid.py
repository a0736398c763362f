"""The grid of a parameter-plane study: two named axes over one model, and the inputs of
the compiled batches (constants and start points) for a block of its rows.

A plane is ``y`` rows by ``x`` columns; the point (i, j) is the model with
``y.name = y.values[i]`` and ``x.name = x.values[j]`` (``omega`` is the forcing
frequency, any other name a named parameter of :meth:`symvi.Model.parameter_names`).
Everything here is plain data, so a :class:`PlaneSpec` can be shipped to a Dask worker
as the text of its model file.
"""
import functools
import json
import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, SymviError
from ..simulations.classifier import MIN_KEPT, min_kept
from ..simulations.simulation import symbol_count

#: points per Dask task aimed at: enough work to hide the scheduling cost (~1 ms a task)
POINTS_PER_TASK = 1024

#: largest grid side and number of points (a plane beyond that is split by the user)
MAX_SIDE = 100_000
MAX_POINTS = 10 ** 8


@dataclass(frozen=True)
class Axis:
    """One axis: ``n`` values of parameter ``name`` from ``lo`` to ``hi`` (inclusive)."""

    name: str
    lo: float
    hi: float
    n: int

    @functools.cached_property
    def values(self):
        return np.linspace(self.lo, self.hi, self.n)

    def text(self):
        # a store's form (resumed stores compare it): NAME:LO:HI:N
        return f"{self.name}:{self.lo!r}:{self.hi!r}:{self.n}"


def parse_axis(text, flag):
    """``NAME=LO:HI:N`` (the command line's one range form) or ``NAME:LO:HI:N`` (the
    stores' form, and the command line's until issue 26) -> :class:`Axis`; an error names
    ``flag`` and the valid form."""
    form = "NAME=LO:HI:N with numbers LO < HI and an integer N >= 2 (or N = 1 and LO = HI)"
    head, eq, rest = str(text).partition("=")
    parts = [head, *rest.split(":")] if eq else str(text).rsplit(":", 3)
    if len(parts) != 4 or not parts[0].strip():
        raise ParameterError(flag, text, form)
    name = parts[0].strip()
    try:
        lo, hi = float(parts[1]), float(parts[2])
        n = int(parts[3])
    except ValueError:
        raise ParameterError(flag, text, form) from None
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ParameterError(flag, text, form, "LO and HI must be finite")
    if not 1 <= n <= MAX_SIDE:
        raise ParameterError(flag, text, form, f"N must be in 1 .. {MAX_SIDE}")
    if (n == 1 and lo != hi) or (n > 1 and not lo < hi):
        raise ParameterError(flag, text, form)
    return Axis(name, lo, hi, n)


@dataclass(frozen=True)
class PlaneSpec:
    """What a plane computes: the model, the axes, the run lengths, the start rule.

    ``omega`` is the forcing frequency where neither axis is ``omega``.
    """

    model: object
    x: Axis
    y: Axis
    impacts: int
    transient: int
    follow: bool = False
    omega: float = None
    chunk_rows: int = None     # rows per task and zarr chunk; default from the grid

    def __post_init__(self):
        _check_spec(self)

    @property
    def shape(self):
        return (self.y.n, self.x.n)

    @property
    def rows_per_task(self):
        """Rows in one task and one zarr chunk: ``chunk_rows``, else a function of the grid
        only (about POINTS_PER_TASK points, at least 8 tasks), never of the workers, so
        that a resumed run finds the same chunks."""
        if self.chunk_rows is not None:
            return self.chunk_rows
        rows = max(1, math.ceil(POINTS_PER_TASK / self.x.n))
        return max(1, min(rows, self.y.n // 8 or 1))

    def blocks(self):
        """Row ranges (r0, r1) of the tasks, in order."""
        k = self.rows_per_task
        return [(r0, min(r0 + k, self.y.n)) for r0 in range(0, self.y.n, k)]

    def as_dict(self):
        """Plain data (JSON): everything that fixes the results, nothing about workers."""
        return {"model": model_text(self.model), "x": self.x.text(), "y": self.y.text(),
                "impacts": self.impacts, "transient": self.transient,
                "follow": bool(self.follow), "omega": self.omega,
                "chunk_rows": self.rows_per_task}

    def text(self):
        """The canonical JSON of :meth:`as_dict` (sorted keys): tasks, store attrs, keys."""
        return json.dumps(self.as_dict(), sort_keys=True)

    @classmethod
    def from_dict(cls, d):
        return cls(model=model_from_text(d["model"]), x=parse_axis(d["x"], "x"),
                   y=parse_axis(d["y"], "y"), impacts=d["impacts"],
                   transient=d["transient"], follow=d["follow"], omega=d["omega"],
                   chunk_rows=d["chunk_rows"])

    def point(self, i, j):
        """(model, omega) at row i, column j."""
        vals, omega = {}, self.omega
        for ax, v in ((self.y, self.y.values[i]), (self.x, self.x.values[j])):
            if self.model.parameter(ax.name).is_forcing_frequency:
                omega = float(v)
            else:
                vals[ax.name] = float(v)
        return (self.model.with_(**vals) if vals else self.model), omega


def _check_spec(spec):
    from ..model import Model
    if not isinstance(spec.model, Model):
        raise ParameterError("model", type(spec.model).__name__, "a symvi.Model")
    names = ["omega"] + spec.model.parameter_names()
    for flag, ax in (("--x", spec.x), ("--y", spec.y)):
        if ax.name not in names:
            raise ParameterError(flag, ax.name, "omega or a named parameter of the model: "
                                 + ", ".join(names))
    if spec.x.name == spec.y.name:
        raise ParameterError("--y", spec.y.name, f"a parameter other than --x ({spec.x.name})")
    if spec.x.n * spec.y.n > MAX_POINTS:
        raise ParameterError("--x", spec.x.text(), f"at most {MAX_POINTS} points in all")
    # the classifier's own floor on kept impacts (4 per stop, per elastic stop's entries
    # and exits), checked here before any store exists
    for flag, value, lo in (("--impacts", spec.impacts, min_kept(symbol_count(spec.model))),
                            ("--transient", spec.transient, 0)):
        if not (isinstance(value, (int, np.integer)) and lo <= value <= 10 ** 7):
            raise ParameterError(flag, value, f"an integer in {lo} .. 10000000"
                                 + (f" ({MIN_KEPT} per stop" + (", entries and exits counted "
                                    "apart" if spec.model.elastic else "") + ")"
                                    if lo > MIN_KEPT else ""))
    if spec.chunk_rows is not None and not (isinstance(spec.chunk_rows, (int, np.integer))
                                            and 1 <= spec.chunk_rows <= spec.y.n):
        raise ParameterError("--chunk-rows", spec.chunk_rows, f"an integer in 1 .. {spec.y.n}")
    if "omega" not in (spec.x.name, spec.y.name):
        if spec.omega is None:
            raise ParameterError("--omega", None, "a forcing frequency (neither axis is omega)")
    elif spec.omega is not None:
        raise ParameterError("--omega", spec.omega, "not given when an axis is omega")
    _check_ranges(spec)


def _check_ranges(spec):
    """Every model and frequency of the grid is valid: the ends of each parameter axis
    (the valid sets are intervals or convex), every omega against every row's modes."""
    from ..flow.linear import LinearFlow
    axes = [(f, a, spec.model.parameter(a.name)) for f, a in (("--x", spec.x), ("--y", spec.y))]
    par = [(f, a) for f, a, p in axes if not p.is_forcing_frequency]
    om = [(f, a) for f, a, p in axes if p.is_forcing_frequency]
    for flag, ax in par:
        for v in (ax.lo, ax.hi):
            try:
                spec.model.with_(**{ax.name: v})
            except SymviError as exc:
                raise ParameterError(flag, ax.text(), f"values of {ax.name} the model accepts",
                                     str(exc)) from None
    omegas = om[0][1].values if om else [spec.omega]
    flag = om[0][0] if om else "--omega"
    if spec.model.nonlinear is not None:     # no modes to resonate: the range only
        from ..flow.linear import check_range
        for w in omegas:
            check_range(w, name=flag)
        return
    # the modes depend on the parameter axis (at most one): check each of its models
    rows = [spec.model] if not par else [spec.model.with_(**{par[0][1].name: float(v)})
                                        for v in par[0][1].values]
    seen = set()
    for m in rows:
        # with elastic stops every contact phase too (LinearFlow.contact: K_S, C_S)
        flows = ([LinearFlow.contact(m)] + [LinearFlow.contact(m, S) for S in _contact_sets(m)]
                 if m.elastic else [LinearFlow.of(m)])
        key = tuple(tuple(np.round(np.asarray(f.lam, dtype=complex), 14)) for f in flows)
        if key in seen:
            continue
        seen.add(key)
        for w in omegas:
            for f in flows:
                try:
                    f.check_omega(w, name=flag, warn=False)
                except SymviError as exc:
                    raise ParameterError(flag, float(w), "forcing frequencies of the grid "
                                         "away from the model's natural frequencies"
                                         + (" (and its contact phases')" if m.elastic
                                            else ""), str(exc)) from None


def _contact_sets(model):
    """Every non-empty set of the model's elastic stops (a contact phase of the walk)."""
    from itertools import combinations
    el = [i for i, c in enumerate(model.constraints) if c.kind == "elastic"]
    return [S for r in range(1, len(el) + 1) for S in combinations(el, r)]


def block_inputs(spec, r0, r1):
    """Constants (m, L) and start points (m, 2N) of rows r0 .. r1-1, row-major.

    A start is the point's admissible period-1 orbit plus the default perturbation
    (:func:`symvi.simulations.simulation.start_point`); where a point has none, the nearest
    point of its row that has one lends its start; where no point of the row has one,
    the model's generic start (v_k+ = -1, the other coordinates 0) is used.  A model with
    no period-1 closed form (several stops, a lower one) starts every point from
    :func:`symvi.simulations.simulation.default_start` on its first stop (has_orbit
    False).  Returns (C, Y0, has_orbit (m,) bool).
    """
    from ..flow import compiled as cf
    from ..simulations.simulation import default_start, start_point
    nx, dim = spec.x.n, spec.model.dim
    if not spec.model.one_rigid_stop:
        pts = [spec.point(i, j) for i in range(r0, r1) for j in range(nx)]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")       # as below: the grid was checked
            C = [cf.constants(model, omega) for model, omega in pts]
        Y0 = [default_start(model, omega) for model, omega in pts]
        return cf.pack(C), np.array(Y0, dtype=np.float64), np.zeros(len(pts), dtype=bool)
    generic = np.zeros(dim)
    generic[0] = -1.0
    C, Y0, have = [], [], []
    with warnings.catch_warnings():
        # near-resonance warnings: the grid was checked; per-point messages would flood
        warnings.simplefilter("ignore")
        for i in range(r0, r1):
            ys = []
            for j in range(nx):
                model, omega = spec.point(i, j)
                C.append(cf.constants(model, omega))
                try:
                    ys.append(np.array(start_point(model, omega)[0]))
                except SymviError:          # no admissible period-1 orbit here
                    ys.append(None)
            ok = [j for j, y in enumerate(ys) if y is not None]
            for j in range(nx):
                if ys[j] is not None:
                    Y0.append(ys[j])
                elif ok:
                    Y0.append(ys[min(ok, key=lambda k: (abs(k - j), k))])
                else:
                    Y0.append(generic)
                have.append(ys[j] is not None)
    return cf.pack(C), np.array(Y0, dtype=np.float64), np.array(have)


def model_text(model):
    """The model as text: the paper preset's five values (its parameter names stay
    usable), else the model file (:func:`symvi.model.dumps`)."""
    from ..model import dumps
    if model.preset is not None:
        return json.dumps({k: v for k, v in model.preset.items() if k != "name"},
                          sort_keys=True)
    return dumps(model)


def model_from_text(text):
    """Inverse of :func:`model_text`."""
    import tomllib

    from ..model import Model, model_from_dict
    if text.lstrip().startswith("{"):
        return Model.luo_xie(**json.loads(text))
    return model_from_dict(tomllib.loads(text), "model")
