"""External control over zenoh: real sessions, controllers in separate processes, on loopback."""

from __future__ import annotations

import json
import os
import queue
import re
import signal
import socket
import subprocess
import sys
import threading
import time

import h5py
import numpy as np
import pytest

from orchestrator.control import protocol
from orchestrator.control.bridge import FAULTS, SOURCES
from orchestrator.control.session import _config
from orchestrator.cosim.simulation import format_summary, run_scenario
from orchestrator.errors import MasterError
from orchestrator.results import read_results
from orchestrator.scenario import load_scenario

from . import toml_text
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
    data, log, _ = controlled_run_summary(tmp_path, fault, damping, **control)
    return data, log


def controlled_run_summary(tmp_path, fault: str, damping: float = DAMPING, **control):
    """The results, the controller's output and the console summary of a run with a test controller."""
    endpoint = free_endpoint()
    run_id = f"t{time.monotonic_ns() % 10**9}"
    s = scenario(run_id=run_id, endpoints=[endpoint], **control)
    proc = peer(fault, run_id, endpoint, FAULT_STEP, damping) if fault != "absent" else None
    path = tmp_path / "run.h5"
    try:
        result = run_scenario(s, path, progress=False, log=None)
    finally:
        log = stop(proc) if proc else ""
    return read_results(path), log, format_summary(result).splitlines()


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
    data, _, summary = controlled_run_summary(tmp_path, fault, fallback="hold")
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
    n = len(data["time"])  # one control period per macro step
    if fault == "disconnect":
        assert np.all(code[FAULT_STEP:] == 1 + FAULTS.index("disconnected"))
        # The controller answered steps 0 .. FAULT_STEP - 1 and then vanished: the console says so.
        assert (f"controller: {FAULT_STEP} of {n} control periods commanded by the controller, {n - FAULT_STEP} on "
                f"the fallback 'hold' (faults: disconnected {n - FAULT_STEP})") in summary
    else:
        assert np.all(code[FAULT_STEP + 2:] == 0)  # the controller recovers after one bad frame
        line = next(x for x in summary if x.startswith("controller: "))
        assert f"on the fallback 'hold' (faults: {expected.replace('_', ' ')} " in line


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


def test_commands_beyond_the_limits_fall_back_visibly(tmp_path, reference) -> None:
    """A controller whose damping exceeds control.damping_limits from FAULT_STEP on (as the latching example's
    old default did on the bundled scenario): every later period runs on the fallback, and the summary says so."""
    data, _, summary = controlled_run_summary(tmp_path, "over_limits", fallback="passive", passive_damping=5.0e4,
                                              damping_limits=[0.0, 1.0e7])
    n = len(data["time"])
    assert np.all(data["control/source"][:FAULT_STEP] == SOURCES["controller"])
    assert np.all(data["control/source"][FAULT_STEP:] == SOURCES["passive"])
    assert np.all(data["control/fault"][FAULT_STEP:] == 1 + FAULTS.index("out_of_limits"))
    assert (f"controller: {FAULT_STEP} of {n} control periods commanded by the controller, {n - FAULT_STEP} on the "
            f"fallback 'passive' (faults: out of limits {n - FAULT_STEP})") in summary


def test_second_controller_on_the_same_run_is_refused(tmp_path, reference) -> None:
    """The owner peer drives the run and, once it does, starts `wec-cosim controller passive` on the same
    run id. The second is refused (exit 2, a message naming the owner); the first keeps driving the run,
    whose results equal the internal damper's; the results file and the summary record the refusal."""
    endpoint = free_endpoint()
    run_id = f"two{time.monotonic_ns() % 10**9}"
    proc = peer("owner", run_id, endpoint)
    try:
        result = run_scenario(scenario(run_id=run_id, endpoints=[endpoint]), tmp_path / "run.h5", progress=False,
                              log=None)
    finally:
        log = stop(proc)
    owner = re.search(r"owner (\w+) ended after (\d+) control steps \(finished\)", log)
    assert owner, log
    second = re.search(r"second controller exit (\S+): (.*)", log, re.DOTALL)
    assert second and second.group(1) == "2", log
    assert (f"is already driven by controller {owner.group(1)}; this controller is refused (one controller per "
            "run id)") in second.group(2)
    assert "Traceback" not in log
    data = read_results(tmp_path / "run.h5")
    stats = data["attrs"]["control_statistics"]
    assert stats["refused_controllers"] == 1 and sum(stats["faults"].values()) == 0
    assert int(owner.group(2)) == stats["periods"] == len(data["time"])
    assert np.all(data["control/source"] == SOURCES["controller"])
    np.testing.assert_allclose(data["bodies/float/displacement"], reference["bodies/float/displacement"],
                               rtol=0, atol=1e-12)
    assert any(x.startswith("controller: 1 other controller(s) refused on this run id")
               for x in format_summary(result).splitlines())


class Lines:
    """The output lines of a process, read by a thread; ``wait_for`` a line with a deadline (no hang)."""

    def __init__(self, proc: subprocess.Popen) -> None:
        self.proc, self.lines, self._queue = proc, [], queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        for line in self.proc.stdout:
            self._queue.put(line)
        self._queue.put(None)

    def wait_for(self, text: str, timeout: float = 90.0) -> None:
        deadline = time.monotonic() + timeout
        while not any(text in x for x in self.lines):
            try:
                line = self._queue.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                raise AssertionError(f"no line with {text!r} within {timeout:g} s: {self.lines}") from None
            if line is None:
                raise AssertionError(f"the process ended without a line with {text!r}: {self.lines}")
            self.lines.append(line)

    def rest(self, timeout: float) -> str:
        """Wait for the end of the process (at most ``timeout`` s) and return all its output."""
        self.proc.wait(timeout=timeout)
        while (line := self._queue.get(timeout=10)) is not None:
            self.lines.append(line)
        return "".join(self.lines)


def cli(*args: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "wec_cosim.cli", *args], cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"})


def test_controller_ends_when_its_master_stops_answering_or_is_killed(tmp_path) -> None:
    """A real master process (`wec-cosim run`). Stopped (SIGSTOP, alive but silent): a controller with
    --timeout 3 ends with exit 2 after 3 s of silence. Killed (SIGKILL): a controller with --timeout 60 ends
    with exit 2 because the master's liveliness token went away, well before its timeout."""
    endpoint = free_endpoint()
    run_id = f"kill{time.monotonic_ns() % 10**9}"
    data = toml_text.bundled("cylinder_regular")
    data["simulation"]["duration"] = 5000.0  # never reached: the master is killed
    data["ptos"][0]["damping"] = 0.0
    data["control"] = {"mode": "lockstep", "run_id": run_id, "endpoints": [endpoint], "timeout": 2.0,
                       "connect_timeout": 120.0, "fallback": "hold"}
    master = cli("run", str(toml_text.write(tmp_path / "ctl.toml", data)), "--out", str(tmp_path / "run.h5"),
                 "--quiet")
    controllers: list[subprocess.Popen] = []
    try:
        Lines(master).wait_for("for a controller on run")
        first = cli("controller", "passive", "--run", run_id, "--connect", endpoint, "--timeout", "3")
        controllers.append(first)
        lines = Lines(first)
        lines.wait_for("attached to run")
        time.sleep(1.0)  # the controller declares its token and answers measurements
        master.send_signal(signal.SIGSTOP)
        try:
            out = lines.rest(timeout=60)
        finally:
            master.send_signal(signal.SIGCONT)
        assert first.returncode == 2, out
        assert "is gone after" in out and "it was silent for 3 s (--timeout)" in out, out

        second = cli("controller", "passive", "--run", run_id, "--connect", endpoint, "--timeout", "60")
        controllers.append(second)
        lines = Lines(second)
        lines.wait_for("attached to run")
        time.sleep(1.5)  # it drives the run now (the first one left: the run had no owner)
        master.kill()
        killed = time.monotonic()
        out = lines.rest(timeout=75)
        ended = time.monotonic() - killed
        assert second.returncode == 2, out
        assert "is gone after" in out and "its liveliness token went away" in out, out
        assert ended < 60  # within its timeout (the liveliness token, not the timeout, ended it)
    finally:
        for proc in (master, *controllers):
            if proc.poll() is None:
                proc.kill()
            proc.wait()


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
    for bad, fault in ((payload[:-8], "wrong_length"), (b"\x01\x00" + payload[2:], "wrong_version"),
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


def example_run(tmp_path, name: str, *settings: str, internal: tuple[float, float] | None = None,
                bundled: bool = False, duration: float = 20.0):
    """Run the cylinder with ``wec-cosim controller NAME`` attached; optionally the same scene with
    an internal PTO (damping, stiffness) for comparison. ``bundled``: the bundled control scenario
    (scenarios/cylinder_control.toml, its limits and fallback)."""
    endpoint = free_endpoint()
    run_id = f"ex{time.monotonic_ns() % 10**9}"
    if bundled:
        s = load_scenario(SCENARIOS / "cylinder_control.toml")
        s.simulation.duration = duration
        s.control.run_id, s.control.endpoints = run_id, [endpoint]
    else:
        s = scenario(duration=duration, run_id=run_id, endpoints=[endpoint])
    args = [sys.executable, "-m", "wec_cosim.cli", "controller", name, "--run", run_id, "--connect", endpoint]
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
    """With its defaults on the bundled control scenario: the latch is the scenario's damping limit (1e7 N s/m),
    so no command is refused and no period falls back."""
    data, _ = example_run(tmp_path, "latching", bundled=True)
    limit = load_scenario(SCENARIOS / "cylinder_control.toml").control.damping_limits[1]
    damping = data["control/commands"][:, 1]
    latched = damping == limit
    stats = data["attrs"]["control_statistics"]
    assert stats["fallback_periods"] == 0 and sum(stats["faults"].values()) == 0
    assert np.all(data["control/source"] == SOURCES["controller"])
    assert latched.any() and (~latched).any()
    starts = np.flatnonzero(np.diff(latched.astype(int)) == 1) + 1
    ends = np.flatnonzero(np.diff(latched.astype(int)) == -1) + 1
    lengths = [e - s for s in starts for e in ends[ends > s][:1]]
    assert lengths and all(9 <= n <= 11 for n in lengths)  # 1 s of latching at a 0.1 s period
    # While latched, (M + A_inf) dv/dt = F - c v with F the hydro FMU's force and c the latch damping: from
    # its speed at the instant the latch engages, |v| cannot exceed max(|v0|, max|F| / c) (a first-order
    # system; 5 % for the sampling). Here max|F| / c is about 0.02 m/s: the latched body barely moves.
    v, force = data["bodies/float/velocity"][:, 2], data["bodies/float/hydro_force"][:, 2]
    for s_, e_ in zip(starts, [ends[ends > s_][:1] for s_ in starts], strict=True):
        if not len(e_):
            continue
        bound = max(abs(v[s_]), np.max(np.abs(force[s_:e_[0]])) / limit)
        assert np.max(np.abs(v[s_:e_[0]])) <= 1.05 * bound


def test_velocity_tracking_example_commands_a_force(tmp_path) -> None:
    data, _ = example_run(tmp_path, "velocity_tracking", "gain=2e5", "elevation_gain=0.5")
    force = data["control/commands"][:, 2]
    eta, v = data["wave/elevation"], data["bodies/float/velocity"][:, 2]
    np.testing.assert_allclose(force, 2e5 * (0.5 * eta - v), rtol=1e-12, atol=1e-6)
    assert np.max(np.abs(force)) > 1e3
