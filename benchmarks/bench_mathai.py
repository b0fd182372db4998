"""Mathai's triple modular assembly (seed 001, section 3.4): breakover angles, time domain against frequency domain.

The breakover angle (relative pitch at each hinge) per foot of wave amplitude from the exact linear
frequency-domain solution over 0.05-1.8 rad/s in following (heading 0) and quartering (45 deg) seas,
and from the time domain (two FMUs through fmpy, macro step T/100, 15 periods, the last 3 fitted) at
five frequencies in each. The report gives the time domain's error at each point (acceptance of
issue 14: 2 %), the peak frequency and height of each curve, and the wall time and real-time factor
of every run; the figure draws the curves with the time-domain points.

    python benchmarks/bench_mathai.py --out benchmarks/results/mathai_assembly.txt \\
        --figure docs/figures/mathai_breakover.png
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import tempfile
from pathlib import Path

import numpy as np
from common import pyplot, save_figure, write_report

from orchestrator.cosim.simulation import run_scenario
from orchestrator.cosim.study import regular_wave
from orchestrator.reference import frequency_domain
from orchestrator.results import read_results
from orchestrator.results.analysis import steady_response
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent
SCENARIO = ROOT / "scenarios" / "mathai_assembly.toml"
FOOT = 0.3048
HINGES = ("hinge1", "hinge2")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--omega", type=float, nargs="*", default=[0.4, 0.7, 1.0, 1.3, 1.6])
    parser.add_argument("--headings", type=float, nargs="*", default=[0.0, 45.0])
    parser.add_argument("--scenario", default=str(SCENARIO))
    parser.add_argument("--out", help="also write the report to this file")
    parser.add_argument("--figure", help="PNG of the breakover angles with the time-domain points")
    a = parser.parse_args(argv)
    base = load_scenario(a.scenario)
    scene = load_scene(base, log=None)
    grid = np.round(np.arange(0.05, 1.8 + 1e-9, 0.01), 10)
    curves = {h: frequency_domain.solve(scene, grid, heading_deg=h) for h in a.headings}
    lines = [f"# command: python benchmarks/bench_mathai.py {' '.join(sys.argv[1:] if argv is None else argv)}",
             f"# python {platform.python_version()}, {os.cpu_count()} cores, load average at start "
             f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}",
             "# frequency domain, breakover angle per foot of wave amplitude over 0.05-1.8 rad/s (0.01 rad/s grid):"]
    for h, fd in curves.items():
        for j in HINGES:
            deg = np.degrees(np.abs(fd.joint_rao[j][:, 0])) * FOOT
            k = int(np.argmax(deg))
            lines.append(f"#   heading {h:4g} deg {j}: peak {deg[k]:.3f} deg/ft at {grid[k]:.2f} rad/s; "
                         f"{deg[0]:.4f} deg/ft at 0.05 rad/s")
    lines.append(f"{'heading':>8}{'omega':>7}{'hinge':>8}{'TD deg/ft':>11}{'FD deg/ft':>11}{'error':>9}{'phase':>9}"
                 f"{'loop s':>8}{'RTF':>6}")
    points = []
    with tempfile.TemporaryDirectory() as tmp:
        for h in a.headings:
            for w in a.omega:
                s = regular_wave(base, 2 * math.pi / w, FOOT, h)
                result = run_scenario(s, Path(tmp) / "run.h5", progress=False, log=None)
                r = steady_response(s, read_results(result.path))
                fd = frequency_domain.solve(scene, np.array([w]), heading_deg=h)
                for j in HINGES:
                    td, exact = r[f"{j} 0"], fd.joint_rao[j][0, 0]
                    lines.append(f"{h:8g}{w:7.2f}{j:>8}{math.degrees(abs(td)) * FOOT:11.4f}"
                                 f"{math.degrees(abs(exact)) * FOOT:11.4f}{100 * (abs(td) / abs(exact) - 1):+8.2f}%"
                                 f"{math.degrees(np.angle(td / exact)):+8.2f}d{result.wall_time:8.1f}"
                                 f"{s.simulation.duration / result.wall_time:6.1f}")
                    print(lines[-1], flush=True)
                    points.append((h, w, j, td))
    lines.append(f"# load average at end {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    write_report(lines, a.out)
    if a.figure:
        figure(grid, curves, points, Path(a.figure))


def figure(grid: np.ndarray, curves: dict, points: list, target: Path) -> None:
    plt = pyplot()
    fig, axes = plt.subplots(1, len(curves), figsize=(6 * len(curves), 4.5), sharey=True, squeeze=False)
    colours = {"hinge1": "tab:blue", "hinge2": "tab:orange"}
    for ax, (h, fd) in zip(axes[0], curves.items(), strict=True):
        for j in HINGES:
            ax.plot(grid, np.degrees(np.abs(fd.joint_rao[j][:, 0])) * FOOT, color=colours[j],
                    label=f"{j}, frequency domain")
            td = [(w, math.degrees(abs(v)) * FOOT) for hh, w, jj, v in points if hh == h and jj == j]
            if td:
                ax.plot(*zip(*td, strict=True), "o", color=colours[j], mfc="none", label=f"{j}, time domain")
        ax.set_title(("following" if h == 0 else "quartering" if h == 45 else f"{h:g} deg") + " seas")
        ax.set_xlabel("wave frequency (rad/s)")
        ax.grid(True, alpha=0.3)
    axes[0, 0].set_ylabel("breakover angle (deg per ft of wave amplitude)")
    axes[0, -1].legend(fontsize=8)
    fig.suptitle("Mathai's triple modular assembly (50 ft of water)", fontsize=10)
    save_figure(fig, target)


if __name__ == "__main__":
    main()
