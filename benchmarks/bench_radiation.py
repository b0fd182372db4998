"""Radiation memory: per-step cost and accuracy of the convolution and of state-space fits of each order.

For two scenes, a free decay is run with the scene's hydro model (:class:`hydro_fmu.model.HydroModel`)
and multibody model stepped together with the master's step-averaged quadratic extrapolation, once
per radiation model:

* ``convolution`` - trapezoidal convolution with the impulse response (kernel of irf_duration / h samples);
* ``state space`` at several tolerances - the order the tolerance selects, its fitted-kernel error.

Error: largest deviation of the decay from the exact frequency-domain decay of the linear model with
the database's A(omega), B(omega) (``frequency_domain.free_decay(radiation="database")``), in % of the
initial displacement; the same against the exact decay of the truncated impulse response
(``radiation="impulse_response"``, the model the convolution discretises), which removes the
database's own truncation error (both evaluated with d_omega = 2.5e-4 rad/s). Cost: median over
repeated runs of the radiation memory alone
(force + step) per step, and of the whole hydro model (forces + advance), interleaved so that machine
noise hits all variants alike. Run from the repository root:

    python benchmarks/bench_radiation.py [--repeat 5] [--out benchmarks/results/radiation.txt]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import time
from datetime import date
from pathlib import Path

import numpy as np
from common import physics_loop, write_report

from orchestrator.reference import frequency_domain
from orchestrator.scenario import load_scenario
from orchestrator.scenario.body_sections import PtoSection
from orchestrator.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent
TOLERANCES = (0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001)


def cylinder_scene():
    s = load_scenario(ROOT / "scenarios" / "cylinder_regular.toml")
    s.waves.kind = "still"
    s.ptos = []
    s.bodies[0].initial_displacement = [0, 0, 0.2, 0, 0, 0]
    return load_scene(s, log=None), "cylinder R 5 m (heave, 1 DOF)"


def two_body_scene():
    """Both cylinders in surge, heave and pitch (6 DOFs), surge moored by springs; the fore one released
    from 0.2 m heave and 0.05 rad pitch."""
    s = load_scenario(ROOT / "scenarios" / "two_cylinders_decay.toml")
    mass = 1025.0 * np.pi * 2.5**2 * 3.0
    for b in s.bodies:
        b.dofs = ["surge", "heave", "pitch"]
        b.inertia = [mass * (3 * 2.5**2 + 3.0**2) / 12] * 2 + [mass * 2.5**2 / 2]
    s.bodies[0].initial_displacement = [0, 0, 0.2, 0, 0.05, 0]
    s.ptos = [PtoSection(name=f"{b.name}_mooring", body=b.name, dof="surge", stiffness=2.0e5) for b in s.bodies]
    return load_scene(s, log=None), "two cylinders (surge, heave, pitch each: 6 DOFs)"


def run_decay(scene, method: str, tolerance: float, h: float, duration: float):
    """Decay with the master's step-averaged quadratic extrapolation; returns (x, hydro model, seconds)."""
    s = scene.scenario
    s.hydro.radiation_method = method
    s.hydro.state_space_tolerance = tolerance
    hydro = scene.hydro_model(dt=h)
    x, seconds = physics_loop(hydro, scene.multibody_system(), h, int(round(duration / h)), record=True)
    return x, hydro, seconds


def time_memory(memory_factory, n_dofs: int, steps: int, h: float) -> float:
    """Seconds per step of the radiation memory alone: force at the current velocity, then step."""
    memory = memory_factory()
    rng = np.random.default_rng(0)
    velocities = rng.normal(size=(steps, n_dofs))
    start = time.perf_counter()
    for v in velocities:
        memory.force(v)
        memory.step(v, h)
    return (time.perf_counter() - start) / steps


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--steps", type=int, default=3000, help="steps of the timing runs")
    parser.add_argument("--out", help="also write the report to this file")
    args = parser.parse_args()
    lines = [
        f"# command: python benchmarks/bench_radiation.py --repeat {args.repeat} --steps {args.steps}",
        f"# date: {date.today()}  machine: {platform.machine()} python {platform.python_version()}, "
        f"{args.repeat} interleaved repeats, medians; load average at the start {os.getloadavg()[0]:.1f} on "
        f"{os.cpu_count()} cores (other jobs share the machine)",
        "",
    ]
    for make in (cylinder_scene, two_body_scene):
        scene, label = make()
        h = 0.05
        duration = 40.0
        variants = [("convolution", 0.0)] + [("state_space", tol) for tol in TOLERANCES]
        coordinates = len(scene.hydro_coordinates)
        t = (np.arange(int(round(duration / h))) + 1) * h
        x0 = scene.multibody_system().q.copy()
        # d_omega finer than free_decay's default: the lightly damped modes of the moored pair have
        # resonance peaks narrower than 1e-3 rad/s (the default leaves a 4 % error in this reference).
        exact_db = frequency_domain.free_decay(scene, t, x0, radiation="database", d_omega=2.5e-4)
        exact_irf = frequency_domain.free_decay(scene, t, x0, radiation="impulse_response", d_omega=2.5e-4)
        scale = np.abs(x0)
        scale[scale == 0] = np.abs(x0).max()
        rows = []
        reference = None
        for method, tol in variants:
            x, hydro, _ = run_decay(scene, method, tol, h, duration)
            if method == "convolution":
                reference = x
            err_db = np.max(np.abs(x - exact_db) / scale) * 100
            err_irf = np.max(np.abs(x - exact_irf) / scale) * 100
            diff = np.max(np.abs(x - reference) / scale) * 100
            rep = hydro.report
            rows.append([method, tol, rep.order if method == "state_space" else rep.kernel_samples,
                         rep.kernel_error, rep.frequency_error, err_db, err_irf, diff, hydro])
        memory_times = {i: [] for i in range(len(rows))}
        model_times = {i: [] for i in range(len(rows))}
        for _ in range(args.repeat):
            for i, row in enumerate(rows):
                hydro = row[-1]
                factory = hydro.reference_memory  # the Python memory (the runtime's reference), new at each call
                memory_times[i].append(time_memory(factory, coordinates, args.steps, h))
                _, _, total = run_decay(scene, row[0], row[1] or 0.02, h, args.steps * h)
                model_times[i].append(total / args.steps)
        lines += [f"## {label}, step {h} s, decay over {duration} s, "
                  f"impulse response {scene.scenario.hydro.irf_duration} s",
                  "",
                  "| radiation model | tolerance | order / kernel samples | fit error | A,B error vs database "
                  "| decay error vs FD (database) % | vs FD (impulse response) % | vs convolution % "
                  "| memory us/step | hydro model us/step | memory cost / convolution |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        conv_cost = statistics.median(memory_times[0])
        for i, row in enumerate(rows):
            method, tol, order, kerr, ferr, e_db, e_irf, diff, _ = row
            mem = statistics.median(memory_times[i])
            mod = statistics.median(model_times[i])
            lines.append(
                f"| {method.replace('_', ' ')} | {tol if tol else '-'} | {order} | "
                f"{kerr:.2g} | {ferr:.3g} | {e_db:.3f} | {e_irf:.3f} | {diff:.3f} | "
                f"{1e6 * mem:.1f} | {1e6 * mod:.1f} | {mem / conv_cost:.2f} |")
        lines.append("")
    write_report(lines, args.out)


if __name__ == "__main__":
    sys.exit(main())
