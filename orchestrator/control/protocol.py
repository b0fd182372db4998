"""Wire protocol between the master and an external controller (version 2).

Version 1 had one ``commands`` key per run and no controller ownership; a version-1 controller
is refused with a clear error when it reads the manifest.

Key expressions, all under ``wec/<run_id>/``:

* ``manifest`` - queryable served by the master: JSON (UTF-8) describing the run, every measured
  signal and every command, in frame order, with units and limits;
* ``measurements`` - published by the master at every control instant;
* ``commands/<id>`` - published by the controller ``<id>`` (a random token of its own), one frame
  per measurement frame it answers;
* ``status`` - published by the master: JSON ``{"state": "running" | "finished" | "failed",
  "controller": <id of the controller that drives the run, or null>}``;
* ``controller/<id>`` - liveliness token declared by a controller while it is connected. The first
  controller to declare one drives the run; while it is connected any other is refused: the master
  ignores its commands, counts it (``refused_controllers``) and names the owner on ``status``, and
  the refused controller ends with an error;
* ``master`` - liveliness token of the master: a controller ends (with an error) when it disappears.

Frame (little-endian), 24-byte header then values::

    offset  size  type     field
    0       2     uint16   protocol version (2)
    2       2     uint16   kind: 1 = measurements, 2 = commands
    4       4     uint32   number of values n
    8       8     int64    control step index k (commands: the k of the measurements answered)
    16      8     float64  simulation time t_k, s
    24      8 n   float64  values in manifest order
"""

from __future__ import annotations

import json
import math
import struct
from dataclasses import asdict, dataclass, field

PROTOCOL_VERSION = 2
MEASUREMENTS = 1
COMMANDS = 2
HEADER = struct.Struct("<HHIqd")


def key(run_id: str, leaf: str) -> str:
    """Key expression ``wec/<run_id>/<leaf>``."""
    return f"wec/{run_id}/{leaf}"


def valid_run_id(run_id: str) -> bool:
    """Run ids are one key-expression chunk: letters, digits, ``_`` and ``-``."""
    return bool(run_id) and all(c.isalnum() or c in "_-" for c in run_id) and run_id.isascii()


@dataclass(frozen=True)
class Signal:
    """One value of a frame: name (the FMU variable it comes from or goes to), unit, meaning."""

    name: str
    unit: str
    description: str = ""
    minimum: float = -math.inf
    maximum: float = math.inf


@dataclass
class Manifest:
    """What the master measures and what it accepts as commands, in frame order."""

    run_id: str
    mode: str
    period: float
    measurements: list[Signal]
    commands: list[Signal]
    ptos: list[dict] = field(default_factory=list)
    protocol_version: int = PROTOCOL_VERSION

    def to_json(self) -> str:
        data = asdict(self)
        for group in ("measurements", "commands"):
            for s in data[group]:
                for bound in ("minimum", "maximum"):
                    if math.isinf(s[bound]):
                        s[bound] = None  # JSON has no infinity
        return json.dumps(data, indent=1)

    @classmethod
    def from_json(cls, text: str | bytes) -> Manifest:
        data = json.loads(text)

        def signals(items: list[dict]) -> list[Signal]:
            out = []
            for s in items:
                lo = -math.inf if s.get("minimum") is None else s["minimum"]
                hi = math.inf if s.get("maximum") is None else s["maximum"]
                out.append(Signal(s["name"], s["unit"], s.get("description", ""), lo, hi))
            return out

        return cls(data["run_id"], data["mode"], data["period"], signals(data["measurements"]),
                   signals(data["commands"]), data.get("ptos", []), data["protocol_version"])

    def measurement_index(self) -> dict[str, int]:
        return {s.name: i for i, s in enumerate(self.measurements)}

    def command_index(self) -> dict[str, int]:
        return {s.name: i for i, s in enumerate(self.commands)}

    def command_limits(self, kind: str) -> tuple[float, float]:
        """The range of command ``kind`` (``damping``, ``stiffness``, ``force_command``) that every
        controlled PTO accepts (the scenario's ``control.*_limits``)."""
        signals = [s for s in self.commands if s.name.rsplit(".", 1)[-1] == kind]
        return (max((s.minimum for s in signals), default=-math.inf),
                min((s.maximum for s in signals), default=math.inf))


@dataclass(frozen=True)
class Frame:
    kind: int
    step: int
    time: float
    values: tuple[float, ...]


class FrameError(ValueError):
    """A frame that cannot be used; ``fault`` names the fault class."""

    def __init__(self, fault: str, message: str) -> None:
        super().__init__(message)
        self.fault = fault


def encode(kind: int, step: int, time: float, values: list[float] | tuple[float, ...]) -> bytes:
    return HEADER.pack(PROTOCOL_VERSION, kind, len(values), step, time) + struct.pack(f"<{len(values)}d", *values)


def decode(payload: bytes, kind: int, n_values: int) -> Frame:
    """Parse and check a frame; raises :class:`FrameError` with the fault class on any defect."""
    if len(payload) < HEADER.size:
        raise FrameError("wrong_length", f"frame of {len(payload)} bytes is shorter than the {HEADER.size}-byte header")
    version, got_kind, n, step, time = HEADER.unpack_from(payload)
    if version != PROTOCOL_VERSION:
        raise FrameError("wrong_version", f"protocol version {version}, expected {PROTOCOL_VERSION}")
    if got_kind != kind:
        raise FrameError("wrong_kind", f"frame kind {got_kind}, expected {kind}")
    if n != n_values or len(payload) != HEADER.size + 8 * n_values:
        raise FrameError("wrong_length",
                         f"frame holds {n} values in {len(payload)} bytes, expected {n_values} values "
                         f"({HEADER.size + 8 * n_values} bytes)")
    values = struct.unpack_from(f"<{n}d", payload, HEADER.size)
    return Frame(got_kind, step, time, values)
