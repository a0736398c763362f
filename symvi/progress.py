"""Progress bars on stderr, drawn by tqdm; silent when stderr is not a TTY unless forced,
so logs and CI output stay short."""
import sys


def Progress(total, label="", stream=None, enabled=None):
    """``with Progress(n, "sweep") as bar: ... bar.update()`` (a :class:`tqdm.tqdm`)."""
    from tqdm import tqdm
    stream = stream or sys.stderr
    enabled = stream.isatty() if enabled is None else enabled
    return tqdm(total=max(int(total), 1), desc=label, file=stream, disable=not enabled,
                mininterval=0.1, leave=True, dynamic_ncols=True)
