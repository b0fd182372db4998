"""Controller client: write an external controller in a few lines.

    from orchestrator.control.client import Controller

    def law(step, t, m, c):          # m: measurements by name; c: the controller (manifest, pto list)
        return {f"{p['name']}.damping": 2.0e5 for p in c.ptos}

    Controller("my_run", law).run()

The controller connects to the master, reads the manifest, declares its liveliness token, and
answers every measurement frame with a command frame for the same step. Commands not returned
by the law keep their previous value (initially the manifest's defaults, the scenario's values).
A name the run does not command (a PTO that does not exist) or a value that is not a number stops the
controller: :meth:`Controller.run` raises ValueError naming it (the master then falls back).
:meth:`Controller.run` returns when the master publishes the end of the run.
"""

from __future__ import annotations

import json
import threading
import time
import uuid
from collections.abc import Callable

from . import protocol
from .protocol import COMMANDS, MEASUREMENTS, FrameError, Manifest
from .session import open_controller

Law = Callable[[int, float, dict[str, float], "Controller"], dict[str, float]]


class Controller:
    """An external controller for run ``run_id``.

    Args:
        run_id: the run to control (``control.run_id`` of the scenario).
        law: ``law(step, t, measurements, controller) -> {command name: value}``.
        endpoints: where the master listens (default loopback, port 7447).
        config_file: a zenoh configuration file instead (TLS, access control...).
        defaults: starting values of commands the law does not set (default: the manifest's).
    """

    def __init__(self, run_id: str, law: Law, endpoints: list[str] | None = None,
                 config_file: str | None = None, defaults: dict[str, float] | None = None) -> None:
        self.run_id = run_id
        self.law = law
        self.session = open_controller(endpoints, config_file)
        self.manifest = self._query_manifest()
        self.names = [s.name for s in self.manifest.measurements]
        self.command_names = [s.name for s in self.manifest.commands]
        self.values = {name: 0.0 for name in self.command_names}
        self.values.update(self._default_commands())
        self.values.update(defaults or {})
        self.steps = 0
        self.id = uuid.uuid4().hex[:16]  # this controller's token and command key: wec/<run>/*/<id>
        self.refused_by: str | None = None  # id of the controller that owns the run, if we are refused
        self.master_gone: str | None = None  # how the master was lost: its liveliness token went, or silence
        self.last_heard = time.monotonic()
        self.finished = threading.Event()
        self.ended = False  # the master announced the end of the run
        self.announced = False  # our liveliness token is declared
        self.state = {}  # free for laws that keep memory between steps
        self.error: Exception | None = None  # what stopped the law (raised by run())

    @property
    def ptos(self) -> list[dict]:
        """The controlled PTOs: name and the names of their position and velocity measurements."""
        return self.manifest.ptos

    def _default_commands(self) -> dict[str, float]:
        """The scenario's PTO settings, as the manifest states them."""
        return {f"{p['name']}.{k}": p[k] for p in self.manifest.ptos for k in ("stiffness", "damping", "force_command")}

    def _query_manifest(self, timeout: float = 20.0) -> Manifest:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for reply in self.session.get(protocol.key(self.run_id, "manifest"), timeout=1.0):
                if reply.ok is not None:
                    manifest = Manifest.from_json(reply.ok.payload.to_bytes())
                    if manifest.protocol_version != protocol.PROTOCOL_VERSION:
                        raise RuntimeError(f"master speaks protocol {manifest.protocol_version}, "
                                           f"this client {protocol.PROTOCOL_VERSION}")
                    return manifest
            time.sleep(0.1)
        raise TimeoutError(f"no master serves run {self.run_id!r} (waited {timeout:g} s)")

    def _on_measurements(self, sample) -> None:  # noqa: ANN001
        self.last_heard = time.monotonic()
        try:
            frame = protocol.decode(sample.payload.to_bytes(), MEASUREMENTS, len(self.names))
        except FrameError:
            return
        if self.error:
            return
        measured = dict(zip(self.names, frame.values, strict=True))
        try:
            update = self.law(frame.step, frame.time, measured, self) or {}
            self.values.update(self.checked(update))
        except Exception as exc:  # noqa: BLE001 - runs in zenoh's thread: handed to run(), which raises it
            self.error = exc
            self.finished.set()
            return
        self.publish(frame.step, frame.time, [self.values[n] for n in self.command_names])
        self.steps += 1

    def checked(self, update: dict) -> dict[str, float]:
        """The law's answer as numbers by command name; a name the run does not command (a PTO that does not
        exist, a misspelt kind) or a value that is not a number is refused (ValueError), never dropped."""
        if not isinstance(update, dict):
            raise ValueError(f"the control law returned a {type(update).__name__}, not a dict of commands")
        unknown = [name for name in update if name not in self.values]
        if unknown:
            raise ValueError(f"the control law set {unknown[0]!r}, which is not a command of run {self.run_id!r} "
                             f"(its commands: {', '.join(self.command_names)})")
        out = {}
        for name, value in update.items():
            try:
                out[name] = float(value)
            except (TypeError, ValueError):
                raise ValueError(f"the control law set {name!r} to {value!r}, not a number") from None
        return out

    def publish(self, step: int, t: float, values: list[float]) -> None:
        """Send one command frame (exposed so tests can send deliberately bad frames)."""
        self._publisher.put(protocol.encode(COMMANDS, step, t, values))

    def _on_status(self, sample) -> None:  # noqa: ANN001
        self.last_heard = time.monotonic()
        try:
            status = json.loads(sample.payload.to_bytes())
        except ValueError:
            return
        owner = status.get("controller") if isinstance(status, dict) else None
        if owner and owner != self.id and self.announced:
            self.refused_by = owner
            self.finished.set()
        if not isinstance(status, dict) or status.get("state") != "running":
            self.ended = True
            self.finished.set()

    def _on_master(self, sample) -> None:  # noqa: ANN001
        # The master withdraws its token also after a normal end (status first): only an unannounced loss counts.
        if not str(sample.kind).upper().endswith("PUT") and not self.ended:
            self.master_gone = "its liveliness token went away (process killed or network lost)"
            self.finished.set()

    def run(self, max_wall_time: float | None = None, timeout: float = 60.0) -> None:
        """Serve measurements until the master ends the run, ``max_wall_time`` s pass, or the master is
        silent for ``timeout`` s or its liveliness token disappears (killed master).

        Raises RuntimeError if another controller already drives the run (this one is refused) or if the
        master disappeared before the end of the run."""
        self._publisher = self.session.declare_publisher(protocol.key(self.run_id, f"commands/{self.id}"))
        self._status = self.session.declare_subscriber(protocol.key(self.run_id, "status"), self._on_status)
        self._master = self.session.liveliness().declare_subscriber(protocol.key(self.run_id, "master"),
                                                                    self._on_master, history=True)
        self._subscriber = self.session.declare_subscriber(protocol.key(self.run_id, "measurements"),
                                                           self._on_measurements)
        # The token tells the master we are ready: declare it only once we can hear measurements.
        self.announced = True  # from now on a status naming another controller means we are refused
        self._token = self.session.liveliness().declare_token(protocol.key(self.run_id, f"controller/{self.id}"))
        start = self.last_heard = time.monotonic()
        try:
            while not self.finished.wait(0.2):
                now = time.monotonic()
                if max_wall_time is not None and now - start >= max_wall_time:
                    break
                if now - self.last_heard > timeout:
                    self.master_gone = f"it was silent for {timeout:g} s (--timeout)"
                    break
        finally:
            self.close()
        if self.error is not None:
            raise ValueError(f"controller of run {self.run_id!r} stopped after {self.steps} control steps: "
                             f"{self.error}") from None
        if self.refused_by:
            raise RuntimeError(f"run {self.run_id!r} is already driven by controller {self.refused_by}; this "
                               "controller is refused (one controller per run id)")
        if self.master_gone:
            raise RuntimeError(f"the master of run {self.run_id!r} is gone after {self.steps} control steps: "
                               f"{self.master_gone}")

    def close(self) -> None:
        if self.session is not None:
            for name in ("_token", "_subscriber", "_status", "_master", "_publisher"):
                entity = getattr(self, name, None)
                if entity is not None:
                    entity.undeclare()
                    setattr(self, name, None)
            self.session.close()
            self.session = None
