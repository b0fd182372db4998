"""Pseudo-spectral steady state with nonlinear forces: convergence in the number of harmonics N,
cost, and the time-domain co-simulation's steady state against it.

Scenes (the foundation cylinder, R = 5 m, draft 5 m, heave, T = 5.6 s near resonance):

* ``drag``: quadratic heave drag Cd = 2 on the water-plane area, 2 m waves (PTO damper 2e5 N s/m);
* ``pto law``: a hydraulic-like saturated PTO (c = 1e5 N s/m, Coulomb 3e4 N, quadratic 1e5 N s^2/m^2,
  limit 1.2e5 N), 1 m waves.

For N = 1, 2, 3, 5, 7, 11, 15, 21, 31: the relative change of the fundamental against N = 81, the mean
PTO power, the third harmonic, the solver's residual and evaluations, the wall time (median of 5).
Then the FMU co-simulation (fmpy, Jacobi, quadratic extrapolation, 240 s at 0.05 s) against the N = 81
solution: fundamental amplitude and phase errors, power error, and the largest waveform error over
the last ten periods. Run from the repository root:

    python benchmarks/bench_nonlinear_steady.py [--out benchmarks/results/nonlinear_steady.txt]
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.common import write_report  # noqa: E402
from orchestrator.cosim.simulation import run_scenario  # noqa: E402
from orchestrator.reference.pseudo_spectral import solve_steady  # noqa: E402
from orchestrator.results import read_results  # noqa: E402
from orchestrator.results.analysis import harmonic_fit, steady_window, window_mean  # noqa: E402
from orchestrator.scenario import load_scenario  # noqa: E402
from orchestrator.scene import load_scene  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
HARMONICS = (1, 2, 3, 5, 7, 11, 15, 21, 31)


def scenario(kind: str):
    s = load_scenario(ROOT / "scenarios" / "cylinder_regular.toml")
    s.simulation.duration, s.simulation.step = 240.0, 0.05
    if kind == "drag":
        s.bodies[0].drag_coefficient = [0.0, 0.0, 2.0, 0.0, 0.0, 0.0]
        s.bodies[0].drag_area = [0.0, 0.0, math.pi * 25.0, 0.0, 0.0, 0.0]
        s.waves.height = 2.0
    else:
        p = s.ptos[0]
        p.damping, p.friction_force, p.quadratic_damping, p.force_limit, p.velocity_scale = 1e5, 3e4, 1e5, 1.2e5, 0.02
        s.multibody.max_step = 0.025
    return s


def timed(scene, omega, amplitude, n):
    times, state = [], None
    for _ in range(5):
        start = time.perf_counter()
        state = solve_steady(scene, omega, amplitude, n)
        times.append(time.perf_counter() - start)
    return state, statistics.median(times)


def report_scene(kind: str, lines: list[str]) -> None:
    s = scenario(kind)
    scene = load_scene(s, log=None)
    omega, amplitude = 2 * math.pi / s.waves.period, s.waves.height / 2
    ref = solve_steady(scene, omega, amplitude, 81)
    lines.append(f"\n## {kind}: reference N = 81, |X1| = {abs(ref.motion[1, 0]):.6g} m, "
                 f"power {ref.pto_power['pto']:.6g} W, residual {ref.residual:.1e}")
    lines.append(f"{'N':>4} {'|dX1|/|X1|':>12} {'power W':>12} {'|X3| m':>11} {'residual':>9} {'evals':>6} "
                 f"{'wall ms':>8}")
    for n in HARMONICS:
        st, wall = timed(scene, omega, amplitude, n)
        x3 = abs(st.motion[3, 0]) if n >= 3 else 0.0
        err = abs(st.motion[1, 0] - ref.motion[1, 0]) / abs(ref.motion[1, 0])
        lines.append(f"{n:>4} {err:>12.2e} {st.pto_power['pto']:>12.6g} {x3:>11.3e} {st.residual:>9.1e} "
                     f"{st.evaluations:>6} {1e3 * wall:>8.2f}")
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        run_scenario(s, Path(tmp) / "td.h5", progress=False, log=None)
        wall = time.perf_counter() - start
        data = read_results(Path(tmp) / "td.h5")
    mask = steady_window(data["time"], s.waves.period, 10)
    t, y = data["time"][mask], data["bodies/float/displacement"][mask, 2]
    first, _ = harmonic_fit(t, y, omega)
    power = window_mean(data["time"], data["ptos/pto/power"], mask)
    exact = ref.motion[1, 0]
    phase = math.degrees(np.angle(first / exact))
    lines.append(f"time domain (FMUs, 240 s at 0.05 s, {wall:.1f} s wall): fundamental "
                 f"{100 * (abs(first) / abs(exact) - 1):+.3f} %, phase {phase:+.3f} deg, "
                 f"power {100 * (power / ref.pto_power['pto'] - 1):+.3f} %, waveform max error "
                 f"{100 * np.max(np.abs(y - ref.time_series(t)[:, 0])) / abs(exact):.3f} % of |X1|")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    lines = ["# command: python benchmarks/bench_nonlinear_steady.py" + (f" --out {args.out}" if args.out else ""),
             f"# python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}"]
    for kind in ("drag", "pto law"):
        report_scene(kind, lines)
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
