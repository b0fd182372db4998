"""Viscous drag and the nonlinear hydrostatic and Froude-Krylov forces, against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import j1

from hydro_fmu.bem import BodyGeometry, body_mesh
from hydro_fmu.drag import ViscousCoefficients, ViscousForce
from hydro_fmu.nonlinear_hydrostatics import BodyPressureModel, clip_below
from hydro_fmu.waves import regular_wave

RHO, G = 1025.0, 9.81


def test_drag_force_per_dof() -> None:
    c = ViscousCoefficients.from_drag(RHO, linear=[0, 0, 1e3, 0, 0, 0], drag_coefficient=[0, 0, 1.2, 0, 0.5, 0],
                                      area=[0, 0, 20.0, 0, 300.0, 0])
    force = ViscousForce(c)(np.array([0.0, 0.0, -0.5, 0.0, 0.1, 0.0]))
    assert force[2] == pytest.approx(-1e3 * -0.5 - 0.5 * RHO * 1.2 * 20.0 * 0.5 * -0.5)
    assert force[4] == pytest.approx(-0.5 * RHO * 0.5 * 300.0 * 0.1 * 0.1)
    assert force[[0, 1, 3, 5]].tolist() == [0, 0, 0, 0]


def quadratic_decay(kappa_a0: float) -> float:
    """Relative error of the averaged amplitude law A(t) = A0 / (1 + (4/(3 pi)) kappa w A0 t) of
    x'' + w^2 x + kappa |x'| x' = 0 after 10 periods, with the drag force from ViscousForce."""
    m, k = 1.0e5, 4.0e5
    w = math.sqrt(k / m)
    a0 = 1.0
    kappa = kappa_a0 / a0
    drag = ViscousForce(ViscousCoefficients(np.zeros(1), np.array([kappa * m])))

    def rhs(_t, y):
        return [y[1], (-k * y[0] + drag(np.array([y[1]]))[0]) / m]

    periods = 10
    t_end = periods * 2 * math.pi / w
    sol = solve_ivp(rhs, (0, t_end + math.pi / w), [a0, 0.0], rtol=1e-10, atol=1e-12, dense_output=True)
    # Energy amplitude sqrt(x^2 + (v/w)^2), averaged over the period centred on t_end (its ripple
    # within a period is zero-mean to first order).
    t = np.linspace(t_end - math.pi / w, t_end + math.pi / w, 2001)
    x, v = sol.sol(t)
    amplitude = np.trapezoid(np.hypot(x, v / w), t) / (t[-1] - t[0])
    expected = a0 / (1 + 4 / (3 * math.pi) * kappa * w * a0 * t_end)
    return abs(amplitude / expected - 1)


def test_quadratic_drag_follows_the_averaged_decay_law() -> None:
    """The law is first-order averaging: its error vanishes with kappa A0 (at least linearly)."""
    errors = [quadratic_decay(ka) for ka in (0.02, 0.01)]
    assert errors[-1] < 1e-3
    assert errors[0] / errors[1] > 1.8, errors


# ---------------------------------------------------------------------- nonlinear hydrostatics
def cylinder_model(radius: float = 5.0, draft: float = 5.0, panel: float = 0.5) -> BodyPressureModel:
    geometry = BodyGeometry("vertical_cylinder", radius=radius, draft=draft, panel_size=panel)
    cg = np.array([0.0, 0.0, -draft / 2])
    return BodyPressureModel(body_mesh(geometry).translated(-cg), cg, RHO, G)


def test_vertical_cylinder_heave_restoring_is_linear_up_to_its_ends() -> None:
    """Vertical walls: F = -rho g A_wp z exactly (A_wp of the polygonal waterline) until the draft or
    freeboard is used up; beyond submersion the force stops growing (full buoyancy)."""
    model = cylinder_model()
    a_wp = -model.forces(np.array([0, 0, 1e-3, 0, 0, 0]))[0][2] / (RHO * G * 1e-3)
    assert a_wp == pytest.approx(math.pi * 25.0, rel=0.01)
    for z in (-4.0, -1.0, 0.5, 3.0):
        assert model.forces(np.array([0, 0, z, 0, 0, 0]))[0][2] == pytest.approx(-RHO * G * a_wp * z, rel=1e-9)
    sunk = model.forces(np.array([0, 0, -7.0, 0, 0, 0]))[0][2]
    assert sunk == pytest.approx(RHO * G * a_wp * 5.0, rel=1e-9)  # total volume 2 x draft: 5 m more


def test_sphere_buoyancy_follows_the_spherical_cap_volume() -> None:
    """A floating sphere (centre on the waterline) heaved by z: the submerged cap of height R - z has
    volume pi (R - z)^2 (3R - (R - z)) / 3; the restoring force is rho g (V(z) - V(0))."""
    radius = 2.0
    geometry = BodyGeometry("sphere", radius=radius, panel_size=0.1)
    model = BodyPressureModel(body_mesh(geometry), np.zeros(3), RHO, G)

    def cap(h: float) -> float:
        return math.pi * h**2 * (3 * radius - h) / 3

    for z in (-1.5, -0.5, 0.7, 1.6):
        expected = RHO * G * (cap(radius - z) - cap(radius))
        assert model.forces(np.array([0, 0, z, 0, 0, 0]))[0][2] == pytest.approx(expected, rel=5e-3)


def test_small_rotations_give_the_database_stiffness() -> None:
    """For small pitch the moment about the cg is -C55 theta, C55 = rho g (I_wp + V (z_b - z_g)), with
    I_wp = int x^2 dA of the mesh's waterline polygon (shoelace formula) and V, z_b of the polygonal
    prism; the first-order surge and heave forces of a pitch vanish (symmetric waterplane)."""
    model = cylinder_model()
    world = model.mesh.translated(model.cg)
    on_line = world.vertices[np.abs(world.vertices[:, 2]) < 1e-9]
    ring = np.unique(np.round(on_line, 9), axis=0)
    ring = ring[np.argsort(np.arctan2(ring[:, 1], ring[:, 0]))]
    x, y = ring[:, 0], ring[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    i_wp = np.sum(cross * (x**2 + x * xn + xn**2)) / 12
    area = np.sum(cross) / 2
    volume = area * 5.0  # prism of the waterline polygon, draft 5 m, centroid at z = -2.5 = z_g
    c55 = RHO * G * (i_wp + volume * (-2.5 - model.cg[2]))
    theta = 1e-4
    hs, _ = model.forces(np.array([0, 0, 0, 0, theta, 0]))
    assert hs[4] == pytest.approx(-c55 * theta, rel=2e-3)
    assert abs(hs[0]) < 1e-6 * c55 * theta and abs(hs[2]) < 1e-3 * RHO * G * 25 * theta


def test_large_rotation_uses_the_rotation_vector() -> None:
    """The pose's rotation is exp([r]x): a 90 deg roll of a sphere changes nothing (symmetry), and a
    rotation by r equals the same rotation given as -r about the opposite axis."""
    model = BodyPressureModel(body_mesh(BodyGeometry("sphere", radius=1.0, panel_size=0.1)), np.zeros(3), RHO, G)
    hs, _ = model.forces(np.array([0, 0, 0, math.pi / 2, 0, 0]))
    assert np.abs(hs[:3]).max() < 1e-3 * RHO * G
    box = BodyPressureModel(body_mesh(BodyGeometry("box", size=(4.0, 2.0, 2.0), panel_size=0.25)), np.zeros(3), RHO, G)
    a, _ = box.forces(np.array([0, 0, 0, 0.3, 0.4, 0.0]))
    b, _ = box.forces(np.array([0, 0, 0, -0.3, -0.4, 0.0]))
    scale = RHO * G * 8.0
    np.testing.assert_allclose(a[2], b[2], atol=1e-9 * scale)  # heave force even in the tilt direction
    np.testing.assert_allclose(a[3:5], -b[3:5], atol=1e-9 * scale)  # moment odd


def test_nonlinear_froude_krylov_tends_to_the_closed_form() -> None:
    """Fixed vertical cylinder, deep water: the linear heave Froude-Krylov force is
    rho g a exp(-k D) 2 pi R J1(k R) / k (pressure on the bottom). For this fixed wall-sided body the
    wetted walls carry no vertical force and the bottom does not move, so the first harmonic of the
    force over the instantaneous wetted surface is linear in the wave height: it matches the closed
    form at every height, up to the panel discretisation (measured 0.10 %)."""
    radius, draft, period = 5.0, 5.0, 8.0
    model = cylinder_model(radius, draft, panel=0.4)
    omega = 2 * math.pi / period
    k = omega**2 / G
    linear = RHO * G * math.exp(-k * draft) * 2 * math.pi * radius * j1(k * radius) / k

    def relative_error(height: float) -> float:
        waves = regular_wave(height, period)
        t = np.linspace(0, period, 16, endpoint=False)
        fz = np.array([model.forces(np.zeros(6), tt, waves, froude_krylov=True)[1][2] for tt in t])
        # First harmonic of the heave force per metre of amplitude.
        first = 2 * np.mean(fz * np.exp(-1j * omega * t)) / (height / 2)
        return abs(abs(first) / linear - 1)

    errors = [relative_error(h) for h in (2.0, 0.1)]
    assert max(errors) < 0.005, errors


def test_clip_keeps_orientation_and_area() -> None:
    """A flat square cut at a sloping surface keeps the wetted area and its normal direction."""
    square = np.array([[[0, 0, 0], [1, 0, 0], [1, 0, 1]], [[0, 0, 0], [1, 0, 1], [0, 0, 1]]], dtype=float)
    surface = np.array([[0.25, 0.75, 0.75], [0.25, 0.75, 0.25]])  # z = 0.25 + 0.5 x on the square
    wet, _ = clip_below(square, surface)
    area = 0.5 * np.cross(wet[:, 1] - wet[:, 0], wet[:, 2] - wet[:, 0])
    assert area.sum(axis=0)[1] == pytest.approx(-0.5, rel=1e-12)  # area below z = 0.25 + 0.5 x, normal -y


# ---------------------------------------------------------------------- through the FMUs
def cylinder_run(tmp_path, **hydro):
    from orchestrator.cosim.simulation import run_scenario
    from orchestrator.scenario import load_scenario

    from .conftest import SCENARIOS

    scenario = load_scenario(SCENARIOS / "cylinder_regular.toml")
    for key, value in hydro.pop("body", {}).items():
        setattr(scenario.bodies[0], key, value)
    for key, value in hydro.items():
        setattr(scenario.hydro, key, value)
    result = run_scenario(scenario, tmp_path / "run.h5", progress=False, log=None)
    return {c.label: c for c in result.comparisons}


def test_linear_viscous_damping_in_the_co_simulation_matches_the_frequency_domain(tmp_path) -> None:
    """Linear damping is linear: the co-simulated steady heave with it matches the exact answer that
    includes it (and differs clearly from the answer without it)."""
    c = cylinder_run(tmp_path, body={"linear_damping": [0, 0, 1.5e5, 0, 0, 0]})
    assert abs(c["float heave"].amplitude_error) < 0.005
    assert abs(c["pto mean power"].amplitude_error) < 0.01


def test_nonlinear_hydrostatics_of_a_wall_sided_float_match_the_linear_answer(tmp_path) -> None:
    """The cylinder's walls are vertical, so its heave restoring force is exactly linear: with the
    pressure integrated over the moving hull (mesh bundled in the FMU) the co-simulation still matches
    the linear frequency-domain answer."""
    c = cylinder_run(tmp_path, nonlinear_hydrostatics=True)
    assert abs(c["float heave"].amplitude_error) < 0.01
    assert abs(c["float heave"].phase_error_deg) < 1.0
