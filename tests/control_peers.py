"""Controller processes for the control tests: a well-behaved passive damper that turns faulty at
a chosen control step, a rogue publisher on another run id, and an owner that starts a second
controller on its own run id.

    python -m tests.control_peers FAULT RUN_ID ENDPOINT STEP [DAMPING]
    python -m tests.control_peers rogue OTHER_RUN_ID ENDPOINT
    python -m tests.control_peers owner RUN_ID ENDPOINT

FAULT: none, late, disconnect, wrong_length, wrong_version, stale_step, nan, inf, out_of_limits (once, at
STEP), over_limits (damping 1e8 at every step from STEP on).
"""

from __future__ import annotations

import os
import struct
import subprocess
import sys
import time

import zenoh

from orchestrator.control import protocol
from orchestrator.control.client import Controller
from orchestrator.control.examples import passive
from orchestrator.control.session import open_controller


class FaultyController(Controller):
    def __init__(self, fault: str, fault_step: int, *args, **kwargs) -> None:
        self.fault, self.fault_step = fault, fault_step
        super().__init__(*args, **kwargs)

    def _on_measurements(self, sample) -> None:  # noqa: ANN001
        frame = protocol.decode(sample.payload.to_bytes(), protocol.MEASUREMENTS, len(self.names))
        if frame.step != self.fault_step or self.fault == "none":
            return super()._on_measurements(sample)
        good = [self.values[n] for n in self.command_names]
        k, t = frame.step, frame.time
        if self.fault == "late":
            time.sleep(2.5)  # longer than the master's 2 s timeout; the answer arrives stale
            self.publish(k, t, good)
        elif self.fault == "disconnect":
            os._exit(0)  # vanish without a goodbye: the liveliness token drops
        elif self.fault == "wrong_length":
            self.publish(k, t, good[:-1])
        elif self.fault == "wrong_version":
            payload = protocol.encode(protocol.COMMANDS, k, t, good)
            self._publisher.put(struct.pack("<H", 99) + payload[2:])
        elif self.fault == "stale_step":
            self.publish(k - 1, t, good)
        elif self.fault in ("nan", "inf"):
            self.publish(k, t, [float(self.fault)] * len(good))
        elif self.fault == "out_of_limits":
            self.publish(k, t, [-1.0e9] * len(good))
        elif self.fault == "over_limits":  # from now on, a damping beyond the run's limit (like a too hard latch)
            self.fault_step += 1
            self.publish(k, t, [1.0e8 if n.endswith(".damping") else 0.0 for n in self.command_names])
        else:
            raise SystemExit(f"unknown fault {self.fault}")


class OwnerController(Controller):
    """A passive damper that, once it drives the run (at its first measurement frame), starts a second
    controller (``wec-cosim controller passive``) on the same run id, and answers slowly (0.5 s, well
    inside the master's 2 s timeout) while that one is alive, so the second one meets a running run."""

    def __init__(self, endpoint: str, *args, **kwargs) -> None:
        self.endpoint = endpoint
        self.second: subprocess.Popen | None = None
        super().__init__(*args, **kwargs)

    def _on_measurements(self, sample) -> None:  # noqa: ANN001
        if self.second is None:
            self.second = subprocess.Popen(
                [sys.executable, "-m", "wec_cosim.cli", "controller", "passive", "--run", self.run_id,
                 "--connect", self.endpoint], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        elif self.second.poll() is None:
            time.sleep(0.5)
        super()._on_measurements(sample)


def rogue(run_id: str, endpoint: str) -> None:
    """Floods another run's command key with NaN frames (it must not affect our run)."""
    session = open_controller([endpoint])
    pub = session.declare_publisher(protocol.key(run_id, "commands/rawpeer"))
    token = session.liveliness().declare_token(protocol.key(run_id, "controller/rawpeer"))
    for k in range(100000):
        pub.put(protocol.encode(protocol.COMMANDS, k, 0.0, [float("nan")] * 3))
        time.sleep(0.001)
    del token


if __name__ == "__main__":
    zenoh.try_init_log_from_env()
    kind, run_id, endpoint = sys.argv[1:4]
    if kind == "rogue":
        rogue(run_id, endpoint)
    elif kind == "owner":
        owner = OwnerController(endpoint, run_id, passive(2.0e5), endpoints=[endpoint])
        owner.run(120.0)
        out, _ = owner.second.communicate(timeout=60) if owner.second else ("(not started)", None)
        code = owner.second.returncode if owner.second else None
        print(f"owner {owner.id} ended after {owner.steps} control steps "
              f"({'finished' if owner.ended else 'not finished'})")
        print(f"second controller exit {code}: {out.strip()}")
    else:
        step = int(sys.argv[4])
        damping = float(sys.argv[5]) if len(sys.argv) > 5 else 2.0e5
        controller = FaultyController(kind, step, run_id, passive(damping), endpoints=[endpoint])
        controller.run(120.0)
        how = "finished" if controller.finished.is_set() else "timeout"
        print(f"ended after {controller.steps} control steps ({how})")
