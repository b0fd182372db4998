"""Scaling: wall time against the number of bodies and against the simulated duration.

* Bundled scenes from 1 to 24 bodies (cylinder, hinge barge, F3OF, Nenuphar, the 4N3LA and 9N9LA arrays) as
  bundled, a fixed number of macro steps each, co-simulation through fmpy, the same with the FMU slaves called
  in process, and the monolithic mode (same physics in one process, no FMI; linear multibody model only, so
  unconstrained scenes only): microseconds per macro step.
* The multibody model alone, a row of N hinged floating cubes (N = 1 to 40: :func:`floating_row`), index-3,
  a new input every step as in co-simulation: microseconds per step (what the joints cost as N grows, without
  hydrodynamics; ``benchmarks/bench_speed.py`` part 2 runs the same row for every formulation).
* The hinge barge at its defaults for growing durations: wall time per simulated second (constant if nothing
  accumulates: the radiation memory is a fixed window, results are flushed in blocks).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .points import Point, Variant, run_point

SCENES = (("scenarios/cylinder_regular.toml", 1), ("scenarios/hinge_barge.toml", 2), ("scenarios/f3of_dt3.toml", 3),
          ("scenarios/nenuphar.toml", 7), ("scenarios/array_4n3la.toml", 10), ("scenarios/array_9n9la.toml", 24))
# (label, overrides, FMU slaves called in process): the FMI layer's share is the difference of the first two;
# the monolithic mode (one process, the linear multibody model only) refuses jointed scenes, and says so.
MODES = (("co-simulation (fmpy)", (), False), ("co-simulation, in-process slaves", (), True),
         ("monolithic", ("simulation.master=monolithic",), False))


@dataclass
class SceneRow:
    scenario: str
    bodies: int
    steps: int
    points: dict[str, Point]  # mode -> point

    def us_per_step(self, mode: str) -> float:
        p = self.points[mode]
        return 1e6 * p.wall_time / self.steps if p.stable else float("nan")


def scene_scaling(quick: bool, log: Callable[[str], None] | None = print) -> list[SceneRow]:
    """Each scene for ``steps`` macro steps at its own step, in both modes."""
    from orchestrator.scenario import load_scenario

    from .points import ROOT

    steps = 100 if quick else 400
    rows = []
    for scenario, bodies in SCENES:
        h = load_scenario(ROOT / scenario).simulation.step
        base = Variant(scenario, (f"simulation.duration={steps * h:g}",))
        points = {}
        for mode, overrides, in_process in MODES:
            v = base.with_(*overrides)
            points[mode] = run_point(Variant(v.scenario, v.overrides, in_process), shadow=False)
            if log is not None:
                p = points[mode]
                log(f"  {scenario} {mode}: {p.status} {1e6 * p.wall_time / steps:.0f} us per step {p.message[:80]}")
        rows.append(SceneRow(scenario, bodies, steps, points))
    return rows


def floating_row(n: int):  # noqa: ANN201 - (MultibodyModel, Pose, velocities)
    """A row of n 1 m cubes of 1000 kg on hydrostatic-like linear moorings (heave, roll, pitch 1e4; weak surge,
    sway, yaw), neighbours hinged about y 1.2 m apart, started with small heave offsets."""
    from mbd_fmu.bodies import RigidBody
    from mbd_fmu.joints import Joint
    from mbd_fmu.model import MultibodyModel
    from mbd_fmu.moorings import LinearMooring

    inertia = 1000.0 / 6 * np.eye(3)
    bodies = [RigidBody(f"b{i}", 1000.0, inertia, [1.2 * i, 0, 0]) for i in range(n)]
    joints = [Joint(f"h{i}", "revolute", f"b{i - 1}", f"b{i}", (1.2 * i - 0.6, 0, 0), (0, 1, 0)) for i in range(1, n)]
    model = MultibodyModel(bodies, joints)
    k = np.diag([1e2, 1e2, 1e4, 1e4, 1e4, 1e2])
    model.elements = [LinearMooring(f"m{i}", i, k, None, model.cg[i].copy()) for i in range(n)]
    pose = model.reference.copy()
    pose.r[:, 2] += 0.05 * np.cos(np.arange(n))
    return model, pose, np.zeros(model.n)


class RowWaves:
    """A wave-like heave force on each body of a :func:`floating_row`, a new value every step (N)."""

    def __init__(self, model) -> None:  # noqa: ANN001 - MultibodyModel
        self.heave = np.array([model.slot_of(f"b{i}", 2) for i in range(model.N)])
        self.n, self.phase = model.n, 0.7 * np.arange(model.N)

    def __call__(self, t: float) -> np.ndarray:
        f = np.zeros(self.n)
        f[self.heave] = 2e3 * np.sin(2.0 * t - self.phase)
        return f


def multibody_row(n: int, steps: int, h: float = 0.01) -> float:
    """Wall seconds per index-3 step (compiled path, generalised-alpha rho 0.8) of :func:`floating_row` (n)."""
    from mbd_fmu.formulations import Settings
    from mbd_fmu.simulator import MultibodySimulator

    model, pose, v = floating_row(n)
    sim = MultibodySimulator(model, Settings("index3", spectral_radius=0.8))
    sim.start(pose, v)
    waves = RowWaves(model)
    sim.advance(h, waves(0.0))  # the kernels' first call outside the timing
    start = time.perf_counter()
    for k in range(1, steps + 1):
        sim.advance(h, waves(k * h))
    return (time.perf_counter() - start) / steps


def body_scaling(quick: bool) -> list[tuple[int, float]]:
    """(N, microseconds per step, minimum of 3) of the multibody row for N = 1 .. 40."""
    sizes = (1, 2, 5, 10, 20, 40)
    return [(n, 1e6 * min(multibody_row(n, 50 if quick else 200) for _ in range(3))) for n in sizes]


def duration_scaling(quick: bool, log: Callable[[str], None] | None = print) -> list[tuple[float, Point]]:
    """The hinge barge at its defaults for growing simulated durations (s)."""
    durations = (10.0, 40.0, 160.0) if quick else (10.0, 40.0, 160.0, 640.0, 2560.0)
    out = []
    for d in durations:
        p = run_point(Variant("scenarios/hinge_barge.toml", (f"simulation.duration={d:g}",)), shadow=False)
        out.append((d, p))
        if log is not None:
            log(f"  hinge barge {d:g} s: {p.status} wall {p.wall_time:.2f} s, RTF {p.real_time_factor:.1f}")
    return out
