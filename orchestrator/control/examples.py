"""Example controllers, usable on any scenario's PTOs (they read the PTO list from the manifest).

Run one with ``wec-cosim controller NAME --run RUN_ID [--connect ENDPOINT] [--set KEY=VALUE ...]``:

* ``passive`` - PTO damping ``damping`` (N s/m or N m s/rad), no stiffness, no force;
* ``reactive`` - spring-damper: ``damping`` and ``stiffness`` (negative stiffness cancels part of
  the hydrostatic spring to bring resonance towards the wave period);
* ``latching`` - holds the PTO (damping ``latch_damping``, by default the largest damping the run
  accepts: the scenario's ``control.damping_limits``, or 1e8 without a limit) for ``latch_time`` s
  each time its velocity changes sign, then releases it to ``damping``;
* ``velocity_tracking`` - force command u = ``gain`` (``elevation_gain`` * eta - v): drives the
  PTO velocity towards a multiple of the incident elevation at the origin (in phase with the
  excitation for a body small against the wavelength), with no passive damping.
"""

from __future__ import annotations

import argparse
import inspect
import math
import sys
from collections.abc import Callable
from dataclasses import dataclass, field

from .client import Controller, Law
from .protocol import Manifest


def _commands(c: Controller, **per_pto: float) -> dict[str, float]:
    return {f"{p['name']}.{k}": v for p in c.ptos for k, v in per_pto.items()}


def passive(damping: float = 2.0e5) -> Law:
    def law(step: int, t: float, m: dict[str, float], c: Controller) -> dict[str, float]:
        return _commands(c, damping=damping, stiffness=0.0, force_command=0.0)
    return law


def reactive(damping: float = 2.0e5, stiffness: float = -1.0e5) -> Law:
    def law(step: int, t: float, m: dict[str, float], c: Controller) -> dict[str, float]:
        return _commands(c, damping=damping, stiffness=stiffness, force_command=0.0)
    return law


UNLIMITED_LATCH_DAMPING = 1.0e8  # N s/m: holds a body of the bundled scenarios' size still (below 1 cm/s)


def latch_damping_for(c: Controller) -> float:
    """The default latch: the largest damping every controlled PTO accepts, or 1e8 without a limit."""
    hi = c.manifest.command_limits("damping")[1]
    return hi if math.isfinite(hi) else UNLIMITED_LATCH_DAMPING


def latching(damping: float = 2.0e5, latch_damping: float | None = None, latch_time: float = 1.0) -> Law:
    def law(step: int, t: float, m: dict[str, float], c: Controller) -> dict[str, float]:
        latch = latch_damping if latch_damping is not None else latch_damping_for(c)
        out = {}
        for p in c.ptos:
            v = m[p["velocity"]]
            memory = c.state.setdefault(p["name"], {"sign": 0.0, "until": -1.0})
            sign = (v > 0) - (v < 0)
            if memory["sign"] and sign and sign != memory["sign"]:
                memory["until"] = t + latch_time
            if sign:
                memory["sign"] = sign
            held = t < memory["until"]
            out.update({f"{p['name']}.damping": latch if held else damping,
                        f"{p['name']}.stiffness": 0.0, f"{p['name']}.force_command": 0.0})
        return out
    return law


def velocity_tracking(gain: float = 2.0e5, elevation_gain: float = 0.5) -> Law:
    def law(step: int, t: float, m: dict[str, float], c: Controller) -> dict[str, float]:
        eta = m.get("wave.elevation", 0.0)
        out = {}
        for p in c.ptos:
            u = gain * (elevation_gain * eta - m[p["velocity"]])
            out.update({f"{p['name']}.force_command": u, f"{p['name']}.damping": 0.0,
                        f"{p['name']}.stiffness": 0.0})
        return out
    return law


@dataclass(frozen=True)
class Example:
    """A law, its help, and which of its parameters are command values (checked against the run's limits)."""

    factory: Callable[..., Law]
    help: str
    commands: dict[str, str] = field(default_factory=dict)  # law parameter -> command kind it sets

    def check(self, params: dict[str, float], manifest: Manifest) -> None:
        """Refuse parameters whose commands the run would reject (``control.*_limits``): every such
        period would fall back, the run would not be the one asked for."""
        defaults = {k: p.default for k, p in inspect.signature(self.factory).parameters.items()}
        for name, kind in self.commands.items():
            value = params.get(name, defaults.get(name))
            if value is None:
                continue
            lo, hi = manifest.command_limits(kind)
            if not lo <= value <= hi:
                given = "--set" if name in params else "default"
                raise ValueError(f"{name} = {value:g} ({given}) is outside the run's {kind} limits [{lo:g}, {hi:g}] "
                                 f"(the scenario's control.{kind}_limits): every command would be refused and the "
                                 f"run would fall back; choose a value inside the limits")


EXAMPLES = {
    "passive": Example(passive, "constant PTO damping", {"damping": "damping"}),
    "reactive": Example(reactive, "constant PTO damping and stiffness",
                        {"damping": "damping", "stiffness": "stiffness"}),
    "latching": Example(latching, "latch at each velocity reversal for a fixed time",
                        {"damping": "damping", "latch_damping": "damping"}),
    "velocity_tracking": Example(velocity_tracking, "force command tracking a velocity proportional to eta"),
}


def add_arguments(p: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Command-line arguments of ``wec-cosim controller`` (shared with ``python -m`` use)."""
    p.add_argument("name", choices=sorted(EXAMPLES),
                   help="controller law: " + "; ".join(f"{k}: {v.help}" for k, v in sorted(EXAMPLES.items())))
    p.add_argument("--run", required=True, help="run id to control (the scenario's control.run_id)")
    p.add_argument("--connect", action="append", help="master endpoint (default tcp/127.0.0.1:7447)")
    p.add_argument("--config", help="zenoh configuration file (endpoints, TLS, access control)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="law parameter, e.g. --set damping=1e5")
    p.add_argument("--max-wall-time", type=float, default=None, help="give up after this many seconds")
    p.add_argument("--timeout", type=float, default=60.0,
                   help="end with an error when the master is silent this many seconds (default 60; a killed "
                        "master is noticed sooner through its liveliness token)")
    return p


def run_example(args: argparse.Namespace) -> int:
    example = EXAMPLES[args.name]
    known = list(inspect.signature(example.factory).parameters)
    params = {}
    for item in args.set:
        key, _, value = item.partition("=")
        key = key.strip()
        if key not in known:
            raise ValueError(f"--set {item}: {args.name} has no parameter {key!r} (its parameters: {', '.join(known)})")
        try:
            params[key] = float(value)
        except ValueError:
            raise ValueError(f"--set {item}: {value.strip()!r} is not a number") from None
    law = example.factory(**params)
    controller = Controller(args.run, law, endpoints=args.connect, config_file=args.config)
    try:
        example.check(params, controller.manifest)
    except ValueError:
        controller.close()
        raise
    print(f"controller {args.name!r} attached to run {args.run!r}: "
          f"{len(controller.ptos)} PTO(s), {len(controller.names)} measurements", flush=True)
    controller.run(args.max_wall_time, args.timeout)
    print(f"run {args.run!r} ended after {controller.steps} control steps", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(run_example(add_arguments(argparse.ArgumentParser(prog="python -m orchestrator.control.examples"))
                         .parse_args()))
