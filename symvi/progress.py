"""Progress on stderr: bars drawn by tqdm, and one-line notes (the first run's compiling);
silent when stderr is not a TTY unless forced, so logs and CI output stay short.

``SYMVI_PROGRESS=1`` forces them on, ``SYMVI_PROGRESS=0`` off, whatever stderr is."""
import os
import sys


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
