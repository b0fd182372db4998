"""The FMUs as third-party FMI hosts see them: validation, variables, state, errors."""

from __future__ import annotations

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

from orchestrator.cosim.masters import JacobiMaster
from orchestrator.cosim.recorder import Recorder
from orchestrator.cosim.simulation import make_components
from orchestrator.errors import MasterError
from orchestrator.fmi.fmu_builder import build_scene_fmus
from orchestrator.scenario import load_scenario
from orchestrator.scene import HYDRO, MBD, load_scene

from .conftest import SCENARIOS


@pytest.fixture(scope="module")
def cylinder():
    scene = load_scene(load_scenario(SCENARIOS / "cylinder_regular.toml"), log=None)
    return scene, build_scene_fmus(scene)


def test_fmus_pass_fmpy_validate(cylinder) -> None:
    _, fmus = cylinder
    for path in fmus.values():
        assert validate_fmu(str(path)) == []


def test_model_structure_declares_feedthrough_and_initial_unknowns(cylinder) -> None:
    _, fmus = cylinder
    hydro = read_model_description(str(fmus[HYDRO]))
    mbd = read_model_description(str(fmus[MBD]))
    deps = {u.variable.name: u.dependencies for u in hydro.outputs}
    assert {v.name for v in deps["float.F[3]"]} == {"float.x[3]", "float.v[3]"}
    assert deps["float.F_exc[3]"] == [] and deps["wave.elevation"] == []
    assert all(u.dependencies == [] for u in mbd.outputs)  # motion outputs are states
    initial = {u.variable.name for u in hydro.initialUnknowns}
    assert "A_inf[3,3]" in initial and "float.F[3]" in initial
    units = {v.name: v.unit for v in hydro.modelVariables}
    assert units["float.F[3]"] == "N" and units["A_inf[3,3]"] == "kg" and units["wave.elevation"] == "m"


@pytest.mark.parametrize("in_process", [False, True])
def test_rollback_through_fmu_state_reproduces_the_run(cylinder, in_process) -> None:
    scene, fmus = cylinder
    comps = make_components(fmus, in_process=in_process)
    master = JacobiMaster(comps, scene.connections(), 2, Recorder.observed(scene))
    master.initialize(0.0, 100.0, scene.parameter_links())
    h = scene.scenario.simulation.step
    for k in range(1, 201):
        master.step(h, k * h)
    checkpoint = master.checkpoint()
    first = []
    for k in range(201, 231):
        master.step(h, k * h)
        first.append(master.outputs[MBD].copy())
    master.restore(checkpoint)
    second = []
    for k in range(201, 231):
        master.step(h, k * h)
        second.append(master.outputs[MBD].copy())
    np.testing.assert_array_equal(np.array(first), np.array(second))
    master.terminate()


def test_non_finite_value_stops_with_a_named_variable(cylinder) -> None:
    scene, fmus = cylinder
    comps = make_components(fmus)
    master = JacobiMaster(comps, scene.connections(), 2, Recorder.observed(scene))
    with pytest.raises(MasterError, match=r"mbd: output pto\.force is not finite at t = 0 s"):
        master.initialize(0.0, 10.0, scene.parameter_links(), parameters={MBD: {"pto.damping": float("nan")}})
    master.terminate()


def test_wrong_step_size_is_reported_by_the_hydro_fmu(cylinder) -> None:
    scene, fmus = cylinder
    comps = make_components(fmus)
    master = JacobiMaster(comps, scene.connections(), 0, Recorder.observed(scene))
    master.initialize(0.0, 10.0, scene.parameter_links())
    with pytest.raises(MasterError, match="is not a whole multiple of the radiation convolution step"):
        master.step(0.37)
    master.terminate()


def test_pto_inputs_drive_the_damper_exactly(cylinder) -> None:
    """Setting the PTO damping input reproduces a scene built with that damping, to round-off."""
    scene, fmus = cylinder
    scenario = load_scenario(SCENARIOS / "cylinder_regular.toml")
    scenario.ptos[0].damping = 5.0e4
    other = load_scene(scenario, log=None)
    other_fmus = build_scene_fmus(other)
    runs = []
    for sc, fm, params in ((scene, fmus, None), (other, other_fmus, {MBD: {"pto.damping": 2.0e5}})):
        comps = make_components(fm)
        master = JacobiMaster(comps, sc.connections(), 2, Recorder.observed(sc))
        master.initialize(0.0, 30.0, sc.parameter_links(), parameters=params)
        out = []
        for k in range(1, 301):
            master.step(0.1, 0.1 * k)
            out.append(master.outputs[MBD].copy())
        master.terminate()
        runs.append(np.array(out))
    np.testing.assert_allclose(runs[1], runs[0], rtol=1e-12, atol=1e-12)
