"""``wec-cosim plot``: PNG figures of a results file (time series), a RAO or steady-state file; other kinds of
file (a sweep file, whose matrices :mod:`wec_cosim.sweeps.plotting` draws) through drawers the caller passes.

Conventions of every figure (also :mod:`.response_plots` and the sweep's heat maps):

* one unit per axis: metres apart from angles, newtons apart from newton metres; angles in degrees (the files
  and the FMU interfaces keep radians); forces, moments and powers in N, kN or MN (W, kW, MW) by their size;
* the title names the scenario, what is drawn and the settings (the sea, the master and step, the form);
* legends stand to the right of their axis, outside the data;
* a results file gives two figures: ``<stem>_timeseries.png`` (the wave, body translations and rotations, joint
  coordinates, PTO power) and ``<stem>_loads.png`` (hydrodynamic forces and moments, PTO forces, joint reactions,
  mooring tensions), and with an energy account ``<stem>_energy.png``.

Each figure is made by a ``draw_*`` function that returns the matplotlib figure (what the tests read) and saved
by the matching ``plot_*`` function.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import h5py
import numpy as np

from orchestrator.errors import WecCosimError
from orchestrator.scenario import DOFS

from . import response_plots
from .figures import MANY_PTOS, WIDTH, finish, pyplot, run_text, save, scaled, sea_text, stacked, stored_scenario, title

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from orchestrator.scenario import Scenario

# A drawer of another kind of file: (open file, output folder, file stem) -> PNG files written.
Drawer = Callable[[h5py.File, Path, str], list[Path]]


# ----------------------------------------------------------------------------- the file's figures
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
                figures = [save(response_plots.draw_rao(f), out / f"{path.stem}_rao.png")]
                if "heading_sweep" in f:
                    figures.append(save(response_plots.draw_heading_sweep(f), out / f"{path.stem}_headings.png"))
                return figures
            if "periods" in f:
                return [save(response_plots.draw_steady(f), out / f"{path.stem}_steady.png")]
            if "time" in f:
                figures = [plot_time_series(f, out / f"{path.stem}_timeseries.png")]
                loads = draw_loads(f)
                if loads is not None:
                    figures.append(save(loads, out / f"{path.stem}_loads.png"))
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


def _active(d: np.ndarray, columns: range | list[int]) -> list[int]:
    return [j for j in columns if np.any(d[:, j] != 0)]


def _bodies(f: h5py.File, scenario: Scenario | None) -> list[str]:
    from .datasets import _ordered

    return _ordered(list(f.get("bodies", {})), [b.name for b in scenario.bodies] if scenario else [])


def _joint_series(f: h5py.File, scenario: Scenario | None) -> list[tuple[str, str, str, np.ndarray]]:
    """(label, coordinate name, unit, series) of every recorded joint coordinate."""
    from .datasets import joint_coordinate_labels

    out = []
    t = f["time"][()]
    for j in f.get("joints", {}):
        if f"joints/{j}/coordinate" not in f:
            continue
        q = np.asarray(f[f"joints/{j}/coordinate"][()]).reshape(len(t), -1)
        for k, (label, name, unit) in enumerate(joint_coordinate_labels(scenario, j, q.shape[1])):
            out.append((label, name, unit, q[:, k]))
    return out


def draw_time_series(f: h5py.File) -> Figure:
    """Motions and power against time: the incident wave, body translations (m) and rotations (deg), joint
    coordinates (deg, m), PTO power (each PTO's with its mean over the run summary's window, or the total for
    many PTOs)."""
    scenario = stored_scenario(f)
    t = f["time"][()]
    panels: list[tuple[str, Callable[[Axes], None]]] = []
    if "wave/elevation" in f:
        panels.append(("wave elevation (m)", lambda ax: ax.plot(t, f["wave/elevation"][()], color="tab:blue",
                                                                 label="incident, at the origin")))
    bodies = _bodies(f, scenario)
    displacement = {b: f[f"bodies/{b}/displacement"][()] for b in bodies}

    def motions(columns: range, factor: float) -> Callable[[Axes], None]:
        def draw(ax: Axes) -> None:
            for b, d in displacement.items():
                for j in _active(d, columns):
                    ax.plot(t, d[:, j] * factor, label=f"{b} {DOFS[j]}")
        return draw

    if any(_active(d, range(3)) for d in displacement.values()):
        panels.append(("body translation (m)", motions(range(3), 1.0)))
    if any(_active(d, range(3, 6)) for d in displacement.values()):
        panels.append(("body rotation (deg)", motions(range(3, 6), 180 / math.pi)))
    joints = _joint_series(f, scenario)
    for unit, label, factor in (("rad", "joint angle (deg)", 180 / math.pi), ("m", "joint displacement (m)", 1.0)):
        chosen = [(lab, name, q) for lab, name, u, q in joints if u == unit]
        if chosen:
            panels.append((label, lambda ax, chosen=chosen, factor=factor: [
                ax.plot(t, q * factor, label=f"{lab} ({name})") for lab, name, q in chosen]))
    ptos = list(f.get("ptos", {}))
    if ptos:
        power = {name: f[f"ptos/{name}/power"][()] for name in ptos}
        means, where = mean_powers_of(f)
        many = len(ptos) > MANY_PTOS
        if many:
            power = {f"total of {len(ptos)} PTOs": np.sum(list(power.values()), axis=0)}
            means = {next(iter(power)): sum(means.values())} if len(means) == len(ptos) else {}
        factor, unit = scaled(np.array(list(power.values())), "W")

        def draw_power(ax: Axes) -> None:
            for name, p in power.items():
                mean = f", mean {means[name] / factor:.4g} {unit}" if name in means else ""
                ax.plot(t, p / factor, label=f"{name}{mean}")
            if means:
                ax.set_title(f"mean over the {where} (as in the run summary)", fontsize=9, loc="left")
        panels.append((f"PTO power ({unit})", draw_power))
    fig, axes = stacked(len(panels))
    for ax, (label, draw) in zip(axes, panels, strict=True):
        draw(ax)
        ax.set_ylabel(label)
    title(fig, scenario, "motions and power", "; ".join(x for x in (sea_text(scenario), run_text(f, scenario)) if x),
          str(f.attrs.get("status", "")))
    return finish(fig, axes, "time (s)")


def plot_time_series(f: h5py.File, target: Path) -> Path:
    return save(draw_time_series(f), target)


def draw_loads(f: h5py.File) -> Figure | None:
    """Loads against time: hydrodynamic forces and moments on the bodies, PTO forces (N) and torques (N m), joint
    reaction forces and moments (world components on body 2 from body 1), mooring fairlead tensions; None when the
    file holds none."""
    scenario = stored_scenario(f)
    t = f["time"][()]
    panels: list[tuple[str, list[tuple[str, np.ndarray]]]] = []
    bodies = [b for b in _bodies(f, scenario) if f"bodies/{b}/hydro_force" in f]
    hydro = {b: f[f"bodies/{b}/hydro_force"][()] for b in bodies}
    for columns, what, unit in ((range(3), "hydrodynamic force", "N"), (range(3, 6), "hydrodynamic moment", "N m")):
        lines = [(f"{b} {DOFS[j]}", h[:, j]) for b, h in hydro.items() for j in _active(h, columns)]
        if lines:
            panels.append((f"{what} ({unit})", lines))
    if "ptos" in f:
        from .datasets import pto_force_unit

        by_unit: dict[str, list[tuple[str, np.ndarray]]] = {}
        for name in f["ptos"]:
            if f"ptos/{name}/force" in f:
                by_unit.setdefault(pto_force_unit(scenario, name), []).append((name, f[f"ptos/{name}/force"][()]))
        for unit, lines in by_unit.items():
            what = {"N": "PTO force", "N m": "PTO torque"}.get(unit, "PTO force or torque")
            panels.append((f"{what} ({unit})", lines))
    for key, what, unit in (("force", "joint reaction force", "N"), ("moment", "joint reaction moment", "N m")):
        lines = []
        for j in f.get("joints", {}):
            if f"joints/{j}/{key}" in f:
                r = f[f"joints/{j}/{key}"][()]
                scale = float(np.max(np.abs(r))) if r.size else 0.0
                lines += [(f"{j} {'xyz'[i]}", r[:, i]) for i in range(3) if np.max(np.abs(r[:, i])) > 1e-9 * scale]
        if lines:
            panels.append((f"{what} ({unit})", lines))
    moorings = [(n, np.linalg.norm(f[f"forces/{n}/force"][()], axis=1)) for n in f.get("forces", {})
                if f"forces/{n}/force" in f]
    if moorings:
        panels.append(("fairlead tension (N)", moorings))
    if not panels:
        return None
    fig, axes = stacked(len(panels))
    for ax, (label, lines) in zip(axes, panels, strict=True):
        what, _, unit = label.rpartition(" (")
        factor, shown = scaled(np.array([y for _, y in lines]), unit.rstrip(")"))
        for name, y in lines:
            ax.plot(t, y / factor, label=name)
        ax.set_ylabel(f"{what} ({shown})")
    title(fig, scenario, "loads", "; ".join(x for x in (sea_text(scenario), run_text(f, scenario)) if x),
          str(f.attrs.get("status", "")))
    return finish(fig, axes, "time (s)")


ENERGY_TERMS = (("work_in", "work in (excitation)"), ("pto", "PTO"), ("radiated", "radiated"),
                ("dissipated", "dissipated (viscous, ropes, dampers)"), ("stored", "stored (change)"))


def draw_energy(f: h5py.File) -> Figure:
    """The wave-to-wire energy account against time: the work the waves did and where it went (PTO, radiated,
    dissipated, stored), and the balance's residual relative to the work in."""
    from .energy import energy_terms

    plt = pyplot()
    scenario = stored_scenario(f)
    t = f["time"][()]
    terms = energy_terms({f"energy/{name}": f[f"energy/{name}"][()] for name in f["energy"]})
    fig, axes = plt.subplots(2, 1, figsize=(WIDTH, 7), sharex=True, height_ratios=(2, 1), layout="constrained")
    factor, unit = scaled(np.array([terms[k] for k, _ in ENERGY_TERMS]), "J")
    for key, label in ENERGY_TERMS:
        axes[0].plot(t, terms[key] / factor, label=f"{label}: {terms[key][-1] / factor:.4g} {unit} at the end")
    axes[0].plot(t, (terms["pto"] + terms["radiated"] + terms["dissipated"] + terms["stored"]) / factor, "k:",
                 label="PTO + radiated + dissipated + stored")
    work = np.abs(terms["work_in"])
    relative = np.divide(terms["residual"], work, out=np.full_like(work, np.nan), where=work > 0.01 * work.max())
    axes[1].plot(t, 100 * relative, color="tab:red",
                 label=f"residual / work in: {100 * relative[-1]:.3g} % at the end")
    axes[0].set_ylabel(f"energy ({unit})")
    axes[1].set_ylabel("residual (%)")
    title(fig, scenario, "wave-to-wire energy account",
          "; ".join(x for x in (sea_text(scenario), run_text(f, scenario)) if x), str(f.attrs.get("status", "")))
    return finish(fig, list(axes), "time (s)")


def plot_energy(f: h5py.File, target: Path) -> Path:
    return save(draw_energy(f), target)


def mean_powers_of(f: h5py.File) -> tuple[dict[str, float], str]:
    """The PTOs' mean power over the run summary's window (:func:`analysis.mean_pto_powers`), from the
    scenario stored in the file; none if the file holds no readable scenario."""
    from .analysis import mean_pto_powers

    scenario = stored_scenario(f)
    if scenario is None:
        return {}, ""
    try:
        return mean_pto_powers(scenario, f)
    except (KeyError, ValueError, TypeError):
        return {}, ""
