"""Controllers that misbehave in time, generated: duplicates of every answer (up to 1000 per period, 10 kHz at a
10 Hz control rate), answers to measurements not published yet (before the real answer), malformed frames before
the real answer, in lock-step and in real time; client laws that set commands the run does not have; a controller
whose negative damping makes the run diverge.

Real controllers in separate processes over zenoh on loopback (tests/hostile_control_peers.py). Lock-step runs
with the external passive damper must equal the internal damper's run (the frames that answer nothing new are
dropped and counted, never acted on); real-time runs must be commanded by the controller in every period that has
an answer (no fallback caused by duplicates, future steps or a malformed frame next to a valid one).
"""

from __future__ import annotations

import subprocess
import sys
import time

import numpy as np
import pytest

from orchestrator.control.bridge import SOURCES
from orchestrator.cosim.simulation import run_scenario
from orchestrator.errors import MasterError
from orchestrator.results import read_results

from .conftest import ROOT
from .test_control import DAMPING, free_endpoint, scenario, stop


def hostile(behaviour: str, run_id: str, endpoint: str, damping: float = DAMPING) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "tests.hostile_control_peers", behaviour, run_id, endpoint,
                             str(damping)], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def run_with(tmp_path, behaviour: str, damping: float = DAMPING, **control) -> tuple[dict, str]:
    endpoint = free_endpoint()
    run_id = f"h{time.monotonic_ns() % 10**9}"
    s = scenario(duration=control.pop("duration", 10.0), run_id=run_id, endpoints=[endpoint], **control)
    proc = hostile(behaviour, run_id, endpoint, damping)
    path = tmp_path / "run.h5"
    try:
        run_scenario(s, path, progress=False, log=None)
    finally:
        log = stop(proc)
    return read_results(path), log


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> dict:
    path = tmp_path_factory.mktemp("ref") / "ref.h5"
    run_scenario(scenario(), path, progress=False, log=None)
    return read_results(path)


LOCKSTEP = ["duplicates:1", "duplicates:20", "future:1", "future:5", "garbage:0"]


@pytest.mark.parametrize("behaviour", LOCKSTEP)
def test_lockstep_drops_what_answers_nothing_new_and_equals_the_internal_damper(tmp_path, reference,
                                                                                 behaviour) -> None:
    data, log = run_with(tmp_path, behaviour)
    stats = data["attrs"]["control_statistics"]
    n = len(data["time"])
    assert sum(stats["faults"].values()) == 0 and np.all(data["control/source"] == SOURCES["controller"]), stats
    kind, count = behaviour.split(":")
    count = int(count)
    dropped = stats["dropped_frames"]
    if kind == "duplicates":
        assert dropped["duplicate"] >= count * (n - 1), dropped  # each answer's copies, the last one's may be unseen
    if kind == "future":
        assert dropped["future_step"] == count * n, dropped
    for key in ("bodies/float/displacement", "bodies/float/velocity", "ptos/pto/power"):
        np.testing.assert_allclose(data[key], reference[key], rtol=0, atol=1e-12, err_msg=key)


REALTIME = ["duplicates:100", "duplicates:1000", "future:3", "garbage:1"]


@pytest.mark.parametrize("behaviour", REALTIME)
def test_realtime_keeps_the_valid_command(tmp_path, behaviour) -> None:
    """10 Hz control for 5 s at twice real time. Duplicates at up to 10 kHz, future answers and a malformed frame
    before each valid answer: every period after the first answer is commanded by the controller, with the
    controller's damping; latencies are positive (no answer to unpublished measurements was taken)."""
    data, log = run_with(tmp_path, behaviour, mode="realtime", duration=5.0, realtime_factor=2.0, max_age=5)
    stats = data["attrs"]["control_statistics"]
    source = data["control/source"]
    first = int(np.argmax(source == SOURCES["controller"]))
    assert source[first] == SOURCES["controller"], (stats, log)
    assert np.all(source[first:] == SOURCES["controller"]), (stats, np.unique(source[first:], return_counts=True))
    assert sum(stats["faults"].values()) == 0, stats
    commands = data["control/commands"]
    damping = commands[first:, 1]
    np.testing.assert_array_equal(damping, DAMPING)
    latency = data["control/latency"]
    assert np.all(latency[np.isfinite(latency)] > 0)
    kind = behaviour.split(":")[0]
    key = {"duplicates": "duplicate", "future": "future_step", "garbage": "wrong_length"}[kind]
    assert stats["dropped_frames"][key] > 0, stats


def test_realtime_controller_that_vanishes_leaves_the_fallback_named(tmp_path) -> None:
    data, _ = run_with(tmp_path, "vanish:10", mode="realtime", duration=5.0, realtime_factor=2.0, fallback="passive")
    stats = data["attrs"]["control_statistics"]
    assert data["attrs"]["status"] == "completed"
    assert stats["faults"]["disconnected"] > 0 and data["control/source"][-1] == SOURCES["passive"], stats


BAD_LAWS = ["nopto.damping=1e5", "pto.dampin=1e5", "pto=1e5", "PTO.damping=1e5", "pto.damping=soft",
            "pto.damping="]


@pytest.mark.parametrize("setting", BAD_LAWS)
def test_the_client_refuses_a_command_the_run_does_not_have(tmp_path, setting) -> None:
    """The law's answer is checked by the client: the controller stops with a message naming the command (or
    the value), never dropping it; the master then rides on its fallback and completes."""
    data, log = run_with(tmp_path, f"law:{setting}", fallback="hold")
    name, _, value = setting.partition("=")
    assert "error: controller of run" in log, log
    if value in ("", "soft"):
        assert f"set {name!r} to" in log and "not a number" in log, log
    else:
        assert f"set {name!r}, which is not a command of run" in log and "pto.damping" in log, log
    assert data["attrs"]["status"] == "completed"
    assert np.all(data["control/source"] != SOURCES["controller"])


def test_negative_damping_from_a_controller_is_named_as_the_cause_of_divergence(tmp_path) -> None:
    with pytest.raises(MasterError) as info:
        run_with(tmp_path, "duplicates:0", damping=-4.0e5, duration=200.0, damping_limits=[-1.0e6, 1.0e6])
    message = str(info.value)
    assert "diverged" in message and "the controller commanded pto.damping = -4e+05" in message, message
