"""External control over zenoh: real sessions, controllers in separate processes, on loopback."""

from __future__ import annotations

import json
import socket
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

from orchestrator.control import protocol
from orchestrator.control.bridge import FAULTS, SOURCES
from orchestrator.control.session import _config
from orchestrator.errors import MasterError
from orchestrator.results import read_results
from orchestrator.scenario import load_scenario
from orchestrator.simulation import run_scenario

from .conftest import ROOT, SCENARIOS

DAMPING = 2.0e5
FAULT_STEP = 40


def free_endpoint() -> str:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{s.getsockname()[1]}"


def scenario(duration: float = 10.0, **control):
    s = load_scenario(SCENARIOS / "cylinder_regular.toml")
    s.simulation.duration = duration
    if control:
        s.ptos[0].damping = 0.0  # the controller supplies the damping
        s.control.mode = control.pop("mode", "lockstep")
        s.control.timeout = 2.0
        s.control.connect_timeout = 15.0
        for k, v in control.items():
            setattr(s.control, k, v)
    return s


def peer(*args: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "tests.control_peers", *map(str, args)], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def stop(proc: subprocess.Popen) -> str:
    try:
        out, _ = proc.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, _ = proc.communicate()
    return out


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The same scene with the internal PTO damper (no controller)."""
    path = tmp_path_factory.mktemp("ref") / "ref.h5"
    run_scenario(scenario(), path, progress=False, log=None)
    return read_results(path)


def controlled_run(tmp_path, fault: str, damping: float = DAMPING, **control):
    endpoint = free_endpoint()
    run_id = f"t{time.monotonic_ns() % 10**9}"
    s = scenario(run_id=run_id, endpoints=[endpoint], **control)
    proc = peer(fault, run_id, endpoint, FAULT_STEP, damping) if fault != "absent" else None
    path = tmp_path / "run.h5"
    try:
        run_scenario(s, path, progress=False, log=None)
    finally:
        log = stop(proc) if proc else ""
    return read_results(path), log


def test_lockstep_passive_controller_reproduces_internal_damper(tmp_path, reference) -> None:
    data, log = controlled_run(tmp_path, "none")
    for key in ("bodies/float/displacement", "bodies/float/velocity", "ptos/pto/power"):
        np.testing.assert_allclose(data[key], reference[key], rtol=0, atol=1e-12, err_msg=key)
    assert np.all(data["control/source"] == SOURCES["controller"])
    stats = data["attrs"]["control_statistics"]
    assert sum(stats["faults"].values()) == 0 and stats["periods"] == len(data["time"])
    assert "(finished)" in log  # the controller saw the end of the run and left cleanly


@pytest.mark.parametrize("fault, expected", [
    ("late", "late"),
    ("disconnect", "disconnected"),
    ("wrong_length", "wrong_length"),
    ("wrong_version", "wrong_version"),
    ("stale_step", "stale_step"),
    ("nan", "non_finite"),
    ("inf", "non_finite"),
    ("out_of_limits", "out_of_limits"),
])
def test_fault_holds_last_command_and_is_counted(tmp_path, reference, fault, expected) -> None:
    data, _ = controlled_run(tmp_path, fault, fallback="hold")
    code = data["control/fault"].astype(int)
    assert code[FAULT_STEP] == 1 + FAULTS.index(expected)
    assert np.all(code[:FAULT_STEP] == 0)
    assert data["control/source"][FAULT_STEP] == SOURCES["hold"]
    assert data["attrs"]["status"] == "completed"
    stats = data["attrs"]["control_statistics"]
    assert stats["faults"][expected] >= 1
    # Holding the last command (the same damping) leaves the whole motion unchanged.
    np.testing.assert_allclose(data["bodies/float/displacement"], reference["bodies/float/displacement"],
                               rtol=0, atol=1e-12)
    if fault == "disconnect":
        assert np.all(code[FAULT_STEP:] == 1 + FAULTS.index("disconnected"))
    else:
        assert np.all(code[FAULT_STEP + 2:] == 0)  # the controller recovers after one bad frame


def test_absent_controller_runs_on_the_fallback(tmp_path) -> None:
    data, _ = controlled_run(tmp_path, "absent", fallback="passive", passive_damping=5.0e4, connect_timeout=0.5)
    assert np.all(data["control/fault"] == 1 + FAULTS.index("absent"))
    assert np.all(data["control/source"] == SOURCES["passive"])
    np.testing.assert_array_equal(data["control/commands"][:, 1], 5.0e4)  # stiffness, damping, force
    assert data["attrs"]["control_statistics"]["faults"]["absent"] == len(data["time"])


def test_passive_fallback_changes_only_what_follows_the_fault(tmp_path, reference) -> None:
    data, _ = controlled_run(tmp_path, "nan", fallback="passive", passive_damping=5.0e4)
    assert data["control/commands"][FAULT_STEP, 1] == 5.0e4
    assert data["control/source"][FAULT_STEP] == SOURCES["passive"]
    x, ref = data["bodies/float/displacement"][:, 2], reference["bodies/float/displacement"][:, 2]
    np.testing.assert_array_equal(x[: FAULT_STEP + 1], ref[: FAULT_STEP + 1])
    assert abs(x[FAULT_STEP + 2] - ref[FAULT_STEP + 2]) > 0


def test_stop_fallback_ends_the_run_and_keeps_results(tmp_path, reference) -> None:
    with pytest.raises(MasterError, match="fallback is 'stop'"):
        controlled_run(tmp_path, "out_of_limits", fallback="stop")
    with h5py.File(tmp_path / "run.h5") as f:
        assert f.attrs["status"].startswith("failed")
        assert json.loads(f.attrs["control_statistics"])["faults"]["out_of_limits"] == 1
        x = f["bodies/float/displacement"][:, 2]
    assert len(x) == FAULT_STEP  # every point before the faulty instant
    np.testing.assert_array_equal(x, reference["bodies/float/displacement"][:FAULT_STEP, 2])


def test_another_run_id_cannot_affect_the_run(tmp_path, reference) -> None:
    endpoint = free_endpoint()
    run_id = f"mine{time.monotonic_ns() % 10**9}"
    rogue = peer("rogue", "someone_else", endpoint)
    good = peer("none", run_id, endpoint, FAULT_STEP)
    try:
        run_scenario(scenario(run_id=run_id, endpoints=[endpoint]), tmp_path / "run.h5", progress=False, log=None)
    finally:
        rogue.kill()
        stop(rogue)
        stop(good)
    data = read_results(tmp_path / "run.h5")
    assert sum(data["attrs"]["control_statistics"]["faults"].values()) == 0
    np.testing.assert_allclose(data["bodies/float/displacement"], reference["bodies/float/displacement"],
                               rtol=0, atol=1e-12)


def test_default_session_is_loopback_only_without_multicast() -> None:
    conf = _config("listen", ["tcp/127.0.0.1:7447"], None)
    assert json.loads(conf.get_json("listen/endpoints")) == ["tcp/127.0.0.1:7447"]
    assert json.loads(conf.get_json("scouting/multicast/enabled")) is False
    assert json.loads(conf.get_json("mode")) == "peer"


def test_zenoh_config_file_sets_the_endpoints(tmp_path, reference) -> None:
    endpoint = free_endpoint()
    config = tmp_path / "zenoh.json5"
    config.write_text(json.dumps({"mode": "peer", "listen": {"endpoints": [endpoint]},
                                  "scouting": {"multicast": {"enabled": False}}}))
    run_id = f"cfg{time.monotonic_ns() % 10**9}"
    s = scenario(run_id=run_id, zenoh_config=str(config), endpoints=["tcp/127.0.0.1:1"])
    proc = peer("none", run_id, endpoint, FAULT_STEP)
    try:
        run_scenario(s, tmp_path / "run.h5", progress=False, log=None)
    finally:
        stop(proc)
    data = read_results(tmp_path / "run.h5")
    np.testing.assert_allclose(data["bodies/float/displacement"], reference["bodies/float/displacement"],
                               rtol=0, atol=1e-12)


def test_frames_round_trip_and_reject_defects() -> None:
    payload = protocol.encode(protocol.COMMANDS, 7, 0.7, [1.0, 2.0, 3.0])
    assert len(payload) == 24 + 3 * 8
    frame = protocol.decode(payload, protocol.COMMANDS, 3)
    assert (frame.step, frame.time, frame.values) == (7, 0.7, (1.0, 2.0, 3.0))
    for bad, fault in ((payload[:-8], "wrong_length"), (b"\x02\x00" + payload[2:], "wrong_version"),
                       (payload[:2] + b"\x01\x00" + payload[4:], "wrong_kind"), (payload[:10], "wrong_length")):
        with pytest.raises(protocol.FrameError) as info:
            protocol.decode(bad, protocol.COMMANDS, 3)
        assert info.value.fault == fault


def test_realtime_100_hz_for_60_s_records_latency_and_deadlines(tmp_path) -> None:
    """Factor 1, control every 10 ms for 60 s against an external passive controller. The test
    asserts that the statistics are recorded and sane, not that this machine meets a deadline."""
    endpoint = free_endpoint()
    run_id = f"rt{time.monotonic_ns() % 10**9}"
    s = scenario(duration=60.0, mode="realtime", run_id=run_id, endpoints=[endpoint], max_age=5)
    s.simulation.step = 0.01
    proc = peer("none", run_id, endpoint, -1)
    start = time.perf_counter()
    try:
        run_scenario(s, tmp_path / "rt.h5", progress=False, log=None)
    finally:
        stop(proc)
    wall = time.perf_counter() - start
    data = read_results(tmp_path / "rt.h5")
    stats = data["attrs"]["control_statistics"]
    n = len(data["time"])
    assert stats["periods"] == n == 6001 and stats["paced_steps"] == n
    assert 0 <= stats["missed_deadlines"] <= n
    lat = stats["latency_s"]
    assert lat["count"] > 0.5 * n
    assert 0 < lat["median"] <= lat["p99"] <= lat["max"] < 60.0
    latency = data["control/latency"]
    assert np.all(latency[np.isfinite(latency)] > 0)
    ages = data["control/age"][data["control/source"] == SOURCES["controller"]]
    assert np.all(ages >= 0) and np.all(ages <= s.control.max_age)
    assert wall >= 59.0  # paced to the wall clock: a 60 s run cannot finish much sooner


def example_run(tmp_path, name: str, *settings: str, internal: tuple[float, float] | None = None):
    """Run the cylinder with ``wec-cosim controller NAME`` attached; optionally the same scene with
    an internal PTO (damping, stiffness) for comparison."""
    endpoint = free_endpoint()
    run_id = f"ex{time.monotonic_ns() % 10**9}"
    s = scenario(duration=20.0, run_id=run_id, endpoints=[endpoint])
    args = [sys.executable, "-m", "orchestrator.cli", "controller", name, "--run", run_id, "--connect", endpoint]
    for item in settings:
        args += ["--set", item]
    proc = subprocess.Popen(args, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        run_scenario(s, tmp_path / "ex.h5", progress=False, log=None)
    finally:
        log = stop(proc)
    assert "ended after" in log, log
    data = read_results(tmp_path / "ex.h5")
    if internal is None:
        return data, None
    ref = scenario(duration=20.0)
    ref.ptos[0].damping, ref.ptos[0].stiffness = internal
    run_scenario(ref, tmp_path / "internal.h5", progress=False, log=None)
    return data, read_results(tmp_path / "internal.h5")


def test_reactive_example_equals_internal_spring_damper(tmp_path) -> None:
    data, ref = example_run(tmp_path, "reactive", "damping=1.5e5", "stiffness=-2.0e5", internal=(1.5e5, -2.0e5))
    np.testing.assert_allclose(data["bodies/float/displacement"], ref["bodies/float/displacement"], rtol=0,
                               atol=1e-12)


def test_latching_example_holds_the_body_after_each_velocity_reversal(tmp_path) -> None:
    data, _ = example_run(tmp_path, "latching", "damping=2e5", "latch_damping=1e8", "latch_time=1.0")
    damping = data["control/commands"][:, 1]
    latched = damping == 1e8
    assert latched.any() and (~latched).any()
    starts = np.flatnonzero(np.diff(latched.astype(int)) == 1) + 1
    ends = np.flatnonzero(np.diff(latched.astype(int)) == -1) + 1
    lengths = [e - s for s in starts for e in ends[ends > s][:1]]
    assert lengths and all(9 <= n <= 11 for n in lengths)  # 1 s of latching at a 0.1 s period
    v = data["bodies/float/velocity"][:, 2]
    held = latched.copy()
    held[starts] = False  # the first row of a latch is the state at the instant the latch engages
    assert np.max(np.abs(v[held])) < 0.05 * np.max(np.abs(v))  # the latched body barely moves


def test_velocity_tracking_example_commands_a_force(tmp_path) -> None:
    data, _ = example_run(tmp_path, "velocity_tracking", "gain=2e5", "elevation_gain=0.5")
    force = data["control/commands"][:, 2]
    eta, v = data["wave/elevation"], data["bodies/float/velocity"][:, 2]
    np.testing.assert_allclose(force, 2e5 * (0.5 * eta - v), rtol=1e-12, atol=1e-6)
    assert np.max(np.abs(force)) > 1e3
