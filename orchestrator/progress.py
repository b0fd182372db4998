"""A progress bar for long runs and BEM solves, on standard error; silent for work shorter than ``delay`` seconds."""

from __future__ import annotations

import math
import sys
import time
from typing import TextIO


class ProgressBar:
    """``update(t)`` as the work goes from ``start`` to ``stop``, ``close()`` at the end (erases the bar).

    The bar names the position ``t = ... s`` (simulated time) unless ``update`` is given a ``detail``
    to show instead (e.g. ``frequency 12 of 100``).
    """

    def __init__(self, start: float, stop: float, *, enabled: bool = True, delay: float = 2.0,
                 interval: float = 0.5, width: int = 30, stream: TextIO | None = None) -> None:
        self.start, self.stop = start, stop
        self.enabled = enabled
        self.delay, self.interval, self.width = delay, interval, width
        self.stream = stream or sys.stderr
        self.t0 = time.monotonic()
        self.last = self.t0
        self.shown = False

    def line(self, t: float, elapsed: float, detail: str | None = None) -> str:
        frac = min(1.0, max(0.0, (t - self.start) / (self.stop - self.start))) if self.stop > self.start else 1.0
        filled = int(round(frac * self.width))
        eta = elapsed * (1 - frac) / frac if frac > 0 else float("nan")
        where = detail if detail is not None else f"t = {t:9.2f} s"
        return (f"\r  [{'#' * filled}{'.' * (self.width - filled)}] {100 * frac:5.1f} %  {where}"
                f"  elapsed {elapsed:6.1f} s  left {eta:6.1f} s")

    def update(self, t: float, detail: str | None = None) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        if now - self.t0 < self.delay or now - self.last < self.interval:
            return
        self.last = now
        self.shown = True
        print(self.line(t, now - self.t0, detail), end="", file=self.stream, flush=True)

    def close(self) -> None:
        if self.shown:
            print("\r" + " " * (self.width + 90) + "\r", end="", file=self.stream, flush=True)
            self.shown = False


class BemProgress:
    """Progress of a Capytaine solve (a :data:`hydro_fmu.bem.Progress` callback): one line in ``log``
    when the solve starts, then a bar on standard error naming the frequency being solved (shown
    once the solve has lasted 2 s, erased at the end)."""

    def __init__(self, headings: int, *, log=print, enabled: bool = True, stream: TextIO | None = None,
                 delay: float = 2.0, interval: float = 0.5) -> None:
        self.headings, self.log, self.enabled, self.stream = headings, log, enabled, stream
        self.delay, self.interval = delay, interval
        self.bar: ProgressBar | None = None
        self.started = math.nan
        self.elapsed = 0.0

    def __call__(self, done: int, total: int, omega: float) -> None:
        if self.bar is None:
            self.started = time.monotonic()
            self.bar = ProgressBar(0.0, float(total), enabled=self.enabled, delay=self.delay,
                                   interval=self.interval, stream=self.stream)
            if self.log is not None:
                self.log(f"computing the hydrodynamic database with Capytaine: {total - 1} frequencies x "
                         f"{self.headings} heading(s) and the infinite frequency (this can take minutes) ...")
        self.elapsed = time.monotonic() - self.started
        where = "infinite frequency" if math.isinf(omega) else f"omega = {omega:.4g} rad/s"
        self.bar.update(float(done), f"BEM frequency {done} of {total} ({where})")

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
