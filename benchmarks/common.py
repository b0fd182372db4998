"""Shared by the benchmark scripts: print a report and keep a copy under ``benchmarks/results/``."""

from __future__ import annotations

from pathlib import Path


def write_report(lines: list[str], out: str | None) -> str:
    """Print the report; also write it to ``out`` if given. Returns the text."""
    report = "\n".join(lines)
    print(report)
    if out:
        Path(out).parent.mkdir(parents=True, exist_ok=True)
        Path(out).write_text(report + "\n")
    return report
