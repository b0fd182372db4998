"""One scene file drives the run, the RAOs and the sweep; the sweep's grid, seeds, file and plots.

The Dask runs (distribution, a killed worker, an interrupted and resumed sweep) are in test_sweeps_dask.py.
"""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest
from matplotlib.image import imread

from orchestrator.errors import ScenarioError, WecCosimError
from orchestrator.results.plotting import plot_file
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene
from wec_cosim.cli import main
from wec_cosim.sweeps import run_sweep
from wec_cosim.sweeps.grid import parse_grid_option, plan_sweep, set_grid
from wec_cosim.sweeps.plotting import DRAWERS

from .conftest import SCENARIOS
from .test_cli import wec_cosim


def _fd_power(hdb, omega: float, damping: float, stiffness: float, amplitude: float) -> float:
    """Mean power of a heave-only body with a linear PTO in a regular wave, from the database alone:
    P = c w^2 |F|^2 a^2 / (2 ((C + k - w^2 (M + A))^2 + w^2 (B + c)^2)) at a database frequency."""
    k = int(np.argmin(np.abs(hdb.omega - omega)))
    assert abs(hdb.omega[k] - omega) < 1e-12
    mass = hdb.rho * float(hdb.displaced_volume[0])
    a33, b33 = hdb.added_mass[k, 2, 2], hdb.radiation_damping[k, 2, 2]
    c33 = hdb.hydrostatic_stiffness[0, 2, 2]
    f = abs(hdb.excitation[0, k, 2])
    real = c33 + stiffness - omega**2 * (mass + a33)
    return damping * omega**2 * f**2 * amplitude**2 / (2 * (real**2 + omega**2 * (b33 + damping) ** 2))


def test_two_dimensional_pto_grid_is_the_single_dof_closed_form(tmp_path) -> None:
    """Mean power against PTO stiffness and damping (the arrays' PTO study) equals the closed form of the
    heave equation built from the database's A, B, C and F, cell by cell; the best damping at zero
    stiffness is the radiation impedance |Z_i| (the optimum of a passive damper)."""
    s = load_scenario(SCENARIOS / "cylinder_regular.toml")
    omega = 0.8
    s.waves.period = 2 * math.pi / omega
    dampings = [5e4, 1e5, 2e5, 4e5, 8e5]
    stiffnesses = [0.0, 1e5, 3e5]
    s.sweep.grid = {"ptos": {"pto": {"stiffness": stiffnesses, "damping": dampings}}}
    out = run_sweep(s, tmp_path / "pto.h5", progress=False, log=None)
    assert out.ran == 15 and out.failed == 0
    hdb = load_scene(s, log=None).hdb
    with h5py.File(out.path) as f:
        power = f["matrices/mean_power"][()]
        assert power.shape == (3, 5)
        assert list(f["matrices/axes/1"][()]) == dampings and f["matrices/axes/0"].attrs["key"] == "ptos.pto.stiffness"
        expected = [[_fd_power(hdb, omega, c, k, s.waves.height / 2) for c in dampings] for k in stiffnesses]
        np.testing.assert_allclose(power, expected, rtol=1e-9)
        # A linear damper's power c qdot^2 peaks at twice its mean (no stiffness).
        np.testing.assert_allclose(f["matrices/ptos/pto/max_power"][0], 2 * power[0], rtol=1e-12)
        width = f["matrices/capture_width"][()]
        rho, g = hdb.rho, hdb.g
        incident = rho * g**2 / (4 * omega) * (s.waves.height / 2) ** 2  # deep water, (1/2) rho g a^2 c_g
        np.testing.assert_allclose(width, power / incident, rtol=1e-9)


def test_time_domain_sweep_agrees_with_frequency_domain_sweep(tmp_path) -> None:
    """Same [sweep] table, two methods: co-simulated steady power within 3 % of the exact linear one."""
    s = load_scenario(SCENARIOS / "two_floats.toml")
    set_grid(s, "ptos.pto_fore.damping", [2.0e4, 1.2e5])
    set_grid(s, "waves.period", [5.0])
    tables = {}
    for method in ("frequency_domain", "time_domain"):
        s.sweep.method = method
        out = run_sweep(s, tmp_path / f"{method}.h5", in_process=True, progress=False, log=None)
        with h5py.File(out.path) as f:
            tables[method] = {p: f[f"matrices/ptos/{p}/mean_power"][()] for p in ("pto_fore", "pto_aft")}
            assert f["matrices/bodies/fore/significant"].shape == (2, 1, 6)
    for p in ("pto_fore", "pto_aft"):
        np.testing.assert_allclose(tables["time_domain"][p], tables["frequency_domain"][p], rtol=0.03)
    fore = tables["frequency_domain"]["pto_fore"][:, 0]
    assert fore[0] != pytest.approx(fore[1], rel=0.05)  # the swept key really changed the answer


def test_resume_runs_only_new_cases_and_a_failing_case_does_not_stop_the_others(tmp_path) -> None:
    s = load_scenario(SCENARIOS / "two_floats.toml")
    set_grid(s, "waves.heading_deg", [0.0, 90.0])  # the database has heading 0 only: heading 90 fails
    out = tmp_path / "sweep.h5"
    first = run_sweep(s, out, progress=False, log=None)
    assert (first.already, first.ran, first.failed) == (0, 18, 9)
    with h5py.File(out) as f:
        failed = [g for g in f["cases"].values() if g.attrs["status"] == "failed"]
        assert len(failed) == 9 and all("heading" in g.attrs["error"] for g in failed)
        assert np.all(np.isnan(f["matrices/mean_power"][:, :, 1])) and np.all(f["matrices/failed"][:, :, 1] == 1)
        assert np.all(np.isfinite(f["matrices/mean_power"][:, :, 0]))
        assert f.attrs["status"] == "completed, 9 cases failed"
    set_grid(s, "waves.period", [4.0, 5.0, 6.0, 7.0])  # one more period: only its 6 cases run
    second = run_sweep(s, out, progress=False, log=None)
    assert (second.already, second.ran, second.failed) == (18, 6, 3)
    set_grid(s, "waves.heading_deg", [0.0])
    third = run_sweep(s, out, progress=False, log=None)
    assert (third.already, third.ran) == (12, 0)
    set_grid(s, "waves.heading_deg", [0.0, 90.0])
    retry = run_sweep(s, out, retry_failed=True, progress=False, log=None)
    assert (retry.already, retry.ran, retry.failed) == (12, 12, 12)
    with h5py.File(out) as f:
        assert len(f["cases"]) == 24 and f.attrs["sessions"] == 4
        assert sorted(g.attrs["session"] for g in f["cases"].values() if g.attrs["status"] == "ok") == [1] * 9 + [2] * 3


def test_seeds_come_from_the_sea_state_not_the_order(tmp_path) -> None:
    s = load_scenario(SCENARIOS / "cylinder_irregular.toml")
    s.sweep.method, s.sweep.seeds = "time_domain", 3
    s.sweep.grid = {"waves": {"hs": [1.0, 2.0]}, "ptos": {"pto": {"damping": [1e5, 2e5]}}}
    plan = plan_sweep(s)
    s.sweep.grid = {"ptos": {"pto": {"damping": [2e5, 1e5]}}, "waves": {"hs": [2.0, 1.0]}}
    reordered = plan_sweep(s)
    assert len(plan.cases) == 12
    seeds = {c.id: c.seed for c in plan.cases}
    assert seeds == {c.id: c.seed for c in reordered.cases}
    by_cell = {(dict(c.params)["waves.hs"], dict(c.params)["ptos.pto.damping"], c.seed_index): c.seed
               for c in plan.cases}
    # Common random numbers across the PTO axis, independent seeds across sea states and seed indices.
    assert all(by_cell[(hs, 1e5, k)] == by_cell[(hs, 2e5, k)] for hs in (1.0, 2.0) for k in range(3))
    assert len({by_cell[(hs, 1e5, k)] for hs in (1.0, 2.0) for k in range(3)}) == 6
    assert all(0 <= seed < 2**31 for seed in seeds.values())
    s.waves.seed = 7  # the scenario's own seed changes the whole ensemble
    assert not set(seeds.values()) & {c.seed for c in plan_sweep(s).cases}
    s.sweep.method = "frequency_domain"
    assert len(plan_sweep(s).cases) == 4 and all(c.seed is None for c in plan_sweep(s).cases)


@pytest.mark.parametrize("grid, fragment", [
    ({"ptos": {"nobody": {"damping": [1.0]}}}, "names no key of this scenario"),
    ({"waves": {"kind": ["regular"]}, "bodies": {"fore": {"cg": [[0, 0, 0]]}}}, "cannot be set"),
    ({"ptos": {"pto_fore": {"damping": [-1.0]}}}, "sweep.grid.ptos.pto_fore.damping[0] must not be negative"),
    ({"waves": {"height": ["one"]}}, "sweep.grid.waves.height[0]: expected a number"),
    ({"waves": {"hs": [1.0, 2.0]}}, "waves.hs applies to irregular waves"),
    ({"waves": {"period": 5.0}}, "expected a non-empty array"),
    ({"waves": {"period": [5.0, 5.0]}}, "appears twice"),
    ({"simulation": {"master": ["jacobi", "nonsense"]}}, "'nonsense' is not one of"),
])
def test_bad_grids_are_scenario_errors(grid, fragment) -> None:
    s = load_scenario(SCENARIOS / "two_floats.toml")
    s.sweep.grid = grid
    with pytest.raises(ScenarioError, match=fragment.replace("[", r"\[").replace("]", r"\]")):
        plan_sweep(s)


@pytest.mark.parametrize("text, expected", [("waves.hs=1,2.5,3", ("waves.hs", [1, 2.5, 3])),
                                            ("waves.tp=5:10:6", ("waves.tp", [5.0, 6.0, 7.0, 8.0, 9.0, 10.0])),
                                            ("simulation.master=jacobi,'iqn_ils'", ("simulation.master",
                                                                                     ["jacobi", "iqn_ils"])),
                                            ("hydro.viscous=false", ("hydro.viscous", [False]))])
def test_grid_option(text, expected) -> None:
    assert parse_grid_option(text) == expected


def test_sweep_file_of_another_scene_is_refused(tmp_path) -> None:
    s = load_scenario(SCENARIOS / "two_floats.toml")
    set_grid(s, "waves.period", [5.0])
    out = run_sweep(s, tmp_path / "a.h5", progress=False, log=None).path
    s2 = load_scenario(SCENARIOS / "cylinder_regular.toml")
    set_grid(s2, "waves.period", [5.0])
    with pytest.raises(WecCosimError, match="sweep of a different scene"):
        run_sweep(s2, out, progress=False, log=None)
    results = tmp_path / "other.h5"
    with h5py.File(results, "w") as f:
        f["time"] = [0.0]
    with pytest.raises(WecCosimError, match="not a wec-cosim sweep file"):
        run_sweep(s, results, progress=False, log=None)


def test_sweep_and_plot_commands_draw_the_power_matrix(tmp_path, capsys) -> None:
    out = tmp_path / "sweep.h5"
    proc = wec_cosim("sweep", str(SCENARIOS / "two_floats.toml"), "--out", str(out), "--quiet")
    assert proc.returncode == 0, proc.stderr
    assert "rows ptos.pto_fore.damping, columns waves.period" in proc.stdout and "9 of 9 cases finished" in proc.stdout
    proc = wec_cosim("plot", str(out), "--out", str(tmp_path / "png"))
    assert proc.returncode == 0, proc.stderr
    image = imread(proc.stdout.strip())
    assert image.shape[1] > 1000 and image.std() > 0.05
    assert main(["sweep", str(SCENARIOS / "two_floats.toml"), "--out", str(out), "--quiet",
                 "--grid", "waves.period=5"]) == 0  # the same command line, in this process
    again = capsys.readouterr().out
    assert "3 already in" in again and "0 to run" in again and "mean power (kW) against ptos.pto_fore.damping" in again
    assert main(["sweep", str(SCENARIOS / "two_floats.toml"), "--out", str(out), "--grid", "waves.period"]) == 2
    assert "expected KEY=V1,V2" in capsys.readouterr().err


def test_plot_of_a_sweep_file_without_finished_cases_is_one_paragraph(tmp_path) -> None:
    s = load_scenario(SCENARIOS / "two_floats.toml")
    s.sweep.grid = {"waves": {"heading_deg": [90.0]}}
    out = run_sweep(s, tmp_path / "failed.h5", progress=False, log=None).path
    with pytest.raises(WecCosimError, match="no case of the sweep has finished"):
        plot_file(out, drawers=DRAWERS)
    with h5py.File(out, "a") as f:
        del f["matrices"]
    proc = wec_cosim("plot", str(out))
    assert proc.returncode == 2 and "without matrices" in proc.stderr and "Traceback" not in proc.stderr


def test_plot_command_draws_results_and_rao_figures(tmp_path) -> None:
    rao = tmp_path / "rao.h5"
    assert wec_cosim("rao", str(SCENARIOS / "two_floats.toml"), "--out", str(rao)).returncode == 0
    proc = wec_cosim("plot", str(rao), "--out", str(tmp_path / "png"))
    assert proc.returncode == 0, proc.stderr
    image = imread(proc.stdout.strip())
    assert image.shape[0] > 500 and image.std() > 0.01  # a real drawing, not a blank canvas
    results = tmp_path / "run.h5"
    s = load_scenario(SCENARIOS / "two_floats.toml")
    s.simulation.duration = 10.0
    from orchestrator.cosim.simulation import run_scenario

    run_scenario(s, results, progress=False, log=None)
    files = plot_file(results, tmp_path / "png")
    assert files[0].name == "run_timeseries.png" and imread(files[0]).std() > 0.01


def test_plot_of_a_missing_or_foreign_file_is_one_paragraph(tmp_path) -> None:
    proc = wec_cosim("plot", str(tmp_path / "none.h5"))
    assert proc.returncode == 2 and "does not exist" in proc.stderr and "Traceback" not in proc.stderr
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = 1.0
    proc = wec_cosim("plot", str(other))
    assert proc.returncode == 2 and "neither a results file" in proc.stderr


def test_sweep_progress_shows_done_failed_and_time_left() -> None:
    import io

    from wec_cosim.sweeps.progress import SweepProgress, duration

    stream = io.StringIO()  # not a terminal: one line per report, the first case and the last always
    bar = SweepProgress(6, 2, stream=stream, interval=3600)
    bar.update(True)
    bar.update(False)
    bar.update(True)
    assert bar.line().startswith("[" + "#" * 25 + "." * 5 + "] 5/6 cases, 1 failed this run")
    bar.update(True)
    lines = stream.getvalue().splitlines()
    assert len(lines) == 2 and "3/6 cases, 0 failed" in lines[0] and "6/6 cases, 1 failed" in lines[1]
    assert "left ~0s" in lines[1] and "left ~" in lines[0]
    assert (duration(5), duration(185), duration(7300)) == ("5s", "3m05s", "2h01m")
