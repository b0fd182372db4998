"""The hydrodynamics FMU for every wave kind and option, run through fmpy: self-contained, exposing only
what the scene selects, and computing what the in-process physics computes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu

from hydro_fmu.sea import SeaSpec, build_sea
from orchestrator.fmi.fmu_builder import build_scene_fmus
from orchestrator.scenario import load_scenario
from orchestrator.scene import HYDRO, load_scene

from .conftest import SCENARIOS


def cylinder_scenario(**waves):
    scenario = load_scenario(SCENARIOS / "cylinder_regular.toml")
    for key, value in waves.items():
        setattr(scenario.waves, key, value)
    return scenario


def variables(path) -> dict[str, object]:
    return {v.name: v for v in read_model_description(str(path)).modelVariables}


def run_alone(path, stop: float, step: float, outputs: list[str], start_values: dict | None = None):
    return simulate_fmu(str(path), start_time=0.0, stop_time=stop, step_size=step, output_interval=step,
                        output=outputs, start_values=start_values or {}, fmi_call_logger=None)


def test_irregular_sea_inside_the_fmu_is_the_scene_sea_and_follows_the_seed() -> None:
    scenario = cylinder_scenario(kind="irregular", hs=2.0, tp=7.0, ramp_time=0.0, seed=4)
    scene = load_scene(scenario, log=None)
    path = build_scene_fmus(scene)[HYDRO]
    assert validate_fmu(str(path)) == []
    names = variables(path)
    assert {"wave.hs", "wave.tp", "wave.gamma", "wave.seed"} <= set(names)
    assert "wave.height" not in names and "wave.period" not in names
    result = run_alone(path, 20.0, 0.1, ["wave.elevation", "float.F_exc[3]"])
    np.testing.assert_allclose(result["wave.elevation"], scene.sea().elevation(result["time"]), atol=1e-10)
    other = run_alone(path, 20.0, 0.1, ["wave.elevation"], {"wave.seed": 9, "wave.hs": 1.0})
    expected = build_sea(SeaSpec(**{**scene.sea_spec().to_json(), "seed": 9, "hs": 1.0}))
    np.testing.assert_allclose(other["wave.elevation"], expected.elevation(other["time"]), atol=1e-10)


def test_imported_elevation_is_bundled_in_the_fmu(tmp_path) -> None:
    t = np.arange(0.0, 100.0, 0.1)
    eta = 0.4 * np.sin(2 * math.pi * t / 6.3) + 0.2 * np.cos(2 * math.pi * t / 4.1 + 1.0)
    record = tmp_path / "eta.csv"
    record.write_text("t,eta\n" + "\n".join(f"{a:.17g},{b:.17g}" for a, b in zip(t, eta, strict=True)))
    scenario = cylinder_scenario(kind="elevation", elevation_file=str(record), ramp_time=0.0)
    scenario.simulation.duration = 50.0
    scene = load_scene(scenario, log=None)
    path = build_scene_fmus(scene)[HYDRO]
    record.unlink()  # the FMU must not need the original file
    result = run_alone(path, 20.0, 0.1, ["wave.elevation", "float.F_exc[3]"])
    np.testing.assert_allclose(result["wave.elevation"], eta[: len(result)], atol=1e-12)
    assert np.abs(result["float.F_exc[3]"]).max() > 0


def test_state_space_fmu_reports_its_fit_and_takes_any_step() -> None:
    scenario = load_scenario(SCENARIOS / "disc_decay.toml")
    scenario.hydro.radiation_method = "state_space"
    scene = load_scene(scenario, log=None)
    path = build_scene_fmus(scene)[HYDRO]
    names = variables(path)
    assert names["radiation.order"].causality == "calculatedParameter"
    result = run_alone(path, 2.0, 0.037, ["radiation.order", "radiation.fit_error", "disc.F[3]"])
    assert result["radiation.order"][-1] >= 2
    assert 0 < result["radiation.fit_error"][-1] <= scenario.hydro.state_space_tolerance


def test_only_selected_parts_exist_and_drag_is_computed() -> None:
    scenario = load_scenario(SCENARIOS / "cylinder_regular.toml")
    scenario.hydro.radiation = False
    body = scenario.bodies[0]
    body.linear_damping = [0, 0, 1.0e4, 0, 0, 0]
    body.drag_coefficient = [0, 0, 1.0, 0, 0, 0]
    body.drag_area = [0, 0, 78.5, 0, 0, 0]
    scene = load_scene(scenario, log=None)
    path = build_scene_fmus(scene)[HYDRO]
    names = variables(path)
    assert "float.F_visc[3]" in names and "float.F_rad[3]" not in names and "float.F[1]" not in names
    v = -0.3
    result = run_alone(path, 0.2, 0.1, ["float.F_visc[3]"], {"float.v[3]": v})
    expected = -1.0e4 * v - 0.5 * 1025.0 * 1.0 * 78.5 * abs(v) * v
    np.testing.assert_allclose(result["float.F_visc[3]"], expected, rtol=1e-12)


def test_spread_sea_with_heading_interpolation_in_the_fmu() -> None:
    scenario = load_scenario(SCENARIOS / "two_cylinders_decay.toml")
    w = scenario.waves
    w.kind, w.hs, w.tp, w.spreading_s, w.n_directions, w.heading_deg = "irregular", 1.5, 6.0, 6.0, 5, 20.0
    w.discretisation, w.n_components = "equal_energy", 40
    scene = load_scene(scenario, log=None)
    assert not scene.waves().unidirectional
    path = build_scene_fmus(scene)[HYDRO]
    result = run_alone(path, 10.0, 0.05, ["fore.F_exc[3]", "aft.F_exc[3]"])
    model = scene.hydro_model()
    expected = np.array([model.excitation(t) for t in result["time"]])
    np.testing.assert_allclose(result["fore.F_exc[3]"], expected[:, 0], rtol=1e-9, atol=1e-6 * np.abs(expected).max())
    np.testing.assert_allclose(result["aft.F_exc[3]"], expected[:, 1], rtol=1e-9, atol=1e-6 * np.abs(expected).max())


def test_spread_sea_outside_the_database_headings_is_refused() -> None:
    from orchestrator.errors import ScenarioError

    scenario = cylinder_scenario(kind="irregular", hs=1.0, tp=6.0, spreading_s=2.0, n_directions=5)
    with pytest.raises(ScenarioError, match="outside the tabulated headings"):
        load_scene(scenario, log=None)


def test_impulse_response_warnings_reach_the_host_log() -> None:
    """The disc database's damping is still 11 % of its peak at 6 rad/s: the FMU says so in its log,
    with the radiation model's report, when it leaves initialisation."""
    from orchestrator.fmi.components import FmuComponent

    scene = load_scene(load_scenario(SCENARIOS / "disc_decay.toml"), log=None)
    comp = FmuComponent("hydro", build_scene_fmus(scene)[HYDRO])
    comp.setup(0.0, 1.0)
    comp.enter_initialization()
    comp.exit_initialization()
    text = "\n".join(str(m) for m in comp.messages)
    comp.terminate()
    assert "disc heave: B at the highest frequency 6 rad/s is still 11%" in text
    assert "radiation: convolution over 601 kernel samples" in text


def test_state_space_and_irregular_sea_roll_back_exactly() -> None:
    """The FMU state holds the whole physics (state-space memory, phasor clock): stepping on from a
    restored state repeats the first pass bit for bit."""
    from orchestrator.fmi.components import FmuComponent

    scenario = load_scenario(SCENARIOS / "cylinder_irregular.toml")
    scene = load_scene(scenario, log=None)
    comp = FmuComponent("hydro", build_scene_fmus(scene)[HYDRO])
    comp.setup(0.0, 100.0)
    comp.enter_initialization()
    comp.exit_initialization()
    pv, pf = comp.port(["float.v[3]"]), comp.port(["float.F[3]", "float.F_visc[3]", "wave.elevation"])

    def run(start: int, steps: int) -> np.ndarray:
        out = []
        for k in range(start, start + steps):
            comp.set_reals(pv, np.array([0.3 * np.sin(0.7 * k * 0.1)]))
            out.append(comp.get_reals(pf).copy())
            comp.do_step(k * 0.1, 0.1)
        return np.array(out)

    run(0, 50)
    state = comp.get_state()
    first = run(50, 30)
    comp.set_state(state)
    second = run(50, 30)
    comp.free_state(state)
    comp.terminate()
    np.testing.assert_array_equal(first, second)
    assert np.abs(first[:, 1]).max() > 0  # the drag is on


def test_the_radiation_history_clock_does_not_drift_from_the_hosts_over_long_runs() -> None:
    """The hydro runtime checks each step's start against its own running time: a plain sum of 500 000 steps
    of 0.02 s (10 000 s) drifts from the host's t = k h by more than that check allows (an FMU stopped a long run
    at t = 26 147 s); the compensated sum stays within a few units in the last place (read from the model state:
    the elapsed time follows the start time after the state's 64-byte header, docs/runtime.md)."""
    import struct

    from hydro_fmu.slave import StepClock

    from .hydro_runtime_cases import runtime

    model = runtime(dofs=[(0, 2)], dt=0.02)
    v = np.zeros(1)
    clock, t, plain = StepClock(0.0), 0.0, 0.0
    for _ in range(500_000):
        model.advance(t, 0.02, v)  # raises if the two clocks disagree
        plain += 0.02
        t = clock.advance(0.02)
    assert abs(plain - t) > 1e-6 * 0.02  # what the plain sum would have done
    elapsed = struct.unpack_from("<d", model.state(), 64 + 8)[0]
    assert abs(elapsed - t) <= 4 * np.spacing(t)
