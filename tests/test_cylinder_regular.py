"""Acceptance of the foundation: the co-simulated floating cylinder against the exact answer.

Cylinder R = 5 m, draft 5 m, deep water, heave only, linear PTO damper, regular waves. Two FMUs
(built with PythonFMU, loaded with fmpy) stepped by the Jacobi master at a macro step of T/50.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from orchestrator.cosim.simulation import run_scenario
from orchestrator.reference import frequency_domain
from orchestrator.results import read_results
from orchestrator.results.analysis import harmonic_fit, steady_window
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS


def cylinder(period: float, steps_per_period: int, extrapolation: int = 2):
    s = load_scenario(SCENARIOS / "cylinder_regular.toml")
    s.waves.period = period
    s.waves.ramp_time = 3 * period
    s.simulation.step = period / steps_per_period
    s.simulation.duration = 30 * period  # the transient has decayed by 1e-8 after 20 periods
    s.simulation.extrapolation = extrapolation
    return s


def resonance_period() -> float:
    """Period of the largest heave response of the damped system, from the frequency domain."""
    scene = load_scene(load_scenario(SCENARIOS / "cylinder_regular.toml"), log=None)
    omega = np.linspace(0.5, 2.0, 3001)
    rao = frequency_domain.solve(scene, omega).rao[:, 0]
    return 2 * math.pi / omega[np.argmax(np.abs(rao))]


@pytest.mark.parametrize("period", [4.0, "resonance", 9.0])
def test_heave_and_power_match_frequency_domain_at_T_over_50(tmp_path, period) -> None:
    period = resonance_period() if period == "resonance" else period
    result = run_scenario(cylinder(period, 50), tmp_path / "run.h5", progress=False, log=None)
    heave, power = result.comparisons
    assert abs(heave.amplitude_error) < 0.01, heave
    assert abs(heave.phase_error_deg) < 2.0, heave
    assert abs(power.amplitude_error) < 0.02, power


def measured_heave(tmp_path, period: float, n: int, extrapolation: int) -> complex:
    s = cylinder(period, n, extrapolation)
    run_scenario(s, tmp_path / f"run_{n}_{extrapolation}.h5", progress=False, log=None)
    data = read_results(tmp_path / f"run_{n}_{extrapolation}.h5")
    t = data["time"]
    mask = steady_window(t, period, 10)
    amp, _ = harmonic_fit(t[mask], data["bodies/float/displacement"][mask, 2], 2 * math.pi / period)
    return amp / (s.waves.height / 2)


@pytest.mark.parametrize("extrapolation, order", [(0, 1.0), (1, 2.0), (2, 2.0)])
def test_convergence_order_of_the_coupling(tmp_path, extrapolation, order) -> None:
    """Halving the macro step divides the error by 2^p: p = 1 with zero-order hold, p = 2 with
    step-averaged extrapolation of order 1 or 2 (inputs stay constant within a step: see
    orchestrator.cosim.masters). Measured here (T = 6 s, steps T/50, T/100, T/200): orders 1.13, 1.06
    (hold); 1.99, 2.00 (linear); 2.09, 2.03 (quadratic, with a 3.5x smaller error at T/50).

    Reference: the exact frequency-domain answer of the time-domain model itself, i.e. with the
    radiation coefficients of the (finely sampled, truncated) impulse response, so that the
    database's own truncation error does not mask the master's convergence."""
    period = 6.0
    omega = 2 * math.pi / period
    scene = load_scene(load_scenario(SCENARIOS / "cylinder_regular.toml"), log=None)
    exact = frequency_domain.solve(scene, np.array([omega]), radiation="impulse_response", dt=0.002).rao[0, 0]
    steps = (50, 100, 200)
    errors = np.array([abs(measured_heave(tmp_path, period, n, extrapolation) - exact) / abs(exact) for n in steps])
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all(np.abs(orders - order) < 0.2), (errors, orders)
