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
never overwritten.  A run holds ``<store>.lock`` (an advisory ``flock`` with its pid in
it) while it writes, so a second run on the same store is refused; the kernel drops the
lock of a process that dies, so a killed run's leftover lock file is simply taken over.

A store is read only after its layout is checked against its own spec (every variable
present with the shape and dtype above, the ``done`` flags readable), so a damaged or
forged store is refused with one line naming it instead of failing halfway.
"""
import contextlib
import errno
import json
import os
import shutil
import stat
import tempfile

import numpy as np

from .._io import current_umask, lstat_or_none
from ..errors import ParameterError, SymviError

#: version of this layout, in the attrs
FORMAT = 1
#: string width of ``attractor`` and ``stop``
LABEL_WIDTH = 16

FLOATS = ("lyapunov", "rotation", "impacts_per_period", "max_velocity")
INTS = ("period", "impacts_per_orbit")
STRINGS = ("attractor", "stop")
#: every (y, x) variable, as a block of rows carries them
GRID_VARS = (*FLOATS, *INTS, *STRINGS, "own_start")
#: the dtype of each variable (the layout's contract, checked on every read)
DTYPES = {**{v: np.dtype(np.float64) for v in FLOATS}, **{v: np.dtype(np.int32) for v in INTS},
          **{v: np.dtype(f"<U{LABEL_WIDTH}") for v in STRINGS},
          "own_start": np.dtype(bool), "done": np.dtype(bool)}

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
        path = os.fspath(path)
        # "P.zarr/" is the folder P.zarr (the rename that creates it takes no trailing /)
        self.path, self.spec = path.rstrip(os.sep) or path, spec

    def check(self):
        """True if the path holds this run's store, False if it is free; raise (naming
        --out) if it holds anything else."""
        if not os.path.lexists(self.path):
            return False
        self._check_same()
        return True

    @classmethod
    def read(cls, path):
        """An existing store, its spec read from its attrs (for plotting and reading); a
        store whose layout does not match its spec is refused naming it."""
        from .grid import PlaneSpec
        path = os.fspath(path)
        valid = "a zarr store written by symvi plane"
        if not os.path.isdir(path):
            raise ParameterError("store", path, valid, "not a folder" if os.path.lexists(path)
                                 else "no such folder")
        fmt, spec = _stored(path, "store", valid)
        if fmt != FORMAT:
            raise ParameterError("store", path, valid, f"store format {fmt!r}, this symvi "
                                 f"reads {FORMAT}")
        try:
            spec = PlaneSpec.from_dict(spec)
        except (SymviError, KeyError, TypeError, ValueError, AttributeError,
                RecursionError) as exc:
            detail = " ".join(str(exc).split())[:200]
            raise ParameterError("store", path, valid, "its spec attribute is not a valid "
                                 f"plane: {type(exc).__name__}: {detail}") from None
        st = cls(path, spec)
        st._check_layout("store", valid)
        return st

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
        if not isinstance(have, dict):
            have = {}
        diff = sorted(k for k in set(want) | set(have) if want.get(k) != have.get(k))
        if diff:
            raise ParameterError("--out", self.path, "a new path, or the store of the same "
                                 "run (same model, axes, --impacts, --transient, --follow) "
                                 "to resume it", "it holds another run; differs in: "
                                 + ", ".join(map(str, diff)))
        self._check_layout("--out", "a new path, or an undamaged plane store of the same run "
                           "to resume", resume=True)

    def _check_layout(self, name, valid, resume=False):
        """Every variable with the shape and dtype of the spec, the done flags readable
        (and, to resume, the attractor labels of the done rows, which the run counts at
        its end); else a ParameterError naming ``name``."""
        import zarr
        ny, nx = self.spec.shape
        yn, xn = self.spec.y.name, self.spec.x.name
        want = {**{v: ((ny, nx), DTYPES[v]) for v in GRID_VARS}, "done": ((ny,), DTYPES["done"]),
                yn: ((ny,), np.dtype(np.float64)), xn: ((nx,), np.dtype(np.float64))}

        def bad(detail):
            return ParameterError(name, self.path, valid, f"damaged store: {detail}")
        try:
            g = zarr.open_group(self.path, mode="r")
            for v, (shape, dtype) in want.items():
                try:
                    a = g[v]
                except KeyError:
                    raise bad(f"no array {v!r}") from None
                # xarray < 2026.9 stores a bool as int8 with the attribute dtype="bool"
                as_bool = (dtype == np.dtype(bool) and getattr(a, "dtype", None) == np.int8
                           and a.attrs.get("dtype") == "bool")
                if not hasattr(a, "dtype") or tuple(a.shape) != shape or (
                        a.dtype != dtype and not as_bool):
                    raise bad(f"{v!r} is {getattr(a, 'dtype', 'a group')} "
                              f"{tuple(getattr(a, 'shape', ()))}, the spec needs {dtype} "
                              f"{shape}")
            done = np.asarray(g["done"][:], dtype=bool)
            if resume:
                for r0, r1 in self.spec.blocks():
                    if done[r0:r1].any():
                        g["attractor"][r0:r1, :]
        except SymviError:
            raise
        except Exception as exc:   # noqa: BLE001 -- unreadable chunk or metadata: one line
            detail = " ".join(str(exc).split())[:200]
            raise bad(f"cannot read it: {type(exc).__name__}: {detail}") from None

    @contextlib.contextmanager
    def lock(self):
        """Hold ``<store>.lock`` while writing; a second run on this store is refused
        (``ParameterError`` naming --out).  Re-entrant in one process."""
        key = os.path.realpath(self.path)
        if key in _HELD:
            _HELD[key] += 1
            try:
                yield
            finally:
                _HELD[key] -= 1
            return
        fd = _acquire(self.path + ".lock", self.path)
        _HELD[key] = 1
        try:
            yield
        finally:
            del _HELD[key]
            _release(self.path + ".lock", fd)

    def done(self):
        """Bool per row: blocks already written."""
        import zarr
        try:
            return np.asarray(zarr.open_group(self.path, mode="r")["done"][:], dtype=bool)
        except Exception as exc:   # noqa: BLE001 -- damaged after the check: one line
            raise ParameterError("--out", self.path, "an undamaged plane store",
                                 f"cannot read its done flags: {type(exc).__name__}") from None

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
        try:
            with xr.open_zarr(self.path, consolidated=True) as ds:
                return ds.load()
        except Exception as exc:   # noqa: BLE001 -- a damaged chunk: one line naming the store
            detail = " ".join(str(exc).split())[:200]
            raise ParameterError("store", self.path, "a zarr store written by symvi plane",
                                 f"damaged store: cannot read it: {type(exc).__name__}: "
                                 f"{detail}") from None


def _stored(path, name, valid):
    """(format, spec dict) from a store's attrs; anything unreadable is refused naming
    ``name`` (the store is only read)."""
    import zarr
    try:
        g = zarr.open_group(path, mode="r")
        return g.attrs.get("symvi_plane_format"), json.loads(g.attrs["spec"])
    except Exception:   # noqa: BLE001 -- any unreadable path: one clear line, touch nothing
        raise ParameterError(name, path, valid, "it is not a symvi plane store") from None


#: realpaths of the stores this process holds locked, with a nesting count
_HELD = {}


def _acquire(lock_path, store):
    """Open and lock ``lock_path`` (never through a symlink); write our pid in it."""
    refuse = ParameterError
    valid = "a plane store no other run is writing"
    flags = os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
    for _ in range(5):
        try:
            fd = os.open(lock_path, flags, 0o644)
        except OSError as exc:
            if exc.errno == errno.ELOOP:
                raise refuse("--out", store, valid, f"{lock_path} is a symlink") from None
            raise refuse("--out", store, valid, f"cannot create {lock_path}: "
                         f"{exc.strerror or exc}") from None
        try:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                raise refuse("--out", store, valid, f"{lock_path} is not a regular file")
            if not _try_lock(fd):
                raise refuse("--out", store, valid, "another symvi plane run "
                             f"{_holder(fd)}is writing it (lock {lock_path})")
            # the holder before us may have removed the file after we opened it: only the
            # file at the path counts
            st, now = os.fstat(fd), lstat_or_none(lock_path)
            if now is None or (now.st_ino, now.st_dev) != (st.st_ino, st.st_dev):
                os.close(fd)
                continue
            os.ftruncate(fd, 0)
            os.write(fd, f"{os.getpid()}\n".encode())
            return fd
        except BaseException:
            with contextlib.suppress(OSError):
                os.close(fd)
            raise
    raise refuse("--out", store, valid, f"{lock_path} keeps changing (another run?)")


def _try_lock(fd):
    """An exclusive lock on ``fd`` without waiting: True if taken.  Without ``fcntl`` the
    file's pid decides (a live pid holds it; a dead one's lock is taken over)."""
    try:
        import fcntl
    except ImportError:        # not POSIX: the pid in the file is the lock
        pid = _pid_in(fd)
        return pid is None or pid == os.getpid() or not _alive(pid)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError as exc:
        if exc.errno in (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK):
            return False
        raise
    return True


def _release(lock_path, fd):
    # remove the file while still holding it (a waiting run then sees a new inode)
    with contextlib.suppress(OSError):
        os.unlink(lock_path)
    os.close(fd)


def _pid_in(fd):
    try:
        text = os.pread(fd, 32, 0).decode("ascii", "replace").strip()
        return int(text) if text.isdigit() else None
    except (OSError, AttributeError):
        return None


def _holder(fd):
    pid = _pid_in(fd)
    return f"(pid {pid}) " if pid else ""


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:            # exists but is not ours
        return True
    return True
