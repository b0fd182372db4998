"""Progress of a sweep on standard error: cases done and failed, elapsed and estimated time left.

On a terminal one line is redrawn; otherwise (a log file, a batch job) a line is printed after the
first case and then at most every ``interval`` seconds, and after the last.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO


def duration(seconds: float) -> str:
    """``1h02m``, ``3m05s`` or ``12s``."""
    if seconds != seconds or seconds == float("inf"):
        return "?"
    s = int(round(seconds))
    if s >= 3600:
        return f"{s // 3600}h{s % 3600 // 60:02d}m"
    return f"{s // 60}m{s % 60:02d}s" if s >= 60 else f"{s}s"


class SweepProgress:
    """``update(ok)`` after each finished case of this session, ``close()`` at the end."""

    def __init__(self, total: int, already: int, *, enabled: bool = True, stream: TextIO | None = None,
                 interval: float = 10.0, width: int = 30) -> None:
        self.total, self.already = total, already
        self.to_run = total - already
        self.done = self.failed = 0
        self.enabled = enabled
        self.stream = stream or sys.stderr
        self.tty = self.stream.isatty()
        self.interval, self.width = interval, width
        self.t0 = time.monotonic()
        self.last = -float("inf")

    def line(self) -> str:
        finished = self.already + self.done + self.failed
        frac = finished / self.total if self.total else 1.0
        filled = int(round(frac * self.width))
        elapsed = time.monotonic() - self.t0
        ran = self.done + self.failed
        left = elapsed / ran * (self.to_run - ran) if ran else float("nan")
        return (f"[{'#' * filled}{'.' * (self.width - filled)}] {finished}/{self.total} cases, "
                f"{self.failed} failed this run, elapsed {duration(elapsed)}, left ~{duration(left)}")

    def update(self, ok: bool) -> None:
        if ok:
            self.done += 1
        else:
            self.failed += 1
        if not self.enabled:
            return
        now = time.monotonic()
        last_case = self.done + self.failed == self.to_run
        if self.tty:
            print("\r" + self.line(), end="", file=self.stream, flush=True)
        elif now - self.last >= self.interval or last_case or self.done + self.failed == 1:
            print(self.line(), file=self.stream, flush=True)
            self.last = now

    def close(self) -> None:
        if self.enabled and self.tty:
            print(file=self.stream, flush=True)
