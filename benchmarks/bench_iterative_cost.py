"""Cost per macro step of the iterative master (IQN-ILS) against Jacobi, side by side, through fmpy.

Each scene runs with ``simulation.master = "jacobi"`` and ``"iqn_ils"`` in alternation (``--repeat`` times each,
the stepping loop's wall time as the run reports it, no error estimate), at a step where IQN-ILS converges in about
two evaluations per step; the table gives the medians, their ratio and IQN-ILS's evaluations per step. The
target: within 3x of Jacobi where the iteration converges in one or two evaluations.

    python benchmarks/bench_iterative_cost.py [--repeat 3] [--out benchmarks/results/iterative_cost.txt]
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

from common import ROOT, load, report_header, write_report

SCENES = (("two_floats", 0.1, 60.0), ("hinge_barge", 0.04, 40.0), ("f3of_dt3", 0.1, 120.0))


def one(scenario: str, master: str, step: float, duration: float) -> tuple[float, int, float]:
    """(stepping wall time per step in us, steps, evaluations per step)."""
    import tempfile

    from orchestrator.cosim.simulation import run_scenario
    from orchestrator.scenario import apply_overrides, load_scenario

    s = apply_overrides(load_scenario(ROOT / "scenarios" / f"{scenario}.toml"),
                        [f"simulation.master={master}", f"simulation.step={step:g}",
                         f"simulation.duration={duration:g}", "simulation.error_estimate=none"])
    with tempfile.TemporaryDirectory() as tmp:
        r = run_scenario(s, Path(tmp) / "r.h5", log=None, progress=False)
    return 1e6 * r.wall_time / r.steps, r.steps, r.statistics.get("mean_iterations", 1.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--out", default=None)
    args = parser.parse_args()
    lines = report_header("bench_iterative_cost.py")
    lines += ["", "| scene | step (s) | jacobi us/step | iqn_ils us/step | ratio | iqn_ils evaluations per step |",
              "|---|---|---|---|---|---|"]
    for scenario, step, duration in SCENES:
        times: dict[str, list[float]] = {"jacobi": [], "iqn_ils": []}
        evaluations = 0.0
        for _ in range(args.repeat):
            for master in times:
                us, _, ev = one(scenario, master, step, duration)
                times[master].append(us)
                if master == "iqn_ils":
                    evaluations = ev
        j, q = statistics.median(times["jacobi"]), statistics.median(times["iqn_ils"])
        lines.append(f"| {scenario} | {step:g} | {j:.0f} | {q:.0f} | {q / j:.2f} | {evaluations:.2f} |")
        print(lines[-1], flush=True)
    lines += ["", f"load average at the end {load()}"]
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
