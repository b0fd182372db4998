"""Accuracy studies: co-simulation error against the monolithic reference, per master and step.

The reference is the monolithic run (same physics, strongly coupled, second order) at two fine
steps, combined by Richardson extrapolation (4 y_{h/2} - y_h) / 3, which removes its O(h^2)
error term; the error of a co-simulation is the largest deviation of the bodies' displacements
from it over the whole run (transient included), relative to the largest reference displacement.
Used by the tests (measured convergence orders) and by ``benchmarks/bench_masters.py``.
"""

from __future__ import annotations

import copy
import time
from dataclasses import dataclass

import numpy as np

from orchestrator.scenario import Scenario
from orchestrator.scene import MBD, Scene, load_scene

from .simulation import prepare_run


@dataclass
class Series:
    """Displacements of every active coordinate at the recorded times, and the run's cost."""

    time: np.ndarray
    displacement: np.ndarray
    wall_time: float
    evaluations: float


def variant(scenario: Scenario, master: str, step: float, extrapolation: int = 2,
            added_mass: str = "mass_matrix", *, interface: str = "force", plain_host: bool = False) -> Scenario:
    """The scenario with another master and step; ``interface`` (``force``, ``linearised``) and ``plain_host``
    (outputs read right after each step, as generic FMI hosts do: ``resolve_feedthrough = false``)."""
    s = copy.deepcopy(scenario)
    s.simulation.master = master
    s.simulation.step = step
    s.simulation.extrapolation = extrapolation
    s.simulation.added_mass = added_mass
    s.simulation.interface = interface
    s.simulation.resolve_feedthrough = not plain_host
    return s


def regular_wave(scenario: Scenario, period: float, amplitude: float, heading_deg: float | None = None,
                 periods: float = 15.0, steps_per_period: int = 100) -> Scenario:
    """A copy of ``scenario`` in a regular wave of ``period`` (s) and ``amplitude`` (m): macro step
    ``period / steps_per_period``, ``periods`` wave periods simulated, the default ramp (3 periods)."""
    s = copy.deepcopy(scenario)
    s.waves.kind = "regular"
    s.waves.period, s.waves.height, s.waves.ramp_time = period, 2 * amplitude, None
    if heading_deg is not None:
        s.waves.heading_deg = heading_deg
    s.simulation.step = period / steps_per_period
    s.simulation.duration = round(periods * steps_per_period) * s.simulation.step
    return s


def run_series(scenario: Scenario, *, scene: Scene | None = None, in_process: bool = False) -> Series:
    """Run without a results file; displacements (m, rad) of every active DOF at every step, and the
    wall time of the stepping alone (initialisation excluded)."""
    plan = prepare_run(scenario, in_process=in_process, log=None, scene=scene)
    names = plan.master.output_names[MBD]
    cols = [names.index(f"{b.name}.x[{['surge', 'sway', 'heave', 'roll', 'pitch', 'yaw'].index(d) + 1}]")
            for b in scenario.bodies for d in b.dofs]
    times, rows = [], []

    def observe(t: float, outputs: dict) -> None:
        times.append(t)
        rows.append(outputs[MBD][cols].copy())

    sim = scenario.simulation
    try:
        plan.master.initialize(0.0, sim.duration, plan.parameter_links)
        start = time.perf_counter()  # stepping only: set-up and initialisation are not counted
        plan.master.run(sim.duration, sim.step, observe, controller=plan.controller)
        wall = time.perf_counter() - start
    finally:
        plan.master.terminate()
    its = getattr(plan.master, "iterations", [])
    return Series(np.array(times), np.array(rows), wall, float(np.mean(its)) if its else 1.0)


def reference(scenario: Scenario, step: float, scene: Scene | None = None) -> Series:
    """Monolithic runs at ``step`` and ``step / 2``, Richardson-extrapolated, at the times of ``step``."""
    scene = scene or load_scene(scenario, log=None)
    coarse = run_series(variant(scenario, "monolithic", step), scene=scene)
    fine = run_series(variant(scenario, "monolithic", step / 2), scene=scene)
    x = (4 * fine.displacement[::2] - coarse.displacement) / 3
    return Series(coarse.time, x, coarse.wall_time + fine.wall_time, 1.0)


def error(series: Series, ref: Series) -> float:
    """Largest displacement deviation from the reference at common times, relative to its largest value."""
    k = int(round((series.time[1] - series.time[0]) / (ref.time[1] - ref.time[0])))
    r = ref.displacement[::k]
    n = min(len(r), len(series.displacement))
    if not np.allclose(series.time[:n], ref.time[::k][:n], atol=1e-9):
        raise ValueError("co-simulation times are not on the reference grid")
    return float(np.max(np.abs(series.displacement[:n] - r[:n])) / np.max(np.abs(r[:n])))


def orders(steps: list[float], errors: list[float]) -> np.ndarray:
    """Observed orders log(e_i / e_{i+1}) / log(h_i / h_{i+1}) between consecutive steps."""
    e, h = np.asarray(errors), np.asarray(steps)
    return np.log(e[:-1] / e[1:]) / np.log(h[:-1] / h[1:])
