"""``wec-cosim plot`` of a sweep file: the matrices as heat maps (two swept keys) or curves (one).

Axes with a single value are dropped. With two or more keys left, the first two are the heat map's
rows (upwards) and columns, and each combination of the others is a panel of its own (at most
``MAX_PANELS``). Each cell shows its value; a cell without a finished case is grey.
Quantities: the device's mean power (kW) and capture width (m); a sweep without PTOs shows the
first body's significant motion instead.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import h5py
import numpy as np

from orchestrator.errors import WecCosimError
from orchestrator.results.plotting import pyplot
from orchestrator.scenario import DOFS

from .matrices import Matrices, read_matrices

MAX_PANELS = 12
MAX_LABELLED_CELLS = 225


def draw_sweep_file(f: h5py.File, out: Path, stem: str) -> list[Path]:
    """The figures of a sweep file (its matrices) in folder ``out``: a drawer of
    :func:`orchestrator.results.plotting.plot_file`."""
    return [plot_sweep(f, out / f"{stem}_matrix.png")]


DRAWERS = {"wec-cosim sweep": draw_sweep_file}  # file formats this package draws, for plot_file


def plot_sweep(f: h5py.File, target: Path) -> Path:
    """Draw the sweep file's matrices into ``target`` (PNG)."""
    if "matrices" not in f:
        raise WecCosimError(f"plot: {f.filename} is a sweep file without matrices (no session finished); run the "
                            "sweep again to assemble them")
    m = read_matrices(f)
    if not np.any(m.data["seeds_done"]):
        raise WecCosimError(f"plot: {f.filename}: no case of the sweep has finished yet: nothing to draw")
    quantities = _quantities(m)
    keep = [i for i, n in enumerate(m.shape) if n > 1] or ([0] if m.shape else [])
    plt = pyplot()
    rest = keep[2:]
    slices = list(itertools.product(*(range(m.shape[i]) for i in rest)))
    shown = slices[:MAX_PANELS]
    fig, axes = plt.subplots(len(shown), len(quantities), figsize=(6.5 * len(quantities), 4.8 * len(shown)),
                             squeeze=False)
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
    title = f"{Path(f.filename).name}: {f.attrs.get('method', '').replace('_', ' ')}, {f.attrs.get('status', '')}"
    if len(slices) > len(shown):
        title += f" (first {len(shown)} of {len(slices)} slices)"
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(target, dpi=110)
    plt.close(fig)
    return target


def _quantities(m: Matrices) -> list[tuple[str, np.ndarray]]:
    out = []
    if "mean_power" in m.data:
        out.append(("mean power (kW)", m.data["mean_power"] / 1e3))
        if "capture_width" in m.data:
            out.append(("capture width (m)", m.data["capture_width"]))
        return out
    for path, data in m.data.items():
        if path.endswith("/significant"):
            active = [j for j in range(6) if np.any(np.nan_to_num(data[..., j]))]
            if active:
                j = active[0]
                unit = "m" if j < 3 else "rad"
                return [(f"{path.split('/')[1]} significant {DOFS[j]} ({unit})", data[..., j])]
    raise WecCosimError("plot: the sweep file has neither PTO power nor body motions to draw")


def _axis_label(m: Matrices, i: int) -> str:
    return m.keys[i] + (f" ({m.units[i]})" if m.units[i] else "")


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
