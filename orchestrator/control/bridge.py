"""Master side of external control: publish measurements, obtain commands, never lose the run.

Lock-step mode: at each control instant the master publishes the measurements of step k and
waits (at most ``timeout`` s of wall time) for the command frame of step k. The run is
deterministic: identical inputs give identical results, run after run.

Real-time mode: the master is paced to the wall clock (``realtime_factor`` simulated seconds per
wall second); at each control instant it publishes the measurements and applies the newest valid
command it has, never waiting. It records the command's age (control periods since the
measurements it answers), the round-trip latency (wall time from publishing measurements k to
receiving command k) and the steps that finished after their wall-clock deadline.

Faults - a controller that is ``absent`` (never connected), ``late`` (no command within the
timeout, or older than ``max_age`` periods in real time), ``disconnected`` (its liveliness token
went away), or that sends a frame with the ``wrong_length``, ``wrong_version`` or ``wrong_kind``,
a ``stale_step``, ``non_finite`` values or values ``out_of_limits`` - trigger the configured
fallback for that control period: ``hold`` the last valid command, ``passive`` damping (the
configured damping, zero stiffness and force), or ``stop`` the run (a :class:`MasterError`, the
results so far kept). Every fault is counted; the counts go to the results file.

Frames that answer nothing new are dropped and counted (``dropped_frames``), never acted on: a
``duplicate`` of the answer already taken, a ``stale`` answer to an earlier step than the newest one
held, and an answer to a ``future_step`` (measurements not yet published: its latency would be
negative). In real time a faulty frame that arrives while a valid command younger than ``max_age`` is
held is dropped and counted the same way: it does not override that command; the fallback applies
only to a period without a valid command.
"""

from __future__ import annotations

import json
import math
import queue
import threading
import time
from dataclasses import dataclass, field

import numpy as np

from orchestrator.errors import MasterError

from . import protocol
from .protocol import COMMANDS, MEASUREMENTS, FrameError, Manifest
from .session import open_master

FAULTS = ("absent", "late", "disconnected", "wrong_length", "wrong_version", "wrong_kind", "stale_step",
          "non_finite", "out_of_limits")
SOURCES = {"controller": 0, "hold": 1, "passive": 2}
# frames dropped without a fallback: those that answer nothing new, and faulty ones next to a held valid command
DROPPED = ("duplicate", "stale", "future_step", "wrong_length", "wrong_version", "wrong_kind", "non_finite",
           "out_of_limits")


@dataclass(frozen=True)
class ControlSettings:
    """How the master talks to the controller (see ``docs/control.md``)."""

    run_id: str
    mode: str = "lockstep"
    period: float = 0.1
    fallback: str = "hold"
    passive_damping: float = 0.0
    timeout: float = 1.0
    connect_timeout: float = 10.0
    max_age: int = 5
    realtime_factor: float = 1.0
    endpoints: tuple[str, ...] = ("tcp/127.0.0.1:7447",)
    config_file: str = ""


@dataclass
class Decision:
    """The commands applied for one control period and why."""

    values: np.ndarray
    source: int
    fault: str | None = None
    age: float = 0.0
    latency: float = math.nan


@dataclass
class ControlStatistics:
    faults: dict[str, int] = field(default_factory=lambda: dict.fromkeys(FAULTS, 0))
    periods: int = 0
    fallback_periods: int = 0
    latencies: list[float] = field(default_factory=list)
    missed_deadlines: int = 0
    paced_steps: int = 0
    refused_controllers: int = 0
    refused_commands: int = 0
    dropped_frames: dict[str, int] = field(default_factory=lambda: dict.fromkeys(DROPPED, 0))

    def summary(self) -> dict:
        lat = np.array(self.latencies)
        stats = {"median": float(np.median(lat)), "p99": float(np.percentile(lat, 99)),
                 "max": float(lat.max()), "count": int(lat.size)} if lat.size else {"count": 0}
        return {"faults": self.faults, "periods": self.periods, "fallback_periods": self.fallback_periods,
                "latency_s": stats, "missed_deadlines": self.missed_deadlines, "paced_steps": self.paced_steps,
                "refused_controllers": self.refused_controllers, "refused_commands": self.refused_commands,
                "dropped_frames": self.dropped_frames}


class ControlBridge:
    """Exchange measurements and commands with one external controller over zenoh.

    Args:
        settings: mode, period, fallback, timeouts, endpoints.
        manifest: signals and commands in frame order (limits in the command signals).
        initial: commands in force before the first valid command (the scenario's PTO values).
        passive: commands of the passive fallback.
    """

    def __init__(self, settings: ControlSettings, manifest: Manifest, initial: np.ndarray,
                 passive: np.ndarray) -> None:
        self.settings = settings
        self.manifest = manifest
        self.n_commands = len(manifest.commands)
        self.lower = np.array([c.minimum for c in manifest.commands])
        self.upper = np.array([c.maximum for c in manifest.commands])
        self.last_valid = np.array(initial, dtype=float)
        self.passive = np.array(passive, dtype=float)
        self.stats = ControlStatistics()
        self._events: queue.Queue = queue.Queue()
        self._alive = threading.Event()
        self._ever_connected = False
        self._published: dict[int, float] = {}
        self._latest: protocol.Frame | None = None
        self._latest_arrival = math.nan
        self._answered = -1  # lock-step: the last step whose answer was taken
        self._last_published = -1  # the newest control step whose measurements were published
        self._wall_start: float | None = None
        self.owner: str | None = None  # id of the controller that drives the run
        self.session = None

    # ------------------------------------------------------------------ life cycle
    def start(self) -> None:
        """Open the session, serve the manifest, wait for the controller (``connect_timeout``)."""
        s = self.settings
        self.session = open_master(list(s.endpoints), s.config_file or None)
        run = s.run_id
        self._queryable = self.session.declare_queryable(
            protocol.key(run, "manifest"), lambda q: q.reply(q.key_expr, self.manifest.to_json()))
        self._publisher = self.session.declare_publisher(protocol.key(run, "measurements"))
        self._status = self.session.declare_publisher(protocol.key(run, "status"))
        self._commands = self.session.declare_subscriber(protocol.key(run, "commands/*"), self._on_command)
        self._liveliness = self.session.liveliness().declare_subscriber(
            protocol.key(run, "controller/*"), self._on_liveliness, history=True)
        # The controller watches this token: it ends when the master disappears (killed, crashed).
        self._token = self.session.liveliness().declare_token(protocol.key(run, "master"))
        self._publish_status("running")
        if self._alive.wait(s.connect_timeout):
            self._ever_connected = True

    def _publish_status(self, state: str) -> None:
        self._status.put(json.dumps({"state": state, "controller": self.owner}))

    def close(self, state: str = "finished") -> None:
        if self.session is None:
            return
        try:
            self._publish_status(state)
            time.sleep(0.05)  # let the status reach the controller before the session goes
        finally:
            # Undeclare explicitly, while the interpreter is healthy, rather than at garbage collection.
            for entity in (self._token, self._liveliness, self._commands, self._queryable, self._publisher,
                           self._status):
                entity.undeclare()
            self.session.close()
            self.session = None

    # ------------------------------------------------------------------ zenoh callbacks
    def _on_command(self, sample) -> None:  # noqa: ANN001
        arrival = time.perf_counter()
        if str(sample.key_expr).rsplit("/", 1)[-1] != self.owner:  # a refused second controller
            self.stats.refused_commands += 1
            return
        try:
            frame = protocol.decode(sample.payload.to_bytes(), COMMANDS, self.n_commands)
        except FrameError as exc:
            self._events.put((arrival, exc))
            return
        if frame.step > self._last_published:  # answers measurements not published yet: judged on arrival
            self.stats.dropped_frames["future_step"] += 1
            return
        self._events.put((arrival, frame))

    def _on_liveliness(self, sample) -> None:  # noqa: ANN001
        """One controller drives a run: the first to declare its token owns it until it disconnects; any
        other is refused (told so on ``status``, its commands ignored, counted in ``refused_controllers``)."""
        who = str(sample.key_expr).rsplit("/", 1)[-1]
        if str(sample.kind).upper().endswith("PUT"):
            if self.owner is not None and who != self.owner:
                self.stats.refused_controllers += 1
                self._publish_status("running")  # names the owner: the newcomer sees it is refused
                return
            self.owner = who
            self._ever_connected = True
            self._alive.set()
            self._publish_status("running")
        elif who == self.owner:
            self._alive.clear()
            self.owner = None
            self._events.put((time.perf_counter(), FrameError("disconnected", "controller disconnected")))

    # ------------------------------------------------------------------ exchange
    def exchange(self, step: int, t: float, measurements: np.ndarray) -> Decision:
        """Publish measurements of control step ``step`` and decide the commands to apply."""
        self.stats.periods += 1
        self._published[step] = time.perf_counter()
        self._published.pop(step - 1000, None)
        self._last_published = step
        self._publisher.put(protocol.encode(MEASUREMENTS, step, t, list(map(float, measurements))))
        if self.settings.mode == "lockstep":
            decision = self._lockstep(step)
        else:
            decision = self._realtime(step)
        if decision.source != SOURCES["controller"]:
            self.stats.fallback_periods += 1
        return decision

    def _check(self, frame: protocol.Frame) -> str | None:
        values = np.array(frame.values)
        if not np.all(np.isfinite(values)):
            return "non_finite"
        if np.any(values < self.lower) or np.any(values > self.upper):
            return "out_of_limits"
        return None

    def _fallback(self, fault: str, step: int, age: float = 0.0) -> Decision:
        self.stats.faults[fault] += 1
        kind = self.settings.fallback
        if kind == "stop":
            raise MasterError(
                f"external controller fault '{fault}' at control step {step}; the scenario's "
                "control.fallback is 'stop' (use 'hold' or 'passive' to ride through faults)")
        values = self.last_valid.copy() if kind == "hold" else self.passive.copy()
        return Decision(values, SOURCES[kind], fault, age)

    def _lockstep(self, step: int) -> Decision:
        if not self._alive.is_set():
            self._drain()
            return self._fallback("disconnected" if self._ever_connected else "absent", step)
        deadline = time.perf_counter() + self.settings.timeout
        stale = False
        while True:
            remaining = deadline - time.perf_counter()
            try:
                if remaining <= 0:
                    raise queue.Empty
                arrival, event = self._events.get(timeout=remaining)
            except queue.Empty:
                return self._fallback("stale_step" if stale else "late", step)
            if isinstance(event, FrameError):
                return self._fallback(event.fault, step)
            if event.step != step:  # dropped, counted; keep waiting for the answer to this step
                if event.step > step:
                    self.stats.dropped_frames["future_step"] += 1
                else:
                    self.stats.dropped_frames["duplicate" if event.step == self._answered else "stale"] += 1
                    stale = True
                continue
            fault = self._check(event)
            if fault is not None:
                return self._fallback(fault, step)
            self._answered = step
            self.last_valid = np.array(event.values)
            latency = arrival - self._published.get(step, arrival)
            self.stats.latencies.append(latency)
            return Decision(self.last_valid.copy(), SOURCES["controller"], None, 0.0, latency)

    def _drain(self) -> list:
        events = []
        while True:
            try:
                events.append(self._events.get_nowait())
            except queue.Empty:
                return events

    def _realtime(self, step: int) -> Decision:
        faults: list[str] = []  # faulty frames of this period
        new_latency = math.nan
        for arrival, event in self._drain():
            if isinstance(event, FrameError):
                if event.fault != "disconnected":  # the liveliness token decides that (below)
                    faults.append(event.fault)
                continue
            if event.step > step:  # answers measurements not published yet
                self.stats.dropped_frames["future_step"] += 1
                continue
            if self._latest is not None and event.step <= self._latest.step:
                self.stats.dropped_frames["duplicate" if event.step == self._latest.step else "stale"] += 1
                continue
            problem = self._check(event)
            if problem is not None:
                faults.append(problem)
                continue
            self._latest, self._latest_arrival = event, arrival
            sent = self._published.get(event.step)
            if sent is not None:
                new_latency = arrival - sent
                self.stats.latencies.append(new_latency)
        fault = faults[-1] if faults else None
        if self._latest is None:
            if fault is None and self._alive.is_set():
                # Connected but no answer yet (the first instants): the initial commands stand.
                return Decision(self.last_valid.copy(), SOURCES["hold"], None, math.nan)
            self._drop(faults[:-1])
            return self._fallback(fault or ("disconnected" if self._ever_connected else "absent"), step)
        age = float(step - self._latest.step)
        if not self._alive.is_set():
            self._drop(faults)
            return self._fallback("disconnected", step, age)
        if age > self.settings.max_age:
            self._drop(faults[:-1])
            return self._fallback(fault or "late", step, age)
        self._drop(faults)  # a valid command younger than max_age is held: faulty frames do not override it
        self.last_valid = np.array(self._latest.values)
        return Decision(self.last_valid.copy(), SOURCES["controller"], None, age, new_latency)

    def _drop(self, faults: list[str]) -> None:
        for fault in faults:
            self.stats.dropped_frames[fault] += 1

    # ------------------------------------------------------------------ pacing
    def pace(self, t: float) -> None:
        """Real time: wait until the wall clock reaches simulated time ``t``; count a missed
        deadline when the simulation got there late (more than 1 ms behind)."""
        if self.settings.mode != "realtime":
            return
        now = time.perf_counter()
        if self._wall_start is None:
            self._wall_start = now - t / self.settings.realtime_factor
        target = self._wall_start + t / self.settings.realtime_factor
        self.stats.paced_steps += 1
        if now > target + 1e-3:
            self.stats.missed_deadlines += 1
        elif target > now:
            time.sleep(target - now)
