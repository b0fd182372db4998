"""Frequency-domain (DAE and ODE forms) and pseudo-spectral steady states (seed 003).

Expected values: the exact linear frequency-domain solution (for the linear model, every method
must reproduce it to round-off), the time-domain co-simulation's steady state (FMUs through fmpy)
for nonlinear drag and PTO laws, and convergence of the Fourier series as N grows.
"""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from orchestrator.cosim.simulation import run_scenario
from orchestrator.reference import frequency_domain
from orchestrator.reference.pseudo_spectral import FourierBasis, PeriodicProblem, solve_steady
from orchestrator.results import read_results
from orchestrator.results.analysis import harmonic_fit, steady_window, window_mean
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene
from wec_cosim.cli import main

from .conftest import SCENARIOS

SEED_OMEGA = np.array([2.61, 3.5, 4.5, 5.5, 6.5, 7.85])  # seed 003's tested range, rad/s


@pytest.fixture(scope="module")
def barge():
    return load_scene(load_scenario(SCENARIOS / "hinge_barge.toml"), log=None)


def relative(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def test_fourier_basis_interpolates_exactly() -> None:
    """Analysis after synthesis is the identity on 2N + 1 points, and the derivative matrix
    differentiates a trigonometric polynomial exactly."""
    basis = FourierBasis(1.3, 4)
    np.testing.assert_allclose(basis.analysis @ basis.synthesis, np.eye(9), atol=1e-13)
    t = basis.times
    y = 0.3 + np.cos(2 * 1.3 * t) - 0.5 * np.sin(4 * 1.3 * t)
    dy = -2 * 1.3 * np.sin(2 * 1.3 * t) - 2.0 * 1.3 * np.cos(4 * 1.3 * t)
    np.testing.assert_allclose(basis.derivative @ (basis.analysis @ y), dy, atol=1e-12)


def test_dae_and_ode_frequency_domain_forms_agree_on_the_hinge_barge(barge) -> None:
    """Bordered DAE system (motion and multipliers) against the null-space ODE: motion, joint angle,
    hinge reaction and PTO power agree to 1e-8 over seed 003's frequencies."""
    dae = frequency_domain.solve(barge, SEED_OMEGA, form="dae")
    ode = frequency_domain.solve(barge, SEED_OMEGA, form="ode")
    assert relative(dae.rao, ode.rao) < 1e-8
    assert relative(dae.joint_rao["hinge"], ode.joint_rao["hinge"]) < 1e-8
    assert relative(dae.reaction_rao["hinge"], ode.reaction_rao["hinge"]) < 1e-8
    assert relative(dae.pto_power["pto"], ode.pto_power["pto"]) < 1e-8
    # The revolute hinge about y carries no moment about y; its force is in the x-z plane.
    assert np.max(np.abs(dae.reaction_rao["hinge"][:, [1, 4]])) < 1e-9 * np.max(np.abs(dae.reaction_rao["hinge"]))
    # Relative rotation of the hinge = pitch of barge 2 minus pitch of barge 1 (small motions).
    np.testing.assert_allclose(dae.joint_rao["hinge"][:, 0],
                               dae.body_rao("barge2")[:, 4] - dae.body_rao("barge1")[:, 4], rtol=1e-9)


@pytest.mark.parametrize("form", ["dae", "ode"])
def test_pseudo_spectral_with_one_harmonic_equals_the_frequency_domain_answer(barge, form) -> None:
    amplitude = 0.03  # seed 003 tested 60 mm wave height
    for omega in SEED_OMEGA[[0, 3, 5]]:
        fd = frequency_domain.solve(barge, np.array([omega]), form=form)
        ps = solve_steady(barge, omega, amplitude, 1, form=form)
        assert ps.residual < 1e-12
        assert relative(ps.motion[1], amplitude * fd.rao[0]) < 1e-8
        assert relative(ps.reactions["hinge"][1], amplitude * fd.reaction_rao["hinge"][0]) < 1e-8
        assert ps.pto_power["pto"] == pytest.approx(amplitude**2 * fd.pto_power["pto"][0], rel=1e-8)
        assert abs(ps.motion[0]).max() < 1e-14  # no mean offset in a linear system


def test_linear_model_with_more_harmonics_has_no_higher_harmonics(barge) -> None:
    ps = solve_steady(barge, 4.5, 0.03, 6, form="dae")
    fd = frequency_domain.solve(barge, np.array([4.5]))
    assert relative(ps.motion[1], 0.03 * fd.rao[0]) < 1e-8
    assert np.max(np.abs(ps.motion[2:])) < 1e-12 * np.max(np.abs(ps.motion[1]))


def test_analytic_jacobian_matches_finite_differences(barge) -> None:
    """The collocation Jacobian (Fourier matrices around pointwise derivatives) of a scene with quadratic
    drag and a saturated, Coulomb PTO, in both forms, against central differences of the residual."""
    s = load_scenario(SCENARIOS / "hinge_barge.toml")
    s.bodies[1].drag_coefficient = [1.0, 0.0, 1.0, 0.0, 0.0, 0.0]
    s.bodies[1].drag_area = [0.1, 0.0, 1.6, 0.0, 0.0, 0.0]
    s.ptos[0].friction_force, s.ptos[0].force_limit, s.ptos[0].velocity_scale = 20.0, 60.0, 0.05
    scene = load_scene(s, log=None)
    for form in ("dae", "ode"):
        problem = PeriodicProblem(scene, 4.0, 0.03, 3, form)
        u = problem.linear_solution()
        _, jac = problem.residual(u)
        h = 1e-7 * max(float(np.max(np.abs(u))), 1e-3)
        fd = np.column_stack([(problem.residual(u + h * e, False) - problem.residual(u - h * e, False)) / (2 * h)
                              for e in np.eye(len(u))])
        assert relative(jac, fd) < 1e-5, form


def drag_scenario(tmp_path=None):
    """The foundation cylinder (R = 5 m, draft 5 m, heave, PTO damper) near resonance in 2 m waves with a
    heave drag of Cd = 2 on the water-plane area: drag cuts the motion by about a fifth."""
    s = load_scenario(SCENARIOS / "cylinder_regular.toml")
    s.bodies[0].drag_coefficient = [0.0, 0.0, 2.0, 0.0, 0.0, 0.0]
    s.bodies[0].drag_area = [0.0, 0.0, math.pi * 25.0, 0.0, 0.0, 0.0]
    s.waves.height = 2.0
    s.simulation.duration = 240.0
    s.simulation.step = 0.05
    return s


def test_quadratic_drag_converges_as_harmonics_grow() -> None:
    """|v| v has a discontinuous second derivative: harmonics of the response fall off algebraically, and
    the fundamental converges as N grows (errors against N = 41 fall by more than 10x from N = 3 to N = 15)."""
    scene = load_scene(drag_scenario(), log=None)
    omega = 2 * math.pi / 5.6
    ref = solve_steady(scene, omega, 1.0, 41)
    assert ref.converged and ref.residual < 1e-10
    errors = []
    for n in (1, 3, 7, 15):
        ps = solve_steady(scene, omega, 1.0, n)
        assert ps.converged and ps.residual < 1e-10
        errors.append(abs(ps.motion[1, 0] - ref.motion[1, 0]) / abs(ref.motion[1, 0]))
    assert all(a > b for a, b in zip(errors, errors[1:], strict=False)), errors
    assert errors[3] < errors[1] / 10, errors
    # Drag is odd in the velocity: only odd harmonics and no mean, up to the aliasing of collocation on an
    # odd number of points (which breaks the half-period antisymmetry).
    assert np.max(np.abs(ref.motion[0::2])) < 1e-3 * abs(ref.motion[3, 0])
    linear = frequency_domain.solve(scene, np.array([omega])).rao[0, 0]
    assert abs(ref.motion[1, 0]) < 0.9 * abs(linear)  # the drag matters


def time_domain_steady(s, tmp_path, name: str) -> tuple[dict, np.ndarray, float]:
    run_scenario(s, tmp_path / f"{name}.h5", progress=False, log=None)
    data = read_results(tmp_path / f"{name}.h5")
    mask = steady_window(data["time"], s.waves.period, 10)
    return data, mask, 2 * math.pi / s.waves.period


def test_time_domain_with_drag_converges_to_the_pseudo_spectral_steady_state(tmp_path) -> None:
    """FMUs through fmpy (hydro FMU applies the drag), T/112 steps: fundamental amplitude within 1 %, phase
    within 2 degrees, mean PTO power within 1 %, and the whole waveform over the last ten periods within 1 %
    of the amplitude (the third harmonic is 0.2 % of the fundamental: below the co-simulation's error)."""
    s = drag_scenario()
    scene = load_scene(s, log=None)
    ps = solve_steady(scene, 2 * math.pi / 5.6, 1.0, 15)
    data, mask, omega = time_domain_steady(s, tmp_path, "drag")
    t, y = data["time"][mask], data["bodies/float/displacement"][mask, 2]
    first, _ = harmonic_fit(t, y, omega)
    exact = ps.motion[1, 0]
    assert abs(abs(first) / abs(exact) - 1) < 0.01
    assert abs(math.degrees(np.angle(first / exact))) < 2.0
    assert np.max(np.abs(y - ps.time_series(t)[:, 0])) < 0.01 * abs(exact)
    power = window_mean(data["time"], data["ptos/pto/power"], mask)
    assert power == pytest.approx(ps.pto_power["pto"], rel=0.01)


def test_nonlinear_pto_law_in_time_domain_and_pseudo_spectral(tmp_path) -> None:
    """A hydraulic-like PTO (Coulomb force plus quadratic damping, saturated) on the cylinder: the multibody
    FMU integrates the law in time (index-3 DAE), the pseudo-spectral solver in the frequency domain; both
    forms agree to 1e-8, and the time-domain steady state within 1 % in amplitude and power, 2 degrees."""
    s = load_scenario(SCENARIOS / "cylinder_regular.toml")
    p = s.ptos[0]
    p.damping, p.friction_force, p.quadratic_damping, p.force_limit, p.velocity_scale = 1.0e5, 3.0e4, 1.0e5, 1.2e5, 0.02
    s.simulation.duration, s.simulation.step = 240.0, 0.05
    s.multibody.max_step = 0.025
    scene = load_scene(s, log=None)
    assert s.formulation == "index3"
    omega = 2 * math.pi / s.waves.period
    dae = solve_steady(scene, omega, 0.5, 25, form="dae")
    ode = solve_steady(scene, omega, 0.5, 25, form="ode")
    assert dae.converged and dae.residual < 1e-9
    assert relative(dae.motion, ode.motion) < 1e-8
    data, mask, _ = time_domain_steady(s, tmp_path, "pto_law")
    t, y = data["time"][mask], data["bodies/float/displacement"][mask, 2]
    first, _ = harmonic_fit(t, y, omega)
    assert abs(abs(first) / abs(dae.motion[1, 0]) - 1) < 0.01
    assert abs(math.degrees(np.angle(first / dae.motion[1, 0]))) < 2.0
    power = window_mean(data["time"], data["ptos/pto/power"], mask)
    assert power == pytest.approx(dae.pto_power["pto"], rel=0.01)


def test_irregular_sea_statistics_follow_the_spectrum() -> None:
    """Incident power of a JONSWAP sea from spectral superposition equals rho g^2 Hs^2 Te / (64 pi) (deep
    water), Hs on the grid is the spectrum's, and the PTO's mean power is the spectrum-weighted RAO power."""
    from hydro_fmu.sea import sea_spectrum
    from hydro_fmu.spectra import deep_water_power, moment

    s = load_scenario(SCENARIOS / "cylinder_irregular.toml")
    scene = load_scene(s, log=None)
    omega = np.linspace(0.05, 4.0, 800)
    fd = frequency_domain.solve(scene, omega)
    spectrum = sea_spectrum(scene.sea_spec())
    stats = frequency_domain.irregular_response(fd, spectrum)
    assert stats.fraction_on_grid > 0.99
    assert stats.hs == pytest.approx(s.waves.hs, rel=0.01)
    te = 2 * math.pi * moment(spectrum, -1, 1e-3, 50.0) / moment(spectrum, 0, 1e-3, 50.0)
    assert stats.incident_power == pytest.approx(deep_water_power(stats.hs, te, scene.hdb.rho, scene.hdb.g), rel=0.01)
    heave = 4 * math.sqrt(np.trapezoid(np.abs(fd.rao[:, 0]) ** 2 * spectrum(omega), omega))
    assert stats.significant_response[0] == pytest.approx(heave, rel=1e-12)


def test_cli_steady_and_rao_write_hdf5_and_figures(tmp_path) -> None:
    out = tmp_path / "steady.h5"
    assert main(["steady", str(SCENARIOS / "hinge_barge.toml"), "--out", str(out), "--harmonics", "3",
                 "--plot"]) == 0
    with h5py.File(out) as f:
        g = f["periods/0"]
        assert g.attrs["converged"] and g.attrs["residual"] < 1e-12
        assert g["bodies/barge1/harmonics"].shape == (4, 6)
        assert g["joints/hinge/harmonics"].shape == (4, 1)
        assert g["ptos/pto/mean_power"][()] > 0
    assert (tmp_path / "steady_steady.png").stat().st_size > 0
    rao = tmp_path / "rao.h5"
    assert main(["rao", str(SCENARIOS / "hinge_barge.toml"), "--out", str(rao), "--form", "ode"]) == 0
    with h5py.File(rao) as f:
        assert f.attrs["form"] == "ode"
        assert f["joints/hinge/reaction"].shape == (len(f["omega"]), 6)
        np.testing.assert_allclose(f["ptos/pto/capture_width"][()],
                                   f["ptos/pto/mean_power"][()] / f["incident_power"][()])


def test_steady_needs_regular_waves(tmp_path, capsys) -> None:
    text = (SCENARIOS / "cylinder_irregular.toml").read_text().replace(
        "[hydro]", f'[hydro]\ncache_dir = "{SCENARIOS / "hydro_cache"}"', 1)
    path = tmp_path / "irregular.toml"
    path.write_text(text)
    assert main(["steady", str(path), "--out", str(tmp_path / "x.h5")]) == 2
    assert "needs regular waves" in capsys.readouterr().err


def test_heading_sweep_obeys_the_mirror_symmetry_of_two_cylinders(tmp_path) -> None:
    """Two identical cylinders at x = +-4 m: waves from 0 deg on the fore body are waves from 180 deg on the
    aft body (mirror x -> -x), and in beam seas (90 deg) both move alike."""
    text = (SCENARIOS / "two_cylinders_decay.toml").read_text().replace(
        "[hydro]", f'[rao]\nheadings_deg = [0.0, 90.0, 180.0]\n\n[hydro]\ncache_dir = "{SCENARIOS / "hydro_cache"}"', 1)
    path = tmp_path / "pair.toml"
    path.write_text(text)
    out = tmp_path / "sweep.h5"
    assert main(["rao", str(path), "--out", str(out)]) == 0
    with h5py.File(out) as f:
        assert list(f["heading_sweep/headings_deg"][()]) == [0.0, 90.0, 180.0]
        fore, aft = f["heading_sweep/bodies/fore/rao"][:, :, 2], f["heading_sweep/bodies/aft/rao"][:, :, 2]
        np.testing.assert_allclose(f["bodies/fore/rao"][:, 2], fore[0])
    scale = np.max(np.abs(fore))
    assert np.max(np.abs(fore[0] - aft[2])) < 1e-3 * scale
    assert np.max(np.abs(fore[1] - aft[1])) < 1e-3 * scale
    assert np.max(np.abs(fore[0] - aft[0])) > 0.05 * scale  # head seas do tell the two apart


def moored_cylinder():
    """The foundation cylinder in surge and heave on two symmetric catenary lines (fairleads at the keel
    edge, anchors 55 m out and 35 m down; 67 m, 2 kN/m), buoyancy set to balance the weight and the
    lines' pretension, a linear surge damper so the 25 s surge mode settles, 1 m waves at T = 5.6 s."""
    from mbd_fmu.moorings import catenary_tensions

    text = (SCENARIOS / "cylinder_regular.toml").read_text()
    text = text.replace('dofs = ["heave"]', 'dofs = ["surge", "heave"]\nlinear_damping = [1.5e5, 0, 0, 0, 0, 0]')
    _, v = catenary_tensions(55.0, 35.0, 67.0, 2000.0, 1e9)
    lines = "".join(f"""
[[forces]]
name = "line{k}"
kind = "catenary"
body = "float"
fairlead = [{5.0 * sign}, 0.0, -5.0]
anchor = [{60.0 * sign}, 0.0, -40.0]
length = 67.0
weight = 2000.0
ea = 1.0e9
""" for k, sign in ((1, 1), (2, -1)))
    return text + lines, 1025.0 * 9.81 * math.pi * 25.0 * 5.0 + 2 * v


def test_catenary_mooring_in_pseudo_spectral_and_time_domain(tmp_path) -> None:
    """Nonlinear elements of the multibody model enter the pseudo-spectral residual with exact kinematics:
    both forms agree to 1e-8, and the co-simulation (catenary integrated by the multibody FMU) settles
    to the same surge and heave within 1 % and 2 degrees."""
    text, buoyancy = moored_cylinder()
    path = tmp_path / "moored.toml"
    path.write_text(text.replace("[hydro]", f'[hydro]\ncache_dir = "{SCENARIOS / "hydro_cache"}"', 1))
    s = load_scenario(path)
    s.bodies[0].buoyancy = buoyancy
    s.simulation.duration, s.simulation.step = 300.0, 0.05
    scene = load_scene(s, log=None)
    omega = 2 * math.pi / s.waves.period
    amplitude = s.waves.height / 2
    dae = solve_steady(scene, omega, amplitude, 7, form="dae")
    ode = solve_steady(scene, omega, amplitude, 7, form="ode")
    assert dae.converged and dae.residual < 1e-9
    assert relative(dae.motion, ode.motion) < 1e-8
    assert np.max(np.abs(dae.motion[2:])) > 1e-6 * np.max(np.abs(dae.motion[1]))  # the lines are nonlinear
    data, mask, _ = time_domain_steady(s, tmp_path, "moored")
    t = data["time"][mask]
    for j, dof in ((0, 0), (1, 2)):
        first, _ = harmonic_fit(t, data["bodies/float/displacement"][mask, dof], omega)
        exact = dae.motion[1, j]
        assert abs(abs(first) / abs(exact) - 1) < 0.01, (dof, first, exact)
        assert abs(math.degrees(np.angle(first / exact))) < 2.0, (dof, first, exact)
