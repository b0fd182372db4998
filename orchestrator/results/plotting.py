"""``wec-cosim plot``: PNG figures of a results file (time series), a RAO or steady-state file; other kinds of
file (a sweep file, whose matrices :mod:`wec_cosim.sweeps.plotting` draws) through drawers the caller passes."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path

import h5py
import numpy as np

from orchestrator.errors import WecCosimError
from orchestrator.scenario import DOFS

UNITS = ("m", "m", "m", "rad", "rad", "rad")


# A drawer of another kind of file: (open file, output folder, file stem) -> PNG files written.
Drawer = Callable[[h5py.File, Path, str], list[Path]]


def pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_file(path: str | Path, out_dir: str | Path | None = None,
              drawers: Mapping[str, Drawer] | None = None) -> list[Path]:
    """Draw every figure the file supports; returns the PNG files written. ``drawers``: file format (the root
    attribute ``format``) -> drawer, for files of the stages above this one (sweep files)."""
    path = Path(path)
    if not path.is_file():
        raise WecCosimError(f"plot: file {path} does not exist")
    out = Path(out_dir) if out_dir else path.parent
    out.mkdir(parents=True, exist_ok=True)
    try:
        with h5py.File(path, "r", swmr=True) as f:
            kind = f.attrs.get("format")
            if drawers and kind in drawers:
                return drawers[kind](f, out, path.stem)
            if kind == "wec-cosim sweep":
                raise WecCosimError(f"plot: {path} is a sweep file: `wec-cosim plot` draws it "
                                    "(wec_cosim.sweeps.plotting.plot_sweep)")
            if "parameter" in f.attrs and "values" in f:
                raise WecCosimError(f"plot: {path} is a sweep file of an earlier version (values x periods); run "
                                    "`wec-cosim sweep` again for a file with matrices that plot draws")
            if "omega" in f:
                figures = [plot_rao(f, out / f"{path.stem}_rao.png")]
                if "heading_sweep" in f:
                    figures.append(plot_heading_sweep(f, out / f"{path.stem}_headings.png"))
                return figures
            if "periods" in f:
                return [plot_steady(f, out / f"{path.stem}_steady.png")]
            if "time" in f:
                figures = [plot_time_series(f, out / f"{path.stem}_timeseries.png")]
                if "energy/excitation_work" in f:
                    figures.append(plot_energy(f, out / f"{path.stem}_energy.png"))
                return figures
    except OSError as exc:
        raise WecCosimError(f"plot: {path} is not a readable HDF5 file ({exc})") from None
    except (KeyError, ValueError, IndexError) as exc:
        raise WecCosimError(f"plot: {path} lacks what its figure needs ({type(exc).__name__}: {exc}); is it a "
                            "complete wec-cosim file?") from None
    raise WecCosimError(f"plot: {path} is neither a results file (/time), a RAO file (/omega) nor a steady-state "
                        "file (/periods)")


def _active(d: np.ndarray) -> list[int]:
    return [j for j in range(6) if np.any(d[:, j] != 0)]


# Scenes with more PTOs than this are drawn with their total power (each PTO's mean in the legend would
# not fit), and with more displacement or force lines than LEGEND_LINES without a legend.
MANY_PTOS = 6
LEGEND_LINES = 16


def plot_time_series(f: h5py.File, target: Path) -> Path:
    """Displacements, hydrodynamic forces, PTO power (each PTO's, or the total for many PTOs), wave elevation and
    mooring-line tensions against time."""
    plt = pyplot()
    t = f["time"][()]
    lines = list(f.get("forces", {}))
    fig, axes = plt.subplots(4 + bool(lines), 1, figsize=(10, 11 + 2.5 * bool(lines)), sharex=True)
    for name in f.get("bodies", {}):
        d = f[f"bodies/{name}/displacement"][()]
        for j in _active(d):
            axes[0].plot(t, d[:, j], label=f"{name} {DOFS[j]} ({UNITS[j]})")
        if f"bodies/{name}/hydro_force" in f:
            force = f[f"bodies/{name}/hydro_force"][()]
            for j in _active(force):
                axes[1].plot(t, force[:, j], label=f"{name} {DOFS[j]}")
    means, where = mean_powers_of(f)
    ptos = list(f.get("ptos", {}))
    power = {name: f[f"ptos/{name}/power"][()] for name in ptos}
    many = len(ptos) > MANY_PTOS
    scale, unit = _power_unit(max((np.max(np.abs(p)) for p in power.values()), default=1e3)
                              * (len(ptos) if many else 1))
    if many:
        total = np.sum(list(power.values()), axis=0)
        mean = f", mean {sum(means.values()) / scale:.4g} {unit}" if len(means) == len(ptos) else ""
        axes[2].plot(t, total / scale, color="tab:red", label=f"total of {len(ptos)} PTOs{mean}")
    else:
        for name, p in power.items():
            mean = f", mean {means[name] / scale:.4g} {unit}" if name in means else ""
            axes[2].plot(t, p / scale, label=f"{name}{mean}")
    if means:
        axes[2].set_title(f"mean power over the {where} (as in the run summary)", fontsize=9)
    if "wave/elevation" in f:
        axes[3].plot(t, f["wave/elevation"][()], color="tab:blue")
    for name in lines:
        axes[4].plot(t, np.linalg.norm(f[f"forces/{name}/force"][()], axis=1) / 1e3, label=name)
    fig.suptitle(f"{Path(f.filename).name}  ({f.attrs.get('status', '')})")
    _drop_crowded_legends(axes[:2])
    labels = ("displacement", "hydro force (N, N m)", f"PTO power ({unit})", "wave elevation (m)")
    return _save(plt, fig, axes, labels + (("fairlead tension (kN)",) if lines else ()), "time (s)", target)


ENERGY_TERMS = (("work_in", "work in (excitation)"), ("pto", "PTO"), ("radiated", "radiated"),
                ("dissipated", "dissipated (viscous, ropes, dampers)"), ("stored", "stored (change)"))


def plot_energy(f: h5py.File, target: Path) -> Path:
    """The wave-to-wire energy account against time: the work the waves did and where it went (PTO, radiated,
    dissipated, stored), and the balance's residual relative to the work in."""
    from .energy import energy_terms

    plt = pyplot()
    t = f["time"][()]
    terms = energy_terms({f"energy/{name}": f[f"energy/{name}"][()] for name in f["energy"]})
    fig, axes = plt.subplots(2, 1, figsize=(10, 7), sharex=True, height_ratios=(2, 1))
    for key, label in ENERGY_TERMS:
        axes[0].plot(t, terms[key], label=f"{label}: {terms[key][-1]:.4g} J at the end")
    axes[0].plot(t, terms["pto"] + terms["radiated"] + terms["dissipated"] + terms["stored"], "k:",
                 label="PTO + radiated + dissipated + stored")
    work = np.abs(terms["work_in"])
    relative = np.divide(terms["residual"], work, out=np.full_like(work, np.nan), where=work > 0.01 * work.max())
    axes[1].plot(t, 100 * relative, color="tab:red",
                 label=f"residual / work in: {100 * relative[-1]:.3g} % at the end")
    fig.suptitle(f"{Path(f.filename).name}: wave-to-wire energy account")
    return _save(plt, fig, axes, ("energy (J)", "residual (%)"), "time (s)", target)


def _power_unit(largest: float) -> tuple[float, str]:
    """Scale and unit of a power axis: W below 1 kW, else kW."""
    return (1.0, "W") if largest < 1e3 else (1e3, "kW")


def mean_powers_of(f: h5py.File) -> tuple[dict[str, float], str]:
    """The PTOs' mean power over the run summary's window (:func:`analysis.mean_pto_powers`), from the
    scenario stored in the file; none if the file holds no readable scenario."""
    import tomllib

    from orchestrator.errors import ScenarioError
    from orchestrator.scenario import Scenario, schema

    from .analysis import mean_pto_powers

    try:
        text = f.attrs["scenario"]
        scenario = schema.load(Scenario, tomllib.loads(text if isinstance(text, str) else text.decode()), f.filename)
        return mean_pto_powers(scenario, f)
    except (KeyError, ValueError, TypeError, ScenarioError, tomllib.TOMLDecodeError):
        return {}, ""


def _save(plt, fig, axes, ylabels: tuple[str, ...], xlabel: str, target: Path) -> Path:  # noqa: ANN001
    """Label, grid and legend every axis, write the PNG, close the figure."""
    for ax, label in zip(axes, ylabels, strict=True):
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel(xlabel)
    fig.tight_layout()
    fig.savefig(target, dpi=110)
    plt.close(fig)
    return target


def plot_rao(f: h5py.File, target: Path) -> Path:
    """Amplitude and phase of every active RAO, and the mean PTO power per m^2 of wave amplitude."""
    plt = pyplot()
    omega = f["omega"][()]
    fig, axes = plt.subplots(3, 1, figsize=(9, 10), sharex=True)
    for name in f.get("bodies", {}):
        rao = f[f"bodies/{name}/rao"][()]
        for j in [j for j in range(6) if np.any(np.abs(rao[:, j]) > 0)]:
            axes[0].plot(omega, np.abs(rao[:, j]), label=f"{name} {DOFS[j]}")
            axes[1].plot(omega, np.degrees(np.angle(rao[:, j])), label=f"{name} {DOFS[j]}")
    ptos = list(f.get("ptos", {}))
    power = {name: f[f"ptos/{name}/mean_power"][()] for name in ptos}
    if len(ptos) > MANY_PTOS:
        power = {f"total of {len(ptos)} PTOs": np.sum(list(power.values()), axis=0)}
    scale, unit = _power_unit(max((np.max(np.abs(p)) for p in power.values()), default=1e3))
    for name, p in power.items():
        axes[2].plot(omega, p / scale, label=name)
    _drop_crowded_legends(axes[:2])
    return _save(plt, fig, axes, ("|RAO| (m/m, rad/m)", "phase (deg)", f"mean power ({unit} per m^2)"),
                 "wave frequency (rad/s)", target)


def _drop_crowded_legends(axes) -> None:  # noqa: ANN001
    """Axes with more than LEGEND_LINES lines get a title saying so instead of a legend."""
    for ax in axes:
        if len(ax.get_lines()) > LEGEND_LINES:
            ax.set_title(f"{len(ax.get_lines())} lines (every active DOF of every body)", fontsize=9)
            for line in ax.get_lines():
                line.set_label("_")


def joint_selection(text: str) -> tuple[str, int]:
    """``NAME[k]`` (k 1-based, as the FMU's ``NAME.coordinate[k]``) -> (name, k - 1); ``NAME`` is ``NAME[1]``."""
    name, _, rest = text.partition("[")
    try:
        k = int(rest.rstrip("]")) if rest else 1
    except ValueError:
        raise WecCosimError(f"plot: joint coordinate {text!r} is not NAME or NAME[k]") from None
    if not name or k < 1:
        raise WecCosimError(f"plot: joint coordinate {text!r} is not NAME or NAME[k] with k >= 1")
    return name, k - 1


def plot_joint_raos(files: list[str | Path], joints: list[str], target: str | Path) -> Path:
    """Amplitude and phase of chosen joint-coordinate RAOs (``NAME[k]``) of one or more RAO files in one
    figure (e.g. the same node's relative pitch in two devices); a joint a file lacks is skipped there,
    a joint no file has is an error."""
    plt = pyplot()
    fig, axes = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    found = set()
    for path in map(Path, files):
        if not path.is_file():
            raise WecCosimError(f"plot: file {path} does not exist")
        with h5py.File(path, "r") as f:
            if "omega" not in f:
                raise WecCosimError(f"plot: {path} is not a RAO file (no /omega); joint RAOs come from "
                                    "`wec-cosim rao`")
            omega = f["omega"][()]
            for text in joints:
                name, k = joint_selection(text)
                key = f"joints/{name}/rao"
                if key not in f or k >= f[key].shape[1]:
                    continue
                found.add(text)
                names = [n.decode() if isinstance(n, bytes) else str(n) for n in f[key].attrs.get("coordinates", [])]
                label = f"{path.stem}: {name}[{k + 1}]" + (f" ({names[k]})" if k < len(names) else "")
                rao = f[key][()][:, k]
                axes[0].plot(omega, np.abs(rao), label=label)
                axes[1].plot(omega, np.degrees(np.angle(rao)), label=label)
    missing = [j for j in joints if j not in found]
    if missing:
        raise WecCosimError(f"plot: no file given has the joint coordinate(s) {', '.join(missing)}")
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    return _save(plt, fig, axes, ("|RAO| (rad/m, m/m)", "phase (deg)"), "wave frequency (rad/s)", target)


def plot_heading_sweep(f: h5py.File, target: Path) -> Path:
    """One column per heading of a RAO file's heading sweep: joint coordinate RAOs (deg or m per m of wave
    amplitude), every body's heave RAO, and the mean PTO power per m^2 of wave amplitude."""
    plt = pyplot()
    omega = f["omega"][()]
    g = f["heading_sweep"]
    headings = g["headings_deg"][()]
    panels = [p for p in ("joints", "bodies", "ptos") if p in g]
    fig, axes = plt.subplots(len(panels), len(headings), figsize=(4.2 * len(headings), 3.3 * len(panels) + 0.5),
                             sharex=True, sharey="row", squeeze=False)
    for k, heading in enumerate(headings):
        for row, panel in enumerate(panels):
            ax = axes[row, k]
            for name in g[panel]:
                if panel == "joints":
                    ds = g[f"joints/{name}/rao"]
                    for i, coordinate in enumerate(ds.attrs.get("coordinates", [])):
                        values = np.abs(ds[k, :, i])
                        rotation = "angle" in coordinate or "rotation" in coordinate
                        ax.plot(omega, np.degrees(values) if rotation else values, label=f"{name} {coordinate}")
                elif panel == "bodies":
                    ax.plot(omega, np.abs(g[f"bodies/{name}/rao"][k, :, 2]), label=f"{name} heave")
                else:
                    ax.plot(omega, g[f"ptos/{name}/mean_power"][k] / 1e3, label=name)
            ax.grid(True, alpha=0.3)
        axes[0, k].set_title(f"heading {heading:g} deg")
        axes[-1, k].set_xlabel("wave frequency (rad/s)")
    labels = {"joints": "|joint RAO| (deg/m, m/m)", "bodies": "|heave RAO| (m/m)", "ptos": "mean power (kW per m^2)"}
    for row, panel in enumerate(panels):
        axes[row, 0].set_ylabel(labels[panel])
        if axes[row, -1].get_legend_handles_labels()[0]:
            axes[row, -1].legend(loc="upper right", fontsize=7)
    fig.tight_layout()
    fig.savefig(target, dpi=110)
    plt.close(fig)
    return target


def plot_steady(f: h5py.File, target: Path) -> Path:
    """One period of every active DOF of each solved wave period (``wec-cosim steady``)."""
    plt = pyplot()
    groups = [f[f"periods/{k}"] for k in sorted(f["periods"], key=int)]
    fig, axes = plt.subplots(len(groups), 1, figsize=(8, 3 * len(groups)), squeeze=False)
    for ax, g in zip(axes[:, 0], groups, strict=True):
        t = g["time"][()]
        for name in g["bodies"]:
            y = g[f"bodies/{name}/one_period"][()]
            for j in [j for j in range(6) if np.any(y[:, j])]:
                ax.plot(t, y[:, j], label=f"{name} {DOFS[j]} ({UNITS[j]})")
        ax.set_title(f"omega = {g.attrs['omega']:.4g} rad/s, {g.attrs['harmonics']} harmonics, "
                     f"residual {g.attrs['residual']:.2g}")
        ax.set_xlabel("t (s)")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(target, dpi=110)
    plt.close(fig)
    return target
