"""Figures of the frequency-domain files: RAOs (``wec-cosim rao``), their heading sweep, chosen joint coordinates'
RAOs of one or more RAO files (``wec-cosim plot --joints``) and the pseudo-spectral steady state (``wec-cosim
steady``). The conventions of :mod:`.plotting`: one unit per axis, angles in degrees (amplitudes in deg/m), phases
unwrapped along the frequency (continuous curves instead of jumps at +-180 deg), titles naming the scenario and the
settings, legends outside the data."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import TYPE_CHECKING

import h5py
import numpy as np

from orchestrator.errors import WecCosimError
from orchestrator.scenario import DOFS

from .figures import (
    WIDTH,
    angle_or_length,
    finish,
    legend_outside,
    pyplot,
    save,
    scaled,
    sea_text,
    stacked,
    stored_scenario,
    title,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from orchestrator.scenario import Scenario


def phase_deg(values: np.ndarray) -> np.ndarray:
    """Phase in degrees, unwrapped along the first axis (the frequency)."""
    return np.degrees(np.unwrap(np.angle(values), axis=0))


def _text(value: object) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


def _rao_settings(f: h5py.File, scenario: Scenario | None) -> str:
    parts = [f"{_text(f.attrs.get('form', '?')).upper()} form", f"heading {float(f.attrs.get('heading_deg', 0)):g} deg"]
    if scenario is not None and scenario.waves.kind == "irregular":
        parts.append(f"irregular statistics in the {sea_text(scenario)}")
    return ", ".join(parts) + "; per metre of wave amplitude, exp(+i omega t)"


def _coordinates(f: h5py.Group, j: str, scenario: Scenario | None, key: str = "rao") -> list[tuple[str, str, str]]:
    from .datasets import joint_coordinate_labels

    ds = f[f"joints/{j}/{key}"]
    stored = [_text(c) for c in ds.attrs.get("coordinates", [])]
    labels = joint_coordinate_labels(scenario, j, ds.shape[-1])
    return [(lab, stored[k] if k < len(stored) else name, unit) for k, (lab, name, unit) in enumerate(labels)]


def draw_rao(f: h5py.File) -> Figure:
    """Amplitude (translations m/m, rotations and joint angles deg/m, joint displacements m/m) and unwrapped phase
    of every active RAO, and the mean PTO power per m^2 of wave amplitude."""
    scenario = stored_scenario(f)
    omega = f["omega"][()]
    series: list[tuple[str, str, np.ndarray]] = []  # (label, unit per metre, complex RAO)
    for name in f.get("bodies", {}):
        rao = f[f"bodies/{name}/rao"][()]
        for j in [j for j in range(6) if np.any(np.abs(rao[:, j]) > 0)]:
            series.append((f"{name} {DOFS[j]}", "m/m" if j < 3 else "rad/m", rao[:, j]))
    for j in f.get("joints", {}):
        if f"joints/{j}/rao" in f:
            rao = f[f"joints/{j}/rao"][()]
            for k, (label, coordinate, unit) in enumerate(_coordinates(f, j, scenario)):
                series.append((f"{label} {coordinate}", f"{unit or 'm'}/m", rao[:, k]))
    amplitude_axes = list(dict.fromkeys(unit for _, unit, _ in series))
    ptos = list(f.get("ptos", {}))
    fig, axes = stacked(len(amplitude_axes) + 1 + bool(ptos))
    for ax, unit in zip(axes, amplitude_axes, strict=False):
        factor, shown = angle_or_length(unit)
        for label, u, rao in series:
            if u == unit:
                ax.plot(omega, np.abs(rao) * factor, label=label)
        kinds = {"m/m": "translation", "deg/m": "rotation or angle"}.get(shown, "")
        ax.set_ylabel(f"|RAO| {kinds} ({shown})".replace("|RAO|  ", "|RAO| "))
    phase_ax = axes[len(amplitude_axes)]
    for label, _, rao in series:
        phase_ax.plot(omega, phase_deg(rao), label=label)
    phase_ax.set_ylabel("phase, unwrapped (deg)")
    if ptos:
        power = {name: f[f"ptos/{name}/mean_power"][()] for name in ptos}
        if len(ptos) > 6:
            power = {f"total of {len(ptos)} PTOs": np.sum(list(power.values()), axis=0)}
        factor, unit = scaled(np.array(list(power.values())), "W")
        for name, p in power.items():
            axes[-1].plot(omega, p / factor, label=name)
        axes[-1].set_ylabel(f"mean power ({unit} per m^2)")
    title(fig, scenario, "response amplitude operators", _rao_settings(f, scenario))
    return finish(fig, axes, "wave frequency (rad/s)")


def draw_heading_sweep(f: h5py.File) -> Figure:
    """One column per heading of a RAO file's heading sweep: joint coordinate RAOs (deg/m or m/m), every body's
    heave RAO (m/m), and the mean PTO power per m^2 of wave amplitude."""
    plt = pyplot()
    scenario = stored_scenario(f)
    omega = f["omega"][()]
    g = f["heading_sweep"]
    headings = g["headings_deg"][()]
    rows: list[tuple[str, str]] = []  # (panel, unit)
    if "joints" in g:
        units = {angle_or_length(u or "m")[1] for j in g["joints"] for _, _, u in _coordinates(g, j, scenario)}
        rows += [("joints", u) for u in sorted(units)]
    if "bodies" in g:
        rows.append(("bodies", "m"))
    if "ptos" in g:
        rows.append(("ptos", "W"))
    fig, axes = plt.subplots(len(rows), len(headings), figsize=(4.2 * len(headings) + 2.5, 3.0 * len(rows) + 1.2),
                             sharex=True, sharey="row", squeeze=False, layout="constrained")
    power_factor, power_unit = scaled(np.array([g[f"ptos/{p}/mean_power"][()] for p in g.get("ptos", {})]), "W") \
        if "ptos" in g else (1.0, "W")
    for k, heading in enumerate(headings):
        for row, (panel, unit) in enumerate(rows):
            ax = axes[row, k]
            if panel == "joints":
                for name in g["joints"]:
                    values = g[f"joints/{name}/rao"][k]
                    for i, (label, coordinate, u) in enumerate(_coordinates(g, name, scenario)):
                        factor, shown = angle_or_length(u or "m")
                        if shown == unit:
                            ax.plot(omega, np.abs(values[:, i]) * factor, label=f"{label} {coordinate}")
            elif panel == "bodies":
                for name in g["bodies"]:
                    ax.plot(omega, np.abs(g[f"bodies/{name}/rao"][k, :, 2]), label=f"{name} heave")
            else:
                for name in g["ptos"]:
                    ax.plot(omega, g[f"ptos/{name}/mean_power"][k] / power_factor, label=name)
            ax.grid(True, alpha=0.3)
        axes[0, k].set_title(f"heading {heading:g} deg")
        axes[-1, k].set_xlabel("wave frequency (rad/s)")
    labels = {"joints": "|joint RAO| ({u}/m)", "bodies": "|heave RAO| (m/m)", "ptos": "mean power ({p} per m^2)"}
    for row, (panel, unit) in enumerate(rows):
        axes[row, 0].set_ylabel(labels[panel].format(u=unit, p=power_unit))
        legend_outside(axes[row, -1], fontsize=7)
    title(fig, scenario, "RAOs across wave headings", f"{_text(f.attrs.get('form', '?')).upper()} form; per metre "
                                                      "of wave amplitude")
    return fig


def joint_selection(text: str) -> tuple[str, int | None]:
    """``NAME[k]`` (k 1-based, as the FMU's ``NAME.coordinate[k]``) -> (name, k - 1); ``NAME`` -> (name, None):
    every coordinate of the joint."""
    name, bracket, rest = text.partition("[")
    try:
        k = int(rest.rstrip("]")) if bracket else None
    except ValueError:
        raise WecCosimError(f"plot: joint coordinate {text!r} is not NAME or NAME[k]") from None
    if not name or (k is not None and k < 1):
        raise WecCosimError(f"plot: joint coordinate {text!r} is not NAME or NAME[k] with k >= 1")
    return name, None if k is None else k - 1


def joints_file_name(files: list[str | Path], joints: list[str]) -> str:
    """The PNG name of ``wec-cosim plot --joints``: the files' stems and the selection (``hinge`` and ``hinge[1]``
    are different selections, so different files)."""
    stems = "_".join(Path(f).stem for f in files)
    chosen = "_".join(re.sub(r"[^A-Za-z0-9_.-]+", "-", j).strip("-") for j in joints)
    return f"{stems}_joints_{chosen}.png"


def draw_joint_raos(files: list[str | Path], joints: list[str]) -> Figure:
    """Amplitude and unwrapped phase of chosen joint coordinates' RAOs (``NAME``: all of the joint's, ``NAME[k]``:
    the k-th) of one or more RAO files in one figure (e.g. the same node's relative pitch in two devices); a joint
    a file lacks is skipped there, a joint no file has is an error."""
    curves: list[tuple[str, str, np.ndarray, np.ndarray]] = []  # (label, unit per metre, omega, RAO)
    found = set()
    scenarios = []
    for path in map(Path, files):
        if not path.is_file():
            raise WecCosimError(f"plot: file {path} does not exist")
        with h5py.File(path, "r") as f:
            if "omega" not in f:
                raise WecCosimError(f"plot: {path} is not a RAO file (no /omega); joint RAOs come from "
                                    "`wec-cosim rao`")
            scenario = stored_scenario(f)
            scenarios.append(scenario.name if scenario else path.stem)
            omega = f["omega"][()]
            for text in joints:
                name, k = joint_selection(text)
                key = f"joints/{name}/rao"
                if key not in f:
                    continue
                coordinates = _coordinates(f, name, scenario)
                chosen = range(len(coordinates)) if k is None else [k] if k < len(coordinates) else []
                rao = f[key][()]
                for i in chosen:
                    found.add(text)
                    label, coordinate, unit = coordinates[i]
                    curves.append((f"{path.stem}: {label} ({coordinate})", f"{unit or 'm'}/m", omega, rao[:, i]))
    missing = [j for j in joints if j not in found]
    if missing:
        raise WecCosimError(f"plot: no file given has the joint coordinate(s) {', '.join(missing)}")
    units = list(dict.fromkeys(unit for _, unit, _, _ in curves))
    fig, axes = stacked(len(units) + 1)
    for ax, unit in zip(axes, units, strict=False):
        factor, shown = angle_or_length(unit)
        for label, u, omega, rao in curves:
            if u == unit:
                ax.plot(omega, np.abs(rao) * factor, label=label)
        ax.set_ylabel(f"|joint RAO| ({shown})")
    for label, _, omega, rao in curves:
        axes[-1].plot(omega, phase_deg(rao), label=label)
    axes[-1].set_ylabel("phase, unwrapped (deg)")
    title(fig, None, f"joint coordinate RAOs of {', '.join(dict.fromkeys(scenarios))}",
          f"{', '.join(joints)}; per metre of wave amplitude")
    return finish(fig, axes, "wave frequency (rad/s)")


def plot_joint_raos(files: list[str | Path], joints: list[str], target: str | Path) -> Path:
    return save(draw_joint_raos(files, joints), Path(target))


def draw_steady(f: h5py.File) -> Figure:
    """One period of every active DOF for each solved wave period (``wec-cosim steady``): translations (m) and
    rotations (deg) side by side."""
    plt = pyplot()
    scenario = stored_scenario(f)
    groups = [f[f"periods/{k}"] for k in sorted(f["periods"], key=int)]
    fig, axes = plt.subplots(len(groups), 2, figsize=(WIDTH + 3, 3.0 * len(groups) + 1.2), squeeze=False,
                             layout="constrained")
    for row, g in zip(axes, groups, strict=True):
        t = g["time"][()]
        for col, (columns, factor, unit) in enumerate(((range(3), 1.0, "m"), (range(3, 6), 180 / math.pi, "deg"))):
            ax = row[col]
            for name in g["bodies"]:
                y = g[f"bodies/{name}/one_period"][()]
                for j in [j for j in columns if np.any(y[:, j])]:
                    ax.plot(t, y[:, j] * factor, label=f"{name} {DOFS[j]}")
            ax.set_ylabel(f"{'translation' if unit == 'm' else 'rotation'} ({unit})")
            ax.set_xlabel("time within the period (s)")
            ax.grid(True, alpha=0.3)
            legend_outside(ax, fontsize=7)
        period = 2 * math.pi / float(g.attrs["omega"])
        row[0].set_title(f"T = {period:.4g} s (omega = {g.attrs['omega']:.4g} rad/s), {g.attrs['harmonics']} "
                         f"harmonics, residual {g.attrs['residual']:.2g}", fontsize=9, loc="left")
    sea = f"wave height {2 * float(groups[0].attrs['amplitude']):g} m" if groups else ""
    title(fig, scenario, "periodic steady state (pseudo-spectral)",
          f"{_text(f.attrs.get('form', '?')).upper()} form, {f.attrs.get('harmonics', '?')} harmonics; {sea}")
    return fig
