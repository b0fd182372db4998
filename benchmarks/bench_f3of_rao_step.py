"""F3OF RAO: the time-domain steady state against the frequency-domain answers, per period, step and duration.

Runs ``scenarios/f3of_rao.toml`` in process at each ``PERIOD:DURATION:STEP`` case, fits the steady harmonic
with ``--modes`` damped free modes over [3 T + 60 s (or ``--start``), duration] (``decay.fit_forced``, on
samples ``--sample`` apart, default 0.1 s) and reports the largest amplitude and phase errors over the nine coordinates
(surge, heave, pitch of the three bodies) against the exact linear answer with the database's A, B and
with the A, B of the impulse response the run convolves (``frequency_domain.solve``). It measured the
9 s step convergence and the 6 / 7 s residuals of docs/f3of.md (RAO section):

    python benchmarks/bench_f3of_rao_step.py 9:3000:0.1 9:3000:0.05 --start 2000 --sample 0.5
    python benchmarks/bench_f3of_rao_step.py 9:600:0.025 9:600:0.0125 6:600:0.1 6:600:0.05 7:600:0.1 --sample 0.2
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

from orchestrator.cosim.simulation import run_scenario
from orchestrator.reference import frequency_domain
from orchestrator.reference.decay import fit_forced
from orchestrator.results import read_results
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent
COORDINATES = [(b, j) for b in ("base", "flap1", "flap2") for j in (0, 2, 4)]
NAMES = {0: "surge", 2: "heave", 4: "pitch"}


def case(period: float, duration: float, step: float, modes: int, start: float | None, sample: float,
         folder: Path) -> str:
    """One report line: errors against the database's and the kernel's linear answers."""
    s = load_scenario(ROOT / "scenarios" / "f3of_rao.toml")
    s.waves.period, s.simulation.duration, s.simulation.step = period, duration, step
    path = folder / f"rao_{period:g}_{duration:g}_{step:g}.h5"
    t0 = time.perf_counter()
    run_scenario(s, path, in_process=True, progress=False, log=None)
    wall = time.perf_counter() - t0
    data = read_results(path)
    every = max(1, round(sample / step))
    x = np.column_stack([data[f"bodies/{b}/displacement"][::every, j] for b, j in COORDINATES])
    omega = 2 * math.pi / period
    window = (start if start is not None else 3 * period + 60.0, duration)
    measured, free = fit_forced(data["time"][::every], x, omega, modes, window)
    scene = load_scene(s, log=None)
    line = f"T = {period:g} s, {duration:g} s run at step {step:g} s ({wall:.0f} s wall), fit over {window}:"
    for radiation in ("database", "impulse_response"):
        fd = frequency_domain.solve(scene, np.array([omega]), radiation=radiation)
        exact = np.array([fd.body_rao(b)[0][j] for b, j in COORDINATES]) * s.waves.height / 2
        ratio = measured / exact
        worst = int(np.argmax(np.abs(np.abs(ratio) - 1)))
        b, j = COORDINATES[worst]
        line += (f" against {radiation} {100 * np.abs(np.abs(ratio) - 1).max():.2f} %, "
                 f"{np.abs(np.degrees(np.angle(ratio))).max():.2f} deg (worst {b} {NAMES[j]});")
    return line + f" free modes {[(round(m.period, 2), round(m.damping_ratio, 4)) for m in free.modes]}"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="+", help="PERIOD:DURATION:STEP (s)")
    parser.add_argument("--modes", type=int, default=1, help="free modes fitted with the harmonic")
    parser.add_argument("--start", type=float, help="start of the fit window (s); default 3 T + 60 s")
    parser.add_argument("--sample", type=float, default=0.1, help="spacing of the samples fitted (s)")
    parser.add_argument("--out")
    a = parser.parse_args(argv)
    lines = [f"# command: python benchmarks/bench_f3of_rao_step.py {' '.join(a.cases)} --modes {a.modes}"
             + (f" --start {a.start:g}" if a.start is not None else "")
             + f" --sample {a.sample:g}" + (f" --out {a.out}" if a.out else ""),
             f"# python {platform.python_version()}, {os.cpu_count()} cores, load average at start "
             f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}"]
    with tempfile.TemporaryDirectory() as tmp:
        for spec in a.cases:
            period, duration, step = (float(v) for v in spec.split(":"))
            lines.append(case(period, duration, step, a.modes, a.start, a.sample, Path(tmp)))
    lines.append(f"# load average at end {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    write_report(lines, a.out)


if __name__ == "__main__":
    main()
