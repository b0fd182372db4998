"""The compiled path of the multibody model (mbd_fmu.fast, mbd_fmu.kernels) against the Python path.

The physics of both paths is tested by the mechanism and element tests (they run on the compiled path
whenever the model is covered); here: the two paths take the same steps for every joint kind, closed
and redundant loops, point masses and every compiled element kind (to the Newton tolerance: they
evaluate the same equations in a different order of operations), models the compiled path does not
cover fall back to the Python path, and the compiled kernels are reused from the on-disk cache by
sources in another folder (an FMU's extraction folder).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mbd_fmu.bodies import RigidBody
from mbd_fmu.coordinates import Angle, Distance, RotationComponent, Slide
from mbd_fmu.fast import compiled_model, unsupported
from mbd_fmu.force_elements import CoordinateSpringDamper, CoulombFriction, PtoLaw, Rope
from mbd_fmu.formulations import Settings
from mbd_fmu.joints import Driver, Harmonic, Joint
from mbd_fmu.model import MultibodyModel
from mbd_fmu.moorings import CatenaryLine, LinearMooring
from mbd_fmu.simulator import MultibodySimulator
from mbd_fmu.spec import coordinate

from .mechanisms import G, bricard, double_four_bar, hexagon_loop, point_pendulum, rod, rod_pendulum

ROOT = Path(__file__).resolve().parent.parent
KINDS = ("fixed", "revolute", "prismatic", "cylindrical", "universal", "spherical", "planar", "distance")


def two_bodies(kind: str) -> tuple[MultibodyModel, object, np.ndarray]:
    """A floating body on a mooring and a rod hanging from it by a joint of ``kind``, a nonlinear PTO between
    them, released moving (every compiled element kind, rotations about all axes)."""
    top = RigidBody("top", 50.0, np.diag([4.0, 5.0, 6.0]), np.array([0.0, 0.0, 0.0]))
    link = rod("link", [0.3, 0.1, -1.0], [0.3, 0.1, -1.0], mass=5.0, length=1.5)
    joint = Joint("j", kind, "top", "link", (0.0, 0.0, -0.2), (0.3, 1.0, 0.2), (1.0, 0.0, -1.5) if kind == "universal"
                  else None, (0.15, 0.05, -0.5) if kind == "distance" else None)
    model = MultibodyModel([top, link], [joint], gravity=(0, 0, -G), static_loads={"top": [0, 0, 55 * G, 0, 0, 0]})
    k = np.diag([2e3, 2e3, 5e3, 3e3, 3e3, 1e3])
    on_axis = np.array([-0.15, -0.05, 0.5])  # a point of the rod's axis (its spin inertia is tiny)
    pto = CoordinateSpringDamper("pto", Distance(0, 1, np.array([0.2, 0, 0.1]), on_axis), 300.0, 40.0, 5.0, 1.2,
                                 PtoLaw(friction=3.0, quadratic=10.0, force_limit=400.0))
    slide = CoordinateSpringDamper("slide", Slide(model.ground, 1, np.array([1.0, 0, 0]), model.cg[1].copy(),
                                                  np.zeros(3)), 50.0, 5.0)
    model.elements = [LinearMooring("m", 0, k, 0.1 * k, model.cg[0].copy()), pto, slide]
    if kind in ("revolute", "cylindrical", "planar"):
        angle = next(c for c in model.joints[0].coordinates if isinstance(c, Angle))
        model.elements.append(CoordinateSpringDamper("rot", angle, 20.0, 2.0, 0.0, 0.0))
    v = np.zeros(model.n)
    v[model.slot_of("top", 3)], v[model.slot_of("top", 2)] = 0.3, 0.2
    return model, model.reference.copy(), v


def device_elements() -> tuple[MultibodyModel, object, np.ndarray]:
    """The element kinds of the arrays' link arms (from branch speed2's test, without its catenary lines): a float
    on a hydrostatic-like spring, a link arm on a spherical joint with penalty PTOs on the relative pitch and yaw
    (rotation-vector components, one with the nonlinear law) and Coulomb friction on the relative roll, a bushing
    on a relative translation, and a 3-DOF point mass hanging from the arm's tip by a tension-only rope that is
    taut at the start and goes slack; released moving."""
    buoy = RigidBody("float", 800.0, np.diag([300.0, 320.0, 400.0]), np.array([0.0, 0.0, -0.2]))
    arm = rod("arm", [1.0, 0.0, -0.2], [1.0, 0.0, 0.0], mass=50.0, length=1.6, spin=0.01)
    weight = RigidBody("weight", 30.0, np.eye(3), np.array([1.8, 0.0, -1.5]), dofs=(0, 1, 2), point_mass=True)
    joint = Joint("ball", "spherical", "float", "arm", (0.2, 0.0, -0.2))
    model = MultibodyModel([buoy, arm, weight], [joint], gravity=(0, 0, -G),
                           static_loads={"float": [0, 0, 900 * G, 0, 0, 0]})
    roll, pitch, yaw = model.joints[0].coordinates
    hydrostatics = np.diag([0.0, 0.0, 3e4, 2e4, 2e4, 0.0])
    sway = coordinate(model, {"kind": "relative", "body1": "float", "body2": "arm", "position": [1.0, 0.0, -0.2],
                              "dof": 1})
    model.elements = [
        LinearMooring("hydrostatics", 0, hydrostatics, None, model.cg[0].copy()),
        CoordinateSpringDamper("pto_pitch", pitch, 2e3, 500.0, 10.0, 0.0, PtoLaw(friction=5.0, force_limit=800.0)),
        CoordinateSpringDamper("pto_yaw", yaw, 1e3, 300.0),
        CoulombFriction("roll_friction", roll, 20.0, 0.05),
        CoordinateSpringDamper("bushing.sway", sway, 5e3, 50.0),
        Rope("rope", Distance(1, 2, np.array([0.8, 0.0, 0.0]), np.zeros(3)), 2e4, 50.0, 1.25),
    ]
    assert isinstance(pitch, RotationComponent) and isinstance(sway, Slide)
    v = np.zeros(model.n)
    v[model.slot_of("float", 2)], v[model.slot_of("float", 3)], v[model.slot_of("float", 5)] = 0.2, 0.1, 0.05
    v[model.slot_of("arm", 4)] = -0.3
    return model, model.reference.copy(), v


def run(build, formulation: str, compiled: bool, steps: int, h: float, inputs: bool = True, each=None):
    out = build()
    model, pose = out[0], out[1]
    v = out[2] if len(out) > 2 else np.zeros(model.n)
    sim = MultibodySimulator(model, Settings(formulation, spectral_radius=0.8))
    if not compiled:
        sim.formulation.python_path = True
    sim.start(pose, v)
    forced = np.array([dof < 3 for _, dof in model.coordinates])  # wave-like forces on the translations
    for k in range(steps):
        f = forced * np.sin(3.0 * k * h + np.arange(model.n)) if inputs else None
        sim.advance(h, f)
        if each is not None:
            each(sim)
    return sim


def assert_same_state(a, b) -> None:
    """Formulations ``a`` (compiled) and ``b`` (Python) at the same pose, velocities and multipliers: each step
    converges to 1e-10 of max(1 m, largest velocity) on either path."""
    assert np.max(np.abs(a.pose.r - b.pose.r)) < 1e-8
    assert np.max(np.abs(a.pose.R - b.pose.R)) < 1e-8
    assert np.max(np.abs(a.v - b.v)) < 1e-7 * max(1.0, np.max(np.abs(b.v)))
    assert np.max(np.abs(a.lam - b.lam)) < 1e-6 * max(1.0, np.max(np.abs(b.lam)))


@pytest.mark.parametrize("formulation", ["index3", "index1", "nullspace"])
@pytest.mark.parametrize("kind", KINDS)
def test_compiled_and_python_paths_take_the_same_steps(kind, formulation) -> None:
    fast = run(lambda: two_bodies(kind), formulation, True, 40, 0.01)
    slow = run(lambda: two_bodies(kind), formulation, False, 40, 0.01)
    assert fast.formulation.compiled is not None and slow.formulation.compiled is None
    a, b = fast.formulation, slow.formulation
    assert_same_state(a, b)  # 40 steps
    assert fast.energy()["balance"] == pytest.approx(slow.energy()["balance"], abs=1e-6 * max(1.0, slow.work))


@pytest.mark.parametrize("formulation", ["index3", "index1", "nullspace"])
def test_ropes_friction_and_rotation_components_take_the_same_steps_on_both_paths(formulation) -> None:
    """Ropes, Coulomb friction and spring-dampers/PTOs on rotation-vector components (the arrays' elements):
    same steps, energy terms and element outputs on both paths; the rope goes slack during the run, so both of
    its branches are stepped."""
    tension = []
    fast = run(device_elements, formulation, True, 40, 0.01,
               each=lambda sim: tension.append(sim.compiled_outputs()["spring_forces"][-1]))
    slow = run(device_elements, formulation, False, 40, 0.01)
    assert fast.formulation.compiled is not None and slow.formulation.compiled is None
    a, b = fast.formulation, slow.formulation
    assert_same_state(a, b)
    ea, eb = fast.energy(), slow.energy()
    scale = max(1.0, abs(slow.work), abs(slow.dissipated))
    for key in ("kinetic", "potential", "dissipated", "external_work", "balance"):
        assert ea[key] == pytest.approx(eb[key], abs=1e-6 * scale), key
    # the kernel's element outputs (rope tension, forces on the coordinates) against the Python elements'
    compiled = np.concatenate(fast.element_outputs()[1:])
    k = slow.kin
    python = np.array([e.output(k)[0] for e in slow.model.elements[1:]])
    assert np.allclose(compiled, python, rtol=1e-6, atol=1e-6 * np.max(np.abs(python)))
    assert np.array_equal(compiled, fast.compiled_outputs()["spring_forces"])  # (not the Python elements' values)
    for x, y in zip(fast.element_outputs(), slow.element_outputs(), strict=True):  # the mooring's wrench too
        assert x.shape == y.shape and np.allclose(x, y, rtol=1e-6, atol=1e-6 * max(1.0, np.max(np.abs(y))))
    assert min(tension) == 0.0 and max(tension) > 0.0  # the rope was taut and slack (both branches)
    for (q1, r1), (q2, r2) in zip(fast.joint_coordinates(), slow.joint_coordinates(), strict=True):
        assert np.allclose(q1, q2, atol=1e-8) and np.allclose(r1, r2, atol=1e-7)


@pytest.mark.parametrize("build", [point_pendulum, rod_pendulum, double_four_bar, hexagon_loop, bricard],
                         ids=["point_mass", "rod", "double_four_bar", "hexagon", "bricard"])
def test_closed_loops_and_point_masses_on_both_paths(build) -> None:
    fast = run(build, "index3", True, 200, 2e-3, inputs=False)
    slow = run(build, "index3", False, 200, 2e-3, inputs=False)
    assert fast.formulation.compiled is not None
    assert np.max(np.abs(fast.formulation.pose.r - slow.formulation.pose.r)) < 1e-8
    assert fast.constraint_violation() < 1e-9


def test_models_the_compiled_path_does_not_cover_run_on_the_python_path() -> None:
    model, pose = rod_pendulum()
    angle = model.joints[0].coordinates[0]
    model.elements = [CoulombFriction("f", angle, 0.5),
                      CatenaryLine("c", 0, np.zeros(3), np.array([5.0, 0.0, -3.0]), 7.0, 10.0, 1e7)]
    model.drivers = []
    assert [s.split(" (")[0] for s in unsupported(model)] == ["force element 'c'"]
    assert compiled_model(model) is None
    sim = MultibodySimulator(model, Settings("index3"))
    sim.start(pose, np.zeros(model.n))
    sim.advance(0.01)
    assert sim.formulation.compiled is None and sim.time == pytest.approx(0.01)
    model2, pose2 = rod_pendulum()
    model2.drivers.append(Driver("d", angle, Harmonic(0.1, 1.0)))
    model2.m += 1
    assert unsupported(model2) == ["prescribed motion (drivers)"]


def test_no_jit_environment_variable_selects_the_python_path(monkeypatch) -> None:
    monkeypatch.setenv("WEC_COSIM_NO_JIT", "1")
    model, _ = rod_pendulum()
    assert compiled_model(model) is None


def test_kernels_are_reused_from_the_cache_by_sources_in_another_folder(tmp_path) -> None:
    """An FMU runs the package from a fresh extraction folder: the kernels compiled for the same sources are
    loaded from the on-disk cache (no new cache entries appear), not compiled again."""
    cache = tmp_path / "cache"
    script = ("import numpy as np, sys; sys.path.insert(0, sys.argv[1]); import mbd_fmu.kernels as k;"
              "assert k.__file__.startswith(sys.argv[1]), k.__file__;"
              "print(k.exp_so3(0.1, 0.2, 0.3)[0, 0])")
    env = dict(os.environ, WEC_COSIM_CACHE=str(cache))
    env.pop("WEC_COSIM_NO_JIT", None)
    env.pop("WEC_COSIM_NUMBA_CACHE", None)
    outputs = []
    entries = []
    for name in ("first", "second"):
        folder = tmp_path / name
        shutil.copytree(ROOT / "mbd_fmu", folder / "mbd_fmu", ignore=shutil.ignore_patterns("__pycache__"))
        proc = subprocess.run([sys.executable, "-c", script, str(folder)], capture_output=True, text=True, env=env,
                              timeout=600)
        assert proc.returncode == 0, proc.stderr
        outputs.append(proc.stdout)
        entries.append(sorted(p.name for p in (cache / "numba").rglob("*") if p.is_file()))
    assert outputs[0] == outputs[1]
    assert any(e.endswith(".nbi") for e in entries[0])
    assert entries[1] == entries[0]


def test_null_space_kernels_cache_follows_the_kernels_they_call(tmp_path, monkeypatch) -> None:
    """nullspace_kernels.py compiles kernels.py's functions into its own cached machine code: its cache key changes
    when kernels.py changes (else a stale cache would run old kernel code on a new plan layout); kernels.py's own
    key does not depend on nullspace_kernels.py."""
    from fmu_base import _jit

    if not _jit.AVAILABLE:
        pytest.skip("numba not installed")
    monkeypatch.setenv("WEC_COSIM_CACHE", str(tmp_path / "cache"))
    monkeypatch.delenv("WEC_COSIM_NUMBA_CACHE", raising=False)
    stamps = []
    for name, extra in (("a", ""), ("b", "\n# changed\n")):
        folder = tmp_path / name / "mbd_fmu"
        folder.mkdir(parents=True)
        for f in ("kernels.py", "nullspace_kernels.py"):
            shutil.copy(ROOT / "mbd_fmu" / f, folder / f)
        with open(folder / "kernels.py", "a") as fh:
            fh.write(extra)
        stamps.append([_jit._ContentLocator(str(folder / f)).get_source_stamp()
                       for f in ("kernels.py", "nullspace_kernels.py")])
    assert stamps[0][0] != stamps[1][0] and stamps[0][1] != stamps[1][1]
    with open(tmp_path / "b" / "mbd_fmu" / "nullspace_kernels.py", "a") as fh:
        fh.write("\n# changed\n")
    assert _jit._ContentLocator(str(tmp_path / "b" / "mbd_fmu" / "kernels.py")).get_source_stamp() == stamps[1][0]


def test_host_input_force_keeps_the_compiled_path_until_a_host_switches_it_on() -> None:
    """The multibody FMU appends the linearised force interface's element after the start. With its inputs at
    zero (our own masters) it adds nothing and the compiled path stays; once a host sets it, the model is looked
    at again and runs on the Python path (which integrates the element's tangent); both take the same step as
    a model built the same way on the Python path from the start."""
    from mbd_fmu.force_elements import LinearisedInputForce

    def build():
        model, pose, v = two_bodies("revolute")
        sim = MultibodySimulator(model, Settings("index3", spectral_radius=0.8))
        sim.start(pose, v)
        element = LinearisedInputForce(np.array([0]), np.array([2]), model.cg)
        model.elements.append(element)
        return sim, element

    sim, element = build()
    assert sim.formulation.compiled is not None
    sim.advance(0.01, np.zeros(sim.model.n))
    restart = element.set(sim.formulation.t, np.array([1.0e3]), np.zeros(1), np.array([[-2.0e4]]), np.zeros((1, 1)))
    assert restart and element.active
    sim.advance(0.01, restart=True)
    assert sim.formulation.compiled is None
    ref, ref_element = build()
    ref.formulation.python_path = True
    ref.advance(0.01, np.zeros(ref.model.n))
    ref_element.set(ref.formulation.t, np.array([1.0e3]), np.zeros(1), np.array([[-2.0e4]]), np.zeros((1, 1)))
    ref.advance(0.01, restart=True)
    np.testing.assert_allclose(sim.formulation.v, ref.formulation.v, rtol=1e-8, atol=1e-10)
