"""Figures an engineer would publish, read back from the matplotlib figures themselves: one unit per axis (metres
apart from degrees, newtons apart from newton metres), angles in degrees in every figure, the recorded joint angles,
reactions, PTO forces and powers drawn, unwrapped phases, titles naming the scenario and its settings, legends
outside the data; ``--joints hinge`` and ``hinge[1]`` write different files.

Files come from real runs (the hinge barge for 4 s, its RAOs, the two floats' frequency-domain sweep); the drawn
values are compared with the files' own (radians times 180/pi where a figure shows degrees)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

import wec_cosim as wc
from orchestrator.results import plotting, response_plots

ROOT = Path(__file__).resolve().parent.parent
SCENARIOS = ROOT / "scenarios"
UNIT = re.compile(r"\(([^()]*)\)$")


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("figures")
    hinge = wc.apply_overrides(SCENARIOS / "hinge_barge.toml", {"simulation.duration": 4.0})
    wc.run(hinge, folder / "hinge.h5", progress=False, log=None, in_process=True)
    wc.rao(SCENARIOS / "hinge_barge.toml", folder / "hinge_rao.h5", progress=False, log=None)
    wc.sweep(SCENARIOS / "two_floats.toml", folder / "sweep.h5", progress=False, log=None)
    return {"run": folder / "hinge.h5", "rao": folder / "hinge_rao.h5", "sweep": folder / "sweep.h5",
            "folder": folder}


def labels(fig) -> list[str]:  # noqa: ANN001 - matplotlib Figure
    return [ax.get_ylabel() for ax in fig.axes if ax.get_ylabel()]


def one_unit(label: str) -> str:
    """The unit in the label's closing parentheses: exactly one, never a list of units."""
    found = UNIT.search(label)
    assert found, f"no unit in {label!r}"
    unit = found.group(1)
    assert "," not in unit and " or " not in unit, f"two units on one axis: {label!r}"
    return unit


def legends_outside(fig) -> None:  # noqa: ANN001
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    shown = 0
    for ax in fig.axes:
        legend = ax.get_legend()
        if legend is not None:
            shown += 1
            assert legend.get_window_extent(renderer).x0 >= ax.get_window_extent(renderer).x1, ax.get_ylabel()
    assert shown


def test_time_series_one_unit_per_axis_with_joint_angle_and_degrees(files) -> None:
    with h5py.File(files["run"], "r") as f:
        fig = plotting.draw_time_series(f)
        pitch = f["bodies/barge1/displacement"][:, 4]
        angle = f["joints/hinge/coordinate"][:, 0]
    found = labels(fig)
    assert found == ["wave elevation (m)", "body translation (m)", "body rotation (deg)", "joint angle (deg)",
                     "PTO power (W)"]
    for label in found:
        one_unit(label)
    axis = {ax.get_ylabel(): ax for ax in fig.axes}
    drawn = {line.get_label(): line.get_ydata() for line in axis["body rotation (deg)"].get_lines()}
    np.testing.assert_allclose(drawn["barge1 pitch"], np.degrees(pitch), rtol=1e-12)
    drawn = {line.get_label(): line.get_ydata() for line in axis["joint angle (deg)"].get_lines()}
    np.testing.assert_allclose(drawn["hinge[1] (angle)"], np.degrees(angle), rtol=1e-12)
    heading = fig._suptitle.get_text()
    assert heading.startswith("hinge_barge: motions and power")
    assert "regular waves H = 0.02 m, T = 2 s" in heading and "jacobi master, step 0.02 s" in heading
    legends_outside(fig)
    plotting.pyplot().close(fig)


def test_loads_have_hydro_pto_and_joint_reactions_each_on_its_unit(files) -> None:
    with h5py.File(files["run"], "r") as f:
        fig = plotting.draw_loads(f)
        reaction = f["joints/hinge/force"][()]
    found = labels(fig)
    assert found == ["hydrodynamic force (N)", "hydrodynamic moment (N m)", "PTO force (N)",
                     "joint reaction force (N)"]
    axis = {ax.get_ylabel(): ax for ax in fig.axes}
    drawn = {line.get_label(): line.get_ydata() for line in axis["joint reaction force (N)"].get_lines()}
    np.testing.assert_allclose(drawn["hinge x"], reaction[:, 0], rtol=1e-12)
    assert fig._suptitle.get_text().startswith("hinge_barge: loads")
    legends_outside(fig)
    plotting.pyplot().close(fig)


def test_rao_figure_degrees_per_metre_unwrapped_phase_and_a_title(files) -> None:
    with h5py.File(files["rao"], "r") as f:
        fig = response_plots.draw_rao(f)
        hinge = f["joints/hinge/rao"][:, 0]
    found = labels(fig)
    assert found[:3] == ["|RAO| translation (m/m)", "|RAO| rotation or angle (deg/m)", "phase, unwrapped (deg)"]
    assert re.fullmatch(r"mean power \((W|kW|MW) per m\^2\)", found[3])
    axis = {ax.get_ylabel(): ax for ax in fig.axes}
    drawn = {line.get_label(): line.get_ydata() for line in axis["|RAO| rotation or angle (deg/m)"].get_lines()}
    np.testing.assert_allclose(drawn["hinge[1] angle"], np.degrees(np.abs(hinge)), rtol=1e-12)
    phases = {line.get_label(): np.asarray(line.get_ydata()) for line in axis["phase, unwrapped (deg)"].get_lines()}
    for phase in phases.values():
        assert np.all(np.abs(np.diff(phase)) <= 180 + 1e-9)  # never a jump of a whole turn
    assert np.ptp(phases["hinge[1] angle"]) > 360  # a phase that a wrapped plot would have cut
    wrapped = np.degrees(np.angle(hinge))
    assert np.max(np.abs(np.diff(wrapped))) > 180  # (and did cut: the figure of earlier versions)
    heading = fig._suptitle.get_text()
    assert heading.startswith("hinge_barge: response amplitude operators") and "DAE form, heading 0 deg" in heading
    legends_outside(fig)
    plotting.pyplot().close(fig)


def test_no_figure_puts_radians_on_an_axis(files) -> None:
    """One convention across figures: angles in degrees (the frequency axes are rad/s)."""
    figures = []
    with h5py.File(files["run"], "r") as f:
        figures += [plotting.draw_time_series(f), plotting.draw_loads(f), plotting.draw_energy(f)]
    with h5py.File(files["rao"], "r") as f:
        figures.append(response_plots.draw_rao(f))
    figures.append(response_plots.draw_joint_raos([files["rao"]], ["hinge"]))
    for fig in figures:
        for ax in fig.axes:
            for label in (ax.get_ylabel(), ax.get_xlabel()):
                assert "rad" not in label.replace("rad/s", ""), label
        plotting.pyplot().close(fig)


def test_joint_selections_write_their_own_files(files) -> None:
    """``--joints hinge`` (every coordinate of the joint) and ``hinge[1]`` (the first) are two files."""
    out = files["folder"] / "joints"
    written = []
    for selection in ("hinge", "hinge[1]"):
        done = subprocess.run([sys.executable, "-m", "wec_cosim", "plot", str(files["rao"]), "--joints", selection,
                               "--out", str(out)], capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, done.stderr
        written.append(Path(done.stdout.strip()))
    assert written[0] != written[1] and all(p.is_file() for p in written)
    assert [p.name for p in written] == ["hinge_rao_joints_hinge.png", "hinge_rao_joints_hinge-1.png"]
    fig = response_plots.draw_joint_raos([files["rao"]], ["hinge"])
    assert labels(fig) == ["|joint RAO| (deg/m)", "phase, unwrapped (deg)"]
    plotting.pyplot().close(fig)


def test_sweep_heat_map_names_the_scenario_settings_and_keys(files) -> None:
    from wec_cosim.sweeps.plotting import draw_sweep

    with h5py.File(files["sweep"], "r") as f:
        fig = draw_sweep(f)
    heading = fig._suptitle.get_text()
    assert heading.startswith("two_floats: power matrix\nexact linear frequency domain, regular waves H = ")
    assert "pto_aft damping 60000 N s/m" in heading
    ylabels = [ax.get_ylabel() for ax in fig.axes if ax.get_xlabel()]
    xlabels = [ax.get_xlabel() for ax in fig.axes if ax.get_xlabel()]
    assert set(ylabels) == {"pto_fore damping, ptos.pto_fore.damping (N s/m)"}
    assert set(xlabels) == {"wave period, waves.period (s)"}
    colour_bars = [ax.get_ylabel() for ax in fig.axes if not ax.get_xlabel()]
    assert colour_bars[0] in ("mean power (W)", "mean power (kW)") and colour_bars[1] == "capture width (m)"
    plotting.pyplot().close(fig)
