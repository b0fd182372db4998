"""F3OF DT3: the mirror-wise mode's damping ratio (about 1.6e-4) measured against the roots, per start
angle, step, record length and fit window.

Runs ``scenarios/f3of_dt3.toml`` in process with the fore flap released from THETA deg at each
``THETA:STEP:DURATION`` case (base fixed, both flaps free), computes the step's own roots of the linear
model (``decay.natural_modes``: the kernel is sampled at the step), and fits each ``--windows`` window two
ways: one damped mode on the half difference of the flap pitches (the fit of the earlier slow test) and
both modes together on the two pitches (``decay.fit_decay`` on two channels, the slow test's fit), on
samples ``--sample`` s apart. Prints period and damping-ratio errors of both modes per window. It measured
the DT3 analysis of docs/f3of.md (decay tests):

    python benchmarks/bench_f3of_dt3_mirror.py 1:0.1:1500 0.1:0.1:1500 1:0.05:1500 1:0.025:1500 \
        --out benchmarks/results/f3of_dt3_mirror.txt
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
from orchestrator.reference.decay import fit_decay, natural_modes
from orchestrator.results import read_results
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent


def dt3_scenario(theta_deg: float, step: float, duration: float):
    """DT3 with the fore flap released from ``theta_deg`` about its hinge (3.5 m below its cg)."""
    s = load_scenario(ROOT / "scenarios" / "f3of_dt3.toml")
    s.simulation.step, s.simulation.duration = step, duration
    th = math.radians(theta_deg)
    flap = next(b for b in s.bodies if b.name == "flap1")
    flap.initial_displacement = [3.5 * math.sin(th), 0.0, 3.5 * (math.cos(th) - 1.0), 0.0, th, 0.0]
    return s


def roots(scene) -> tuple:
    """(same way, mirror-wise) roots by the relative sign of the flap pitches in the mode shape."""
    coords = list(scene.multibody_simulator().model.coordinates)
    p1, p2 = coords.index(("flap1", 4)), coords.index(("flap2", 4))
    modes = natural_modes(scene)
    same = next(m for m in modes if np.real(m.shape[p1] / m.shape[p2]) > 0)
    mirror = next(m for m in modes if np.real(m.shape[p1] / m.shape[p2]) < 0)
    return same, mirror


def errors(fitted, root) -> str:
    return f"{fitted.period / root.period - 1:+.2e}, {fitted.damping_ratio / root.damping_ratio - 1:+.2%}"


def case(theta: float, step: float, duration: float, windows: list[tuple[float, float]], sample: float,
         folder: Path) -> list[str]:
    s = dt3_scenario(theta, step, duration)
    path = folder / f"dt3_{theta:g}_{step:g}_{duration:g}.h5"
    t0 = time.perf_counter()
    run_scenario(s, path, in_process=True, progress=False, log=None)
    wall = time.perf_counter() - t0
    same, mirror = roots(load_scene(s, log=None))
    data = read_results(path)
    every = max(1, round(sample / step))
    t = data["time"][::every]
    x = np.column_stack([data[f"bodies/{b}/displacement"][::every, 4] for b in ("flap1", "flap2")])
    lines = [f"{theta:g} deg, step {step:g} s, {duration:g} s run ({wall:.0f} s wall, load "
             f"{os.getloadavg()[0]:.1f}); roots: same way {same.period:.4f} s, {same.damping_ratio:.4e}; "
             f"mirror-wise {mirror.period:.4f} s, {mirror.damping_ratio:.4e}"]
    for window in windows:
        if window[1] > duration + 1e-9:
            continue
        half = fit_decay(t, (x[:, 0] - x[:, 1]) / 2, 1, window).modes[0]
        both = fit_decay(t, x, 2, window)
        m_same = min(both.modes, key=lambda m: abs(m.omega - same.omega.real))
        m_mirror = min(both.modes, key=lambda m: abs(m.omega - mirror.omega.real))
        lines.append(f"  window {window[0]:g}-{window[1]:g} s: mirror-wise (period, damping ratio) errors: "
                     f"half difference, one mode {errors(half, mirror)}; both pitches, two modes "
                     f"{errors(m_mirror, mirror)}; same way (both pitches) {errors(m_same, same)}")
    return lines


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="+", help="THETA:STEP:DURATION (deg, s, s)")
    parser.add_argument("--windows", nargs="+", default=["20:400", "100:400", "300:1000", "300:1500"],
                        help="fit windows START:END (s)")
    parser.add_argument("--sample", type=float, default=0.5, help="spacing of the samples fitted (s)")
    parser.add_argument("--out")
    a = parser.parse_args(argv)
    windows = [tuple(float(v) for v in w.split(":")) for w in a.windows]
    lines = [f"# command: python benchmarks/bench_f3of_dt3_mirror.py {' '.join(a.cases)} --windows "
             f"{' '.join(a.windows)} --sample {a.sample:g}" + (f" --out {a.out}" if a.out else ""),
             f"# python {platform.python_version()}, {platform.machine()}, {os.cpu_count()} cores, load average "
             f"at start {' '.join(f'{x:.2f}' for x in os.getloadavg())}"]
    with tempfile.TemporaryDirectory() as tmp:
        for spec in a.cases:
            theta, step, duration = (float(v) for v in spec.split(":"))
            lines += case(theta, step, duration, windows, a.sample, Path(tmp))
    lines.append(f"# load average at end {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    write_report(lines, a.out)


if __name__ == "__main__":
    main()
