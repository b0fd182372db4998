"""Joints, drivers, force elements, moorings and the linearisation against closed-form physics."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from mbd_fmu.assembly import analyse
from mbd_fmu.bodies import RigidBody
from mbd_fmu.force_elements import CoordinateSpringDamper, CoulombFriction, PtoLaw, Rope
from mbd_fmu.formulations import Settings
from mbd_fmu.joints import JOINT_DOF, Driver, Harmonic, Joint
from mbd_fmu.linearize import linearize
from mbd_fmu.model import MultibodyModel
from mbd_fmu.moorings import CatenaryLine, LinearMooring, catenary_tensions
from mbd_fmu.simulator import MultibodySimulator
from mbd_fmu.spec import coordinate

from . import mechanisms as mech

G = mech.G


def block(name="b", mass=2.0, cg=(0.0, 0.0, 0.0), dofs=(0, 1, 2, 3, 4, 5)) -> RigidBody:
    return RigidBody(name, mass, np.diag([0.5, 0.7, 0.9]), np.asarray(cg, float), dofs)


@pytest.mark.parametrize("kind", ["fixed", "revolute", "prismatic", "cylindrical", "universal", "spherical",
                                  "planar", "distance"])
def test_every_joint_kind_removes_its_degrees_of_freedom(kind) -> None:
    extra = {"position2": (0.0, 0.0, -1.0)} if kind == "distance" else {}
    extra |= {"axis2": (1.0, 0.0, 0.0)} if kind == "universal" else {}
    j = Joint("j", kind, None, "b", (0.0, 0.0, 0.0), (0.0, 1.0, 0.0), **extra)
    model = MultibodyModel([block(cg=(0.0, 0.0, -1.0))], [j])
    report = analyse(model, model.reference)
    assert report.dof == JOINT_DOF[kind] and not report.redundant


@pytest.mark.parametrize("kind, index, amplitude", [("revolute", 0, 0.4), ("prismatic", 0, 0.3),
                                                    ("cylindrical", 1, 0.5)])
def test_drivers_prescribe_joint_coordinates(kind, index, amplitude) -> None:
    """A harmonic driver on a joint coordinate: the joint coordinate output follows it to 1e-9, and
    for the revolute joint under gravity the driving torque is the pendulum's m g d sin(theta) + I theta''."""
    model = MultibodyModel([block(cg=(0.5, 0.0, 0.0))], [Joint("j", kind, None, "b", (0, 0, 0), (0, 1, 0))],
                           gravity=(0, 0, -G))
    omega = 2.0
    law = Harmonic(amplitude, omega)
    c = model.joints[0].coordinates[index]
    model.drivers.append(Driver("drive", c, law))
    model.m += 1
    model.kept = np.arange(model.m)
    sim = MultibodySimulator(model, Settings("index3", spectral_radius=0.8))
    v = np.zeros(model.n)
    sim.start(model.reference, v)
    worst = 0.0
    for _ in range(200):
        sim.advance(0.005)
        q, qd = sim.joint_coordinates()[0]
        worst = max(worst, abs(q[index] - law.value(sim.time)))
    assert worst < 1e-9


def test_locked_revolute_joint_holds_the_body_and_carries_the_moment() -> None:
    """Horizontal arm (cg 0.5 m from the hinge) on a locked hinge: no motion, moment m g d about y."""
    model = MultibodyModel([block(cg=(0.5, 0.0, 0.0))],
                           [Joint("j", "revolute", None, "b", (0, 0, 0), (0, 1, 0), locked=True)], gravity=(0, 0, -G))
    sim = MultibodySimulator(model, Settings("index3"))
    sim.start(model.reference, np.zeros(model.n))
    sim.advance(0.5)
    assert np.max(np.abs(model.displacement(sim.formulation.pose))) < 1e-12
    force, moment = sim.reactions()[0]
    np.testing.assert_allclose(force, [0, 0, 2.0 * G], rtol=1e-9)
    np.testing.assert_allclose(moment, [0, -2.0 * G * 0.5, 0], rtol=1e-9, atol=1e-9)


def hanging(element_builder, mass=3.0):
    body = RigidBody("m", mass, np.eye(3), np.array([0.0, 0.0, -1.0]), (2,), point_mass=True)
    model = MultibodyModel([body], gravity=(0, 0, -G))
    model.elements = [element_builder(model)]
    return model


def test_point_to_point_spring_period_and_static_stretch() -> None:
    k, m = 300.0, 3.0
    model = hanging(lambda mo: CoordinateSpringDamper(
        "s", coordinate(mo, {"kind": "points", "body1": None, "point1": [0, 0, 0], "body2": "m",
                             "point2": [0, 0, -1.0]}), k, 0.0, 0.0, 1.0), m)
    lin = linearize(model, model.pose_from_displacement(np.array([[0, 0, -m * G / k, 0, 0, 0]])))
    assert lin.equilibrium_residual < 1e-9
    assert lin.natural_frequencies()[0] == pytest.approx(math.sqrt(k / m), rel=1e-7)


def test_rope_is_slack_in_compression_and_stretches_under_the_weight() -> None:
    k, m = 5000.0, 3.0
    model = hanging(lambda mo: Rope("r", coordinate(mo, {"kind": "points", "body1": None, "point1": [0, 0, 0],
                                                        "body2": "m", "point2": [0, 0, -1.0]}), k, 0.0, 1.0), m)
    sim = MultibodySimulator(model, Settings("index1"))
    up = model.pose_from_displacement(np.array([[0, 0, 0.2, 0, 0, 0]]))  # rope slack: free fall
    sim.start(up, np.zeros(model.n))
    assert sim.formulation.vdot[0] == pytest.approx(-G, rel=1e-12)
    down = model.pose_from_displacement(np.array([[0, 0, -0.01, 0, 0, 0]]))  # stretched 1 cm
    sim.start(down, np.zeros(model.n))
    assert sim.formulation.vdot[0] == pytest.approx(-G + k * 0.01 / m, rel=1e-12)
    assert model.elements[0].output(sim.kin)[0] == pytest.approx(k * 0.01)


@pytest.mark.parametrize("push, moves", [(0.8, False), (1.5, True)])
def test_coulomb_friction_sticks_below_and_slides_above_the_friction_force(push, moves) -> None:
    """Block on a prismatic joint with friction F_c = 10 N, pushed by push * F_c."""
    m, fc = 2.0, 10.0
    model = MultibodyModel([block(mass=m)], [Joint("slide", "prismatic", None, "b", (0, 0, 0), (1, 0, 0))])
    model.elements = [CoulombFriction("f", coordinate(model, {"kind": "joint", "joint": "slide"}), fc, 1e-3)]
    sim = MultibodySimulator(model, Settings("index3", spectral_radius=0.5))
    sim.start(model.reference, np.zeros(model.n))
    inputs = np.zeros(model.n)
    inputs[model.coordinates.index(("b", 0))] = push * fc
    for _ in range(50):
        sim.advance(0.01, inputs)
    half = sim.joint_coordinates()[0][1][0]
    for _ in range(50):
        sim.advance(0.01, inputs)
    speed = sim.joint_coordinates()[0][1][0]
    if moves:  # steady sliding: constant acceleration (push - 1) F_c / m once the friction is saturated
        assert speed - half == pytest.approx((push - 1) * fc / m * 0.5, rel=1e-6)
    else:
        assert speed == pytest.approx(1e-3 * math.atanh(push), rel=1e-6)  # the regularised law's creep speed


def test_bushing_on_a_spherical_joint_gives_the_relative_pitch_frequency() -> None:
    """Seed 000's node - link arm pair: spherical joint plus a relative pitch/yaw penalty element.
    Arm (rod, 1 m) pivoting about its end on a fixed node: pitch frequency sqrt(k / (m L^2 / 3))."""
    k, m = 50.0, 4.0
    node = block("node", 100.0, (0, 0, 0), ())
    arm = mech.rod("arm", (1.0, 0, 0), (1, 0, 0), m, 2.0)
    model = MultibodyModel([node, arm], [Joint("ball", "spherical", "node", "arm", (0, 0, 0))])
    model.elements = [CoordinateSpringDamper(f"pto.{d}", coordinate(model, {"kind": "relative", "body1": "node",
                      "body2": "arm", "position": [0, 0, 0], "dof": d}), k, 0.0) for d in (4, 5)]
    freqs = linearize(model).natural_frequencies()
    expected = math.sqrt(k / (m * 2.0**2 / 3))
    assert np.sum(np.isclose(freqs, expected, rtol=1e-7)) == 2  # pitch and yaw


def test_linear_mooring_heave_and_pitch_frequencies_and_energy() -> None:
    m = 1000.0
    k = np.diag([1e3, 1e3, 4e4, 2e3, 3e3, 1e3])
    body = RigidBody("float", m, np.diag([100.0, 150.0, 200.0]), np.zeros(3))
    model = MultibodyModel([body])
    model.elements = [LinearMooring("moor", 0, k, None, np.zeros(3))]
    freqs = linearize(model).natural_frequencies()
    expected = np.sort(np.sqrt(np.diag(k) / np.array([m, m, m, 100.0, 150.0, 200.0])))
    np.testing.assert_allclose(freqs, expected, rtol=1e-7)
    sim = MultibodySimulator(model, Settings("index3", spectral_radius=1.0))
    sim.start(model.pose_from_displacement(np.array([[0.3, 0, 0.2, 0.2, -0.3, 0.1]])), np.zeros(6))
    for _ in range(400):
        sim.advance(0.02)
    e = sim.energy()
    assert abs(e["balance"]) < 2e-3 * (e["kinetic"] + e["potential"])  # large rotations: O(h^2) energy error


def catenary_by_quadrature(h: float, v: float, length: float, w: float, ea: float) -> tuple[float, float]:
    """Fairlead position relative to the anchor from the tensions, by integrating the elastic line
    (tension T(s) = sqrt(H^2 + (V - w (L - s))^2), stretch T/EA) over the suspended length; the part
    lying on the sea bed (V < w L) is straight and carries H."""
    lying = max(0.0, length - v / w)

    def t(s):
        return math.hypot(h, v - w * (length - s))

    x = quad(lambda s: h / t(s) * (1 + t(s) / ea), lying, length, epsabs=1e-13, epsrel=1e-13)[0]
    z = quad(lambda s: (v - w * (length - s)) / t(s) * (1 + t(s) / ea), lying, length, epsabs=1e-13, epsrel=1e-13)[0]
    return x + lying * (1 + h / ea), z


@pytest.mark.parametrize("x, z", [(80.0, 50.0), (95.0, 20.0), (60.0, 70.0)])
def test_catenary_tensions_reproduce_the_line_geometry(x, z) -> None:
    length, w, ea = 110.0, 700.0, 5e8
    h, v = catenary_tensions(x, z, length, w, ea)
    xq, zq = catenary_by_quadrature(h, v, length, w, ea)
    assert xq == pytest.approx(x, abs=1e-6) and zq == pytest.approx(z, abs=1e-6)


def test_catenary_line_pulls_the_body_towards_the_anchor() -> None:
    body = RigidBody("buoy", 5e4, np.diag([1e5, 1e5, 1e5]), np.zeros(3))
    model = MultibodyModel([body])
    line = CatenaryLine("line", 0, np.array([0.0, 0, -2.0]), np.array([-90.0, 0, -50.0]), 110.0, 700.0, 5e8)
    model.elements = [line]
    f = model.forces_full(model.kin(model.reference, np.zeros(6)))[:6]
    h, v = catenary_tensions(90.0, 48.0, 110.0, 700.0, 5e8)
    np.testing.assert_allclose(f[:3], [-h, 0, -v], rtol=1e-12)
    np.testing.assert_allclose(f[3:], np.cross([0, 0, -2.0], [-h, 0, -v]), rtol=1e-12)


def test_linearised_pendulum_frequency() -> None:
    """Point pendulum about its hanging equilibrium: sqrt(g / L) (the geometric stiffness of the rod force)."""
    model, _ = mech.point_pendulum()
    lin = linearize(model)
    assert lin.null_space.shape == (2, 1)
    assert lin.natural_frequencies()[0] == pytest.approx(math.sqrt(G / 1.0), rel=1e-7)


def test_joint_pto_force_command_sets_the_static_deflection() -> None:
    """Controllable PTO on a prismatic joint (k = 500 N/m): a command u = 20 N deflects it by u / k."""
    model = MultibodyModel([block()], [Joint("slide", "prismatic", None, "b", (0, 0, 0), (1, 0, 0))])
    pto = CoordinateSpringDamper("pto", coordinate(model, {"kind": "joint", "joint": "slide"}), 500.0, 80.0)
    model.elements = [pto]
    sim = MultibodySimulator(model, Settings("nullspace"), ptos=[pto])
    sim.start(model.reference, np.zeros(model.n))
    sim.set_pto_commands([500.0], [80.0], [20.0])
    for _ in range(300):
        sim.advance(0.02)
    position, velocity, force, power = sim.pto_outputs()[0]
    assert position == pytest.approx(20.0 / 500.0, rel=1e-6)
    assert abs(force) < 1e-6 and abs(power) < 1e-6


@pytest.mark.parametrize("law", [Harmonic(0.7, 2.0, 0.3, 0.2), "table"])
def test_velocity_level_drivers_integrate_the_law_exactly(law) -> None:
    """A prescribed velocity becomes the position law start + integral of the velocity (checked by quadrature)."""
    from mbd_fmu.joints import Table

    if law == "table":
        law = Table([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 0.0, 2.0])
    position = law.integral(0.5, 3.0)
    for t in (0.2, 1.7, 2.9, 4.0):
        assert position.value(t) == pytest.approx(3.0 + quad(law.value, 0.5, t, epsabs=1e-13, limit=200)[0],
                                                  abs=1e-9)
        assert position.d1(t) == pytest.approx(law.value(t), abs=1e-12)


def test_rotary_spring_about_a_revolute_axis() -> None:
    """Disc on a revolute joint through its cg with a torsion spring k: frequency sqrt(k / I_axis)."""
    k = 80.0
    model = MultibodyModel([block()], [Joint("axle", "revolute", None, "b", (0, 0, 0), (0, 0, 1))])
    model.elements = [CoordinateSpringDamper("torsion", coordinate(model, {"kind": "joint", "joint": "axle"}), k)]
    assert linearize(model).natural_frequencies()[0] == pytest.approx(math.sqrt(k / 0.9), rel=1e-7)


def test_nonlinear_pto_law_derivatives_and_energy_balance() -> None:
    """A hydraulic-like, saturated PTO law on a sprung block: the analytic derivatives match central
    differences, and the energy balance (stored + kinetic + dissipated by the law) closes to the
    integrator's O(h^2) error over a free decay; the absorbed power equals the dissipation here (u = 0)."""
    law = PtoLaw(friction=5.0, quadratic=40.0, force_limit=30.0, velocity_scale=0.05)
    model = MultibodyModel([block()], [Joint("slide", "prismatic", None, "b", (0, 0, 0), (1, 0, 0))])
    pto = CoordinateSpringDamper("pto", coordinate(model, {"kind": "joint", "joint": "slide"}), 200.0, 3.0, law=law)
    model.elements = [pto]
    for x, v in [(0.01, -0.2), (0.2, 0.03), (-0.05, 0.5)]:
        dx, dv = pto.law_derivatives(x, v)
        h = 1e-6
        assert dx == pytest.approx((pto.law_force(x + h, v) - pto.law_force(x - h, v)) / (2 * h), rel=1e-6)
        assert dv == pytest.approx((pto.law_force(x, v + h) - pto.law_force(x, v - h)) / (2 * h), rel=1e-6)
    assert abs(pto.law_force(1.0, 0.0)) < law.force_limit  # the saturation bounds the spring force too
    sim = MultibodySimulator(model, Settings("index3", spectral_radius=1.0), ptos=[pto])
    sim.start(model.pose_from_displacement(np.array([[0.3, 0, 0, 0, 0, 0]])), np.zeros(model.n))
    e0 = sim.energy()["potential"]
    for _ in range(500):
        sim.advance(0.005)
    e = sim.energy()
    assert e["dissipated"] > 0.5 * e0  # the law took most of the energy out
    assert abs(e["balance"]) < 1e-3 * e0


def test_relative_rotation_rate_is_the_jacobian_times_the_velocities() -> None:
    """``RotationComponent.rate`` (what PTOs and bushings use, without the curvature term) returns the value
    and Jacobian of ``evaluate`` and the rate ``jac . w``; the rate also equals the finite-difference
    derivative of the value along the motion (a large relative rotation, all three components)."""
    from mbd_fmu.rotations import exp_so3

    node = RigidBody("node", 10.0, np.diag([1.0, 2.0, 3.0]), np.zeros(3))
    arm = mech.rod("arm", (1.0, 0, 0), (1, 0, 0), 4.0, 2.0)
    model = MultibodyModel([node, arm], [Joint("ball", "spherical", "node", "arm", (0, 0, 0))])
    pose = model.reference.copy()
    pose.R[0] = exp_so3(np.array([0.3, -0.5, 0.2]))
    pose.R[1] = exp_so3(np.array([-0.4, 0.9, 0.6]))
    v = np.array([0.1, -0.2, 0.3, 0.7, -0.4, 0.5, -0.3, 0.2, 0.1, -0.6, 0.8, 0.2])
    for k in range(3):
        c = model.joints[0].coordinates[k]
        value, rate, jac = c.rate(model.kin(pose, v))
        ref_value, ref_jac, _ = c.evaluate(model.kin(pose, v))
        assert value == ref_value and np.array_equal(jac, ref_jac)
        h = 1e-6
        ahead = c.rate(model.kin(pose.retract(model.full(h * v)), v))[0]
        behind = c.rate(model.kin(pose.retract(model.full(-h * v)), v))[0]
        assert rate == pytest.approx((ahead - behind) / (2 * h), rel=1e-6)
