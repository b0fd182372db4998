"""Hydro step cost: the numba path of the Python hydro model against the compiled runtime, side by side (issue 29).

Per scene, one model is prepared (``scene.hydro_model()``) and the runtime made from it (``hydro_fmu.runtime``); both
are driven through the same input histories at the scene's macro step, as the hydro FMU drives them at each
communication point, with the inputs written into the same two arrays each time (an FMU's value store): the outputs
of the point (forces, powers, work, elevation: ``HydroModel.outputs``, the numba
pass; ``HydroRuntime.outputs``), then the step (work committed, velocity into the memory: ``WorkAccount.commit`` +
``HydroModel.advance``; ``HydroRuntime.do_step``). A second figure adds the linearised interface (``HydroModel.affine``,
numpy; ``HydroRuntime.linearise``), which the FMU computes only when a host reads it. Runs of the two paths
alternate in one process (after a warm-up: numba compiled, caches filled); microseconds per macro step, the median
over the runs and the ratio numba / runtime, of wall time and of the process's CPU time (less sensitive to the other
work on the machine; OpenBLAS is held to one thread so that its idle helpers do not count). In process, without FMI.
Not a timed assertion anywhere: the machine has two cores shared with other work (load in the header and footer).

    python benchmarks/bench_hydro_runtime.py --out benchmarks/results/hydro_runtime.txt
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy: helper threads would count as CPU time

import numpy as np  # noqa: E402
from common import ROOT, load, report_header, write_report

from hydro_fmu.runtime import HydroRuntime  # noqa: E402
from hydro_fmu.runtime_input import runtime_input  # noqa: E402
from hydro_fmu.work import WorkAccount  # noqa: E402
from orchestrator.scenario import load_scenario  # noqa: E402
from orchestrator.scene import load_scene  # noqa: E402

SCENES = (("cylinder (regular)", "cylinder_regular", 2000), ("hinge barge", "hinge_barge", 1000),
          ("F3OF DT3", "f3of_dt3", 600), ("9N9LA", "array_9n9la", 200))


def histories(index: np.ndarray, h: float, steps: int) -> list[tuple[float, np.ndarray, np.ndarray]]:
    k = np.arange(1, len(index) + 1)
    size = np.where(index % 6 >= 3, 0.03, 0.3)
    out = []
    for j in range(steps):
        t = j * h
        out.append((t, size * np.sin(0.61 * t + 0.7 * k), size * 0.61 * np.cos(0.61 * t + 0.7 * k)))
    return out


class Numba:
    def __init__(self, model, pattern) -> None:
        self.model, self.pattern = model, pattern
        n = model.n
        self.rows, self.out = np.arange(5, dtype=np.intp), np.zeros((5, n))
        self.power, self.work, self.account = np.zeros(4), np.zeros(4), WorkAccount()
        self.x, self.v = np.zeros(n), np.zeros(n)

    def point(self, t: float, h: float, x_in: np.ndarray, v_in: np.ndarray, linearised: bool) -> None:
        x, v = self.x, self.v
        x[:], v[:] = x_in, v_in
        self.model.outputs(t, x, v, self.rows, self.out, self.power, self.account, self.work)
        if linearised:
            self.model.affine(t, x, v, self.pattern)
        self.account.commit(t, self.power, self.work)
        self.model.advance(t, h, v)


class Runtime:
    def __init__(self, model, pattern) -> None:
        self.runtime = HydroRuntime(runtime_input(model))
        n = model.n
        self.masks = pattern.mask(n, "stiffness"), pattern.mask(n, "damping")
        self.rows, self.out = np.arange(5, dtype=np.int64), np.zeros((5, n))
        self.power, self.work = np.zeros(4), np.zeros(4)
        self.x, self.v = np.zeros(n), np.zeros(n)

    def point(self, t: float, h: float, x_in: np.ndarray, v_in: np.ndarray, linearised: bool) -> None:
        x, v = self.x, self.v
        x[:], v[:] = x_in, v_in
        self.runtime.outputs(t, x, v, self.rows, self.out, self.power, self.work)
        if linearised:
            self.runtime.linearise(t, x, v, *self.masks)
        self.runtime.do_step(t, h, x, v)


def measure(scene, steps: int, runs: int, linearised: bool) -> dict[str, list[tuple[float, float]]]:
    """(wall, CPU) microseconds per macro step of each path, one pair per run (runs alternate between the paths)."""
    h = scene.scenario.simulation.step
    pattern = scene.coupling_pattern()
    times: dict[str, list[tuple[float, float]]] = {"numba": [], "runtime": []}
    inputs = histories(scene.hydro_model(dt=h).index, h, steps * (runs + 1))
    paths = {"numba": Numba(scene.hydro_model(dt=h), pattern), "runtime": Runtime(scene.hydro_model(dt=h), pattern)}
    for path in paths.values():  # warm-up: numba compiled or loaded, first blocks, caches
        for t, x, v in inputs[:steps]:
            path.point(t, h, x, v, linearised)
    for r in range(runs):
        chunk = inputs[(r + 1) * steps:(r + 2) * steps]
        for name in (("numba", "runtime") if r % 2 == 0 else ("runtime", "numba")):
            path = paths[name]
            start, cpu = time.perf_counter(), time.process_time()
            for t, x, v in chunk:
                path.point(t, h, x, v, linearised)
            times[name].append(((time.perf_counter() - start) / steps * 1e6, (time.process_time() - cpu) / steps * 1e6))
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", help="also write the report here")
    parser.add_argument("--runs", type=int, default=7)
    args = parser.parse_args()
    cpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    model_line = next((line.split(":", 1)[1].strip() for line in cpu.splitlines() if line.startswith("Model name")),
                      "unknown")
    lines = [*report_header("bench_hydro_runtime.py"), f"# lscpu model name: {model_line}",
             f"# uptime at start: {subprocess.run(['uptime'], capture_output=True, text=True).stdout.strip()}",
             f"# microseconds per macro step, median over {args.runs} alternating runs (min .. max), wall and CPU "
             "time of the process; in process, no FMI", ""]
    header = (f"{'scene':20s} {'n':>3s} {'step s':>7s} {'steps':>6s}  {'part':28s} {'numba wall':>24s} "
              f"{'runtime wall':>24s} {'ratio':>6s} {'numba CPU':>9s} {'runtime CPU':>11s} {'ratio':>6s}")
    lines.append(header)
    for label, name, steps in SCENES:
        scene = load_scene(load_scenario(ROOT / "scenarios" / f"{name}.toml"), log=None)
        for linearised in (False, True):
            times = measure(scene, steps, args.runs, linearised)
            wall = {k: [w for w, _ in v] for k, v in times.items()}
            cpu = {k: statistics.median(c for _, c in v) for k, v in times.items()}
            part = "outputs + step" + (" + linearised" if linearised else "")

            def cell(v: list[float]) -> str:
                return f"{statistics.median(v):8.1f} ({min(v):.1f}..{max(v):.1f})"

            row = (f"{label:20s} {len(scene.hydro_index()):3d} {scene.scenario.simulation.step:7.3f} {steps:6d}  "
                   f"{part:28s} {cell(wall['numba']):>24s} {cell(wall['runtime']):>24s} "
                   f"{statistics.median(wall['numba']) / statistics.median(wall['runtime']):6.2f} "
                   f"{cpu['numba']:9.1f} {cpu['runtime']:11.1f} {cpu['numba'] / cpu['runtime']:6.2f}")
            lines.append(row)
            print(row, flush=True)
    lines += ["", f"# uptime at the end: {subprocess.run(['uptime'], capture_output=True, text=True).stdout.strip()}",
              f"# load average at the end {load()}"]
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
