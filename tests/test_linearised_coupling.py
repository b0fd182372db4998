"""The linearised force interface (hydro_fmu.linearisation): exact derivatives of the discrete
hydrodynamic model, exact integration of an affine force by the multibody models, and the
coupled scheme's second order under a plain fixed-step host (in tests/test_masters.py, against
the monolithic reference)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydro_fmu.drag import ViscousCoefficients
from hydro_fmu.model import HydroModel, HydroOptions
from hydro_fmu.radiation import RadiationMemory
from mbd_fmu.bodies import RigidBody
from mbd_fmu.force_elements import LinearisedInputForce
from mbd_fmu.linear_system import LinearMultibodySystem
from mbd_fmu.spec import build_simulator
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS


@pytest.fixture(scope="module")
def cylinder():
    s = load_scenario(SCENARIOS / "cylinder_regular.toml")
    return load_scene(s, log=None)


def _model(scene, method: str = "convolution", viscous: ViscousCoefficients | None = None) -> HydroModel:
    s = scene.scenario
    sea = scene.sea()
    options = HydroOptions(radiation_method=method, viscous=viscous)
    return HydroModel(scene.hdb, scene.hydro_bodies, [[2]], sea.components, sea.ramp, 0.1, s.hydro.irf_duration,
                      scene.switches(), options)


@pytest.mark.parametrize("q", [1, 3])
def test_instantaneous_damping_is_the_weight_of_the_current_velocity(q) -> None:
    rng = np.random.default_rng(1)
    kernel = rng.normal(size=(12, 2, 2))
    memory = RadiationMemory(kernel, 0.05)
    for _ in range(5):
        memory.advance(rng.normal(size=2), q)
    d = memory.instantaneous_damping()
    v = rng.normal(size=2)
    np.testing.assert_allclose(memory.force(v) - memory.force(np.zeros(2)), d @ v, rtol=1e-12, atol=1e-12)
    if q == 1:
        np.testing.assert_allclose(d, kernel[0] * 0.05 / 2, rtol=1e-15)


@pytest.mark.parametrize("method", ["convolution", "state_space"])
def test_affine_model_is_the_force_and_its_constant_does_not_depend_on_the_inputs(cylinder, method) -> None:
    """Linear hydrodynamics: F0 + dF_dx x + dF_dv v equals the force for any (x, v), so F0 is the same whichever
    motion sample a host handed the FMU (the reason a plain host's ordering no longer matters)."""
    model = _model(cylinder, method)
    pattern = cylinder.coupling_pattern()
    assert pattern.stiffness == ((0, 0),) and pattern.damping == ((0, 0),)
    rng = np.random.default_rng(2)
    t = 0.0
    for _ in range(30):
        model.advance(t, 0.1, rng.normal(size=1))
        t += 0.1
    constants = []
    for _ in range(3):
        x, v = rng.normal(size=1), rng.normal(size=1)
        a = model.affine(t, x, v, pattern)
        total = model.forces(t, x, v).total
        np.testing.assert_allclose(a.constant + a.dfdx @ x + a.dfdv @ v, total, rtol=1e-12)
        constants.append(a.constant)
    np.testing.assert_allclose(constants[1:], constants[:1] * 2, rtol=1e-12)
    c = cylinder.hdb.hydrostatic_stiffness[0][2, 2]
    np.testing.assert_allclose(a.dfdx, [[-c]], rtol=1e-12)
    assert a.dfdv[0, 0] < 0  # radiation takes energy out


def test_viscous_tangent_is_the_derivative_of_the_drag(cylinder) -> None:
    model = _model(cylinder, viscous=ViscousCoefficients(np.array([1e3]), np.array([5e4])))
    pattern = cylinder.coupling_pattern()
    v, eps = np.array([0.7]), 1e-6
    a = model.affine(0.0, np.zeros(1), v, pattern)
    fd = (model.forces(0.0, np.zeros(1), v + eps).total - model.forces(0.0, np.zeros(1), v - eps).total) / (2 * eps)
    np.testing.assert_allclose(a.dfdv[0, 0], fd[0], rtol=1e-7)


def test_excitation_rate_is_its_time_derivative(cylinder) -> None:
    """The exact rate the hydro FMU publishes (ramp included) against a central difference of the force."""
    model = _model(cylinder)
    for t in (3.0, 17.3, 25.0):  # inside and after the 20 s ramp
        eps = 1e-5
        fd = (model.excitation(t + eps) - model.excitation(t - eps)) / (2 * eps)
        np.testing.assert_allclose(model.excitation.rate(t), fd, rtol=1e-6)


def _oscillator_response(m: float, c: float, k: float, f0: float, r: float, t: float) -> float:
    """x(t) of m x'' + c x' + k x = f0 + r t from rest (underdamped): particular a + b t plus the free part."""
    b = r / k
    a = (f0 - c * b) / k
    w0 = math.sqrt(k / m)
    zeta = c / (2 * math.sqrt(k * m))
    wd = w0 * math.sqrt(1 - zeta**2)
    big_a = -a
    big_b = (zeta * w0 * big_a - b) / wd
    return a + b * t + math.exp(-zeta * w0 * t) * (big_a * math.cos(wd * t) + big_b * math.sin(wd * t))


def test_linear_model_integrates_an_affine_force_exactly() -> None:
    """m x'' = F0 + r t + dF_dx x + dF_dv v stepped by the matrix exponential equals the closed form."""
    m, k, c, f0, r = 2.0e3, 8.0e4, 1.5e3, 3.0e3, -400.0
    body = RigidBody("b", m, np.eye(3), np.zeros(3), (2,))
    system = LinearMultibodySystem([body], [])
    system.set_force_tangents([("b", 2)], np.array([[-k]]), np.array([[-c]]))
    h, t = 0.1, 0.0
    for _ in range(40):
        # the affine model restarted at each step: constant at t_n, same rate
        system.step(h, np.array([f0 + r * t]), np.array([r]))
        t += h
    np.testing.assert_allclose(system.q[0], _oscillator_response(m, c, k, f0, r, t), rtol=1e-10)


def _index3_heave_error(h: float, m: float, k: float, f0: float, duration: float) -> tuple[float, float]:
    spec = {"bodies": [{"name": "b", "mass": m, "inertia": np.eye(3).tolist(), "cg": [0.0, 0.0, 0.0],
                        "dofs": [2], "x0": [0.0] * 6, "v0": [0.0] * 6}],
            "ptos": [], "multibody": {"formulation": "index3", "max_step": 0.0}}
    sim = build_simulator(spec)
    element = LinearisedInputForce(np.array([0]), np.array([2]), sim.model.cg)
    sim.model.elements.append(element)
    worst = 0.0
    for n in range(int(round(duration / h))):
        restart = element.set(sim.time, np.array([f0]), np.zeros(1), np.array([[-k]]), np.zeros((1, 1)))
        sim.advance(h, restart=restart)
        exact = f0 / k * (1 - math.cos(math.sqrt(k / m) * (n + 1) * h))
        worst = max(worst, abs(sim.displacement()[0] - exact))
    return worst, sim.energy()["balance"]


def test_index3_formulation_takes_the_linearised_force_implicitly() -> None:
    """A free body in heave held only by the element's stiffness (omega = 20 rad/s): generalised-alpha
    reproduces the closed-form oscillation with its second-order error, and the element's power is booked
    as external work (the energy balance closes)."""
    m, k, f0 = 1.0e3, 4.0e5, 2.0e4
    amplitude = 2 * f0 / k
    e1, b1 = _index3_heave_error(0.01, m, k, f0, 2.0)
    e2, b2 = _index3_heave_error(0.005, m, k, f0, 2.0)
    assert e1 < 0.1 * amplitude, e1  # phase error of generalised-alpha accumulated over 6 periods
    assert 3.5 < e1 / e2 < 4.5, (e1, e2)
    # the work is integrated by the trapezoidal rule (O(h^2)): the balance closes as h^2
    assert abs(b1) < 3e-3 * f0 * amplitude and 3.0 < abs(b1 / b2) < 5.0, (b1, b2)
