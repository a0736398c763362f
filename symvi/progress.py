"""Progress on stderr: bars drawn by tqdm, and one-line notes (the first run's compiling);
silent when stderr is not a TTY unless forced, so logs and CI output stay short.

``SYMVI_PROGRESS=1`` forces them on, ``SYMVI_PROGRESS=0`` off, whatever stderr is."""
import contextlib
import contextvars
import os
import sys

#: the bar the running command counts its work on (:func:`counting`), None outside one
_COUNTER = contextvars.ContextVar("symvi_counter", default=None)
#: a counting bar appears only after this many seconds: short runs print nothing
DELAY = 2.0


def shown(stream=None):
    """Whether progress goes to ``stream`` (stderr): SYMVI_PROGRESS if set, else a TTY."""
    forced = os.environ.get("SYMVI_PROGRESS", "").strip()
    if forced in ("0", "1"):
        return forced == "1"
    stream = stream or sys.stderr
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


def Progress(total, label="", stream=None, enabled=None):
    """``with Progress(n, "sweep") as bar: ... bar.update()`` (a :class:`tqdm.tqdm`)."""
    from tqdm import tqdm
    stream = stream or sys.stderr
    enabled = shown(stream) if enabled is None else enabled
    return tqdm(total=max(int(total), 1), desc=label, file=stream, disable=not enabled,
                mininterval=0.1, leave=True, dynamic_ncols=True)


@contextlib.contextmanager
def counting(label, unit="points", stream=None, enabled=None):
    """A bar counting work of unknown total while the block runs (continuation points:
    the engine calls :func:`tick`), drawn only once the wait exceeds :data:`DELAY`."""
    from tqdm import tqdm
    stream = stream or sys.stderr
    enabled = shown(stream) if enabled is None else enabled
    bar = tqdm(total=None, desc=label, unit=f" {unit}", file=stream, disable=not enabled,
               mininterval=0.2, delay=DELAY, leave=False, dynamic_ncols=True)
    token = _COUNTER.set(bar)
    try:
        yield bar
    finally:
        _COUNTER.reset(token)
        bar.close()


def tick(n=1):
    """Count ``n`` units of work on the running command's bar, if it has one."""
    bar = _COUNTER.get()
    if bar is not None:
        bar.update(n)
