"""One scene file drives the run, the RAOs and the sweep; plots of results and RAO files."""

from __future__ import annotations

import h5py
import numpy as np
import pytest
from matplotlib.image import imread

from orchestrator.errors import ScenarioError
from orchestrator.plotting import plot_file
from orchestrator.scenario import load_scenario
from orchestrator.sweep import run_sweep, set_key

from .conftest import SCENARIOS
from .test_cli import wec_cosim


def test_time_domain_sweep_agrees_with_frequency_domain_sweep(tmp_path) -> None:
    """Same [sweep] table, two methods: co-simulated steady power within 3 % of the exact linear one."""
    s = load_scenario(SCENARIOS / "two_floats.toml")
    s.sweep.values = [2.0e4, 1.2e5]
    s.sweep.periods = [5.0]
    tables = {}
    for method in ("frequency_domain", "time_domain"):
        s.sweep.method = method
        with h5py.File(run_sweep(s, tmp_path / f"{method}.h5", log=None)) as f:
            tables[method] = {p: f[f"ptos/{p}/mean_power"][()] for p in ("pto_fore", "pto_aft")}
            assert f["values"].shape == (2,) and f["bodies/fore/amplitude"].shape == (2, 1, 6)
    for p in ("pto_fore", "pto_aft"):
        np.testing.assert_allclose(tables["time_domain"][p], tables["frequency_domain"][p], rtol=0.03)
    fore = tables["frequency_domain"]["pto_fore"][:, 0]
    assert fore[0] != pytest.approx(fore[1], rel=0.05)  # the swept key really changed the answer


@pytest.mark.parametrize("path, fragment", [("ptos.nobody.damping", "names no numeric key"),
                                            ("waves.kind", "is not a numeric key"),
                                            ("ptos.pto_fore.damping", "must not be negative")])
def test_bad_sweep_keys_are_scenario_errors(path, fragment) -> None:
    s = load_scenario(SCENARIOS / "two_floats.toml")
    with pytest.raises(ScenarioError, match=fragment):
        set_key(s, path, -1.0)


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
    from orchestrator.simulation import run_scenario

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
