"""A plain-text progress bar on stderr (no dependency); silent when stderr is not a TTY
unless forced, so logs and CI output stay short."""
import sys
import time


class Progress:
    """``with Progress(n, "sweep") as bar: ... bar.update()``."""

    def __init__(self, total, label="", stream=None, enabled=None, width=30):
        self.total, self.label, self.width = max(int(total), 1), label, width
        self.stream = stream or sys.stderr
        self.enabled = self.stream.isatty() if enabled is None else enabled
        self.n, self.t0, self._last = 0, time.perf_counter(), 0.0

    def __enter__(self):
        self._draw()
        return self

    def update(self, k=1):
        self.n = min(self.n + k, self.total)
        now = time.perf_counter()
        if now - self._last > 0.1 or self.n == self.total:
            self._last = now
            self._draw()

    def _draw(self):
        if not self.enabled:
            return
        frac = self.n / self.total
        fill = int(frac * self.width)
        el = time.perf_counter() - self.t0
        eta = el / frac - el if frac > 0 else 0.0
        self.stream.write(f"\r{self.label} [{'#' * fill}{'.' * (self.width - fill)}] "
                          f"{self.n}/{self.total} {el:5.1f}s eta {eta:5.1f}s")
        self.stream.flush()

    def __exit__(self, *exc):
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()
        return False
