"""The hydro side of the energy account (hydro_fmu/work.py): work of each force part on a prescribed motion
against closed forms of linear potential flow."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydro_fmu.work import COMPONENTS, WorkAccount
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS


def test_trapezoidal_work_of_a_linear_power_is_exact() -> None:
    """P(t) = a + b t is integrated exactly by the trapezoidal rule, on uneven steps too."""
    account = WorkAccount()
    times = [0.0, 0.3, 0.5, 1.2, 2.0]
    for t in times[:-1]:
        account.commit(t, np.full(len(COMPONENTS), 2.0 + 3.0 * t))
    end = times[-1]
    assert account.value(end, np.full(len(COMPONENTS), 2.0 + 3.0 * end)) == pytest.approx(
        np.full(len(COMPONENTS), 2.0 * end + 1.5 * end**2))


def test_radiated_and_hydrostatic_work_of_a_heaving_cylinder() -> None:
    """The project's floating cylinder forced in heave, x = a sin(w t) in still water: over whole periods
    after the memory has filled, the radiation force takes pi w B(w) a^2 per period (the mean radiated
    power w^2 B a^2 / 2, B from the database), and the hydrostatic work is -C (x^2 - x0^2) / 2 at every
    point (to the trapezoidal rule's O(h^2)); no excitation work in still water."""
    s = load_scenario(SCENARIOS / "cylinder_regular.toml")
    s.waves.kind = "still"
    scene = load_scene(s, log=None)
    period, a = 5.6, 0.2
    omega = 2 * math.pi / period
    h = period / 100
    hydro = scene.hydro_model(h)
    account = WorkAccount()
    steps = round(12 * period / h)
    start = round(8 * period / h)  # the 40 s impulse response has filled
    work = []
    for k in range(steps + 1):
        t = k * h
        x, v = np.array([a * math.sin(omega * t)]), np.array([a * omega * math.cos(omega * t)])
        f = hydro.forces(t, x, v)
        power = WorkAccount.powers(f.excitation, f.radiation, f.hydrostatic, f.viscous, v)
        work.append(account.value(t, power))
        account.commit(t, power)
        hydro.advance(t, h, v)
    work = np.array(work)
    idx = scene.hydro_index()
    b = float(np.interp(omega, scene.hdb.omega, scene.hdb.radiation_damping[:, idx[0], idx[0]]))
    radiated_per_period = -(work[-1, 1] - work[start, 1]) / ((steps - start) * h / period)
    assert radiated_per_period == pytest.approx(math.pi * omega * b * a**2, rel=0.01)
    c = float(scene.hdb.hydrostatic_stiffness[0][2, 2])
    x_end = a * math.sin(omega * steps * h)
    assert work[-1, 2] == pytest.approx(-0.5 * c * x_end**2, abs=1e-3 * c * a**2)
    assert np.all(work[:, 0] == 0.0)
