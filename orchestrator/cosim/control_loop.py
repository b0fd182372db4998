"""The control loop inside a co-simulation run: measurements from the master's outputs, commands
into the multibody FMU's PTO inputs, pacing, and what goes to the results file.

At every control instant t_k = k * period (a whole number of macro steps) the loop takes the
measurements at t_k, obtains the commands through :class:`~orchestrator.control.bridge.ControlBridge`
and sets them on the multibody FMU; they are held (not extrapolated) until the next instant.
"""

from __future__ import annotations

import math

import numpy as np

from orchestrator.control.bridge import FAULTS, ControlBridge, ControlSettings
from orchestrator.control.protocol import Manifest, Signal
from orchestrator.scene import MBD, Scene

COMMAND_UNITS = {
    "stiffness": ("N/m", "N.m/rad"),
    "damping": ("N.s/m", "N.m.s/rad"),
    "force_command": ("N", "N.m"),
}


def build_manifest(scene: Scene, master, settings: ControlSettings, ptos: list[str],  # noqa: ANN001
                   limits: dict[str, tuple[float, float]]) -> Manifest:
    """Every observed output of the master as a measurement; stiffness, damping and force command
    of each controlled PTO as commands (the multibody FMU's input names)."""
    measurements = []
    for comp, names in master.output_names.items():
        for name in names:
            info = master.components[comp].variables[name]
            measurements.append(Signal(name, info.unit or "1", f"output of the {comp} FMU"))
    commands, pto_info = [], []
    for p in scene.scenario.ptos:
        if p.name not in ptos:
            continue
        rot = p.dof in ("roll", "pitch", "yaw")
        i = ("surge", "sway", "heave", "roll", "pitch", "yaw").index(p.dof) + 1
        for kind, units in COMMAND_UNITS.items():
            lo, hi = limits.get(kind, (-math.inf, math.inf))
            commands.append(Signal(f"{p.name}.{kind}", units[rot], f"PTO {kind.replace('_', ' ')}", lo, hi))
        pto_info.append({"name": p.name, "body": p.body, "dof": p.dof,
                         "position": f"{p.body}.x[{i}]", "velocity": f"{p.body}.v[{i}]",
                         "stiffness": p.stiffness, "damping": p.damping, "force_command": 0.0})
    return Manifest(settings.run_id, settings.mode, settings.period, measurements, commands, pto_info)


class ControlLoop:
    """Couples an external controller to a running master (see the module docstring)."""

    def __init__(self, scene: Scene, master, settings: ControlSettings, ptos: list[str],  # noqa: ANN001
                 limits: dict[str, tuple[float, float]], step: float) -> None:
        self.master = master
        self.settings = settings
        self.manifest = build_manifest(scene, master, settings, ptos, limits)
        self.every = int(round(settings.period / step))
        self._sources = [(comp, master.output_names[comp].index(s.name))
                         for s in self.manifest.measurements
                         for comp in master.output_names if s.name in master.output_names[comp]]
        self._mbd = master.components[MBD]
        self._port = self._mbd.port([c.name for c in self.manifest.commands])
        initial = np.array([p[k] for p in self.manifest.ptos for k in ("stiffness", "damping", "force_command")])
        passive = np.array([v for _ in self.manifest.ptos for v in (0.0, settings.passive_damping, 0.0)])
        self.bridge = ControlBridge(settings, self.manifest, initial, passive)
        self.current = initial.copy()
        self.source, self.fault, self.age, self.latency = 0, 0, 0.0, math.nan
        self.count = 0
        # commands that can feed energy in (negative damping or stiffness): name -> (most negative value, first t)
        self.negative: dict[str, tuple[float, float]] = {}
        self._signed = [i for i, c in enumerate(self.manifest.commands) if c.name.endswith((".damping", ".stiffness"))]

    @property
    def series(self) -> dict[str, tuple[int, ...]]:
        n = len(self.manifest.commands)
        return {"control/commands": (n,), "control/source": (), "control/fault": (), "control/age": (),
                "control/latency": ()}

    def start(self) -> None:
        self.bridge.start()

    def measurements(self, outputs: dict[str, np.ndarray]) -> np.ndarray:
        return np.array([outputs[comp][i] for comp, i in self._sources])

    def on_point(self, t: float, outputs: dict[str, np.ndarray]) -> None:
        """Called at every communication point, after the outputs are resolved."""
        self.bridge.pace(t)
        self.fault, self.latency = 0, math.nan
        if self.count % self.every == 0:
            decision = self.bridge.exchange(self.count // self.every, t, self.measurements(outputs))
            self.current = decision.values
            self.source, self.age, self.latency = decision.source, decision.age, decision.latency
            self.fault = 0 if decision.fault is None else 1 + FAULTS.index(decision.fault)
            self._mbd.set_reals(self._port, self.current)
            for i in self._signed:
                if self.current[i] < 0:
                    name = self.manifest.commands[i].name
                    low, first = self.negative.get(name, (0.0, t))
                    self.negative[name] = (min(low, float(self.current[i])), first)
        self.count += 1

    def row(self) -> dict[str, np.ndarray | float]:
        return {"control/commands": self.current, "control/source": self.source, "control/fault": self.fault,
                "control/age": self.age, "control/latency": self.latency}

    def close(self, state: str) -> dict:
        self.bridge.close(state)
        return self.bridge.stats.summary()


def control_loop(scene: Scene, master) -> ControlLoop | None:  # noqa: ANN001
    """The scenario's control loop, or None when ``[control] mode = "off"``."""
    s = scene.scenario
    c = s.control
    if c.mode == "off":
        return None
    settings = ControlSettings(
        run_id=c.run_id or s.name, mode=c.mode, period=c.period or s.simulation.step, fallback=c.fallback,
        passive_damping=c.passive_damping, timeout=c.timeout, connect_timeout=c.connect_timeout,
        max_age=c.max_age, realtime_factor=c.realtime_factor, endpoints=tuple(c.endpoints),
        config_file=str(s.resolve(c.zenoh_config)) if c.zenoh_config else "",
    )
    limits = {"damping": tuple(c.damping_limits), "stiffness": tuple(c.stiffness_limits),
              "force_command": tuple(c.force_limits)}
    ptos = c.ptos or [p.name for p in s.ptos]
    return ControlLoop(scene, master, settings, ptos, limits, s.simulation.step)
