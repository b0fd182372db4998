"""Wall time and real-time factor of every bundled device scenario at its default settings.

Each scenario is run as a user runs it (``wec-cosim run SCENARIO``: scene, database from the
committed cache, FMUs through fmpy, the scenario's own master, step and duration), ``--repeat``
times; the table gives the median and minimum of the whole run's wall time (set-up included)
and of the stepping loop's (``RunResult.wall_time``), the real-time factor of the loop, and the
whole run's CPU time of this process (the FMUs run in it through fmpy; on a loaded machine CPU
time is the load-independent figure). A third element in a ``SCENARIOS`` entry gives ``--set``
overrides (the same scene with another choice, e.g. the mooring model).

Run (on a quiet machine; the load average is recorded in the output):

    python benchmarks/bench_scenarios.py --repeat 3 --out benchmarks/results/scenarios.txt
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import tempfile
import time
from pathlib import Path

from common import write_report

from orchestrator.cosim.simulation import run_scenario
from orchestrator.scenario import apply_overrides, load_scenario

ROOT = Path(__file__).resolve().parent.parent

# (scenario file under scenarios/, what it is[, `--set` overrides]). Add a line per bundled device scenario.
SCENARIOS: list[tuple] = [
    ("cylinder_regular.toml", "one float, heave, regular waves"),
    ("cylinder_irregular.toml", "one float, heave, irregular sea"),
    ("hinge_barge.toml", "seed 003 two-body hinge barge, index-3"),
    ("f3of_dt1.toml", "seed 000 F3OF decay 1: base surge on a prismatic joint, flaps locked"),
    ("f3of_dt2.toml", "seed 000 F3OF decay 2: base pitch about (0, 0, -9), flaps locked"),
    ("f3of_dt3.toml", "seed 000 F3OF decay 3: base fixed, two flaps on hinges"),
    ("f3of_rao.toml", "seed 000 F3OF, regular waves T = 10 s, base moored, flaps free"),
    ("rm3_regular.toml", "RM3 two bodies, MoorDyn lines, regular waves"),
    ("rm3_irregular.toml", "RM3, MoorDyn lines, Pierson-Moskowitz sea"),
    ("rm3_irregular.toml", "RM3, quasi-static catenary lines, same sea", ("mooring_lines.model=quasi_static",)),
    ("nenuphar.toml", "seed 001 Nenuphar: 7 bodies, 6 hinges, tether, 6 catenaries"),
    ("mathai_assembly.toml", "seed 001 Mathai's three hinged rafts, finite depth"),
    ("array_4n3la.toml", "seed 000 4N3LA: 4 nodes, 3 link arms, 12 PTOs, irregular sea, index-3"),
    ("array_9n9la.toml", "seed 000 9N9LA: 9 nodes, 9 arms, hexagonal loop, 36 PTOs, irregular sea, index-3"),
]


def run_once(path: Path, folder: Path, overrides: tuple[str, ...] = ()) -> tuple[float, float, float, float]:
    """(whole-run wall s, stepping-loop wall s, simulated s, whole-run CPU s of this process) of one run."""
    scenario = apply_overrides(load_scenario(path), list(overrides))
    start, cpu = time.perf_counter(), time.process_time()
    result = run_scenario(scenario, folder / f"{path.stem}.h5", progress=False, log=None)
    return time.perf_counter() - start, result.wall_time, result.simulated_time, time.process_time() - cpu


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--only", nargs="*", help="scenario file names to run (default: all in the table)")
    parser.add_argument("--out", help="also write the report to this file")
    a = parser.parse_args(argv)
    lines = [f"# command: python benchmarks/bench_scenarios.py --repeat {a.repeat}"
             + (f" --only {' '.join(a.only)}" if a.only else ""),
             f"# python {platform.python_version()}, {os.cpu_count()} cores, load average at start "
             f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}",
             f"{'scenario':<28}{'simulated s':>12}{'run s med':>10}{'run s min':>10}{'loop s med':>11}"
             f"{'RTF (loop, med)':>16}{'run cpu s':>10}  what"]
    with tempfile.TemporaryDirectory() as tmp:
        for name, what, *rest in SCENARIOS:
            if a.only and name not in a.only:
                continue
            overrides = rest[0] if rest else ()
            runs = [run_once(ROOT / "scenarios" / name, Path(tmp), overrides) for _ in range(a.repeat)]
            whole = [r[0] for r in runs]
            loop = [r[1] for r in runs]
            simulated = runs[0][2]
            lines.append(f"{name:<28}{simulated:12.1f}{statistics.median(whole):10.2f}{min(whole):10.2f}"
                         f"{statistics.median(loop):11.2f}{simulated / statistics.median(loop):16.1f}"
                         f"{statistics.median(r[3] for r in runs):10.1f}  {what}")
    lines.append(f"# load average at end {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    write_report(lines, a.out)


if __name__ == "__main__":
    main()
