"""F3OF database: the project's own checks, measured, on each of the four F3OF scenes.

For each bundled scenario ``scenarios/f3of_*.toml`` (all four share one 18 x 18 database) this reports
the worst value each check finds on the scene's degrees of freedom (``HydroDatabase.check_physics``
at tolerance 0, so that it names the worst place; the scenes load it at the default 5 %), the
change and spread of Ogilvie's A_inf, and the scaled error of A and B rebuilt from the truncated
impulse response the time-domain model convolves (the run's ``radiation.frequency_error``, from a
1 s in-process run). No BEM solve if the database is cached.

    python benchmarks/bench_f3of_checks.py --out benchmarks/results/f3of_checks.txt
"""

from __future__ import annotations

import argparse
import os
import platform
import tempfile
from pathlib import Path

import numpy as np
from common import write_report

from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene
from orchestrator.simulation import format_summary, run_scenario

ROOT = Path(__file__).resolve().parent.parent
NAMES = ("f3of_dt1", "f3of_dt2", "f3of_dt3", "f3of_rao")


def scene_checks(name: str, folder: Path) -> list[str]:
    """Report lines of one scene: worst asymmetry and B eigenvalue, A_inf fit, kernel rebuild error."""
    scenario = load_scenario(ROOT / "scenarios" / f"{name}.toml")
    messages: list[str] = []
    scene = load_scene(scenario, log=messages.append)
    index = np.asarray(scene.hydro_index())
    lines = [f"{name} (check tolerance {scenario.hydro.check_tolerance:g}; loads: yes)"]
    lines += [f"    worst: {m[len(scene.hdb.source) + 2:]}" for m in scene.hdb.check_physics(index, 0.0)]
    lines += [f"    {m}" for m in messages if "Ogilvie" in m]
    scenario.simulation.duration = 1.0
    result = run_scenario(scenario, folder / f"{name}.h5", in_process=True, log=None, progress=False)
    lines += [f"    {m}" for m in format_summary(result).splitlines() if m.startswith("radiation")]
    return lines


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out")
    a = parser.parse_args(argv)
    lines = [f"# command: python benchmarks/bench_f3of_checks.py{' --out ' + a.out if a.out else ''}",
             f"# python {platform.python_version()}, {os.cpu_count()} cores, load average at start "
             f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}"]
    with tempfile.TemporaryDirectory() as tmp:
        for name in NAMES:
            lines += scene_checks(name, Path(tmp))
    lines.append(f"# load average at end {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    write_report(lines, a.out)


if __name__ == "__main__":
    main()
