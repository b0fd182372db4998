"""Cost of one co-simulation macro step, split into FMI-interface overhead, master and physics.

Runs the bundled floating-cylinder scene three ways, side by side, several times each:

1. ``fmi``        - the two FMUs through fmpy and the PythonFMU binary (what `wec-cosim run` does);
2. ``in-process`` - the same slave objects called directly by the same master (no fmpy, no C++);
3. ``physics``    - the same physics objects (HydroModel, LinearMultibodySystem) in a bare loop
   with the same extrapolation, no master and no slave wrapper.

Differences of medians give the FMI interface cost (1 - 2) and the master and wrapper cost
(2 - 3). Run from the repository root:

    python benchmarks/bench_cosim_step.py [--steps 4000] [--repeat 5] [--out benchmarks/results/cosim_step.txt]
"""

from __future__ import annotations

import argparse
import platform
import statistics
import sys
import time
from datetime import date
from pathlib import Path

from common import physics_loop, write_report

from hydro_fmu.model import HydroModel
from orchestrator.cosim.masters import JacobiMaster
from orchestrator.cosim.recorder import Recorder
from orchestrator.cosim.simulation import make_components
from orchestrator.fmi.fmu_builder import build_scene_fmus
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent


def time_master(scene, fmus, steps: int, in_process: bool) -> float:
    comps = make_components(fmus, in_process=in_process)
    master = JacobiMaster(comps, scene.connections(), scene.scenario.simulation.extrapolation,
                          Recorder.observed(scene))
    h = scene.scenario.simulation.step
    master.initialize(0.0, steps * h, scene.parameter_links())
    start = time.perf_counter()
    for k in range(1, steps + 1):
        master.step(h, k * h)
    elapsed = time.perf_counter() - start
    master.terminate()
    return elapsed


def time_physics(scene, steps: int) -> float:
    s = scene.scenario
    h = s.simulation.step
    hydro = HydroModel(scene.hdb, scene.hydro_bodies, [[2]], scene.waves(), scene.ramp(), h, s.hydro.irf_duration)
    return physics_loop(hydro, scene.multibody_system(), h, steps)[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=4000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--scenario", default=str(ROOT / "scenarios" / "cylinder_regular.toml"))
    parser.add_argument("--out", help="also write the report to this file")
    args = parser.parse_args()
    scene = load_scene(load_scenario(args.scenario), log=None)
    fmus = build_scene_fmus(scene)
    h = scene.scenario.simulation.step
    runs = {"fmi": [], "in-process": [], "physics": []}
    for _ in range(args.repeat):  # interleaved so that machine noise hits all three alike
        runs["fmi"].append(time_master(scene, fmus, args.steps, in_process=False))
        runs["in-process"].append(time_master(scene, fmus, args.steps, in_process=True))
        runs["physics"].append(time_physics(scene, args.steps))
    med = {k: statistics.median(v) for k, v in runs.items()}
    per = {k: 1e6 * v / args.steps for k, v in med.items()}
    lines = [
        f"# command: python benchmarks/bench_cosim_step.py --steps {args.steps} --repeat {args.repeat}",
        f"# date: {date.today()}  machine: {platform.machine()} {platform.processor() or ''} "
        f"python {platform.python_version()}",
        f"# scene: {Path(args.scenario).name}, macro step {h} s, {args.steps} steps, medians of {args.repeat} runs",
        "",
        f"{'variant':<12}{'wall time s':>12}{'us/step':>10}{'real-time factor':>18}",
    ]
    for k in runs:
        lines.append(f"{k:<12}{med[k]:>12.3f}{per[k]:>10.1f}{args.steps * h / med[k]:>18.0f}")
    lines += [
        "",
        "cost of one macro step:",
        f"  physics (hydro forces + exact multibody step)   {per['physics']:8.1f} us",
        f"  master and slave wrappers                       {per['in-process'] - per['physics']:8.1f} us",
        f"  FMI interface (fmpy + PythonFMU binary)         {per['fmi'] - per['in-process']:8.1f} us",
        f"  total through FMI                               {per['fmi']:8.1f} us"
        f"  ({per['fmi'] / per['physics']:.1f} x the bare physics)",
    ]
    write_report(lines, args.out)


if __name__ == "__main__":
    sys.exit(main())
