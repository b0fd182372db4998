"""What modelling only what a scene needs saves: per-step cost of the hydro model and FMU by DOF subset,
by body selection and by force component, on the two-cylinder scene (12-DOF interaction database).

Variants (irregular JONSWAP sea of 100 equal-energy components, radiation convolution over 40 s at
0.05 s = 801 kernel samples, unless stated):

* ``6 + 6 DOFs``: both bodies in all six degrees of freedom (12 hydro coordinates);
* ``planar 3 + 3``: surge, heave, pitch each (6);
* ``heave 1 + 1``: heave only (2);
* ``heave 1, aft no hydro``: the aft body has no hydrodynamics (a link arm or counterweight) (1);
* ``6 + 6, no radiation`` / ``no excitation`` / ``state space``: component switches and the
  alternative radiation model on the full 12-DOF scene.

Cost per step: ``model`` = HydroModel.forces + advance in-process; ``fmu`` = the hydro FMU alone through
fmpy (set x, v; get F; do_step), medians of interleaved repeats; ratios against the 12-DOF variant.
Run from the repository root:

    python benchmarks/bench_dof_reduction.py [--steps 2000] [--repeat 5] [--out benchmarks/results/dof_reduction.txt]
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
from common import write_report

from orchestrator.fmi.components import FmuComponent
from orchestrator.fmi.fmu_builder import build_scene_fmus
from orchestrator.scenario import load_scenario
from orchestrator.scene import HYDRO, load_scene

ROOT = Path(__file__).resolve().parent.parent
ALL = ["surge", "sway", "heave", "roll", "pitch", "yaw"]


def make_scene(dofs: list[str], aft_hydro: bool = True, **hydro):
    s = load_scenario(ROOT / "scenarios" / "two_cylinders_decay.toml")
    s.waves.kind, s.waves.hs, s.waves.tp = "irregular", 1.5, 6.0
    s.waves.discretisation, s.waves.n_components, s.waves.ramp_time = "equal_energy", 100, 10.0
    mass = 1025.0 * np.pi * 2.5**2 * 3.0
    for b in s.bodies:
        b.dofs = list(dofs)
        b.inertia = [mass * (3 * 2.5**2 + 3.0**2) / 12] * 2 + [mass * 2.5**2 / 2]
        b.initial_displacement = [0.0] * 6
    if not aft_hydro:
        s.bodies[1].hydro = False
        s.bodies[1].mass = mass
    for key, value in hydro.items():
        setattr(s.hydro, key, value)
    return load_scene(s, log=None)


VARIANTS = {
    "6 + 6 DOFs": lambda: make_scene(ALL),
    "planar 3 + 3": lambda: make_scene(["surge", "heave", "pitch"]),
    "heave 1 + 1": lambda: make_scene(["heave"]),
    "heave 1, aft no hydro": lambda: make_scene(["heave"], aft_hydro=False),
    "6 + 6, no radiation": lambda: make_scene(ALL, radiation=False),
    "6 + 6, no excitation": lambda: make_scene(ALL, excitation=False),
    "6 + 6, state space": lambda: make_scene(ALL, radiation_method="state_space"),
}


def time_model(scene, steps: int) -> float:
    model = scene.hydro_model()
    h = scene.scenario.simulation.step
    rng = np.random.default_rng(1)
    x = rng.normal(scale=0.01, size=(steps, model.n))
    v = rng.normal(scale=0.01, size=(steps, model.n))
    start = time.perf_counter()
    for k in range(steps):
        model.forces(k * h, x[k], v[k])
        model.advance(k * h, h, v[k])
    return (time.perf_counter() - start) / steps


def time_fmu(scene, path: Path, steps: int) -> float:
    comp = FmuComponent("hydro", path)
    names_x = [f"{b}.x[{d + 1}]" for b, d in scene.hydro_coordinates]
    names_v = [f"{b}.v[{d + 1}]" for b, d in scene.hydro_coordinates]
    names_f = [f"{b}.F[{d + 1}]" for b, d in scene.hydro_coordinates]
    px, pv, pf = comp.port(names_x), comp.port(names_v), comp.port(names_f)
    h = scene.scenario.simulation.step
    comp.setup(0.0, steps * h)
    comp.enter_initialization()
    comp.exit_initialization()
    rng = np.random.default_rng(1)
    x = rng.normal(scale=0.01, size=(steps, len(names_x)))
    v = rng.normal(scale=0.01, size=(steps, len(names_v)))
    start = time.perf_counter()
    for k in range(steps):
        comp.set_reals(px, x[k])
        comp.set_reals(pv, v[k])
        comp.get_reals(pf)
        comp.do_step(k * h, h)
    elapsed = (time.perf_counter() - start) / steps
    comp.terminate()
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--out", help="also write the report to this file")
    args = parser.parse_args()
    scenes = {name: make() for name, make in VARIANTS.items()}
    fmus = {name: build_scene_fmus(scene)[HYDRO] for name, scene in scenes.items()}
    model_t = {name: [] for name in scenes}
    fmu_t = {name: [] for name in scenes}
    for _ in range(args.repeat):
        for name, scene in scenes.items():
            model_t[name].append(time_model(scene, args.steps))
            fmu_t[name].append(time_fmu(scene, fmus[name], args.steps))
    base = "6 + 6 DOFs"
    med_m = {k: statistics.median(v) for k, v in model_t.items()}
    med_f = {k: statistics.median(v) for k, v in fmu_t.items()}
    lines = [
        f"# command: python benchmarks/bench_dof_reduction.py --steps {args.steps} --repeat {args.repeat}",
        f"# date: {date.today()}  machine: {platform.machine()} python {platform.python_version()}; "
        f"medians of {args.repeat} interleaved runs of {args.steps} steps; load average at the end "
        f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores (other jobs share the machine)",
        "# scene: two_cylinders_decay.toml database (12 x 12 interaction), JONSWAP Hs 1.5 m Tp 6 s, 100 components,"
        " step 0.05 s, radiation kernel 40 s",
        "",
        "| variant | hydro coordinates | FMU variables | model us/step | model / 12-DOF | FMU us/step | FMU / 12-DOF |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, scene in scenes.items():
        n_vars = len(_variables(fmus[name]))
        lines.append(
            f"| {name} | {len(scene.hydro_coordinates)} | {n_vars} | {1e6 * med_m[name]:.1f} | "
            f"{med_m[name] / med_m[base]:.2f} | {1e6 * med_f[name]:.1f} | {med_f[name] / med_f[base]:.2f} |")
    write_report(lines, args.out)


def _variables(path: Path) -> list:
    from fmpy import read_model_description

    return read_model_description(str(path)).modelVariables


if __name__ == "__main__":
    sys.exit(main())
