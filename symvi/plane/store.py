"""The zarr store of a plane: an xarray Dataset, created whole, then filled block by block.

Layout (zarr format 2, whose fixed-width strings are stable)::

    dims      (<y name>, <x name>)           coordinates: the parameter values
    attractor str    period-k | circle | doubled-torus | chaos | no-impact | sticking |
                     escape | grazing ("" = not computed yet)
    period, impacts_per_orbit   int32        k forcing periods, q impacts (0 if not periodic)
    lyapunov, rotation, impacts_per_period, max_velocity   float64 (NaN: not defined)
    stop      str    how the run ended (symvi.simulations.simulation stop names)
    own_start bool   the point started from its own period-1 orbit
    done      bool (<y name>)                rows whose block is written

A block's data are written before its ``done`` flags, so a run killed at any moment
leaves only blocks that are complete and flagged, or unflagged (recomputed on restart).
The store is created under a temporary name and renamed into place: an existing path is
never overwritten.
"""
import json
import os
import shutil
import tempfile

import numpy as np

from .._io import current_umask
from ..errors import ParameterError

#: version of this layout, in the attrs
FORMAT = 1
#: string width of ``attractor`` and ``stop``
LABEL_WIDTH = 16

FLOATS = ("lyapunov", "rotation", "impacts_per_period", "max_velocity")
INTS = ("period", "impacts_per_orbit")
STRINGS = ("attractor", "stop")
#: every (y, x) variable, as a block of rows carries them
GRID_VARS = (*FLOATS, *INTS, *STRINGS, "own_start")

DESCRIPTIONS = {
    "attractor": "kind of attractor reached from the point's start: period-k (a periodic "
                 "orbit of k forcing periods), circle (an invariant circle of P), "
                 "doubled-torus (a quasi-periodic attractor that is not one closed curve "
                 "about its centre, as after a torus doubling), chaos (largest exponent "
                 "> 0), no-impact, sticking (chatter or sticking), escape (unbounded or "
                 "non-finite), grazing (a grazing contact ended the run)",
    "period": "forcing periods k of a periodic attractor (0 otherwise)",
    "impacts_per_orbit": "impacts q in one period of a periodic attractor (0 otherwise)",
    "lyapunov": "largest Lyapunov exponent of the impact map P, natural log per impact, "
                "over the kept impacts (NaN if the run stopped)",
    "rotation": "rotation number in [0, 1/2]: mean angle advance per impact about the "
                "attractor's centre in its two leading principal directions, over 2 pi "
                "(NaN for period-1, period-2 and stopped runs)",
    "impacts_per_period": "impacts per forcing period over the kept impacts",
    "max_velocity": "largest impact speed |v_k-| over the kept impacts",
    "stop": "how the run ended: completed, grazing, chatter, sticking, no-impact, non-finite",
    "own_start": "the run started from the point's own period-1 orbit (else from a "
                 "neighbour's, the previous point's attractor with --follow, or a generic start)",
    "done": "the row's block is computed and written",
}


def _template(spec, command, version):
    import xarray as xr
    ny, nx = spec.shape
    yn, xn = spec.y.name, spec.x.name
    dims = (yn, xn)
    data = {}
    for v in FLOATS:
        data[v] = (dims, np.full((ny, nx), np.nan))
    for v in INTS:
        data[v] = (dims, np.zeros((ny, nx), dtype=np.int32))
    for v in STRINGS:
        data[v] = (dims, np.full((ny, nx), "", dtype=f"<U{LABEL_WIDTH}"))
    data["own_start"] = (dims, np.zeros((ny, nx), dtype=bool))
    data["done"] = ((yn,), np.zeros(ny, dtype=bool))
    ds = xr.Dataset(data, coords={yn: spec.y.values, xn: spec.x.values})
    for v, text in DESCRIPTIONS.items():
        ds[v].attrs["description"] = text
    ds.attrs.update(attrs_of(spec, command, version))
    return ds


def attrs_of(spec, command, version):
    """The store's attrs: what fixes the results (``spec``), and who made them."""
    from ..model import dumps
    return {"symvi_plane_format": FORMAT, "spec": spec.text(),
            "model": dumps(spec.model),
            "preset": spec.as_dict()["model"] if spec.model.preset else "",
            "symvi_version": version, "command": command or "",
            "x": spec.x.name, "y": spec.y.name, "impacts": spec.impacts,
            "transient": spec.transient, "follow": int(bool(spec.follow)),
            "omega": "" if spec.omega is None else spec.omega}


class PlaneStore:
    """A plane store on disk: create it or reopen it for the same run, write blocks."""

    def __init__(self, path, spec):
        self.path, self.spec = os.fspath(path), spec

    def check(self):
        """True if the path holds this run's store, False if it is free; raise (naming
        --out) if it holds anything else."""
        if not os.path.lexists(self.path):
            return False
        self._check_same()
        return True

    @classmethod
    def read(cls, path):
        """An existing store, its spec read from its attrs (for plotting and reading)."""
        from .grid import PlaneSpec
        path = os.fspath(path)
        valid = "a zarr store written by symvi plane"
        if not os.path.isdir(path):
            raise ParameterError("store", path, valid, "no such directory")
        fmt, spec = _stored(path, "store", valid)
        if fmt != FORMAT:
            raise ParameterError("store", path, valid, f"store format {fmt}, this symvi "
                                 f"reads {FORMAT}")
        return cls(path, PlaneSpec.from_dict(spec))

    def create(self, command, version):
        """Write the empty store (all blocks to do) under a temporary name, then rename."""
        ds = _template(self.spec, command, version)
        k = self.spec.rows_per_task
        enc = {v: {"chunks": (k, self.spec.x.n)} for v in GRID_VARS}
        enc["done"] = {"chunks": (k,)}
        folder = os.path.dirname(os.path.abspath(self.path))
        os.makedirs(folder, exist_ok=True)
        tmp = tempfile.mkdtemp(prefix=".tmp-plane-", dir=folder)
        try:
            ds.to_zarr(tmp, mode="w", zarr_format=2, encoding=enc, consolidated=True)
            mode = 0o777 & ~current_umask()
            os.chmod(tmp, mode)        # mkdtemp's 0700 would make the store private
            os.rename(tmp, self.path)
        finally:
            if os.path.exists(tmp):
                shutil.rmtree(tmp)

    def _check_same(self):
        want = json.loads(self.spec.text())
        fmt, have = _stored(self.path, "--out", "a new path, or a plane store of the same "
                            "run to resume")
        if fmt != FORMAT:
            raise ParameterError("--out", self.path, "a new path, or a plane store of the "
                                 "same run", f"store format {fmt}, this symvi writes {FORMAT}")
        diff = sorted(k for k in set(want) | set(have) if want.get(k) != have.get(k))
        if diff:
            raise ParameterError("--out", self.path, "a new path, or the store of the same "
                                 "run (same model, axes, --impacts, --transient, --follow) "
                                 "to resume it", "it holds another run; differs in: "
                                 + ", ".join(diff))

    def done(self):
        """Bool per row: blocks already written."""
        import zarr
        return np.asarray(zarr.open_group(self.path, mode="r")["done"][:], dtype=bool)

    def missing_blocks(self):
        d = self.done()
        return [(r0, r1) for r0, r1 in self.spec.blocks() if not d[r0:r1].all()]

    def write(self, r0, r1, block):
        """Write the arrays of rows r0 .. r1-1 (``block``: name -> (r1 - r0, nx)), then
        their done flags."""
        import zarr
        g = zarr.open_group(self.path, mode="r+", zarr_format=2)
        for name in GRID_VARS:
            g[name][r0:r1, :] = block[name]
        g["done"][r0:r1] = True

    def dataset(self):
        """The store as an xarray Dataset (loaded)."""
        import xarray as xr
        with xr.open_zarr(self.path, consolidated=True) as ds:
            return ds.load()


def _stored(path, name, valid):
    """(format, spec dict) from a store's attrs; anything unreadable is refused naming
    ``name`` (the store is only read)."""
    import zarr
    try:
        g = zarr.open_group(path, mode="r")
        return g.attrs.get("symvi_plane_format"), json.loads(g.attrs["spec"])
    except Exception:   # noqa: BLE001 -- any unreadable path: one clear line, touch nothing
        raise ParameterError(name, path, valid, "it is not a symvi plane store") from None
