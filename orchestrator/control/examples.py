"""Example controllers, usable on any scenario's PTOs (they read the PTO list from the manifest).

Run one with ``wec-cosim controller NAME --run RUN_ID [--connect ENDPOINT] [--set KEY=VALUE ...]``:

* ``passive`` - PTO damping ``damping`` (N s/m or N m s/rad), no stiffness, no force;
* ``reactive`` - spring-damper: ``damping`` and ``stiffness`` (negative stiffness cancels part of
  the hydrostatic spring to bring resonance towards the wave period);
* ``latching`` - holds the PTO (damping ``latch_damping``) for ``latch_time`` s each time its
  velocity changes sign, then releases it to ``damping``;
* ``velocity_tracking`` - force command u = ``gain`` (``elevation_gain`` * eta - v): drives the
  PTO velocity towards a multiple of the incident elevation at the origin (in phase with the
  excitation for a body small against the wavelength), with no passive damping.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from dataclasses import dataclass

from .client import Controller, Law


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


def latching(damping: float = 2.0e5, latch_damping: float = 1.0e8, latch_time: float = 1.0) -> Law:
    def law(step: int, t: float, m: dict[str, float], c: Controller) -> dict[str, float]:
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
            out.update({f"{p['name']}.damping": latch_damping if held else damping,
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
    factory: Callable[..., Law]
    help: str


EXAMPLES = {
    "passive": Example(passive, "constant PTO damping"),
    "reactive": Example(reactive, "constant PTO damping and stiffness"),
    "latching": Example(latching, "latch at each velocity reversal for a fixed time"),
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
    params = {}
    for item in args.set:
        key, _, value = item.partition("=")
        params[key.strip()] = float(value)
    law = EXAMPLES[args.name].factory(**params)
    controller = Controller(args.run, law, endpoints=args.connect, config_file=args.config)
    print(f"controller {args.name!r} attached to run {args.run!r}: "
          f"{len(controller.ptos)} PTO(s), {len(controller.names)} measurements", flush=True)
    controller.run(args.max_wall_time, args.timeout)
    print(f"run {args.run!r} ended after {controller.steps} control steps", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(run_example(add_arguments(argparse.ArgumentParser(prog="python -m orchestrator.control.examples"))
                         .parse_args()))
