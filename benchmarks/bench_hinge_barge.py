"""Cost and agreement of the multibody formulations on seed 003's hinge-barge in waves.

The scenario scenarios/hinge_barge.toml is co-simulated (hydrodynamics FMU + multibody FMU, the
slaves called in-process so that the FMI layer's cost does not blur the comparison) for 6 s with
each formulation; reported: wall time of the whole run and per macro step (setup included: scene,
database, FMU build, about 3 s), the stepping loop's cost per macro step (hydrodynamics, master and
multibody), and the largest difference of the barges' motion from the null-space (reduced ODE)
run, relative to each coordinate's amplitude.

Run: python benchmarks/bench_hinge_barge.py > benchmarks/results/hinge_barge.txt
"""

from __future__ import annotations

import platform
import tempfile
import time
from pathlib import Path

import numpy as np

from orchestrator.cosim.simulation import run_scenario
from orchestrator.results import read_results
from orchestrator.scenario import load_scenario

ROOT = Path(__file__).resolve().parent.parent
CASES = (("nullspace", "rk4", 0.01), ("index1", "rk4", 0.01), ("index3", "generalized_alpha", 0.01),
         ("index3", "generalized_alpha", 0.005), ("index3", "generalized_alpha", 0.0025))


def run(formulation: str, integrator: str, max_step: float, duration: float, folder: Path):
    s = load_scenario(ROOT / "scenarios" / "hinge_barge.toml")
    s.multibody.formulation, s.multibody.integrator, s.multibody.max_step = formulation, integrator, max_step
    s.simulation.duration = duration
    out = folder / f"{formulation}_{max_step}.h5"
    t0 = time.perf_counter()
    result = run_scenario(s, out, in_process=True, progress=False, log=None)
    wall = time.perf_counter() - t0
    data = read_results(out)
    motion = np.hstack([data["bodies/barge1/displacement"], data["bodies/barge2/displacement"]])
    return wall, result.wall_time, result.steps, motion


def main() -> None:
    duration = 6.0
    print("# command: python benchmarks/bench_hinge_barge.py")
    print(f"# python {platform.python_version()}, numpy {np.__version__}; {duration} s simulated, macro step 0.02 s, "
          "in-process slaves")
    print(f"{'formulation':>12}{'integrator':>19}{'max_step':>10}{'wall s':>9}{'ms/macro':>10}{'loop ms/macro':>15}"
          f"{'max rel diff':>14}")
    with tempfile.TemporaryDirectory() as tmp:
        reference = None
        for formulation, integrator, h in CASES:
            wall, loop, steps, motion = run(formulation, integrator, h, duration, Path(tmp))
            if reference is None:
                reference = motion
                scale = np.max(np.abs(reference), axis=0)
                scale[scale == 0] = 1.0
            diff = float(np.max(np.abs(motion - reference) / scale))
            print(f"{formulation:>12}{integrator:>19}{h:10.4f}{wall:9.2f}{1e3 * wall / steps:10.2f}"
                  f"{1e3 * loop / steps:15.2f}{diff:14.2e}", flush=True)


if __name__ == "__main__":
    main()
