"""Seed 003's cost comparison redone on its hinge-barge: time-domain integration against the
pseudo-spectral (periodic steady state) solution, wall time and error against the exact answer.

Time-domain half (this file): the hinge-barge (`scenarios/hinge_barge.toml`, index-3 DAE,
generalised-alpha) in regular waves of frequency ``--omega``

* for a 15 s simulation at steps 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1 s (the macro step is
  also the multibody integrator's step and the radiation convolution's grid), and
* for simulation lengths 15, 60, 300 s (``--quick``, the default) or 15, 60, 300, 1000, 3000 s
  (``--full``) at the fixed step ``--fixed-step`` (default 0.05 s = T/40 at 3.14 rad/s, seed 003's
  fixed step; the steady state is then within 0.3 % of the exact answer, see the 15 s rows),

each with the error of its steady-state amplitude (harmonic fit over the last two whole periods)
against the exact linear frequency-domain answer (``orchestrator.reference.frequency_domain.solve``) at the
wave frequency: heave of barge 2 (the quantity seed 003 measured) and the worst of the heave and
pitch of both barges. A 15 s run is the seed's setting (ramp 6 s); whether its transient has
decayed shows in the length series (same step, longer runs). Surge is left out of the columns: the
lightest free mode, barge 1's surge on its mooring at 9.3 rad/s (damping ratio about 0.003), rings
for minutes.

Integration: the two physics objects of the FMUs (hydro model, multibody simulator) stepped in one
process by the Jacobi master (``in_process=True``: no FMI layer). The monolithic mode
(``simulation.master = "monolithic"``) supports only the ``linear`` multibody model, not scenes with
joints, so it cannot run this scene. For reference the FMU co-simulation through fmpy is timed
at two steps.

Pseudo-spectral half: :func:`pseudo_spectral_rows`, the periodic steady state directly (no transient,
no time step), DAE and ODE forms; its errors against the exact answer are round-off.

Wall time: stepping only (initialisation and FMU loading excluded), median of ``--repeat`` runs
for runs of at most 2000 steps, one run otherwise. Run from the repository root:

    python benchmarks/bench_pseudo_spectral.py [--quick | --full] [--omega 3.14159] [--repeat 3]
        [--out benchmarks/results/pseudo_spectral.txt]
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from orchestrator.cosim import study
from orchestrator.reference import frequency_domain
from orchestrator.results.analysis import harmonic_fit
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

try:  # the pseudo-spectral solver is being written in parallel (issue 7)
    from orchestrator.reference.pseudo_spectral import solve_steady
except ImportError:
    solve_steady = None

ROOT = Path(__file__).resolve().parent.parent
SCENARIO = ROOT / "scenarios" / "hinge_barge.toml"
STEPS = [0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1]
LENGTHS_QUICK = [15.0, 60.0, 300.0]
LENGTHS_FULL = [15.0, 60.0, 300.0, 1000.0, 3000.0]
COLUMNS = ["barge1 heave", "barge1 pitch", "barge2 heave", "barge2 pitch"]
LABELS = [f"{b} {d}" for b in ("barge1", "barge2") for d in ("surge", "heave", "pitch")]


def exact_answer(scene, omega: float, amplitude: float) -> dict[str, complex]:
    """Complex amplitudes of every active coordinate (exp(+i omega t)) from the frequency-domain solver."""
    fd = frequency_domain.solve(scene, np.array([omega]))
    return {label: complex(fd.rao[0, j]) * amplitude for j, label in enumerate(LABELS)}


def errors(series: study.Series, omega: float, exact: dict[str, complex]) -> dict[str, tuple[float, float]]:
    """(relative amplitude error, phase error in degrees) of each coordinate over the last two periods."""
    period = 2 * math.pi / omega
    t = series.time
    mask = t >= t[-1] - 2 * period - 1e-9
    out = {}
    for j, label in enumerate(LABELS):
        y, _ = harmonic_fit(t[mask], series.displacement[mask, j], omega)
        out[label] = (abs(y) / abs(exact[label]) - 1, math.degrees(np.angle(y / exact[label])))
    return out


def time_domain(scenario, scene, step: float, duration: float, repeat: int, in_process: bool = True):
    """Median stepping time (s) and the last run's displacements, Jacobi master, step = integrator step."""
    s = study.variant(scenario, "jacobi", step)
    s.simulation.duration = duration
    s.multibody.max_step = step
    runs = repeat if duration / step <= 2000 else 1
    walls, series = [], None
    for _ in range(runs):
        series = study.run_series(s, scene=scene, in_process=in_process)
        walls.append(series.wall_time)
    return statistics.median(walls), series


def row(kind: str, step: float, duration: float, wall: float, err: dict[str, tuple[float, float]]) -> str:
    worst = max((abs(err[c][0]), c) for c in COLUMNS)
    phase = max(abs(err[c][1]) for c in COLUMNS)
    h2 = err["barge2 heave"]
    per_step = 1e3 * wall / round(duration / step) if step == step else math.nan  # nan: no time steps
    return (f"{kind:<28}{step:>8g}{duration:>8g}{wall:>10.3f}{per_step:>9.2f}"
            f"{100 * h2[0]:>+10.3f}{h2[1]:>+8.2f}{100 * worst[0]:>10.2g}{phase:>8.2g}  {worst[1]}")


# ---------------------------------------------------------------- pseudo-spectral rows
def pseudo_spectral_rows(scene, omega: float, amplitude: float) -> list[str]:
    """Rows of the pseudo-spectral solver (DAE and ODE forms, N = 1 and N = 5 on the linear model): wall
    time of the whole solve including the linearisation and the hydrodynamic coefficients (median of 5),
    and the same error columns as the time-domain rows."""
    if solve_steady is None:
        return ["pseudo-spectral: not available (orchestrator.reference.pseudo_spectral.solve_steady not found)"]
    exact = exact_answer(scene, omega, amplitude)
    out = []
    for form in ("dae", "ode"):
        for harmonics in (1, 5):
            walls = []
            for _ in range(5):
                start = time.perf_counter()
                result = solve_steady(scene, omega, amplitude, harmonics, form=form)
                walls.append(time.perf_counter() - start)
            first = result.motion[1]  # first harmonic per coordinate, LABELS order
            err = {label: (abs(first[j]) / abs(exact[label]) - 1, math.degrees(np.angle(first[j] / exact[label])))
                   for j, label in enumerate(LABELS)}
            out.append(row(f"pseudo-spectral {form}, N={harmonics}", math.nan, math.nan, statistics.median(walls),
                           err))
    return out


# ---------------------------------------------------------------- end of the pseudo-spectral rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--quick", action="store_true", help="lengths 15, 60, 300 s (default)")
    group.add_argument("--full", action="store_true", help="lengths 15, 60, 300, 1000, 3000 s (17 minutes in all)")
    parser.add_argument("--omega", type=float, default=math.pi, help="wave frequency, rad/s (default pi: T = 2 s)")
    parser.add_argument("--fixed-step", type=float, default=0.05, help="step of the length series, s")
    parser.add_argument("--repeat", type=int, default=3, help="repeats of runs of at most 2000 steps (median)")
    parser.add_argument("--steps", type=float, nargs="*", default=STEPS)
    parser.add_argument("--lengths", type=float, nargs="*", help="override the simulation lengths, s")
    parser.add_argument("--fmu-steps", type=float, nargs="*", default=[0.02, 0.01])
    parser.add_argument("--out", help="also write the report to this file")
    args = parser.parse_args()
    lengths = args.lengths or (LENGTHS_FULL if args.full else LENGTHS_QUICK)

    scenario = load_scenario(SCENARIO)
    scenario.waves.period = 2 * math.pi / args.omega
    scene = load_scene(scenario, log=None)
    amplitude = scenario.waves.height / 2
    exact = exact_answer(scene, args.omega, amplitude)

    lines = [f"# command: python {' '.join(sys.argv)}",
             f"# python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}; "
             f"hinge-barge, omega = {args.omega:.5g} rad/s, wave amplitude {amplitude:g} m, ramp "
             f"{scenario.waves.ramp_time:g} s; index-3 DAE, one generalised-alpha step per macro step",
             "# errors: steady amplitude (fit over the last 2 periods) against the exact frequency-domain answer;",
             "# 'worst': largest |amplitude error| and |phase error| over heave and pitch of both barges",
             "# exact: " + ", ".join(f"{c} {abs(exact[c]):.4g}" for c in COLUMNS),
             f"{'method':<28}{'step s':>8}{'T_sim s':>8}{'wall s':>10}{'ms/step':>9}"
             f"{'h2 amp %':>10}{'h2 deg':>8}{'worst %':>10}{'w. deg':>8}  worst at"]
    print("\n".join(lines), flush=True)
    body: list[str] = []

    def emit(text: str) -> None:
        print(text, flush=True)
        body.append(text)

    emit("# 15 s simulations at several steps (time domain, in-process Jacobi, no FMI)")
    for h in args.steps:
        wall, series = time_domain(scenario, scene, h, 15.0, args.repeat)
        emit(row("time domain (in-process)", h, 15.0, wall, errors(series, args.omega, exact)))
    emit(f"# simulation lengths at step {args.fixed_step:g} s")
    for length in lengths:
        wall, series = time_domain(scenario, scene, args.fixed_step, length, args.repeat)
        emit(row("time domain (in-process)", args.fixed_step, length, wall, errors(series, args.omega, exact)))
    emit("# FMU co-simulation through fmpy (Jacobi), 15 s, for reference")
    for h in args.fmu_steps:
        wall, series = time_domain(scenario, scene, h, 15.0, 1, in_process=False)
        emit(row("co-simulation (fmpy FMUs)", h, 15.0, wall, errors(series, args.omega, exact)))
    emit("# pseudo-spectral")
    for text in pseudo_spectral_rows(scene, args.omega, amplitude):
        emit(text)
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text("\n".join(lines + body) + "\n")


if __name__ == "__main__":
    main()
