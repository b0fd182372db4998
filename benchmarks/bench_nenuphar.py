"""Nenuphar (seed 001): time domain against the linear frequency domain, and the amplitude dependence.

At 0.5 m and each of ``--periods``, and at 1.0 and 1.5 m (``--amplitudes``) and each of ``--amplitude-periods``,
the scenario ``scenarios/nenuphar.toml`` is run as a user runs it
(two FMUs through fmpy, the scenario's master and macro step T/100, 15 periods, the last 3 fitted),
with the linear hydrodynamics of the database (``linear``) and, with ``--nonlinear``, with the
hydrostatic and Froude-Krylov forces integrated over the instantaneous wetted hulls
(``nonlinear``, at 0.5, 1.0 and 1.5 m: the lateral bodies' 0.7 m draft and freeboard are small against
1-1.5 m waves). The
steady first harmonic of the six hinge angles, the central heave and the mean PTO powers are
compared with the exact linear frequency-domain answer (per metre of amplitude). The report gives
the errors (the acceptance of issue 14 is 1 % and 2 deg at 0.5 m), the wall time and real-time factor of every
run; the figure the hinge-angle and heave RAOs against frequency, frequency domain as lines, time domain as
markers per amplitude. With ``--nonlinear`` the runs at 0.5 m and above did not reach a periodic state
(docs/nenuphar.md): their first harmonics over the last 3 periods are not steady amplitudes.

Run (slow: one run is 15 wave periods of the seven-body model):

    python benchmarks/bench_nenuphar.py --out benchmarks/results/nenuphar.txt \\
        --figure docs/figures/nenuphar_amplitude.png
"""

from __future__ import annotations

import argparse
import dataclasses
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
from orchestrator.scene import Scene, load_scene

ROOT = Path(__file__).resolve().parent.parent
SCENARIO = ROOT / "scenarios" / "nenuphar.toml"
HINGES = [f"hinge{k}" for k in range(1, 7)]


@dataclasses.dataclass
class Steady:
    """Steady first harmonics per metre of wave amplitude (complex) and mean powers per m^2."""

    hinges: np.ndarray
    heave: complex
    power: dict[str, float]


def time_domain(scenario, folder: Path) -> tuple[Steady, float]:
    """Run and fit; returns the steady state and the stepping loop's wall time."""
    result = run_scenario(scenario, folder / "run.h5", progress=False, log=None)
    r = steady_response(scenario, read_results(result.path))
    return (Steady(np.array([r[f"{j} 0"] for j in HINGES]), r["central heave"],
                   {p.name: r[f"{p.name} power"] for p in scenario.ptos}), result.wall_time)


def frequency_domain_answer(scene: Scene, omega: np.ndarray, heading: float) -> frequency_domain.FrequencyResponse:
    return frequency_domain.solve(scene, omega, heading_deg=heading)


def errors(td: Steady, fd: frequency_domain.FrequencyResponse, k: int = 0) -> list[tuple[str, float, float]]:
    """(quantity, amplitude error, phase error deg) of every hinge, the heave and every PTO's power."""
    out = []
    for i, j in enumerate(HINGES):
        exact = fd.joint_rao[j][k, 0]
        out.append((j, abs(td.hinges[i]) / abs(exact) - 1, math.degrees(np.angle(td.hinges[i] / exact))))
    exact = fd.body_rao("central")[k, 2]
    out.append(("central heave", abs(td.heave) / abs(exact) - 1, math.degrees(np.angle(td.heave / exact))))
    for name, p in td.power.items():
        out.append((f"{name} power", p / fd.pto_power[name][k] - 1, math.nan))
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--periods", type=float, nargs="*", default=[3.5, 4.8, 6.5],
                        help="wave periods of the 0.5 m runs (the acceptance of issue 14)")
    parser.add_argument("--amplitude-periods", type=float, nargs="*", default=[4.8],
                        help="wave periods of the amplitude study (1.0 and 1.5 m; with --nonlinear also 0.5 m)")
    parser.add_argument("--amplitudes", type=float, nargs="*", default=[1.0, 1.5])
    parser.add_argument("--heading", type=float, default=0.0)
    parser.add_argument("--nonlinear", action="store_true", help="also run the nonlinear hydrostatics and FK model")
    parser.add_argument("--scenario", default=str(SCENARIO), help="scenario file (default the bundled Nenuphar)")
    parser.add_argument("--out", help="also write the report to this file")
    parser.add_argument("--figure", help="PNG of the RAOs against frequency with the time-domain points")
    a = parser.parse_args(argv)
    base = load_scenario(a.scenario)
    scene = load_scene(base, log=None)
    lines = [f"# command: python benchmarks/bench_nenuphar.py {' '.join(sys.argv[1:] if argv is None else argv)}",
             f"# python {platform.python_version()}, {os.cpu_count()} cores, load average at start "
             f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}",
             "# errors of the time-domain steady state against the exact linear frequency-domain answer "
             "(amplitude %, phase deg); power: mean over the last 3 periods",
             f"{'model':<10}{'T s':>5}{'a m':>5}  {'worst hinge':>22}{'central heave':>18}{'worst power':>13}"
             f"{'loop s':>8}{'RTF':>6}"]
    points = []
    cases = [("linear", period, 0.5) for period in a.periods]
    cases += [("linear", period, amplitude) for period in a.amplitude_periods for amplitude in a.amplitudes]
    if a.nonlinear:
        cases += [("nonlinear", period, amplitude) for period in a.amplitude_periods
                  for amplitude in [0.5, *a.amplitudes]]
    with tempfile.TemporaryDirectory() as tmp:
        for model, period, amplitude in cases:
            fd = frequency_domain_answer(scene, np.array([2 * math.pi / period]), a.heading)
            s = regular_wave(base, period, amplitude, a.heading)
            s.hydro.nonlinear_hydrostatics = s.hydro.nonlinear_froude_krylov = model == "nonlinear"
            td, loop = time_domain(s, Path(tmp))
            err = errors(td, fd)
            hinge = max(err[:6], key=lambda e: abs(e[1]))
            phase = max(abs(e[2]) for e in err[:6])
            heave = err[6]
            power = max(err[7:], key=lambda e: abs(e[1]))
            lines.append(f"{model:<10}{period:5.1f}{amplitude:5.1f}  {hinge[0]:>7} {100 * hinge[1]:+6.2f}% "
                         f"{phase:5.2f}deg{100 * heave[1]:+9.2f}% {heave[2]:+5.2f}deg"
                         f"{100 * power[1]:+12.2f}%{loop:8.1f}{s.simulation.duration / loop:6.1f}")
            points.append((model, period, amplitude, td))
            print(lines[-1], flush=True)
    lines.append(f"# load average at end {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    write_report(lines, a.out)
    if a.figure:
        figure(scene, points, a.heading, Path(a.figure))


def figure(scene: Scene, points: list, heading: float, target: Path) -> None:
    plt = pyplot()
    omega = np.linspace(0.4, 3.0, 131)
    fd = frequency_domain_answer(scene, omega, heading)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    colours = {0: "tab:blue", 3: "tab:orange", 2: "tab:green", 1: "tab:red"}
    shown = [(0, "hinge 1"), (3, "hinge 4"), (2, "hinges 3, 5"), (1, "hinges 2, 6")]
    for i, label in shown:
        axes[0].plot(omega, np.degrees(np.abs(fd.joint_rao[HINGES[i]][:, 0])), color=colours[i], label=label)
    axes[1].plot(omega, np.abs(fd.body_rao("central")[:, 2]), color="k", label="linear frequency domain")
    markers = {0.5: "o", 1.0: "s", 1.5: "^"}
    for model, period, amplitude, td in points:
        w = 2 * math.pi / period
        face = "none" if model == "nonlinear" else None
        for i, _ in shown:
            axes[0].plot(w, math.degrees(abs(td.hinges[i])), markers.get(amplitude, "x"), color=colours[i],
                         mfc=face if face else colours[i], ms=7)
        axes[1].plot(w, abs(td.heave), markers.get(amplitude, "x"), color="k", mfc=face if face else "k", ms=7,
                     label=f"time domain, {model}, a = {amplitude:g} m")
    axes[0].set_ylabel("hinge angle per metre of wave amplitude (deg/m)")
    axes[1].set_ylabel("central heave per metre of wave amplitude (m/m)")
    for ax in axes:
        ax.set_xlabel("wave frequency (rad/s)")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8, title="lines: linear frequency domain", title_fontsize=8)
    handles, labels = axes[1].get_legend_handles_labels()
    unique = dict(zip(labels, handles, strict=True))
    axes[1].legend(unique.values(), unique.keys(), fontsize=7)
    nonlinear = any(p[0] == "nonlinear" for p in points)
    fig.suptitle(f"Nenuphar, heading {heading:g} deg: markers time domain "
                 + ("(filled: linear hydrodynamics, open: nonlinear hydrostatics and Froude-Krylov), " if nonlinear
                    else "(multibody nonlinear, hydrodynamics linear), ")
                 + "circles 0.5 m, squares 1.0 m, triangles 1.5 m", fontsize=9)
    save_figure(fig, target)


if __name__ == "__main__":
    main()
