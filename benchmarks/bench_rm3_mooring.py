"""RM3's mooring models side by side: MoorDyn's lumped-mass lines against the quasi-static catenary.

1. At rest: each line's fairlead force from MoorDyn (10, 20, 40 segments) against Jonkman's closed-form
   elastic catenary with sea-bed contact (same length, weight, EA, anchor, fairlead, sea bed), and the
   cost of MoorDyn's initial shape.
2. Surge decay (``scenarios/rm3_surge_decay.toml``, 5 m) with each model, as ``wec-cosim run`` runs it:
   periods (mean spacing of the spar's surge up-crossings), logarithmic decrement of successive peaks,
   each cycle's period against its amplitude, wall time, CPU time and real-time factors; the quasi-static
   model also from 2.5 m (the catenary stiffens with the offset); and the undamped natural periods of the
   scene linearised at rest (``Re Z(omega)`` singular, A(omega) from the database) as the small-motion
   reference.

Run (the load average is recorded in the output):

    python benchmarks/bench_rm3_mooring.py --out benchmarks/results/rm3_mooring.txt
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import tempfile
import time
from pathlib import Path

import numpy as np
from common import write_report

from mbd_fmu.moorings import catenary_tensions
from mbd_fmu.spec import build_simulator
from orchestrator.cosim.simulation import run_scenario
from orchestrator.reference.frequency_domain import linear_model
from orchestrator.results import read_results
from orchestrator.scenario import apply_overrides, load_scenario
from orchestrator.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent
DECAY = ROOT / "scenarios" / "rm3_surge_decay.toml"


def machine() -> str:
    model = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                  if line.startswith("model name")), platform.processor()) if Path("/proc/cpuinfo").exists() else ""
    return f"{model}, {os.cpu_count()} cores, python {platform.python_version()}"


def load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def rest_tensions(segments: int) -> tuple[np.ndarray, float]:
    """(relative differences (lines, 2: horizontal, vertical), seconds to set MoorDyn up) at rest."""
    s = load_scenario(DECAY)
    for b in s.bodies:
        b.initial_displacement = [0.0] * 6
    for e in s.forces:
        e.segments = segments
    scene = load_scene(s, log=None)
    start = time.perf_counter()
    sim = build_simulator(scene.mbd_spec(), np.zeros((len(scene.hydro_coordinates),) * 2))
    seconds = time.perf_counter() - start
    force = sim.model.elements[0].system.force
    out = []
    for e, f in zip(s.forces, force, strict=True):
        d = np.subtract(e.fairlead, e.anchor)
        h, v = catenary_tensions(math.hypot(d[0], d[1]), d[2], e.length, e.weight, e.ea)
        out.append((math.hypot(f[0], f[1]) / h - 1, -f[2] / v - 1))
    return np.array(out), seconds


def crossings(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Times of the up-crossings of zero (linear interpolation)."""
    i = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    return t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])


def peaks(x: np.ndarray) -> np.ndarray:
    i = np.flatnonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:])) + 1
    return x[i]


def decay_row(label: str, t: np.ndarray, x: np.ndarray, extra: str = "") -> list[str]:
    """Mean period, log decrement, damping ratio; then each cycle's period against its amplitude."""
    up = crossings(t, x)
    period = float(np.mean(np.diff(up))) if len(up) > 1 else math.nan
    p = peaks(x)
    p = p[p > 0]
    dec = float(np.mean(np.log(p[:-1] / p[1:]))) if len(p) > 1 else math.nan
    zeta = dec / math.sqrt(4 * math.pi ** 2 + dec ** 2) if math.isfinite(dec) else math.nan
    cycles = ", ".join(f"{b - a:.2f} s at {np.abs(x[(t >= a) & (t < b)]).max():.2f} m"
                       for a, b in zip(up[:-1], up[1:], strict=True))
    return [f"{label:<34}{period:10.2f}{len(up):6d}{dec:11.3f}{100 * zeta:9.2f}   {extra}",
            f"{'':<6}cycles (period at amplitude): {cycles}"]


def linear_periods(scene) -> list[tuple[float, str]]:
    """Undamped natural periods of the scene linearised at rest (quasi-static lines): the frequencies where
    Re Z(omega) = K - omega^2 (M + A(omega)) is singular, with the mode's largest coordinate."""
    omega = np.arange(0.05, 1.5, 5e-4)
    lm = linear_model(scene, omega)
    det = np.array([np.linalg.det(z.real) for z in lm.impedance])
    out = []
    for i in np.flatnonzero(np.sign(det[:-1]) != np.sign(det[1:])):
        w = omega[i] - det[i] * (omega[i + 1] - omega[i]) / (det[i + 1] - det[i])
        _, _, vh = np.linalg.svd(linear_model(scene, np.array([w])).impedance[0].real)
        mode = lm.basis @ vh[-1]
        b, d = lm.coordinates[int(np.argmax(np.abs(mode)))]
        out.append((2 * math.pi / w, f"{b} {('surge', 'sway', 'heave', 'roll', 'pitch', 'yaw')[d]}"))
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="also write the report to this file")
    parser.add_argument("--duration", type=float, help="decay duration (default the scenario's)")
    a = parser.parse_args(argv)
    lines = ["# command: python benchmarks/bench_rm3_mooring.py" + (f" --duration {a.duration}" if a.duration else ""),
             f"# {machine()}; load average at start {load()}", "",
             "## 1. At rest: MoorDyn's fairlead force against the closed-form elastic catenary (3 lines)",
             f"{'segments':>8}{'horizontal':>14}{'vertical':>12}{'set-up s':>10}"]
    for n in (10, 20, 40):
        diff, seconds = rest_tensions(n)
        worst = np.abs(diff).argmax(axis=0)
        lines.append(f"{n:8d}{100 * diff[worst[0], 0]:+13.3f}%{100 * diff[worst[1], 1]:+11.3f}%{seconds:10.2f}")
    lines += ["", "## 2. Surge decay from 5 m (spar cg surge)",
              f"{'model':<34}{'period s':>10}{'ups':>6}{'log dec':>11}{'zeta %':>9}"]
    periods = linear_periods(load_scene(load_scenario(DECAY), log=None))
    lines.append("linearised at rest (quasi-static lines), undamped natural periods: "
                 + ", ".join(f"{p:.2f} s ({mode})" for p, mode in periods))
    with tempfile.TemporaryDirectory() as tmp:
        for model, offset in (("quasi_static", 5.0), ("quasi_static", 2.5), ("moordyn", 5.0)):
            s = apply_overrides(load_scenario(DECAY), [f"mooring_lines.model={model}"])
            for b in s.bodies:
                b.initial_displacement = [offset, 0.0, 0.0, 0.0, 0.0, 0.0]
            if a.duration:
                s.simulation.duration = a.duration
            before, cpu = load(), time.process_time()
            result = run_scenario(s, Path(tmp) / f"{model}.h5", progress=False, log=None)
            cpu = time.process_time() - cpu
            r = read_results(result.path)
            t, x = r["time"], r["bodies/spar/displacement"][:, 0]
            lines += decay_row(f"{model} from {offset:g} m", t, x,
                               f"loop wall {result.wall_time:.1f} s (RTF {result.real_time_factor:.2f}), "
                               f"run cpu {cpu:.1f} s (RTF {result.simulated_time / cpu:.1f}), load {before}")
    lines.append(f"# load average at end {load()}")
    write_report(lines, a.out)


if __name__ == "__main__":
    main()
