"""Progress of long runs and BEM solves on standard error; silent for work shorter than ``delay`` seconds.

On a terminal a bar is redrawn in place (carriage returns) and erased at the end; anywhere else (a log file
``2> run.err``, a notebook, a batch job) a plain line is printed each time the work passes another ``step_percent``
(5 %), so that a log holds readable lines only."""

from __future__ import annotations

import math
import sys
import time
from typing import TextIO


def is_terminal(stream: TextIO) -> bool:
    """Whether ``stream`` is a terminal (where carriage returns redraw a line)."""
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # a closed or unusual stream
        return False


class ProgressBar:
    """``update(t)`` as the work goes from ``start`` to ``stop``, ``close()`` at the end (erases the bar).

    The bar names the position ``t = ... s`` (simulated time) unless ``update`` is given a ``detail``
    to show instead (e.g. ``frequency 12 of 100``). ``terminal``: redraw a bar (default: whether ``stream`` is a
    terminal); otherwise one plain line per ``step_percent`` of progress (module docstring).
    """

    def __init__(self, start: float, stop: float, *, enabled: bool = True, delay: float = 2.0,
                 interval: float = 0.5, width: int = 30, stream: TextIO | None = None,
                 terminal: bool | None = None, step_percent: float = 5.0) -> None:
        self.start, self.stop = start, stop
        self.enabled = enabled
        self.delay, self.interval, self.width = delay, interval, width
        self.stream = stream or sys.stderr
        self.terminal = is_terminal(self.stream) if terminal is None else terminal
        self.step_percent = step_percent
        self.next_percent = step_percent  # plain lines: the next percentage to report
        self.t0 = time.monotonic()
        self.last = self.t0
        self.shown = False

    def fraction(self, t: float) -> float:
        return min(1.0, max(0.0, (t - self.start) / (self.stop - self.start))) if self.stop > self.start else 1.0

    def text(self, t: float, elapsed: float, detail: str | None = None) -> str:
        """``35.0 %  t = 70.00 s  elapsed 12.3 s  left 22.9 s`` (without the bar)."""
        frac = self.fraction(t)
        eta = elapsed * (1 - frac) / frac if frac > 0 else float("nan")
        where = detail if detail is not None else f"t = {t:9.2f} s"
        return f"{100 * frac:5.1f} %  {where}  elapsed {elapsed:6.1f} s  left {eta:6.1f} s"

    def line(self, t: float, elapsed: float, detail: str | None = None) -> str:
        """The terminal frame: carriage return, bar, :meth:`text`."""
        filled = int(round(self.fraction(t) * self.width))
        return f"\r  [{'#' * filled}{'.' * (self.width - filled)}] {self.text(t, elapsed, detail)}"

    def update(self, t: float, detail: str | None = None) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        if now - self.t0 < self.delay:
            return
        if not self.terminal:
            percent = 100 * self.fraction(t)
            if percent + 1e-9 < self.next_percent:
                return
            while self.next_percent <= percent + 1e-9:
                self.next_percent += self.step_percent
            print(f"  {self.text(t, now - self.t0, detail)}", file=self.stream, flush=True)
            return
        if now - self.last < self.interval:
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
                 delay: float = 2.0, interval: float = 0.5, terminal: bool | None = None) -> None:
        self.headings, self.log, self.enabled, self.stream = headings, log, enabled, stream
        self.delay, self.interval, self.terminal = delay, interval, terminal
        self.bar: ProgressBar | None = None
        self.started = math.nan
        self.elapsed = 0.0

    def __call__(self, done: int, total: int, omega: float) -> None:
        if self.bar is None:
            self.started = time.monotonic()
            self.bar = ProgressBar(0.0, float(total), enabled=self.enabled, delay=self.delay,
                                   interval=self.interval, stream=self.stream, terminal=self.terminal)
            if self.log is not None:
                self.log(f"computing the hydrodynamic database with Capytaine: {total - 1} frequencies x "
                         f"{self.headings} heading(s) and the infinite frequency (this can take minutes) ...")
        self.elapsed = time.monotonic() - self.started
        where = "infinite frequency" if math.isinf(omega) else f"omega = {omega:.4g} rad/s"
        self.bar.update(float(done), f"BEM frequency {done} of {total} ({where})")

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
