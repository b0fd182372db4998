"""A light body whose A_inf is many times its mass: why A_inf lives in the multibody mass matrix.

Thin floating disc (R = 5 m, draft 0.25 m, Capytaine database): A_inf is about 9 times the
disc's mass. The co-simulation (A_inf in the multibody FMU's mass matrix, only the radiation
memory exchanged) decays stably and matches the exact free decay; the same physics coupled
explicitly with A_inf as a force computed from the previous acceleration diverges.
"""

from __future__ import annotations

import numpy as np
import pytest

from hydro_fmu.model import HydroModel
from orchestrator.cosim.simulation import run_scenario
from orchestrator.reference import frequency_domain
from orchestrator.results import read_results
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS


@pytest.fixture(scope="module")
def disc():
    scenario = load_scenario(SCENARIOS / "disc_decay.toml")
    return scenario, load_scene(scenario, log=None)


def test_disc_is_light_compared_with_its_added_mass(disc) -> None:
    scenario, scene = disc
    ratio = scene.hdb.added_mass_inf[2, 2] / scene.body_mass(scenario.bodies[0])
    assert ratio > 5


def test_cosimulated_decay_is_stable_and_exact(disc, tmp_path) -> None:
    scenario, scene = disc
    run_scenario(scenario, tmp_path / "disc.h5", progress=False, log=None)
    data = read_results(tmp_path / "disc.h5")
    t, heave = data["time"], data["bodies/disc/displacement"][:, 2]
    x0 = scenario.bodies[0].initial_displacement[2]
    exact = frequency_domain.free_decay(scene, t, np.array([x0]))[:, 0]
    assert np.max(np.abs(heave - exact)) < 5e-3 * x0
    assert np.max(np.abs(heave[t > 15])) < 1e-3 * x0  # decayed, no growing mode


def explicit_added_mass_coupling(scene, steps: int, h: float) -> np.ndarray:
    """Same physics, A_inf moved to the force side: F = F_hydro - A_inf a(t_n) (mode 'b')."""
    system = scene.multibody_system(added_mass=False)  # structural mass only
    hydro = HydroModel(scene.hdb, scene.hydro_bodies, [[2]], scene.waves(), scene.ramp(), h,
                       scene.scenario.hydro.irf_duration)
    a_inf = scene.hdb.added_mass_inf[2, 2]
    mass = system.mass[0, 0]
    acceleration = 0.0
    out = []
    for n in range(steps):
        force = hydro.forces(n * h, system.q, system.qd).total - a_inf * acceleration
        hydro.advance(n * h, h, system.qd.copy())
        v_before = system.qd[0]
        system.step(h, force)
        acceleration = (system.qd[0] - v_before) / h
        out.append(system.q[0])
        if not np.isfinite(system.q[0]) or abs(system.q[0]) > 1e6:
            break
    assert mass < a_inf
    return np.array(out)


@pytest.mark.parametrize("h", [0.05, 0.01])
def test_added_mass_as_a_force_diverges_at_any_step(disc, h) -> None:
    _, scene = disc
    x = explicit_added_mass_coupling(scene, steps=int(10.0 / h), h=h)
    assert not np.isfinite(x[-1]) or abs(x[-1]) > 1e3
