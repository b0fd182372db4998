"""The wec-cosim command line as a user runs it (separate processes), results file layout."""

from __future__ import annotations

import os
import subprocess
import sys

import h5py
import numpy as np
import pytest

from orchestrator.reference import frequency_domain
from orchestrator.results.analysis import averaging_window
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import ROOT, SCENARIOS


def wec_cosim(*args: str, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "wec_cosim.cli", *args], capture_output=True, text=True,
                          cwd=cwd or ROOT, env=os.environ.copy(), timeout=600)


@pytest.fixture(scope="module")
def run_output(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "cyl.h5"
    proc = wec_cosim("run", str(SCENARIOS / "cylinder_regular.toml"), "--out", str(out), "--quiet")
    return proc, out


def test_run_prints_summary_against_exact_answer(run_output) -> None:
    proc, _ = run_output
    assert proc.returncode == 0, proc.stderr
    for text in ("float heave", "pto mean power", "exact", "real-time factor", "wall time"):
        assert text in proc.stdout


def test_results_file_layout(run_output) -> None:
    _, out = run_output
    scenario = load_scenario(SCENARIOS / "cylinder_regular.toml")
    n = int(round(scenario.simulation.duration / scenario.simulation.step)) + 1
    with h5py.File(out) as f:
        assert f["time"].shape == (n,)
        for key in ("displacement", "velocity", "hydro_force"):
            assert f[f"bodies/float/{key}"].shape == (n, 6)
        assert f["ptos/pto/force"].shape == (n,) and f["ptos/pto/power"].shape == (n,)
        assert f["wave/elevation"].shape == (n,)
        assert f.attrs["status"] == "completed" and f.attrs["wall_time"] > 0
        assert "cylinder_regular" in f.attrs["scenario"] and "pythonfmu" in f.attrs["versions"]
        assert '"master": "jacobi"' in f.attrs["settings"]
        d = f["bodies/float/displacement"][()]
        assert not d[:, [0, 1, 3, 4, 5]].any()  # inactive DOFs stay zero
        # PTO force is -c v on the heave velocity, power is c v^2.
        v = f["bodies/float/velocity"][:, 2]
        np.testing.assert_allclose(f["ptos/pto/force"][()], -2.0e5 * v, rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(f["ptos/pto/power"][()], 2.0e5 * v**2, rtol=1e-12, atol=1e-9)
        eta = f["wave/elevation"][()]
        t = f["time"][()]
        np.testing.assert_allclose(eta[t > 20], 0.5 * np.cos(2 * np.pi / 5.6 * t[t > 20]), atol=1e-12)


def test_plot_mean_power_uses_the_summarys_window(run_output, tmp_path) -> None:
    """The figure's mean PTO power is the summary's (the last steady_periods wave periods, one function for
    both), not the mean over the whole run, which includes the 20 s ramp from rest."""
    from orchestrator.results.plotting import mean_powers_of, plot_file

    proc, out = run_output
    line = next(x for x in proc.stdout.splitlines() if "pto mean power" in x)
    printed = float(line.split()[3])  # quantity (3 words), co-simulation value (%.5g), unit, exact, ...
    scenario = load_scenario(SCENARIOS / "cylinder_regular.toml")
    with h5py.File(out) as f:
        means, where = mean_powers_of(f)
        t, power = f["time"][()], f["ptos/pto/power"][()]
    assert means["pto"] == pytest.approx(printed, rel=1e-4)
    assert where.startswith("last 10 wave periods")
    mask, _ = averaging_window(scenario, t)
    assert t[mask][0] == pytest.approx(t[-1] - 10 * 5.6, abs=0.1) and t[mask][-1] == t[-1]
    assert abs(np.mean(power) / means["pto"] - 1) > 0.05  # what the figure showed before: the ramp included
    assert [p.name for p in plot_file(out, tmp_path)] == ["cyl_timeseries.png", "cyl_loads.png"]


def test_averaging_window_after_the_ramp_when_there_is_no_wave_period() -> None:
    scenario = load_scenario(SCENARIOS / "cylinder_irregular.toml")
    t = np.arange(0.0, 2 * scenario.ramp_time, 0.5)
    mask, where = averaging_window(scenario, t)
    assert where == f"after the {scenario.ramp_time:g} s wave ramp"
    np.testing.assert_array_equal(mask, t >= scenario.ramp_time)
    mask, where = averaging_window(scenario, t[t < scenario.ramp_time / 2])
    assert mask.all() and where == "whole run (shorter than the wave ramp)"


def test_rao_command_matches_frequency_domain(tmp_path) -> None:
    out = tmp_path / "rao.h5"
    proc = wec_cosim("rao", str(SCENARIOS / "cylinder_regular.toml"), "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    scene = load_scene(load_scenario(SCENARIOS / "cylinder_regular.toml"), log=None)
    with h5py.File(out) as f:
        omega = f["omega"][()]
        rao = f["bodies/float/rao"][()]
        power = f["ptos/pto/mean_power"][()]
    assert rao.shape == (len(omega), 6) and rao.dtype == complex
    fd = frequency_domain.solve(scene, omega)
    np.testing.assert_allclose(rao[:, 2], fd.rao[:, 0])
    np.testing.assert_allclose(power, 0.5 * omega**2 * 2.0e5 * np.abs(rao[:, 2]) ** 2)
    # Long-wave limit: the float follows the surface (heave RAO -> 1).
    assert abs(rao[0, 2]) == pytest.approx(1.0, abs=0.01)


def test_hydro_and_build_fmus_commands(tmp_path) -> None:
    proc = wec_cosim("hydro", str(SCENARIOS / "cylinder_regular.toml"))
    assert proc.returncode == 0, proc.stderr
    assert "cached hydrodynamic database" in proc.stdout  # the bundled database: no BEM solve
    proc = wec_cosim("build-fmus", str(SCENARIOS / "cylinder_regular.toml"), "--out", str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "cylinder_regular_hydro.fmu").is_file() and (tmp_path / "cylinder_regular_mbd.fmu").is_file()


@pytest.mark.parametrize("content, fragment", [
    ("[simulation]\nduration = 10.0\nstep = 0.1\nbogus = 1\n", "unknown key 'simulation.bogus'"),
    ("[simulation]\nduration = 'long'\n", "simulation.duration: expected a number"),
])
def test_user_errors_print_one_paragraph_without_traceback(tmp_path, content, fragment) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(content)
    proc = wec_cosim("run", str(path))
    assert proc.returncode == 2
    assert fragment in proc.stderr and str(path) in proc.stderr
    assert "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1


def test_missing_scenario_file_is_a_clear_error(tmp_path) -> None:
    proc = wec_cosim("run", str(tmp_path / "none.toml"))
    assert proc.returncode == 2 and "does not exist" in proc.stderr and "Traceback" not in proc.stderr
