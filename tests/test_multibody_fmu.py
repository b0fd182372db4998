"""The nonlinear multibody FMU as FMI hosts see it, and scenario validation of the multibody keys."""

from __future__ import annotations

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

from orchestrator.cosim.masters import JacobiMaster
from orchestrator.cosim.recorder import Recorder
from orchestrator.cosim.simulation import make_components
from orchestrator.fmi.fmu_builder import build_scene_fmus
from orchestrator.scenario import load_scenario
from orchestrator.scene import MBD, load_scene
from wec_cosim.cli import main

from .conftest import SCENARIOS
from .test_scenario import assert_rejected, write

BASE = (SCENARIOS / "hinge_barge.toml").read_text()


@pytest.fixture(scope="module")
def barge():
    scene = load_scene(load_scenario(SCENARIOS / "hinge_barge.toml"), log=None)
    return scene, build_scene_fmus(scene)


def test_multibody_fmu_validates_and_declares_its_outputs(barge) -> None:
    _, fmus = barge
    assert validate_fmu(str(fmus[MBD])) == []
    md = read_model_description(str(fmus[MBD]))
    assert all(u.dependencies == [] for u in md.outputs)  # no direct feedthrough
    names = {v.name: v for v in md.modelVariables}
    for name in ("hinge.coordinate[1]", "hinge.rate[1]", "hinge.force[3]", "hinge.moment[2]", "pto.position",
                 "pto.velocity", "pto.force", "pto.power", "energy.balance", "mbd.dof", "barge2.pose[5]",
                 "barge1.F[5]", "barge1.x[5]", "pto.damping"):
        assert name in names, name
    assert names["hinge.coordinate[1]"].unit == "rad" and names["hinge.force[3]"].unit == "N"
    assert names["pto.damping"].causality == "input" and names["pto.position"].unit == "m"


def run(master, scene, n, h, start=1):
    out = []
    for k in range(start, start + n):
        master.step(h, k * h)
        out.append(master.outputs[MBD].copy())
    return np.array(out)


def test_rollback_restores_the_integrator_history(barge) -> None:
    """Checkpoint (serialised FMU state incl. generalised-alpha history) and restore through fmpy."""
    scene, fmus = barge
    comps = make_components(fmus)
    master = JacobiMaster(comps, scene.connections(), 2, Recorder.observed(scene))
    master.initialize(0.0, 10.0, scene.parameter_links())
    h = scene.scenario.simulation.step
    run(master, scene, 100, h)
    checkpoint = master.checkpoint()
    first = run(master, scene, 20, h, 101)
    master.restore(checkpoint)
    second = run(master, scene, 20, h, 101)
    master.terminate()
    np.testing.assert_array_equal(first, second)
    assert np.max(np.abs(first)) > 0


def test_pto_damping_input_drives_the_point_to_point_pto(barge) -> None:
    """Setting the PTO damping input reproduces a scene built with that damping, to round-off."""
    scene, fmus = barge
    scenario = load_scenario(SCENARIOS / "hinge_barge.toml")
    scenario.ptos[0].damping = 2000.0
    other = load_scene(scenario, log=None)
    runs = []
    for sc, fm, params in ((other, build_scene_fmus(other), None), (scene, fmus, {MBD: {"pto.damping": 2000.0}})):
        master = JacobiMaster(make_components(fm), sc.connections(), 2, Recorder.observed(sc))
        master.initialize(0.0, 10.0, sc.parameter_links(), parameters=params)
        runs.append(run(master, sc, 150, sc.scenario.simulation.step))
        master.terminate()
    np.testing.assert_allclose(runs[1], runs[0], rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("edit, fragments", [
    (lambda t: t.replace('body2 = "barge2"\nposition = [0.78', 'body2 = "barge3"\nposition = [0.78'),
     ["joints[0] (hinge)", "body2 'barge3' is not a defined body"]),
    (lambda t: t.replace('kind = "revolute"', 'kind = "hinge"'), ["joints[0].kind", "'hinge' is not one of"]),
    (lambda t: t.replace('axis = [0.0, 1.0, 0.0]', 'axis = [0.0, nan, 0.0]'), ["joints[0].axis[1]", "finite"]),
    (lambda t: t.replace('axis = [0.0, 1.0, 0.0]', 'axis = [0.0, 1.0, 0.0]\nlock = true'),
     ["unknown key 'joints[0].lock'", "Did you mean 'locked'"]),
    (lambda t: t.replace('formulation = "index3"', 'formulation = "linear"'), ["formulation = 'linear'", "joints"]),
    (lambda t: t.replace('formulation = "index3"', 'formulation = "index2"'), ["multibody.formulation", "not one of"]),
    (lambda t: t.replace('spectral_radius = 0.8', 'spectral_radius = 1.5'), ["spectral_radius must be in [0, 1]"]),
    (lambda t: t.replace('inertia = [17.6, 34.9, 37.7]', 'inertia = [17.6, 34.9, 37.7]\nmass = -1.0'),
     ["bodies[0].mass must be positive"]),
    (lambda t: t.replace('point2 = [1.71, 0.0, 0.1]', 'point2 = [1.71, 0.1]'), ["ptos[0] (pto)", "point2 needs 3"]),
    (lambda t: t + '\n[[ptos]]\nname = "p2"\nbody = "barge1"\njoint = "knee"\n', ["joint 'knee' is not defined"]),
    (lambda t: t + '\n[[forces]]\nname = "f"\nkind = "rotary_spring_damper"\njoint = "elbow"\n',
     ["forces[1] (f)", "joint 'elbow' is not defined"]),
    (lambda t: t + '\n[[drivers]]\nname = "d"\nbody = "barge1"\ndof = "yaw"\n', ["dof 'yaw' is not active"]),
    (lambda t: t.replace('stiffness_matrix = [3.5e4, 0.0, 3.5e4, 0.0, 0.0, 0.0]', 'stiffness_matrix = [1.0, 2.0]'),
     ["stiffness_matrix needs 6 or 36 values"]),
])
def test_invalid_multibody_scenarios_name_file_and_key(tmp_path, edit, fragments) -> None:
    assert_rejected(write(tmp_path, edit(BASE)), fragments)


def test_cli_reports_a_bad_joint_without_a_traceback(tmp_path, capsys) -> None:
    path = write(tmp_path, BASE.replace('body1 = "barge1"\nbody2', 'body1 = "barge9"\nbody2'))
    assert main(["run", str(path)]) == 2
    err = capsys.readouterr().err
    assert "body1 'barge9' is not a defined body" in err and "Traceback" not in err


EXTRAS = '''
[[bodies]]
name = "arm"
cg = [0.0, 2.0, -0.2]
mass = 40.0
inertia = [10.0, 1.0, 10.0]
hydro = false
buoyancy = 392.4

[[bodies]]
name = "weight"
cg = [0.0, 3.5, -1.0]
mass = 5.0
hydro = false
point_mass = true
dofs = ["surge", "sway", "heave"]

[[joints]]
name = "ball"
kind = "spherical"
body1 = "barge1"
body2 = "arm"
position = [0.0, 1.0, -0.2]

[[joints]]
name = "pin"
kind = "revolute"
body1 = "barge2"
body2 = "arm"
position = [0.0, 3.0, -0.2]
axis = [1.0, 0.0, 0.0]
locked = true

[[forces]]
name = "pitch_pto"
kind = "bushing"
body1 = "barge1"
body2 = "arm"
position = [0.0, 1.0, -0.2]
stiffness_matrix = [0.0, 0.0, 0.0, 0.0, 500.0, 500.0]
damping_matrix = [0.0, 0.0, 0.0, 0.0, 100.0, 100.0]

[[forces]]
name = "tether"
kind = "rope"
body1 = "arm"
point1 = [0.0, 2.5, -0.2]
body2 = "weight"
point2 = [0.0, 3.5, -1.0]
stiffness = 1e4

[[forces]]
name = "anchor_line"
kind = "catenary"
body = "barge2"
fairlead = [3.5, 0.0, -0.05]
anchor = [20.0, 0.0, -15.0]
length = 25.0
weight = 5.0
ea = 1e7

[[forces]]
name = "hinge_spring"
kind = "rotary_spring_damper"
joint = "hinge"
stiffness = 200.0

[[forces]]
name = "hinge_friction"
kind = "friction"
joint = "hinge"
force = 2.0
velocity = 0.01

[[drivers]]
name = "wiggle"
body = "weight"
dof = "surge"
function = "harmonic"
amplitude = 0.05
period = 3.0
'''


def test_every_element_kind_is_wired_from_the_scenario_to_the_fmu_outputs(tmp_path) -> None:
    """A scene with a spherical and a locked revolute joint, a point mass, a bushing, a rope, a
    catenary line, a rotary spring, friction and a driver: the nonlinear model builds, reports its
    mobility, and the FMU's outputs for every element are finite after a short co-simulation."""
    text = BASE.replace('dofs = ["surge", "heave", "pitch"]',
                        'dofs = ["surge", "sway", "heave", "roll", "pitch", "yaw"]')
    path = tmp_path / "extras.toml"
    path.write_text(text + EXTRAS)
    scenario = load_scenario(path)
    scenario.hydro.cache_dir = str(SCENARIOS / "hydro_cache")  # the committed hinge-barge database
    # The database's out-of-plane coefficients at its top frequency (barge 2 sway-roll damping, 12 rad/s)
    # are 6 % asymmetric with the 0.05 m mesh; this test checks the wiring of elements, not hydrodynamics.
    scenario.hydro.check_tolerance = 0.1
    scene = load_scene(scenario, log=None)
    sim = scene.multibody_simulator()
    # 3 x 6 rigid + 3 point-mass coordinates; hinge 5, ball 3, locked pin 6, driver 1 equations. With the
    # arm locked to barge 2, the hinge (5) and the ball (3) both tie barge 1 to that pair: 8 equations on
    # 6 relative DOF, so 2 are redundant and the rank is 13.
    assert (sim.report.coordinates, sim.report.rank, len(sim.report.redundant)) == (21, 13, 2)
    fmus = build_scene_fmus(scene)
    master = JacobiMaster(make_components(fmus), scene.connections(), 2, Recorder.observed(scene))
    master.initialize(0.0, 1.0, scene.parameter_links())
    out = run(master, scene, 10, 0.02)
    names = ["pitch_pto.force[1]", "pitch_pto.force[2]", "tether.force[1]", "anchor_line.force[3]",
             "hinge_spring.force[1]", "hinge_friction.force[1]", "pin.moment[1]", "energy.balance",
             "weight.pose[1]", "mbd.constraint_violation"]
    comp = master.components[MBD]
    values = comp.get_reals(comp.port(names))
    master.terminate()
    assert np.all(np.isfinite(out)) and np.all(np.isfinite(values))
    assert values[3] < 0  # the catenary pulls the fairlead down
    assert values[-1] < 1e-8


def test_outputs_gathered_from_the_fused_step_equal_the_outputs_by_groups(barge) -> None:
    """The multibody slave's get_real on the compiled index-3 path gathers every output from the fused macro step's
    flat array (MultibodySimulator.output_values); the same values, to the last bit, as the outputs computed by
    groups from the simulator's output methods (the path every other formulation takes), over steps with the PTO
    damping changed, for every output variable read one by one and all at once."""
    scene, fmus = barge
    comps = make_components(fmus, in_process=True)
    master = JacobiMaster(comps, scene.connections(), 2, Recorder.observed(scene))
    master.initialize(0.0, 10.0, scene.parameter_links())
    slave = comps[MBD].slave
    outputs = [v.valueReference for v in comps[MBD].model_description.modelVariables if v.causality == "output"]
    h = scene.scenario.simulation.step
    for k in range(1, 31):
        if k == 15:
            comps[MBD].set_reals(comps[MBD].port(["pto.damping"]), np.array([2000.0]))
        master.step(h, k * h)
        assert slave.system.output_values() is not None  # the compiled index-3 path
        gathered = slave.get_real(outputs)
        one_by_one = [slave.get_real([vr])[0] for vr in outputs]
        slave.mark_outputs_stale()
        grouped = slave._get_real_grouped(outputs)
        assert gathered == grouped == one_by_one
    assert any(v != 0.0 for v in gathered)


@pytest.mark.parametrize("in_process", [True, False], ids=["in-process", "fmpy"])
def test_pto_commands_set_through_fmi_act_from_the_next_step_also_after_a_restore(barge, in_process) -> None:
    """The slave looks at its PTO command inputs only after a set_real wrote one of them or a state was restored
    (MultibodySlave._pending): a command set through FMI at any step, before or after a restore (serialised or
    in memory), drives the next step. Checked on the outputs by the PTO law itself, force = -k x - c v + u with the
    commands set (the hinge barge's linear dash-pot law), each check chosen so that the previous commands give a
    clearly different force."""
    scene, fmus = barge
    comps = make_components(fmus, in_process=in_process)
    master = JacobiMaster(comps, scene.connections(), 2, Recorder.observed(scene))
    master.initialize(0.0, 10.0, scene.parameter_links())
    mbd = comps[MBD]
    h = scene.scenario.simulation.step
    commands = mbd.port(["pto.stiffness", "pto.damping", "pto.force_command"])
    law = mbd.port(["pto.position", "pto.velocity", "pto.force"])

    def holds(k: float, c: float, u: float, other: tuple[float, float, float]) -> np.ndarray:
        x, v, force = mbd.get_reals(law)
        assert abs(force - (-k * x - c * v + u)) <= 1e-12 * (abs(k * x) + abs(c * v) + abs(u))
        k0, c0, u0 = other  # the commands before: they would give another force
        assert abs(force - (-k0 * x - c0 * v + u0)) > 1e-3 * (abs(k * x) + abs(c * v) + abs(u))
        return master.outputs[MBD].copy()

    run(master, scene, 40, h)
    holds(0.0, 850.0, 0.0, (2e3, 3000.0, 40.0))
    mbd.set_reals(commands, np.array([2e3, 3000.0, 40.0]))
    run(master, scene, 1, h, 41)
    holds(2e3, 3000.0, 40.0, (0.0, 850.0, 0.0))
    checkpoint = master.checkpoint()
    mbd.set_reals(commands, np.array([0.0, 5000.0, -25.0]))
    run(master, scene, 1, h, 42)
    first = holds(0.0, 5000.0, -25.0, (2e3, 3000.0, 40.0))
    master.restore(checkpoint)  # the commands of the checkpoint: 2e3, 3000, 40
    mbd.set_reals(commands, np.array([0.0, 5000.0, -25.0]))  # the values the slave saw last, set again
    run(master, scene, 1, h, 42)
    np.testing.assert_array_equal(holds(0.0, 5000.0, -25.0, (2e3, 3000.0, 40.0)), first)
    master.restore(checkpoint)  # nothing set after the restore: the restored commands act
    run(master, scene, 1, h, 42)
    holds(2e3, 3000.0, 40.0, (0.0, 5000.0, -25.0))
    mbd.set_reals(commands, np.array([0.0, 7000.0, 10.0]))
    in_memory = mbd.get_state()  # in memory (getFMUstate): commands set, not yet used by a step
    run(master, scene, 1, h, 43)
    holds(0.0, 7000.0, 10.0, (2e3, 3000.0, 40.0))
    mbd.set_reals(commands, np.array([2e3, 3000.0, 40.0]))
    run(master, scene, 1, h, 44)
    holds(2e3, 3000.0, 40.0, (0.0, 7000.0, 10.0))
    mbd.set_state(in_memory)  # setFMUstate: the commands set before it was taken act at the next step
    mbd.free_state(in_memory)
    run(master, scene, 1, h, 44)
    holds(0.0, 7000.0, 10.0, (2e3, 3000.0, 40.0))
    master.terminate()


def test_linearised_force_inputs_set_through_fmi_act_from_the_next_step_also_after_a_restore(barge) -> None:
    """The linearised force interface's inputs (F0, ...), left at zero by a master that uses the force F only, are
    looked at after a set_real that writes them or a restore: a constant F0 set through FMI moves the barges as the
    same force through the held input F does (two routes to one force: the same motion within the Newton
    tolerance), from the step after it is set, also after a restore to a state without it; a restore to a state
    without it, with nothing set after, gives the motion without it."""
    _, fmus = barge
    heave = np.array([0.0, 150.0, 0.0, 0.0, 0.0, 0.0])  # barge1 heave (inputs ordered as the multibody's DOFs)

    def start():  # the multibody FMU alone, in process, its force inputs driven here
        comp = make_components({MBD: fmus[MBD]}, in_process=True)[MBD]
        comp.setup(0.0, 10.0)
        comp.enter_initialization()
        comp.exit_initialization()
        return comp

    def motion(comp, steps: int, first: int, force: np.ndarray, f0: np.ndarray | None = None) -> np.ndarray:
        forces, out = comp.port([v.name for v in comp.model_description.modelVariables if ".F[" in v.name]), []
        if f0 is not None:
            comp.set_reals(comp.port([v.name for v in comp.model_description.modelVariables
                                      if ".F0[" in v.name]), f0)
        for k in range(first, first + steps):
            comp.set_reals(forces, force)
            comp.do_step(k * 0.02, 0.02)
            out.append(comp.get_reals(comp.port([v.name for v in comp.model_description.modelVariables
                                                 if ".x[" in v.name])))
        return np.array(out)

    by_f = start()
    motion(by_f, 10, 0, np.zeros(6))
    reference = motion(by_f, 10, 10, heave)
    assert np.abs(reference).max() > 1e-4  # the force moves the barges
    by_f0 = start()
    motion(by_f0, 10, 0, np.zeros(6))
    state = by_f0.get_state()
    np.testing.assert_allclose(motion(by_f0, 10, 10, np.zeros(6), f0=heave), reference, rtol=0, atol=1e-9)
    by_f0.set_state(state)  # before F0 was set: F0 = 0 restored
    free = motion(by_f0, 10, 10, np.zeros(6))
    assert np.abs(free - reference).max() > 1e-4  # without the force
    by_f0.set_state(state)
    np.testing.assert_allclose(motion(by_f0, 10, 10, np.zeros(6), f0=heave), reference, rtol=0, atol=1e-9)
    by_f0.free_state(state)
    for comp in (by_f, by_f0):
        comp.terminate()
