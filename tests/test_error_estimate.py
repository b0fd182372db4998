"""Every run's error estimate (orchestrator.cosim.error_estimate) against exact answers, and the macro step chosen for
an error tolerance (orchestrator.cosim.step_choice).

The floating cylinder in regular waves has an exact answer: the linear frequency-domain steady state on the
database (the run's summary compares with it). Its error splits into the time stepping's, measured against the
frequency-domain answer with the run's own radiation model (the truncated kernel transformed at a step 16 times
finer than the run's: no time stepping), and the radiation model's (that answer against the database's). The
estimate must follow both: its time-stepping part converges at the run's order 2 and matches the true time-stepping
error, and the whole estimate matches the true error against the database.
"""

from __future__ import annotations

import json
import math

import h5py
import numpy as np
import pytest

from orchestrator.cosim.error_estimate import richardson, richardson_order, shadow_scenario
from orchestrator.cosim.simulation import format_summary, run_scenario
from orchestrator.reference import frequency_domain
from orchestrator.results import read_results
from orchestrator.scenario import apply_overrides, load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS

STEPS = (0.1, 0.05, 0.025)  # T/56, T/112, T/224 of the cylinder's 5.6 s wave


@pytest.fixture(scope="module")
def cylinder():
    scenario = load_scenario(SCENARIOS / "cylinder_regular.toml")
    return scenario, load_scene(scenario, log=None)


@pytest.fixture(scope="module")
def runs(cylinder, tmp_path_factory):
    """(step, RunResult, heave error against the database answer, against the run's own radiation model)."""
    scenario, scene = cylinder
    w = scenario.waves
    omega = np.array([2 * math.pi / w.period])
    exact = frequency_domain.solve(scene, omega).body_rao("float")[0, 2] * w.height / 2
    out = []
    for h in STEPS:
        s = apply_overrides(scenario, [f"simulation.step={h}"])
        result = run_scenario(s, tmp_path_factory.mktemp("cyl") / "r.h5", in_process=True, log=None, progress=False,
                              scene=scene)
        heave = next(c for c in result.comparisons if c.label == "float heave").measured
        own = frequency_domain.solve(scene, omega, radiation="impulse_response", dt=h / 16).body_rao("float")[0, 2]
        out.append((h, result, abs(heave - exact) / abs(exact), abs(heave - own * w.height / 2) / abs(exact)))
    return out


def test_the_time_stepping_estimate_converges_at_the_runs_order(runs) -> None:
    """Jacobi with quadratic extrapolation is second order: halving the step divides the estimated time-stepping
    error by about 4, as it divides the true one."""
    estimated = [r.error_estimate.time_discretisation for _, r, _, _ in runs]
    true = [t for _, _, _, t in runs]
    orders = np.log2(np.array(estimated[:-1]) / np.array(estimated[1:]))
    true_orders = np.log2(np.array(true[:-1]) / np.array(true[1:]))
    print(f"\nestimated time-stepping errors {estimated}, orders {orders}; true {true}, orders {true_orders}")
    assert np.all(np.abs(orders - 2.0) < 0.35), orders
    assert np.all(np.abs(true_orders - 2.0) < 0.3), true_orders
    for e, t in zip(estimated, true, strict=True):
        assert t / 1.35 < e < 1.35 * t, (e, t)


def test_the_estimate_matches_the_true_error_against_the_database(runs) -> None:
    """The whole estimate (time stepping plus the radiation model, added as signed complex errors) against the
    heave's true error against the exact answer on the database, where at the finest step the radiation model's
    part is 40 % of the total: within 25 % at every step."""
    for h, result, true, _ in runs:
        e = result.error_estimate
        print(f"h = {h}: estimate {e.value:.3e} (time {e.time_discretisation:.2e}, model {e.radiation_model:.2e}), "
              f"true {true:.3e}")
        assert e.available and e.quantities["float heave"] == e.value
        assert true / 1.25 < e.value < 1.25 * true, (h, e.value, true)
    assert runs[-1][1].error_estimate.radiation_model > 0.3 * runs[-1][2]  # the model's part matters there


def test_the_estimate_is_in_the_summary_and_the_results_file(runs) -> None:
    h, result, _, _ = runs[0]
    assert "error estimate: " in format_summary(result) and "Richardson" in format_summary(result)
    data = read_results(result.path)
    stored = data["attrs"]["error_estimate"]
    assert stored["value"] == pytest.approx(result.error_estimate.value, rel=1e-12)
    assert stored["order"] == 2 and stored["shadow_step"] == pytest.approx(2 * h)
    shadow_t = data["error_estimate/shadow/time"]
    assert shadow_t[1] - shadow_t[0] == pytest.approx(2 * h) and shadow_t[-1] == pytest.approx(data["time"][-1])
    assert data["error_estimate/shadow/bodies/float/displacement"].shape == (len(shadow_t), 6)


def test_no_estimate_when_switched_off(cylinder, tmp_path) -> None:
    scenario, scene = cylinder
    s = apply_overrides(scenario, ["simulation.error_estimate=none", "simulation.duration=20"])
    result = run_scenario(s, tmp_path / "r.h5", in_process=True, log=None, progress=False, scene=scene)
    assert "error estimate: none (simulation.error_estimate = 'none')" in format_summary(result)
    with h5py.File(tmp_path / "r.h5", "r") as f:
        assert json.loads(f.attrs["error_estimate"])["available"] is False
        assert "error_estimate" not in f


def test_richardson_order_and_the_shadow(cylinder) -> None:
    """The order is 1 for a held input (extrapolation 0), 2 otherwise; the shadow doubles the step and the
    multibody substep and has no estimate of its own."""
    scenario, _ = cylinder
    assert richardson_order(scenario) == 2
    assert richardson_order(apply_overrides(scenario, ["simulation.extrapolation=0"])) == 1
    assert richardson_order(apply_overrides(scenario, ["simulation.extrapolation=0", "simulation.master=monolithic"])
                            ) == 2
    shadow = shadow_scenario(apply_overrides(scenario, ["simulation.duration=200.3"]))
    assert shadow.simulation.step == pytest.approx(0.2) and shadow.simulation.duration == pytest.approx(200.2)
    assert shadow.simulation.error_estimate == "none"
    # exact for an error C h^p: y_h = y + C h^p, y_2h = y + C (2h)^p
    assert richardson(1.0 + 3e-3, 1.0 + 12e-3, 2) == pytest.approx(3e-3)


def test_error_tolerance_chooses_a_step_whose_true_error_meets_it(cylinder, tmp_path) -> None:
    """``simulation.error_tolerance = 0.01`` from a first step of 0.4 s (T/14, 8 % off): the step chosen gives
    a heave within 1 % of the exact answer, every step tried is reported, the chosen run's file is the one
    written."""
    scenario, scene = cylinder
    s = apply_overrides(scenario, ["simulation.step=0.4", "simulation.error_tolerance=0.01"])
    result = run_scenario(s, tmp_path / "r.h5", in_process=True, log=None, progress=False, scene=scene)
    choice = result.step_choice
    heave = next(c for c in result.comparisons if c.label == "float heave")
    print(f"\n{choice.text()}; true heave error {abs(heave.measured - heave.exact) / abs(heave.exact):.3e}")
    assert choice.met and choice.attempts[0].step == pytest.approx(0.4) and len(choice.attempts) >= 2
    assert choice.attempts[0].estimate > 0.01 and result.error_estimate.value <= 0.01
    assert abs(heave.measured - heave.exact) / abs(heave.exact) <= 0.01
    assert 200.0 / choice.step == pytest.approx(round(200.0 / choice.step)) and round(200.0 / choice.step) % 2 == 0
    data = read_results(tmp_path / "r.h5")
    assert data["time"][1] == pytest.approx(choice.step)
    assert data["attrs"]["step_choice"]["step"] == pytest.approx(choice.step)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.h5"]  # the other attempts' files removed
    assert "error tolerance 1 %: step" in format_summary(result)
