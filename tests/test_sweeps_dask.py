"""Sweeps on a real local Dask cluster: distributed cases equal serial runs, a killed worker loses and
duplicates nothing, an interrupted sweep resumes with only the missing cases.

The cases are short time-domain runs of the floating cylinder in irregular seas (40 s, statistics
after 20 s), so that each one is a full co-simulation (FMUs built or taken from the cache and
instantiated in the worker process) of a couple of seconds.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading

import h5py
import numpy as np
import pytest

from orchestrator.cosim.simulation import run_scenario
from orchestrator.results import read_results
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene
from wec_cosim.sweeps import run_sweep
from wec_cosim.sweeps.case import prepare_time_domain
from wec_cosim.sweeps.grid import case_scenario, plan_sweep
from wec_cosim.sweeps.scheduler import close_quietly, local_cluster
from wec_cosim.sweeps.summary import analysis_window, time_domain_summary

from .conftest import ROOT, SCENARIOS

SCENARIO = SCENARIOS / "cylinder_irregular.toml"
SHORT = ["--method", "time_domain", "--grid", "simulation.duration=40", "--grid", "waves.tp=7", "--seeds", "1",
         "--transient", "20"]
TIMEOUT = 600  # s: generous, the machine may be loaded; nothing is timed


def short_sweep(grid: dict, seeds: int = 1, time_series: bool = False):
    s = load_scenario(SCENARIO)
    s.simulation.duration = 40.0
    s.sweep.method, s.sweep.transient, s.sweep.seeds, s.sweep.time_series = "time_domain", 20.0, seeds, time_series
    s.sweep.grid = grid
    return s


@pytest.fixture(scope="module")
def client():
    from distributed import Client

    cluster = local_cluster(2, dashboard=False)
    client = Client(cluster, timeout="120s")
    client.wait_for_workers(2, timeout=TIMEOUT)
    yield client
    client.close()
    close_quietly(cluster)


def serial_run(plan, case, tmp_path) -> dict:
    """The same case as a plain run in this process."""
    s = prepare_time_domain(case_scenario(plan, case))
    path = tmp_path / f"serial_{case.id}.h5"
    run_scenario(s, path, progress=False, log=None)
    return read_results(path) | {"scene": load_scene(s, log=None)}


def test_cases_on_two_workers_equal_serial_runs(client, tmp_path) -> None:
    s = short_sweep({"waves": {"hs": [1.0, 2.5]}}, seeds=2, time_series=True)
    out = run_sweep(s, tmp_path / "sweep.h5", client=client, progress=False, log=None)
    assert (out.ran, out.failed, out.duplicates) == (4, 0, 0)
    with h5py.File(out.path) as f:
        groups = {c.id: f[f"cases/{c.id}"] for c in out.plan.cases}
        assert {int(g.attrs["pid"]) for g in groups.values()}.isdisjoint({os.getpid()})  # run in workers
        elevations = []
        for case in out.plan.cases:
            g = groups[case.id]
            serial = serial_run(out.plan, case, tmp_path)
            for key in ("time", "bodies/float/displacement", "ptos/pto/power", "ptos/pto/force", "wave/elevation"):
                ref = serial[key]
                np.testing.assert_allclose(g[f"series/{key}"][()], ref, rtol=1e-12, atol=1e-12 * np.max(np.abs(ref)))
            scene = serial["scene"]
            summary = time_domain_summary(scene, serial, analysis_window(scene, serial["time"], 20.0))
            for key, value in summary.items():
                np.testing.assert_allclose(g[key][()], value, rtol=1e-12, atol=1e-12)
            elevations.append(g["series/wave/elevation"][()])
        # Two seeds of a cell are two different seas of the same spectrum.
        assert not np.allclose(elevations[0], elevations[1])
        assert f["matrices/seeds_done"][()].tolist() == [2, 2]
        assert np.all(f["matrices/mean_power_std"][()] > 0)


def test_a_killed_worker_loses_and_duplicates_no_case(client, tmp_path) -> None:
    s = short_sweep({"waves": {"hs": [1.0, 1.5, 2.0]}, "ptos": {"pto": {"damping": [1e5, 3e5]}}})
    outcome: dict = {}
    sweep = threading.Thread(target=lambda: outcome.update(result=run_sweep(
        s, tmp_path / "sweep.h5", client=client, progress=False, log=None)), daemon=True)
    sweep.start()

    def executing(dask_worker) -> list[str]:  # noqa: ANN001 - injected by Client.run
        return [str(ts.key) for ts in dask_worker.state.executing]

    victim = None
    while victim is None and sweep.is_alive():
        running = client.run(executing)
        victim = next(((addr, keys[0]) for addr, keys in running.items() if keys and "wec-case" in keys[0]), None)
    assert victim is not None, "the sweep ended before a case could be seen running"
    address, key = victim
    pid = client.run(os.getpid, workers=[address])[address]
    os.kill(pid, signal.SIGKILL)  # the worker process itself, not its nanny: a real crash
    sweep.join(TIMEOUT)
    assert not sweep.is_alive()
    result = outcome["result"]
    assert (result.ran, result.failed, result.duplicates) == (6, 0, 0)
    killed_case = key.split("-")[2]
    with h5py.File(result.path) as f:
        assert sorted(f["cases"]) == sorted(c.id for c in result.plan.cases)  # each case once, none missing
        assert all(g.attrs["status"] == "ok" for g in f["cases"].values())
        assert f[f"cases/{killed_case}"].attrs["pid"] != pid  # recomputed by another worker process
        case = next(c for c in result.plan.cases if c.id == killed_case)
        serial = serial_run(result.plan, case, tmp_path)
        scene = serial["scene"]
        summary = time_domain_summary(scene, serial, analysis_window(scene, serial["time"], 20.0))
        assert f[f"cases/{killed_case}/ptos/pto/mean_power"][()] == pytest.approx(
            summary["ptos/pto/mean_power"], rel=1e-12)
        assert np.all(f["matrices/seeds_done"][()] == 1)


def test_an_interrupted_sweep_resumes_with_only_the_missing_cases(tmp_path) -> None:
    out = tmp_path / "sweep.h5"
    command = [sys.executable, "-m", "wec_cosim.cli", "sweep", str(SCENARIO), "--out", str(out), *SHORT,
               "--grid", "waves.hs=1,1.5,2", "--workers", "1"]
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    watchdog = threading.Timer(TIMEOUT, proc.kill)  # a sweep that never reports cannot hang the suite
    watchdog.start()
    seen = []
    for line in proc.stderr:
        seen.append(line)
        if re.search(r"\] 1/3 cases", line):  # the first case is in the file: stop the sweep (Ctrl-C)
            proc.send_signal(signal.SIGINT)
            break
    stdout, stderr = proc.communicate(timeout=TIMEOUT)
    watchdog.cancel()
    assert proc.returncode == 130, "".join(seen) + stderr
    assert re.search(r"interrupted: [12] of 3 cases are in", stderr) and "Traceback" not in stderr, stderr
    with h5py.File(out) as f:
        first = {name: dict(g.attrs) for name, g in f["cases"].items()}
        assert f.attrs["status"] == "interrupted"
    assert 1 <= len(first) < 3
    proc = subprocess.run(command, capture_output=True, text=True, cwd=ROOT, timeout=TIMEOUT)
    assert proc.returncode == 0, proc.stderr
    assert f"{len(first)} already in {out}, {3 - len(first)} to run" in proc.stdout
    with h5py.File(out) as f:
        assert len(f["cases"]) == 3 and f.attrs["status"] == "completed"
        for name, attrs in first.items():  # the first session's cases were not run again
            assert {k: str(v) for k, v in f[f"cases/{name}"].attrs.items()} == {k: str(v) for k, v in attrs.items()}
        assert sorted(int(g.attrs["session"]) for g in f["cases"].values()) == [1] * len(first) + [2] * (
            3 - len(first))
        grid = {"waves": {"hs": [1.0, 1.5, 2.0], "tp": [7.0]}, "simulation": {"duration": [40.0]}}
        plan = plan_sweep(short_sweep(grid))
        assert set(f["cases"]) == {c.id for c in plan.cases}  # the command line planned the API's cases
