"""Ctrl-C during a run: the run stops at the next communication point, its file closed as ``interrupted``.

A SIGINT raises KeyboardInterrupt in whatever Python code runs at that instant. During a run that is
most often an FMU's own ``do_step`` (PythonFMU slaves run in this interpreter), where PythonFMU turns
the exception into a failed FMI call: the user would read "doStep failed" instead of "interrupted".
:class:`InterruptAtStep` defers the first SIGINT to the master's next communication point
(:meth:`InterruptAtStep.check`); a second one interrupts at once (a step that hangs).
"""

from __future__ import annotations

import signal
import threading
from types import FrameType


class InterruptAtStep:
    """Context manager: within it, the first SIGINT is recorded and raised by :meth:`check`.

    It changes nothing outside the main thread, or when SIGINT has a handler other than Python's
    default (a host application's own)."""

    def __init__(self) -> None:
        self.requested = False
        self._previous = None

    def __enter__(self) -> InterruptAtStep:
        if threading.current_thread() is threading.main_thread() and \
                signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            self._previous = signal.signal(signal.SIGINT, self._on_sigint)
        return self

    def _on_sigint(self, signum: int, frame: FrameType | None) -> None:
        if self.requested:
            raise KeyboardInterrupt
        self.requested = True

    def check(self) -> None:
        """Raise KeyboardInterrupt if a SIGINT arrived (call it where stopping is clean)."""
        if self.requested:
            raise KeyboardInterrupt

    def __exit__(self, *exc: object) -> None:
        if self._previous is not None:
            signal.signal(signal.SIGINT, self._previous)
            self._previous = None
