"""External control over zenoh: round-trip latency, and the cost of lock-step control.

1. Round trip: the master's bridge publishes a measurement frame, an example controller in
   another process (``wec-cosim controller passive``) answers; wall time from publishing to
   receiving the answer, over many exchanges (median, p99).
2. Slowdown: the bundled cylinder at a 1 ms macro step for ``--duration`` s, with the internal
   PTO damper, and with the same damper as an external lock-step controller at control periods
   from 1 ms to 100 ms (same results to 1e-12; only the wall time differs).

Run from the repository root:

    python benchmarks/bench_control.py [--exchanges 3000] [--duration 5] [--out benchmarks/results/control.txt]
"""

from __future__ import annotations

import argparse
import platform
import socket
import subprocess
import sys
from datetime import date
from pathlib import Path

import numpy as np

from orchestrator.control.bridge import ControlBridge, ControlSettings
from orchestrator.control.protocol import Manifest, Signal
from orchestrator.cosim.simulation import run_scenario
from orchestrator.scenario import load_scenario

ROOT = Path(__file__).resolve().parent.parent


def free_endpoint() -> str:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{s.getsockname()[1]}"


def controller(run_id: str, endpoint: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "wec_cosim.cli", "controller", "passive", "--run", run_id,
                             "--connect", endpoint], cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def round_trips(n: int) -> np.ndarray:
    endpoint, run_id = free_endpoint(), "bench_rtt"
    measurements = [Signal(f"m{i}", "1") for i in range(6)]
    commands = [Signal(f"pto.{k}", "1") for k in ("stiffness", "damping", "force_command")]
    ptos = [{"name": "pto", "position": "m0", "velocity": "m1", "stiffness": 0.0, "damping": 1.0,
             "force_command": 0.0}]
    manifest = Manifest(run_id, "lockstep", 0.001, measurements, commands, ptos)
    bridge = ControlBridge(ControlSettings(run_id, endpoints=(endpoint,), connect_timeout=30.0), manifest,
                           np.zeros(3), np.zeros(3))
    proc = controller(run_id, endpoint)
    try:
        bridge.start()
        for k in range(n):
            bridge.exchange(k, k * 0.001, np.zeros(6))
    finally:
        bridge.close()
        proc.wait(timeout=20)
    return np.array(bridge.stats.latencies)


def timed_run(duration: float, step: float, period: float | None) -> float:
    s = load_scenario(ROOT / "scenarios" / "cylinder_regular.toml")
    s.simulation.duration, s.simulation.step = duration, step
    proc = None
    if period is not None:
        endpoint, run_id = free_endpoint(), f"bench{int(period * 1e6)}"
        s.ptos[0].damping = 0.0
        s.control.mode, s.control.run_id, s.control.period = "lockstep", run_id, period
        s.control.endpoints, s.control.connect_timeout = [endpoint], 30.0
        proc = controller(run_id, endpoint)
    out = Path("/tmp") / f"bench_control_{period}.h5"
    try:
        result = run_scenario(s, out, progress=False, log=None)
    finally:
        if proc:
            proc.wait(timeout=20)
    return result.wall_time


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--exchanges", type=int, default=3000)
    parser.add_argument("--duration", type=float, default=5.0)
    parser.add_argument("--out")
    args = parser.parse_args()
    lat = round_trips(args.exchanges) * 1e3
    lines = [f"# command: python benchmarks/bench_control.py --exchanges {args.exchanges} --duration {args.duration}",
             f"# date: {date.today()}  machine: {platform.machine()}  python {platform.python_version()}", "",
             f"round trip master -> controller process -> master over zenoh on loopback ({len(lat)} exchanges):",
             f"  median {np.median(lat):.3f} ms   p99 {np.percentile(lat, 99):.3f} ms   max {lat.max():.3f} ms", ""]
    step = 0.001
    internal = timed_run(args.duration, step, None)
    lines += [f"cylinder, macro step {step * 1e3:g} ms, {args.duration:g} s simulated:",
              f"{'control period':>16}{'wall time s':>14}{'slowdown':>10}",
              f"{'internal law':>16}{internal:>14.2f}{1.0:>10.2f}"]
    for period in (0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1):
        wall = timed_run(args.duration, step, period)
        lines.append(f"{period * 1e3:>13g} ms{wall:>14.2f}{wall / internal:>10.2f}")
    report = "\n".join(lines)
    print(report)
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(report + "\n")


if __name__ == "__main__":
    sys.exit(main())
