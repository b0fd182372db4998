"""The machine a figure was measured on: processor model and load (figures from two machine types differ)."""

from __future__ import annotations

import os
import platform
from pathlib import Path


def cpu_model() -> str:
    """The processor's model name as the kernel reports it (``/proc/cpuinfo``), or the platform's guess."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown processor"


def load_text() -> str:
    """The load averages (1, 5, 15 min) as text."""
    return " ".join(f"{x:.2f}" for x in os.getloadavg())
