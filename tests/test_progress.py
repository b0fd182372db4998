"""Progress bar of long runs: silent on short runs, a percentage and time left on long ones, erased at the end."""

from __future__ import annotations

import io

from orchestrator.progress import ProgressBar


def test_short_runs_print_nothing() -> None:
    stream = io.StringIO()
    bar = ProgressBar(0.0, 100.0, delay=3600.0, stream=stream)
    for t in range(101):
        bar.update(float(t))
    bar.close()
    assert stream.getvalue() == ""


def test_long_runs_show_fraction_and_are_erased() -> None:
    stream = io.StringIO()
    bar = ProgressBar(0.0, 200.0, delay=0.0, interval=0.0, width=10, stream=stream)
    bar.update(60.0)
    shown = stream.getvalue()
    assert "[###.......]" in shown and " 30.0 %" in shown and "t =     60.00 s" in shown and "left" in shown
    bar.close()
    assert stream.getvalue().endswith("\r") and not bar.shown


def test_disabled_bar_is_silent() -> None:
    stream = io.StringIO()
    bar = ProgressBar(0.0, 1.0, enabled=False, delay=0.0, interval=0.0, stream=stream)
    bar.update(0.5)
    bar.close()
    assert stream.getvalue() == ""
