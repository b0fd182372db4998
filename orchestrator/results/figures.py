"""What every figure of wec-cosim shares (:mod:`.plotting`, :mod:`.response_plots`, the sweep's heat maps): one
unit per axis, angles in degrees (the files and FMU interfaces keep radians), forces, moments and powers in N, kN
or MN (W, kW, MW) by their size, a title naming the scenario, what is drawn and the settings, legends to the right
of their axis, outside the data."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import TYPE_CHECKING

import h5py
import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from orchestrator.scenario import Scenario

# Scenes with more PTOs than this are drawn with their total power (each PTO's mean in the legend would
# not fit), and axes with more lines than LEGEND_LINES without a legend.
MANY_PTOS = 6
LEGEND_LINES = 16
PANEL_HEIGHT = 2.3  # inches per axis of a stacked figure
WIDTH = 11.0  # inches: axes and the legends to their right


def pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def scaled(values: np.ndarray | float, unit: str) -> tuple[float, str]:
    """Scale and prefixed unit for values in ``unit`` (N, N m, W, J): unit, k or M by the largest magnitude."""
    largest = float(np.nanmax(np.abs(values))) if np.size(values) else 0.0
    for factor, prefix in ((1e6, "M"), (1e3, "k")):
        if largest >= factor:
            return factor, prefix + unit
    return 1.0, unit


def stored_scenario(f: h5py.File) -> Scenario | None:
    from .datasets import stored_scenario as load

    return load(f.attrs, str(f.filename))


def sea_text(scenario: Scenario | None, swept: tuple[str, ...] = ()) -> str:
    """``regular waves H = 2 m, T = 8 s`` and the like; keys in ``swept`` (``waves.hs``...) are left out (a sweep's
    axes give them)."""
    if scenario is None:
        return ""
    w = scenario.waves

    def value(key: str, text: str) -> list[str]:
        return [] if f"waves.{key}" in swept else [text]

    if w.kind == "regular":
        parts = value("height", f"H = {w.height:g} m") + value("period", f"T = {w.period:g} s")
        parts += value("heading_deg", f"heading {w.heading_deg:g} deg") if w.heading_deg else []
        return "regular waves" + (" " + ", ".join(parts) if parts else "")
    if w.kind == "irregular":
        name = {"jonswap": "JONSWAP", "pierson_moskowitz": "Pierson-Moskowitz", "bretschneider": "Bretschneider",
                "file": "spectrum file"}[w.spectrum]
        parts = value("hs", f"Hs = {w.hs:g} m") + (value("tp", f"Tp = {w.tp:g} s") if w.tp > 0 else [])
        return f"irregular sea ({name})" + (" " + ", ".join(parts) if parts else "")
    return {"still": "still water", "elevation": "imported wave elevation"}.get(w.kind, w.kind)


def run_text(f: h5py.File, scenario: Scenario | None) -> str:
    """``Jacobi master, step 0.02 s, extrapolation 2, index3 formulation, fmpy``."""
    try:
        settings = json.loads(f.attrs["settings"])
    except (KeyError, ValueError, TypeError):
        return ""
    parts = [f"{settings.get('master', '?')} master", f"step {settings.get('step', 0):g} s"]
    if settings.get("master") != "monolithic":
        parts.append(f"extrapolation {settings.get('extrapolation', '?')}")
    if scenario is not None:
        parts.append(f"{scenario.formulation} multibody")
    if settings.get("overrides"):
        parts.append("set: " + ", ".join(settings["overrides"]))
    return ", ".join(parts)


def title(fig: Figure, scenario: Scenario | None, what: str, settings: str = "", status: str = "") -> None:
    """Two lines: ``<scenario>: <what>`` and the settings."""
    name = scenario.name if scenario is not None else ""
    head = f"{name}: {what}" if name else what
    if status and status != "completed":
        head += f" ({status})"
    fig.suptitle(head + (f"\n{settings}" if settings else ""), fontsize=11)


def legend_outside(ax: Axes, fontsize: int = 8) -> None:
    """The axis's legend to its right, outside the data (nothing for an axis without labelled lines)."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=fontsize)


def crowded(ax: Axes, what: str = "lines") -> None:
    """An axis with more than LEGEND_LINES lines gets a note instead of a legend."""
    if len(ax.get_lines()) > LEGEND_LINES:
        ax.set_title(f"{len(ax.get_lines())} {what}", fontsize=9, loc="left")
        for line in ax.get_lines():
            line.set_label("_")


def finish(fig: Figure, axes: list[Axes], xlabel: str) -> Figure:
    for ax in axes:
        ax.grid(True, alpha=0.3)
        crowded(ax)
        legend_outside(ax)
    axes[-1].set_xlabel(xlabel)
    return fig


def save(fig: Figure, target: Path) -> Path:
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(target, dpi=110, bbox_inches="tight")
    pyplot().close(fig)
    return target


def stacked(panels: int, height: float = PANEL_HEIGHT) -> tuple[Figure, list[Axes]]:
    plt = pyplot()
    fig, axes = plt.subplots(panels, 1, figsize=(WIDTH, 1.2 + height * panels), sharex=True, squeeze=False,
                             layout="constrained")
    return fig, list(axes[:, 0])


def angle_or_length(unit: str) -> tuple[float, str]:
    """Factor and figure unit of a quantity in ``unit`` (``rad`` -> degrees; ``rad/m`` -> deg/m; others as
    they are)."""
    if unit.startswith("rad"):
        return 180 / math.pi, "deg" + unit[3:]
    return 1.0, unit
