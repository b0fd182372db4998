"""Points per pass over the radiation weights (the runtime's ``radiation.block_points``, native/src/hydro/
radiation_convolution.c): the hydro FMU's per-point cost in a real co-simulation loop for several block sizes, side
by side in one process.

The hinge barge runs in process (the FMUs' slave classes called directly, so the block size can be set for each
run; the multibody FMU works between two points and evicts the weights from cache, as through fmpy). Each block
size is run in turn, ``--repeats`` times alternating; reported per block size: the hydro get_reals CPU time per
macro step (the call that runs the runtime's pass). B = 1 is one pass over the weights at every point (the direct
sum's memory traffic). The record in benchmarks/results/hydro_block.txt was measured with the numba pass that the
runtime replaced (same blocks; it also timed the pass alone, split into block starts and the other points).

    python benchmarks/bench_radiation_block.py --out benchmarks/results/hydro_block.txt
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def run(scenario, blocks: int) -> float:  # noqa: ANN001
    """One in-process run with ``blocks`` points per pass: get_reals CPU per step, microseconds."""
    import hydro_fmu.runtime_input as runtime_input
    from orchestrator.cosim import simulation
    from orchestrator.fmi import components

    saved = runtime_input.BLOCK_POINTS
    runtime_input.BLOCK_POINTS = blocks
    cpu = [0.0]
    get_reals = components.InProcessComponent.get_reals

    def timed_get(self, *a):  # noqa: ANN001, ANN002, ANN202
        c0 = time.thread_time()
        try:
            return get_reals(self, *a)
        finally:
            if self.name == "hydro":
                cpu[0] += time.thread_time() - c0

    components.InProcessComponent.get_reals = timed_get
    try:
        with tempfile.TemporaryDirectory() as tmp:
            simulation.run_scenario(scenario, Path(tmp) / "w.h5", progress=False, log=None, in_process=True)
    finally:
        components.InProcessComponent.get_reals = get_reals
        runtime_input.BLOCK_POINTS = saved
    steps = round(scenario.simulation.duration / scenario.simulation.step)
    return cpu[0] / steps * 1e6


def main() -> None:
    from common import ROOT, load, report_header, write_report

    from orchestrator.scenario import load_scenario

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--blocks", default="1,4,8,16,32", help="comma-separated block sizes")
    p.add_argument("--duration", type=float, default=20.0, help="simulated seconds per run")
    p.add_argument("--repeats", type=int, default=5, help="runs per block size, alternating")
    p.add_argument("--out", default="", help="also write the report to this file")
    args = p.parse_args()
    scenario = load_scenario(ROOT / "scenarios" / "hinge_barge.toml")
    scenario.simulation.duration = args.duration
    blocks = [int(b) for b in args.blocks.split(",")]
    lines = report_header("bench_radiation_block.py")
    run(scenario, blocks[0])  # builds or loads the FMUs, compiles or loads the multibody kernels
    results: dict[int, list[float]] = defaultdict(list)
    for _ in range(args.repeats):
        for b in blocks:
            results[b].append(run(scenario, b))
    lines += [f"# hinge barge in process, {args.duration:g} s, {args.repeats} alternating runs per block size; "
              "microseconds per macro step (min / median over the runs)",
              "# get cpu: hydro get_reals, CPU time of the calling thread", "",
              f"{'B':>4}{'get cpu min':>13}{'median':>9}"]
    for b in blocks:
        r = np.array(results[b])
        lines.append(f"{b:>4}{r.min():13.1f}{np.median(r):9.1f}")
    lines.append(f"# load average at the end {load()}")
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
