"""Controller processes that misbehave in time or in what they send, for tests/test_hostile_control.py.

    python -m tests.hostile_control_peers BEHAVIOUR RUN_ID ENDPOINT [DAMPING]

BEHAVIOUR: ``duplicates:N`` (every answer followed by N copies), ``future:N`` (before each answer, N frames for the
steps after it, with three times the damping), ``garbage:N`` (before each answer, N frames one value short),
``law:NAME=VALUE`` (the law sets command NAME, which the run may not have; VALUE parsed as a float when it can be),
``vanish:K`` (the process ends without a goodbye at step K).
A passive damper otherwise. Prints ``ended after N control steps`` or ``error: MESSAGE``.
"""

from __future__ import annotations

import sys

from orchestrator.control import protocol
from orchestrator.control.client import Controller
from orchestrator.control.examples import passive


class Hostile(Controller):
    def __init__(self, behaviour: str, *args, **kwargs) -> None:
        self.behaviour, _, count = behaviour.partition(":")
        self.count = int(count) if count.isdigit() else 0
        super().__init__(*args, **kwargs)

    def _on_measurements(self, sample) -> None:  # noqa: ANN001
        frame = protocol.decode(sample.payload.to_bytes(), protocol.MEASUREMENTS, len(self.names))
        if self.behaviour == "vanish" and frame.step >= self.count:
            import os

            os._exit(0)
        values = [self.values[n] for n in self.command_names]
        if self.behaviour == "future":
            wrong = [3 * v for v in values]
            for k in range(1, self.count + 1):
                self.publish(frame.step + k, frame.time, wrong)
        if self.behaviour == "garbage":
            for _ in range(self.count):
                self.publish(frame.step, frame.time, values[:-1])
        super()._on_measurements(sample)
        if self.behaviour == "duplicates":
            answer = [self.values[n] for n in self.command_names]
            for _ in range(self.count):
                self.publish(frame.step, frame.time, answer)


def law_setting(spec: str, damping: float):  # noqa: ANN201
    name, _, text = spec.partition("=")
    try:
        value: object = float(text)
    except ValueError:
        value = text or None
    passive_law = passive(damping)

    def law(step, t, m, c):  # noqa: ANN001, ANN202
        out = dict(passive_law(step, t, m, c))
        out[name] = value
        return out
    return law


if __name__ == "__main__":
    behaviour, run_id, endpoint = sys.argv[1:4]
    damping = float(sys.argv[4]) if len(sys.argv) > 4 else 2.0e5
    if behaviour.startswith("law:"):
        controller = Controller(run_id, law_setting(behaviour[4:], damping), endpoints=[endpoint])
    else:
        controller = Hostile(behaviour, run_id, passive(damping), endpoints=[endpoint])
    try:
        controller.run(120.0)
    except (ValueError, RuntimeError) as exc:
        print(f"error: {exc}", flush=True)
        sys.exit(2)
    print(f"ended after {controller.steps} control steps", flush=True)
