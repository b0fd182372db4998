"""``wec-cosim plot`` of a sweep file: the matrices as heat maps (two swept keys) or curves (one).

Axes with a single value are dropped. With two or more keys left, the first two are the heat map's
rows (upwards) and columns, and each combination of the others is a panel of its own (at most
``MAX_PANELS``). Each cell shows its value; a cell without a finished case is grey.
Quantities: the device's mean power (W, kW or MW by its size) and capture width (m); a sweep without PTOs shows
the first body's significant motion instead (m, or deg for a rotation). The conventions of
:mod:`orchestrator.results.figures`: the title names the scenario, the method, the sea and the seeds; the axes
name the swept quantity, its key and its unit.
"""

from __future__ import annotations

import itertools
import json
from pathlib import Path
from typing import TYPE_CHECKING

import h5py
import numpy as np

from orchestrator.errors import WecCosimError
from orchestrator.results.datasets import key_unit
from orchestrator.results.figures import pyplot, save, scaled, sea_text, stored_scenario
from orchestrator.scenario import DOFS

from .matrices import Matrices, read_matrices

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

MAX_PANELS = 12
MAX_LABELLED_CELLS = 225


def draw_sweep_file(f: h5py.File, out: Path, stem: str) -> list[Path]:
    """The figures of a sweep file (its matrices) in folder ``out``: a drawer of
    :func:`orchestrator.results.plotting.plot_file`."""
    return [plot_sweep(f, out / f"{stem}_matrix.png")]


DRAWERS = {"wec-cosim sweep": draw_sweep_file}  # file formats this package draws, for plot_file


def plot_sweep(f: h5py.File, target: Path) -> Path:
    """Draw the sweep file's matrices into ``target`` (PNG)."""
    return save(draw_sweep(f), target)


def draw_sweep(f: h5py.File) -> Figure:
    """The figure of the sweep file's matrices (module docstring)."""
    if "matrices" not in f:
        raise WecCosimError(f"plot: {f.filename} is a sweep file without matrices (no session finished); run the "
                            "sweep again to assemble them")
    m = read_matrices(f)
    if not np.any(m.data["seeds_done"]):
        raise WecCosimError(f"plot: {f.filename}: no case of the sweep has finished yet: nothing to draw")
    quantities = _quantities(m)
    scenario = stored_scenario(f)
    m.units = [key_unit(scenario, key, unit) for key, unit in zip(m.keys, m.units, strict=True)]
    keep = [i for i, n in enumerate(m.shape) if n > 1] or ([0] if m.shape else [])
    plt = pyplot()
    rest = keep[2:]
    slices = list(itertools.product(*(range(m.shape[i]) for i in rest)))
    shown = slices[:MAX_PANELS]
    fig, axes = plt.subplots(len(shown), len(quantities), figsize=(6.5 * len(quantities), 4.8 * len(shown) + 0.6),
                             squeeze=False, layout="constrained")
    for row, combo in enumerate(shown):
        index = [0] * len(m.shape)
        for i, k in zip(rest, combo, strict=True):
            index[i] = k
        where = ", ".join(f"{m.keys[i]} = {_fmt(m.values[i][k])}" for i, k in zip(rest, combo, strict=True))
        for col, (label, data) in enumerate(quantities):
            ax = axes[row, col]
            sel = tuple(slice(None) if i in keep[:2] else index[i] for i in range(len(m.shape)))
            values = data[sel] if m.shape else data
            if len(keep[:2]) == 2:
                _heat_map(fig, ax, m, keep[0], keep[1], values, label)
            else:
                _curve(ax, m, keep[0] if keep else None, np.atleast_1d(values), label)
            ax.set_title(label + (f"  ({where})" if where else ""), fontsize=10)
    fig.suptitle(sweep_title(f, scenario) + (f" (first {len(shown)} of {len(slices)} slices)"
                                              if len(slices) > len(shown) else ""), fontsize=11)
    return fig


def sweep_title(f: h5py.File, scenario) -> str:  # noqa: ANN001 - Scenario or None
    """``<scenario>: power matrix`` and a line of settings: method, sea, seeds, duration, status."""
    method = str(f.attrs.get("method", ""))
    name = scenario.name if scenario is not None else Path(f.filename).stem
    what = "power matrix" if scenario is not None and scenario.ptos else "sweep"
    parts = ["exact linear frequency domain" if method == "frequency_domain" else "time-domain co-simulation"]
    if scenario is not None:
        swept = tuple(json.loads(f["matrices"].attrs["keys"])) if "matrices" in f else ()
        parts.append(sea_text(scenario, swept))
        for p in scenario.ptos[:2]:
            parts += [f"{p.name} {leaf} {getattr(p, leaf):g} {key_unit(scenario, f'ptos.{p.name}.{leaf}', unit)}"
                      for leaf, unit in (("damping", "N s/m or N m s/rad"), ("stiffness", "N/m or N m/rad"))
                      if getattr(p, leaf) and f"ptos.{p.name}.{leaf}" not in swept]
        if method == "time_domain":
            parts.append(f"{scenario.simulation.duration:g} s per run, step {scenario.simulation.step:g} s")
    seeds = int(f.attrs.get("seeds", 1))
    if method == "time_domain" and seeds > 1:
        parts.append(f"mean of {seeds} seeds")
    status = str(f.attrs.get("status", ""))
    return f"{name}: {what}" + (f" ({status})" if status and status != "completed" else "") + "\n" + ", ".join(parts)


def _quantities(m: Matrices) -> list[tuple[str, np.ndarray]]:
    out = []
    if "mean_power" in m.data:
        factor, unit = scaled(m.data["mean_power"][np.isfinite(m.data["mean_power"])], "W")
        out.append((f"mean power ({unit})", m.data["mean_power"] / factor))
        if "capture_width" in m.data:
            out.append(("capture width (m)", m.data["capture_width"]))
        return out
    for path, data in m.data.items():
        if path.endswith("/significant"):
            active = [j for j in range(6) if np.any(np.nan_to_num(data[..., j]))]
            if active:
                j = active[0]
                factor, unit = (1.0, "m") if j < 3 else (180 / np.pi, "deg")
                return [(f"{path.split('/')[1]} significant {DOFS[j]} ({unit})", data[..., j] * factor)]
    raise WecCosimError("plot: the sweep file has neither PTO power nor body motions to draw")


# What a swept key is, for the axis labels (the key itself follows in the label)
KEY_NAMES = {"waves.hs": "significant wave height", "waves.tp": "peak period", "waves.period": "wave period",
             "waves.height": "wave height", "waves.heading_deg": "wave heading", "waves.seed": "sea seed"}
LEAF_NAMES = {"damping": "damping", "stiffness": "stiffness", "mass": "mass"}


def _axis_label(m: Matrices, i: int) -> str:
    key = m.keys[i]
    parts = key.split(".")
    name = KEY_NAMES.get(key) or (f"{parts[1]} {LEAF_NAMES.get(parts[-1], parts[-1])}" if len(parts) == 3 else "")
    return (f"{name}, {key}" if name else key) + (f" ({m.units[i]})" if m.units[i] else "")


def _fmt(value) -> str:  # noqa: ANN001
    return f"{value:.4g}" if isinstance(value, (float, np.floating)) else str(value)


def _heat_map(fig, ax, m: Matrices, rows: int, cols: int, values: np.ndarray, label: str) -> None:  # noqa: ANN001
    """Rows upwards, columns to the right; equal cells whatever the spacing of the values."""
    import matplotlib

    data = values  # dimensions (rows, cols): the matrices keep the grid's order
    masked = np.ma.masked_invalid(data)
    cmap = matplotlib.colormaps["viridis"].with_extremes(bad="0.85")
    image = ax.imshow(masked, origin="lower", aspect="auto", cmap=cmap)
    fig.colorbar(image, ax=ax, label=label)
    ax.set_xticks(range(data.shape[1]), [_fmt(v) for v in m.values[cols]], rotation=45 if data.shape[1] > 8 else 0)
    ax.set_yticks(range(data.shape[0]), [_fmt(v) for v in m.values[rows]])
    ax.set_xlabel(_axis_label(m, cols))
    ax.set_ylabel(_axis_label(m, rows))
    if data.size <= MAX_LABELLED_CELLS:
        top = np.nanmax(data) if np.any(np.isfinite(data)) else 0.0
        for (r, c), v in np.ndenumerate(data):
            text = "-" if not np.isfinite(v) else f"{v:.3g}"
            ax.text(c, r, text, ha="center", va="center", fontsize=7,
                    color="black" if np.isfinite(v) and v > 0.6 * top else "white")


def _curve(ax, m: Matrices, axis: int | None, values: np.ndarray, label: str) -> None:  # noqa: ANN001
    x = m.values[axis] if axis is not None else np.arange(len(values))
    numeric = np.issubdtype(np.asarray(x).dtype, np.number)
    ax.plot(x if numeric else np.arange(len(values)), values, "o-")
    if not numeric:
        ax.set_xticks(range(len(values)), [str(v) for v in x])
    ax.set_xlabel(_axis_label(m, axis) if axis is not None else "case")
    ax.set_ylabel(label)
    ax.grid(True, alpha=0.3)
