"""Crash safety: a run killed with SIGKILL leaves a readable results file holding every row up to the
last flush; `wec-cosim resume` continues from the last checkpoint and ends with exactly the results
of an uninterrupted run (to 1e-12)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

from orchestrator.results import read_results
from orchestrator.results.checkpoints import checkpoint_path, read_checkpoint

from .conftest import ROOT, SCENARIOS

SERIES = ["time", "bodies/fore/displacement", "bodies/aft/velocity", "bodies/aft/hydro_force",
          "ptos/pto_fore/power", "wave/elevation"]


def scenario_file(tmp_path, master: str, duration: float, every: float) -> str:
    text = (SCENARIOS / "two_floats.toml").read_text()
    text = text.replace("duration = 60.0", f"duration = {duration}")
    text = text.replace('master = "jacobi"', f'master = "{master}"')
    text = text.replace("[waves]", f"flush_seconds = 0.2\ncheckpoint_every = {every}\n\n[waves]")
    text = text.replace("[hydro]", f'[hydro]\ncache_dir = "{SCENARIOS / "hydro_cache"}"')
    path = tmp_path / f"long_{master}.toml"
    path.write_text(text)
    return str(path)


def cli(*args: str, **kwargs) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "wec_cosim.cli", *args], cwd=ROOT, env=os.environ.copy(),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kwargs)


def finish(proc: subprocess.Popen) -> str:
    out, err = proc.communicate(timeout=600)
    assert proc.returncode == 0, err
    return out


@pytest.mark.parametrize("master, duration, every", [("jacobi", 500.0, 25.0), ("iqn_ils", 200.0, 10.0)])
def test_sigkill_then_resume_equals_an_uninterrupted_run(tmp_path, master, duration, every) -> None:
    """The iterative master's case also restores its solver memory (IQN-ILS secant data of past steps)."""
    scenario = scenario_file(tmp_path, master, duration, every)
    killed, whole = tmp_path / "killed.h5", tmp_path / "whole.h5"
    reference = cli("run", scenario, "--out", str(whole), "--quiet")
    proc = cli("run", scenario, "--out", str(killed), "--quiet")
    ckpt = checkpoint_path(killed)
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and proc.poll() is None:
        if ckpt.is_file() and read_checkpoint(ckpt)["time"] >= 3 * every:
            break
        time.sleep(0.05)
    assert proc.poll() is None, "the run ended before it could be killed; make it longer"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    saved = read_checkpoint(ckpt)
    finish(reference)
    full = read_results(whole)
    # The killed file opens and holds consistent data up to its last flush (at least to the checkpoint).
    partial = read_results(killed)
    n = len(partial["time"])
    assert partial["attrs"]["status"] == "running"
    assert saved["rows"] <= n < len(full["time"])
    for key in SERIES:
        np.testing.assert_array_equal(partial[key], full[key][:n])
    # Resume from the checkpoint: the finished file equals the uninterrupted run.
    out = finish(cli("resume", str(killed), "--quiet"))
    assert "wall time" in out
    resumed = read_results(killed)
    assert resumed["attrs"]["status"] == "completed"
    assert len(resumed["time"]) == len(full["time"])
    for key in SERIES:
        np.testing.assert_allclose(resumed[key], full[key], rtol=1e-12, atol=1e-12 * np.max(np.abs(full[key])))


def test_resume_without_checkpoint_is_a_clear_error(tmp_path) -> None:
    path = tmp_path / "r.h5"
    with h5py.File(path, "w") as f:
        f.attrs["scenario"] = "x"
        f.attrs["scenario_file"] = "x.toml"
        f.attrs["settings"] = "{}"
    proc = cli("resume", str(path))
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 2 and "no checkpoint" in err and "Traceback" not in err


def test_resume_of_a_foreign_file_is_a_clear_error(tmp_path) -> None:
    path = tmp_path / "foreign.h5"
    with h5py.File(path, "w") as f:
        f["x"] = 1.0
    proc = cli("resume", str(path))
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 2 and "not a wec-cosim results file" in err and "Traceback" not in err
