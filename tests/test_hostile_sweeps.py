"""Ctrl-C on a big sweep, as a terminal sends it: SIGINT to the whole process group (the sweep and its local Dask
cluster's worker processes), at generated moments (just after the plan is made, as the cluster starts, while the
workers run cases) and twice in a row.

Each ends with exit status 130 and one paragraph (the sweep file keeps what finished, status ``interrupted``);
never a worker's KeyboardInterrupt traceback. Two of the moments are marked slow: each case pays for planning ten
thousand cases and starting a cluster. A lost connection to the scheduler stops the sweep instead of recording
every pending case as failed.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time

import h5py
import pytest

from .conftest import ROOT, SCENARIOS  # noqa: F401

GRID = ["--grid", "simulation.duration=40", "--grid", "waves.hs=" + ",".join(f"{1 + i / 100:g}" for i in range(100)),
        "--grid", "waves.tp=" + ",".join(f"{6 + i / 50:g}" for i in range(100)), "--seeds", "1"]
TIMEOUT = 600


def sweep(out) -> subprocess.Popen:  # noqa: ANN001
    return subprocess.Popen([sys.executable, "-m", "wec_cosim.cli", "sweep", str(SCENARIOS / "cylinder_irregular.toml"),
                             "--out", str(out), "--method", "time_domain", "--transient", "20", "--workers", "1",
                             *GRID], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)  # its own process group, as a terminal's foreground job


@pytest.mark.parametrize("moment, after, presses", [
    pytest.param("planned", 0.0, 1, id="just after planning"),
    pytest.param("cluster", 0.0, 1, id="as the cluster starts", marks=pytest.mark.slow),  # each pays the planning
    pytest.param("cluster", 4.0, 1, id="while cases run", marks=pytest.mark.slow),  # of 10 000 cases and a cluster
    pytest.param("cluster", 4.0, 2, id="twice while cases run")])
def test_ctrl_c_on_a_ten_thousand_case_sweep_is_one_line(tmp_path, moment, after, presses) -> None:
    out = tmp_path / "sweep.h5"
    proc = sweep(out)
    watchdog = threading.Timer(TIMEOUT, lambda: os.killpg(proc.pid, signal.SIGKILL))
    watchdog.start()
    lines = []
    marker = "= 10000 cases" if moment == "planned" else "local Dask cluster"
    try:
        for line in proc.stdout:
            lines.append(line)
            if marker in line:
                break
        time.sleep(after)
        for _ in range(presses):
            os.killpg(proc.pid, signal.SIGINT)
            time.sleep(0.3)
        stdout, stderr = proc.communicate(timeout=TIMEOUT)
    finally:
        watchdog.cancel()
    text = "".join(lines) + stdout
    assert "= 10000 cases" in text, text + stderr
    assert proc.returncode == 130, f"status {proc.returncode}\n{stderr}"
    assert "Traceback" not in stderr and "KeyboardInterrupt" not in stderr, stderr
    messages = [x for x in stderr.splitlines() if x.strip() and not x.startswith("[")]  # progress lines aside
    assert len(messages) == 1 and "interrupted" in messages[0], stderr
    if out.is_file():
        with h5py.File(out, "r") as f:
            assert f.attrs["status"] == "interrupted"


def test_a_lost_scheduler_stops_the_sweep_without_failing_the_pending_cases(tmp_path) -> None:
    """The local cluster's scheduler process is gone mid-sweep (a remote scheduler restarted, a network cut):
    the sweep stops with one message; no pending case is recorded as failed."""
    from distributed import Client, Future

    from orchestrator.errors import WecCosimError
    from orchestrator.scenario import load_scenario
    from wec_cosim.sweeps import run_sweep
    from wec_cosim.sweeps.scheduler import close_quietly, local_cluster

    s = load_scenario(SCENARIOS / "cylinder_irregular.toml")
    s.simulation.duration = 40.0
    s.sweep.method, s.sweep.transient, s.sweep.seeds = "time_domain", 20.0, 1
    s.sweep.grid = {"waves": {"hs": [1.0 + 0.1 * i for i in range(40)]}}
    cluster = local_cluster(1, dashboard=False)
    client = Client(cluster, timeout="120s")
    client.wait_for_workers(1, timeout=TIMEOUT)
    stop = threading.Event()

    def lose_the_scheduler() -> None:  # as the client does when its scheduler connection drops: every future cancelled
        while not stop.is_set() and len(client.futures) < 10:
            time.sleep(0.1)
        if not stop.is_set():
            pending = [Future(key, client) for key in list(client.futures)]
            client.cancel(pending, reason="scheduler-connection-lost")

    cut = threading.Thread(target=lose_the_scheduler, daemon=True)
    cut.start()
    try:
        with pytest.raises(WecCosimError) as info:
            run_sweep(s, tmp_path / "sweep.h5", client=client, progress=False, log=None)
    finally:
        stop.set()
        client.close()
        close_quietly(cluster)
    assert "connection to the Dask scheduler was lost" in str(info.value) and "none is recorded as failed" in str(
        info.value)
    with h5py.File(tmp_path / "sweep.h5", "r") as f:
        statuses = [str(g.attrs["status"]) for g in f["cases"].values()] if "cases" in f else []
        assert "failed" not in statuses and str(f.attrs["status"]).startswith("interrupted")
