"""Output paths: checked before any computation, written atomically, never over a special file.

``check_output`` validates a path the user named (``--out``, ``--plot``, a scene's output
folder) before the work starts, so a bad path costs nothing and gives one line naming the
flag.  ``atomic_path`` writes to a temporary name in the same folder and renames it onto the
target, so nothing already written is lost when a run fails halfway.  It refuses to replace
anything but a regular file: a device node, a FIFO, a socket or a symlink stays as it was
(as root, ``os.replace`` would otherwise turn ``/dev/full`` into a data file).  The renamed
file gets the permission bits an ordinary ``open(path, "w")`` would give (0666 less the
umask), or those of the file it replaces; never setuid, setgid or sticky bits, and never
``mkstemp``'s private 0600.
"""
import errno
import os
import stat
import tempfile
from contextlib import contextmanager

from .errors import OutputError, ParameterError

#: the figure formats symvi writes (symvi.reporting.figures.save), by suffix
FIGURE_SUFFIXES = (".png", ".pdf")

_SPECIAL = "a regular file or a new name (not a folder, device, FIFO, socket or symlink)"


def _kind(mode):
    if stat.S_ISLNK(mode):
        return "a symlink"
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a FIFO"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    return "not a regular file"


def _probe(folder, flag, path, valid):
    """Create and remove a file in ``folder``: the only test that holds as root (for whom
    ``os.access`` says yes to everything) and on a read-only file system."""
    try:
        fd, tmp = tempfile.mkstemp(prefix=".tmp-probe-", dir=folder)
    except OSError as exc:
        raise ParameterError(flag, path, valid, f"cannot create a file in {folder}: "
                             f"{exc.strerror or exc}") from None
    os.close(fd)
    os.unlink(tmp)


def _writable_parent(path, flag, valid):
    """The nearest existing ancestor folder of ``path`` must be a folder we can write in."""
    folder = os.path.dirname(os.path.abspath(path))
    probe = folder
    while not os.path.lexists(probe):
        parent = os.path.dirname(probe)
        if parent == probe:
            break
        probe = parent
    if not os.path.isdir(probe):
        raise ParameterError(flag, path, valid, f"{probe} is not a folder")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise ParameterError(flag, path, valid, f"folder {probe} is not writable")
    _probe(probe, flag, path, valid)
    return folder


def check_output(path, *, flag, suffixes=None, folder=False):
    """Validate an output path before computing; return it (raise ``ParameterError``).

    ``folder=False``: a regular file to create or replace, with one of ``suffixes``
    (case-insensitive, e.g. ``(".png", ".pdf")``) when given.  ``folder=True``: a folder to
    create or reuse (a trailing separator is allowed; a symlink to a folder is used as the
    folder).  The folder that will hold the output must exist or be creatable, and a file
    must be creatable in it.
    """
    if path is None:
        return None
    path = os.fspath(path)
    try:
        return _check_output(path, flag, suffixes, folder)
    except (OSError, ValueError) as exc:
        if isinstance(exc, ParameterError):
            raise
        # a name the OS refuses (too long, embedded NUL, ...)
        raise ParameterError(flag, path, "a usable file name",
                             getattr(exc, "strerror", None) or str(exc)) from None


def _check_output(path, flag, suffixes, folder):
    if "\0" in path:
        raise ParameterError(flag, path, "a file name", "it contains a NUL character")
    if folder:
        valid = "a writable folder (new or existing)"
        bare = path.rstrip(os.sep + (os.altsep or ""))
        if path.strip() == "":
            raise ParameterError(flag, path, valid, "empty path")
        if bare == "":
            raise ParameterError(flag, path, valid, "the root folder")
        if lstat_or_none(bare) is not None:
            if not os.path.isdir(bare):
                mode = os.lstat(bare).st_mode
                what = ("a dangling symlink" if stat.S_ISLNK(mode) else
                        "a file" if stat.S_ISREG(mode) else _kind(mode))
                raise ParameterError(flag, path, valid, f"it is {what}, not a folder")
            if not os.access(bare, os.W_OK | os.X_OK):
                raise ParameterError(flag, path, valid, "folder is not writable")
            _probe(bare, flag, path, valid)
            return path
        _writable_parent(bare, flag, valid)
        return path
    exts = tuple(s.lower() for s in suffixes) if suffixes else ()
    valid = _SPECIAL + (f" ending in {'/'.join(exts)}" if exts else "")
    if path.strip() == "":
        raise ParameterError(flag, path, valid, "empty path")
    if path.endswith(os.sep) or (os.altsep and path.endswith(os.altsep)):
        raise ParameterError(flag, path, valid, "names a folder")
    st = lstat_or_none(path)
    if st is not None:
        mode = st.st_mode
        if not stat.S_ISREG(mode):
            raise ParameterError(flag, path, valid, f"it is {_kind(mode)}")
        if not os.access(path, os.W_OK):
            raise ParameterError(flag, path, valid, "the file is read-only")
    if exts and not path.lower().endswith(exts):
        raise ParameterError(flag, path, valid, "unknown file extension")
    _writable_parent(path, flag, valid)
    return path


def lstat_or_none(path):
    """lstat of ``path``, None if it does not exist (or a component is not a folder, which
    the parent check reports); any other failure (name too long, a loop of symlinks,
    no permission) raises OSError."""
    try:
        return os.lstat(path)
    except (FileNotFoundError, NotADirectoryError):
        return None


def distinct_outputs(*pairs):
    """Refuse two output flags naming the same file: ``pairs`` of (flag, path or None)."""
    seen = {}
    for flag, path in pairs:
        if path is None:
            continue
        key = os.path.realpath(os.fspath(path))
        if key in seen:
            raise ParameterError(flag, path, f"a file other than {seen[key][0]}",
                                 f"both write {path}")
        seen[key] = (flag, path)


def _refuse_special(path):
    """Raise ``OutputError`` if ``path`` exists and is not a regular file (checked again at
    rename time: the target may have changed since ``check_output``)."""
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return
    if not stat.S_ISREG(mode):
        raise OutputError(f"refusing to replace {path}: it is {_kind(mode)}, not a regular file")


@contextmanager
def atomic_path(path, suffix=None):
    """Yield a temporary path beside ``path``; rename it onto ``path`` on success.

    Raises ``OutputError`` (one line) when the target is a special file or the write fails
    (full disk, read-only folder); the target is then left as it was.
    """
    path = os.fspath(path)
    _refuse_special(path)
    folder = os.path.dirname(os.path.abspath(path))
    sfx = suffix if suffix is not None else os.path.splitext(path)[1]
    try:
        os.makedirs(folder, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=sfx, dir=folder)
    except OSError as exc:
        raise OutputError(f"cannot write {path}: {exc.strerror or exc}") from None
    os.close(fd)
    try:
        yield tmp
        _refuse_special(path)
        os.chmod(tmp, _mode_for(path))
        os.replace(tmp, path)
    except OSError as exc:
        if exc.errno in (errno.ENOSPC, errno.EDQUOT, errno.EACCES, errno.EROFS, errno.EPERM,
                         errno.EISDIR, errno.ENOTDIR, errno.EFBIG):
            raise OutputError(f"cannot write {path}: {exc.strerror}") from None
        raise
    finally:
        if os.path.lexists(tmp):
            os.unlink(tmp)


def _mode_for(path):
    """Permission bits a plain write of ``path`` would leave: the old file's, else 0666 & ~umask."""
    try:
        return os.stat(path).st_mode & 0o777
    except FileNotFoundError:
        return 0o666 & ~current_umask()


def current_umask():
    """The process umask (read by setting it and setting it back)."""
    umask = os.umask(0)
    os.umask(umask)
    return umask


def write_text(path, text):
    """Atomically write ``text`` (UTF-8) to ``path``."""
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)


def write_bytes(path, data):
    """Atomically write ``data`` to ``path``."""
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(data)
