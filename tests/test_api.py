"""The Python API (``import wec_cosim as wc``): values changed in Python are checked with the file's checks and
worded for Python; results, RAO, steady-state and sweep files as labelled xarray datasets that go back to HDF5
without loss and out to NetCDF with their units; the pandas view.

Expected values come from physics (absorbed power = -force x velocity, the frequency-domain answer, the
pseudo-spectral solution of a linear scene equal to the RAO, the hinge angle equal to the bodies' relative pitch),
from the HDF5 files themselves read with h5py (labelling must not move data), and from identities of the layout.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
import xarray as xr

import wec_cosim as wc
from orchestrator.errors import ScenarioError

ROOT = Path(__file__).resolve().parent.parent
SCENARIOS = ROOT / "scenarios"


@pytest.fixture(scope="module")
def cylinder_run(tmp_path_factory: pytest.TempPathFactory):
    """The quick-start cylinder with its wave height changed in Python (1.5 m instead of the file's 1 m)."""
    s = wc.load_scenario(SCENARIOS / "cylinder_regular.toml")
    s.waves.height = 1.5
    out = tmp_path_factory.mktemp("api") / "cyl.h5"
    return wc.run(s, out, progress=False, log=None)


# ----------------------------------------------------------------------------- checks of values set in Python
def test_a_value_set_in_python_is_refused_with_the_files_check_worded_for_python(tmp_path: Path) -> None:
    s = wc.load_scenario(SCENARIOS / "cylinder_regular.toml")
    s.waves.height = -3.0
    with pytest.raises(ScenarioError) as caught:
        wc.run(s, tmp_path / "never.h5", progress=False, log=None)
    text = str(caught.value)
    assert text.startswith("waves.height = -3.0, set in Python: must not be negative")
    assert "--set" not in text
    assert not (tmp_path / "never.h5").exists()  # refused before any work
    s.waves.height = "2"
    with pytest.raises(ScenarioError, match=r"^waves.height = '2', set in Python: expected a number, got a string"):
        wc.check(s)
    s.waves.height = 2  # an integer for a float: converted as the file's value would be
    wc.check(s)
    assert s.waves.height == 2.0 and isinstance(s.waves.height, float)


def test_checks_across_keys_name_what_was_changed_in_python() -> None:
    s = wc.load_scenario(SCENARIOS / "cylinder_regular.toml")
    s.simulation.step = 300.0  # one step longer than the 200 s run
    with pytest.raises(ScenarioError) as caught:
        wc.check(s)
    text = str(caught.value)
    assert "simulation.step (300.0 s) is longer than the duration (200.0 s)" in text
    assert text.endswith(f"(the scenario of {SCENARIOS / 'cylinder_regular.toml'}, changed in Python "
                         "(simulation.step))")
    assert not text.startswith(str(SCENARIOS))  # the file itself is fine


def test_a_list_of_sections_changed_in_python_is_checked_and_recorded_as_toml() -> None:
    """A PTO added in Python: the whole scenario is checked and written again as TOML that loads into the same
    values (what a results file records and ``wec-cosim resume`` reads)."""
    import copy

    from orchestrator.scenario import parse_scenario
    from orchestrator.scenario.changes import python_changes

    s = wc.load_scenario(SCENARIOS / "cylinder_regular.toml")
    extra = copy.deepcopy(s.ptos[0])
    extra.name, extra.damping = "pto2", -5.0
    s.ptos.append(extra)
    with pytest.raises(ScenarioError, match=r"^ptos\[1\].damping must not be negative \(got -5.0\) \(a value set in "):
        wc.check(s)
    extra.damping = 1e5
    wc.check(s)
    again = parse_scenario(s.text, s.file)
    assert [p.name for p in again.ptos] == ["pto", "pto2"] and again.ptos[1].damping == 1e5
    assert python_changes(s) == ([], [])


def test_apply_overrides_from_python_takes_a_mapping_and_never_says_set() -> None:
    s = wc.load_scenario(SCENARIOS / "cylinder_regular.toml")
    changed = wc.apply_overrides(s, {"waves.height": np.float64(0.5), "bodies.float.dofs": ("heave",)})
    assert changed.waves.height == 0.5 and s.waves.height == 1.0  # a copy; the file says 1 m
    assert changed._overrides == ["waves.height=0.5", 'bodies.float.dofs=["heave"]']
    for bad, expected in (({"waves.height": -1.0}, "waves.height must not be negative"),
                          ({"waves.hieght": 1.0}, "'waves.hieght' names no key"),
                          (["waves.height"], "write KEY=VALUE")):
        with pytest.raises(ScenarioError, match=expected) as caught:
            wc.apply_overrides(s, bad)
        assert "--set" not in str(caught.value)


# ----------------------------------------------------------------------------- a run and its dataset
def test_a_run_from_python_has_its_mean_power_beside_the_exact_answer(cylinder_run) -> None:
    r = cylinder_run
    exact = next(c for c in r.comparisons if c.label == "pto mean power")
    assert r.mean_power and r.power_window
    assert r.mean_power["pto"] == pytest.approx(exact.measured, rel=1e-12)  # one window, one number
    assert abs(r.mean_power["pto"] / exact.exact - 1) < 0.01  # the exact frequency-domain power at H = 1.5 m
    assert r.setup_time > 0 and r.wall_time > 0
    summary = r.summary()
    assert "set-up" in summary and "stepping" in summary and summary.count("mean power") == 1
    with h5py.File(r.path, "r") as f:
        assert json.loads(f.attrs["settings"])["overrides"] == ["waves.height=1.5"]  # the scene that ran


def test_the_results_dataset_is_labelled_and_holds_the_files_data(cylinder_run) -> None:
    ds = cylinder_run.dataset()
    assert set(ds.dims) == {"time", "body", "dof", "pto"}
    assert list(ds.dof.values) == ["surge", "sway", "heave", "roll", "pitch", "yaw"]
    assert ds.time.attrs["units"] == "s"
    assert ds.displacement.attrs["units"] == "m or rad"
    assert ds.displacement.attrs["units_by_dof"] == ["m", "m", "m", "rad", "rad", "rad"]
    assert ds.pto_force.attrs["units"] == "N" and ds.pto_power.attrs["units"] == "W"
    assert all("long_name" in ds[v].attrs and "units" in ds[v].attrs for v in ds.data_vars)
    with h5py.File(cylinder_run.path, "r") as f:
        np.testing.assert_array_equal(ds.displacement.sel(body="float", dof="heave"),
                                      f["bodies/float/displacement"][:, 2])
        np.testing.assert_array_equal(ds.wave_elevation, f["wave/elevation"][()])
        assert ds.attrs["scenario"] == f.attrs["scenario"]
    # absorbed power is minus the PTO force times the heave velocity, sample by sample
    power = ds.pto_power.sel(pto="pto")
    work = -ds.pto_force.sel(pto="pto") * ds.velocity.sel(body="float", dof="heave")
    np.testing.assert_allclose(power, work, rtol=0, atol=1e-9 * float(abs(power).max()))


def test_a_results_dataset_goes_to_hdf5_and_back_identical(cylinder_run, tmp_path: Path) -> None:
    """Acceptance: written and read back, the dataset is identical; the file written holds the same datasets and
    root attributes as the run's own file, so the readers of results files read it as the run's."""
    from orchestrator.results import read_results

    ds = cylinder_run.dataset()
    copy_path = wc.write_results(ds, tmp_path / "copy.h5")
    xr.testing.assert_identical(wc.open_dataset(copy_path), ds)
    original, copied = read_results(cylinder_run.path), read_results(copy_path)
    assert original.keys() == copied.keys()
    for name in original:
        if name != "attrs":
            np.testing.assert_array_equal(original[name], copied[name])
    assert original["attrs"] == copied["attrs"]


def test_the_netcdf_export_opens_in_plain_xarray_with_units(cylinder_run, tmp_path: Path) -> None:
    """Acceptance: ``xr.open_dataset`` on the export gives the same data with the units."""
    ds = cylinder_run.dataset()
    path = wc.to_netcdf(ds, tmp_path / "cyl.nc")
    with xr.open_dataset(path) as opened:
        back = opened.load()
    xr.testing.assert_identical(back, ds)
    assert back.pto_power.attrs["units"] == "W" and back.displacement.attrs["units_by_dof"][2] == "m"


def test_the_pandas_view_is_indexed_by_time_with_units(cylinder_run) -> None:
    ds = cylinder_run.dataset()
    frame = wc.to_pandas(ds)
    assert frame.index.name == "time" and len(frame) == ds.sizes["time"]
    np.testing.assert_array_equal(frame["displacement[float,heave]"], ds.displacement.sel(body="float", dof="heave"))
    np.testing.assert_array_equal(frame["wave_elevation"], ds.wave_elevation)
    assert frame.attrs["units"]["displacement[float,pitch]"] == "rad"
    assert frame.attrs["units"]["pto_power[pto]"] == "W"


def test_a_jointed_device_has_joint_coordinates_and_reactions(tmp_path: Path) -> None:
    """The hinge barge for 4 s: the hinge angle is labelled ``hinge[1]`` (``angle``, rad) and equals barge 2's
    pitch less barge 1's (a revolute joint about y in a planar motion); reactions are on ``joint`` x ``axis``."""
    s = wc.apply_overrides(SCENARIOS / "hinge_barge.toml", {"simulation.duration": 4.0})
    ds = wc.run(s, tmp_path / "hinge.h5", progress=False, log=None, in_process=True).dataset()
    assert list(ds.coordinate.values) == ["hinge[1]"] and list(ds.coordinate_name.values) == ["angle"]
    assert ds.joint_coordinate.attrs["units"] == "rad" and ds.joint_force.attrs["units"] == "N"
    assert ds.joint_moment.attrs["units"] == "N m" and list(ds.axis.values) == ["x", "y", "z"]
    pitch = ds.displacement.sel(dof="pitch")
    relative = pitch.sel(body="barge2") - pitch.sel(body="barge1")
    angle = ds.joint_coordinate.sel(coordinate="hinge[1]")
    assert float(abs(angle).max()) > 1e-3
    np.testing.assert_allclose(angle, relative, rtol=0, atol=1e-9)
    with h5py.File(tmp_path / "hinge.h5", "r") as f:
        np.testing.assert_array_equal(ds.joint_force.sel(joint="hinge"), f["joints/hinge/force"][()])
    xr.testing.assert_identical(wc.open_dataset(wc.write_results(ds, tmp_path / "copy.h5")), ds)


# ----------------------------------------------------------------------------- frequency domain, steady, sweep
def test_rao_and_steady_state_datasets_agree_for_a_linear_scene(tmp_path: Path) -> None:
    """For the linear cylinder the pseudo-spectral steady state's first harmonic per metre of amplitude is the
    RAO (two solvers); the RAO dataset holds the file's complex values under its labels and survives NetCDF."""
    s = wc.load_scenario(SCENARIOS / "cylinder_regular.toml")
    rao = wc.rao(s, tmp_path / "rao.h5", log=None, progress=False)
    assert rao.body_rao.dtype.kind == "c" and rao.body_rao.attrs["units_by_dof"][2] == "m/m"
    with h5py.File(tmp_path / "rao.h5", "r") as f:
        np.testing.assert_array_equal(rao.body_rao.sel(body="float"), f["bodies/float/rao"][()])
    back = wc.open_netcdf(wc.to_netcdf(rao, tmp_path / "rao.nc"))
    xr.testing.assert_identical(back, rao)
    steady = wc.steady(s, tmp_path / "steady.h5", harmonics=3, log=None, progress=False)
    omega = 2 * math.pi / s.waves.period
    first = complex(steady.body_harmonics.sel(body="float", dof="heave", harmonic=1).values[0])
    amplitude = float(steady.amplitude.values[0])
    from orchestrator.reference import frequency_domain
    from orchestrator.scene import load_scene

    exact = complex(frequency_domain.solve(load_scene(s, log=None), np.array([omega])).body_rao("float")[0, 2])
    assert abs(first / amplitude - exact) < 1e-6 * abs(exact)
    assert bool(steady.converged.values[0]) and steady.pto_mean_power.attrs["units"] == "W"


def test_a_sweep_dataset_has_one_dimension_per_swept_key(tmp_path: Path) -> None:
    """The two floats' frequency-domain grid: dimensions named by the keys with their units; the device's power
    matrix is the sum of its PTOs' powers in every cell."""
    ds = wc.sweep(SCENARIOS / "two_floats.toml", tmp_path / "sweep.h5", progress=False, log=None)
    assert ds["ptos.pto_fore.damping"].attrs["units"] == "N s/m" and ds["waves.period"].attrs["units"] == "s"
    assert ds.mean_power.dims == ("ptos.pto_fore.damping", "waves.period")
    np.testing.assert_allclose(ds.mean_power, ds.pto_mean_power.sum("pto"), rtol=1e-12)
    assert ds.mean_power.attrs["units"] == "W" and int(ds.seeds_done.min()) == 1
    assert wc.open_dataset(tmp_path / "sweep.h5").equals(ds)


# ----------------------------------------------------------------------------- import cost
def test_import_and_a_plain_run_do_not_import_the_heavy_libraries(tmp_path: Path) -> None:
    """``import wec_cosim`` and a plain ``wec-cosim run`` (its own process) import neither xarray, pandas,
    matplotlib, Dask nor Capytaine; the run's log (standard error to a file) has no carriage returns."""
    heavy = ("xarray", "pandas", "matplotlib", "dask", "distributed", "capytaine")
    code = ("import sys, wec_cosim\n"
            "from wec_cosim.cli import main\n"
            f"print(sorted(m for m in {heavy!r} if m in sys.modules))\n"
            "rc = main(['run', sys.argv[1], '--out', sys.argv[2]])\n"
            f"print(sorted(m for m in {heavy!r} if m in sys.modules), rc)\n")
    err = tmp_path / "run.err"
    with err.open("w") as stderr:
        done = subprocess.run([sys.executable, "-c", code, str(SCENARIOS / "cylinder_regular.toml"),
                               str(tmp_path / "cyl.h5")], stdout=subprocess.PIPE, stderr=stderr, text=True,
                              timeout=600, cwd=tmp_path)
    lines = done.stdout.splitlines()
    assert lines[0] == "[]" and lines[-1] == "[] 0", done.stdout + err.read_text()
    assert "\r" not in err.read_text()
    assert any(line.startswith("wall time: set-up") for line in lines)


def test_a_first_run_is_announced_with_its_compile_time(cylinder_run, tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    """With no compiled kernels in the cache the run says what it compiles and how long that takes (the measured
    CPU seconds of benchmarks/results/first_run*.txt); once they are there (the run above), nothing. The linear
    cylinder needs no kernel at all (its hydrodynamics is the runtime compiled at install): no notice even cold."""
    from orchestrator.cosim.simulation import compile_notice
    from orchestrator.scene import load_scene

    cylinder = load_scene(wc.load_scenario(SCENARIOS / "cylinder_regular.toml"), log=None)
    hinge = load_scene(wc.load_scenario(SCENARIOS / "hinge_barge.toml"), log=None)
    assert compile_notice(cylinder) is None
    monkeypatch.setenv("WEC_COSIM_NUMBA_CACHE", str(tmp_path / "empty"))
    assert compile_notice(cylinder) is None
    assert compile_notice(hinge) == (
        f"compiling the multibody kernels for this version of wec-cosim: about 3 minutes of CPU on a 2-core machine, "
        f"longer under load; once: later runs load them from {tmp_path / 'empty'} ...")
