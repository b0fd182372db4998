"""BEMIO files as users bring them: both writers' layouts, optional groups absent or NaN, a reference point other
than the centre of gravity, the water depth, and the impulse-response and state-space groups WEC-Sim reads.

The files in scenarios/data/bemio/ are Capytaine databases written in each writer's layout
(scenarios/data/bemio/README.md says how and what they follow)."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from hydro_fmu.bem import BemBody, BemSettings, BodyGeometry, body_mesh, compute_database, frequency_grid
from hydro_fmu.bemio import EXCITATION_PARTS, read_bemio, read_wec_sim_groups, write_bemio
from hydro_fmu.hydrostatics import hull_hydrostatics
from hydro_fmu.radiation import impulse_response
from hydro_fmu.reference_point import buoyancy_stiffness_about, moved_to

from .conftest import ROOT, SCENARIOS

FILES = SCENARIOS / "data" / "bemio"


def test_buoyancy_stiffness_moves_between_points_as_the_formula_says() -> None:
    """C about G from C about P (rigid-body congruence plus the buoyancy terms) equals Capytaine's rigid-body formula
    evaluated directly about G, for a hull with every coupling (box off the axes)."""
    wet = body_mesh(BodyGeometry(shape="box", size=(4.0, 3.0, 2.0), position=(1.3, -0.7, -0.4),
                                 panel_size=0.5)).immersed_part()
    p, g = np.array([0.5, 0.2, -1.0]), np.array([1.1, -0.4, -0.3])
    volume, _, about_p = hull_hydrostatics(wet, p, 1025.0, 9.81)
    _, _, about_g = hull_hydrostatics(wet, g, 1025.0, 9.81)
    moved = buoyancy_stiffness_about(about_p, volume, 1025.0, 9.81, g - p)
    np.testing.assert_allclose(moved, about_g, rtol=0, atol=1e-9 * np.abs(about_g).max())


def _box_database(cg: tuple[float, float, float], tmp: Path, name: str) -> Path:
    """A box (3 x 2 x 2 m, centre at (0.4, 0.3, -0.2), so 1.2 m draft) computed by Capytaine with its rotation
    centre (the BEMIO file's reference point) at ``cg``."""
    body = BemBody("box", BodyGeometry(shape="box", size=(3.0, 2.0, 2.0), position=(0.4, 0.3, -0.2),
                                       panel_size=0.3), cg)
    settings = BemSettings(omega=frequency_grid(0.5, 2.5, 0.25), headings_deg=(0.0, 30.0), rho=1025.0, g=9.81)
    return write_bemio(compute_database([body], settings), tmp / f"{name}.h5")


BOX_SCENARIO = """
name = "box_{name}"
[simulation]
duration = 10.0
step = 0.05
[environment]
rho = 1025.0
g = 9.81
water_depth = inf
[waves]
kind = "regular"
height = 1.0
period = 4.0
heading_deg = 30.0
[hydro]
database = "{name}.h5"
[rao]
headings_deg = [0.0, 30.0]
[[bodies]]
name = "box"
cg = [0.4, 0.3, -0.5]
mass = 7380.0
inertia = [4000.0, 7000.0, 8000.0]
[[ptos]]
name = "pto"
body = "box"
dof = "heave"
damping = 3.0e3
"""


@pytest.fixture(scope="module")
def box_files(tmp_path_factory) -> Path:
    """The box's database about its cg (about_cg.h5) and about the origin (about_origin.h5), in one folder."""
    folder = tmp_path_factory.mktemp("box")
    _box_database((0.4, 0.3, -0.5), folder, "about_cg")
    _box_database((0.0, 0.0, 0.0), folder, "about_origin")
    return folder


def test_database_about_another_point_gives_the_rao_of_one_about_the_cg(box_files) -> None:
    """Acceptance: Capytaine databases of one box computed about its cg and about the origin (0, 0, 0); the second,
    read with the body's cg given in the scenario, is moved to the cg and gives the same 6-DOF RAOs at two headings
    (within 0.5 %; the transformation is exact for the discretised BEM problem, so far closer in fact)."""
    from orchestrator.reference.response_files import write_rao_file
    from orchestrator.scenario import load_scenario
    from orchestrator.scene import load_scene

    tmp_path = box_files
    raos, logs = {}, []
    for name in ("about_cg", "about_origin"):
        (tmp_path / f"{name}.toml").write_text(BOX_SCENARIO.format(name=name))
        scene = load_scene(load_scenario(tmp_path / f"{name}.toml"), log=logs.append)
        responses = write_rao_file(scene, tmp_path / f"{name}_rao.h5")
        raos[name] = np.array([r.body_rao("box") for r in responses])
    assert any("moved to the cg" in m and "(0, 0, 0) m" in m for m in logs), logs
    ref, moved = raos["about_cg"], raos["about_origin"]
    scale = np.abs(ref).max(axis=(0, 1), keepdims=True)  # each DOF on its own scale (m/m, rad/m)
    error = np.abs(moved - ref) / scale
    assert error.max() < 0.005, error.max()
    assert np.abs(ref[..., 2]).max() > 0.5 and np.abs(ref[1, :, 1]).max() > 0.05  # heave, and sway at 30 deg


def test_moved_coefficients_equal_those_computed_about_the_cg(box_files) -> None:
    """Every coefficient, not only the RAO: A, B, A_inf, the excitation (both headings) and C."""
    at_g = read_bemio(box_files / "about_cg.h5")
    at_p = read_bemio(box_files / "about_origin.h5")
    moved = moved_to(at_p, at_g.cg)
    for name in ("added_mass", "radiation_damping", "added_mass_inf", "excitation", "hydrostatic_stiffness"):
        ref, got = getattr(at_g, name), getattr(moved, name)
        assert np.abs(got - ref).max() <= 1e-6 * np.abs(ref).max(), name


# ---------------------------------------------------------------------- both writers' layouts
def test_matlab_sphere_file_reads_without_its_nan_parts() -> None:
    """The MATLAB-layout sphere (scalars (1, 1), vectors (N, 1), strings as arrays, Froude-Krylov and scattering
    groups all NaN) reads; the parts are dropped with the reason kept; the physics is the sphere's."""
    path = FILES / "sphere_matlab_ss.h5"
    with h5py.File(path) as f:  # the layout really is MATLAB's
        assert f["simulation_parameters/rho"].shape == (1, 1)
        assert f["simulation_parameters/w"].shape[1] == 1
        assert np.isnan(f["body1/hydro_coeffs/excitation/froude-krylov/re"][()]).all()
    hdb = read_bemio(path)
    assert hdb.body_names == ["sphere"] and hdb.froude_krylov is None and hdb.diffraction is None
    assert "froude-krylov has" in hdb.extra[EXCITATION_PARTS] and "non-finite" in hdb.extra[EXCITATION_PARTS]
    radius, rho, g = 5.0, 1000.0, 9.81
    assert hdb.rho == rho and math.isinf(hdb.water_depth)
    np.testing.assert_allclose(hdb.displaced_volume[0], 2 / 3 * math.pi * radius ** 3, rtol=0.01)
    np.testing.assert_allclose(hdb.hydrostatic_stiffness[0, 2, 2], rho * g * math.pi * radius ** 2, rtol=0.01)
    np.testing.assert_allclose(hdb.cg[0], [0.0, 0.0, -2.0])
    np.testing.assert_allclose(hdb.cb[0], [0.0, 0.0, -3 * radius / 8], atol=0.02)
    # Heave added mass and damping against Hulme's (1982) multipole solution (tests/multipole_hemisphere.py) at
    # omega = 1 rad/s and 2 rad/s: within 3 % (a 0.45 m panel on a 5 m sphere).
    from .multipole_hemisphere import hemisphere_heave

    volume = 2 / 3 * math.pi * radius ** 3
    for omega in (1.0, 2.0):
        k = int(np.argmin(np.abs(hdb.omega - omega)))
        mu, lam, _ = hemisphere_heave(omega ** 2 * radius / g)
        np.testing.assert_allclose(hdb.added_mass[k, 2, 2] / (rho * volume), mu, rtol=0.03)
        np.testing.assert_allclose(hdb.radiation_damping[k, 2, 2] / (rho * volume * omega), lam, rtol=0.03)


def test_matlab_sphere_file_groups_are_the_transform_and_a_realisation_of_its_damping() -> None:
    """The file's radiation impulse response is the cosine transform of its own damping (so the layout's index
    order and normalisation by rho are right) and its per-entry state-space realisation reproduces it."""
    path = FILES / "sphere_matlab_ss.h5"
    hdb, groups = read_bemio(path), read_wec_sim_groups(path)
    assert groups.kernel.shape == (len(groups.t), 6, 6) and groups.ss_order.shape == (6, 6)
    expected = impulse_response(hdb.omega, hdb.radiation_damping, groups.t)
    np.testing.assert_allclose(groups.kernel, expected, rtol=0, atol=1e-9 * np.abs(expected).max())
    fitted = groups.state_space_response(groups.t)
    for k in (0, 2, 4):  # surge, heave, pitch: each within 5 % of its own size (the fit's tolerance is 2 %)
        size = np.linalg.norm(expected[:, k, k])
        assert np.linalg.norm(fitted[:, k, k] - expected[:, k, k]) < 0.05 * size, k
        assert groups.ss_order[k, k] >= 1
    assert groups.ex_kernel.shape == (1, len(groups.ex_t), 6)


def test_both_layouts_of_one_database_read_the_same() -> None:
    """The two-cylinder database written in both layouts (MATLAB with the parts, Python bemio with 'components'
    groups, no dof keys) reads to the same arrays; interaction blocks included."""
    a, b = read_bemio(FILES / "two_cylinders_matlab.h5"), read_bemio(FILES / "two_cylinders_python.h5")
    assert a.body_names == b.body_names == ["fore", "aft"]
    assert a.water_depth == b.water_depth == 30.0
    for name in ("omega", "headings", "added_mass", "radiation_damping", "added_mass_inf", "excitation",
                 "froude_krylov", "diffraction", "hydrostatic_stiffness", "cg", "cb", "displaced_volume"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), rtol=1e-12, atol=0, err_msg=name)
    assert np.abs(a.added_mass[:, 2, 8]).max() > 1e-3 * np.abs(a.added_mass[:, 2, 2]).max()  # they interact
    np.testing.assert_allclose(a.excitation, a.froude_krylov + a.diffraction, rtol=1e-9, atol=1e-9)


def test_python_layout_one_body_with_groups_and_infinite_depth() -> None:
    path = FILES / "buoy_python_ss.h5"
    with h5py.File(path) as f:
        assert f["simulation_parameters/water_depth"][()] in (b"infinite", "infinite")
        assert "dof" not in f["body1/properties"]
    hdb, groups = read_bemio(path), read_wec_sim_groups(path)
    assert hdb.body_names == ["buoy"] and math.isinf(hdb.water_depth)
    expected = impulse_response(hdb.omega, hdb.radiation_damping, groups.t)
    np.testing.assert_allclose(groups.kernel, expected, rtol=0, atol=1e-9 * np.abs(expected).max())
    assert groups.ss_order[2, 2] >= 1


def test_write_bemio_adds_the_groups_wec_sim_reads(tmp_path) -> None:
    """write_bemio(wec_sim_groups=True): K/rho (6, 6N, Nt), the state space (6, 6N, r, r) ... with C/rho, the
    excitation kernel; read back, they reproduce the impulse response of the database's own damping."""
    hdb = read_bemio(FILES / "two_cylinders_matlab.h5")
    path = write_bemio(hdb, tmp_path / "out.h5", wec_sim_groups=True)
    with h5py.File(path) as f:
        hc = f["body2/hydro_coeffs"]
        nt = len(f["body1/hydro_coeffs/radiation_damping/impulse_response_fun/t"])
        assert hc["radiation_damping/impulse_response_fun/K"].shape == (6, 12, nt)
        r = hc["radiation_damping/state_space/A/all"].shape[-1]
        assert hc["radiation_damping/state_space/A/all"].shape == (6, 12, r, r)
        assert hc["radiation_damping/state_space/B/all"].shape == (6, 12, r, 1)
        assert hc["radiation_damping/state_space/C/all"].shape == (6, 12, 1, r)
        assert hc["radiation_damping/state_space/D/all"].shape == (6, 12)
        assert hc["radiation_damping/state_space/it"].shape == (6, 12)
        assert hc["excitation/impulse_response_fun/f"].shape[:2] == (6, 2)
        k33 = hc["radiation_damping/impulse_response_fun/K"][2, 8, 0]  # aft heave from aft heave at t = 0
    groups = read_wec_sim_groups(path)
    expected = impulse_response(hdb.omega, hdb.radiation_damping, groups.t)
    np.testing.assert_allclose(k33 * hdb.rho, expected[0, 8, 8], rtol=1e-12)
    fitted = groups.state_space_response(groups.t)
    size = np.linalg.norm(expected[:, 8, 8])
    assert np.linalg.norm(fitted[:, 8, 8] - expected[:, 8, 8]) < 0.05 * size


# ---------------------------------------------------------------------- what a scene checks
SPHERE = """
name = "sphere_file"
[simulation]
duration = 10.0
step = 0.05
[environment]
rho = 1000.0
g = 9.81
water_depth = {depth}
[waves]
kind = "still"
[hydro]
database = "{database}"
nonlinear_froude_krylov = {fk}
[[bodies]]
name = "sphere"
cg = [0.0, 0.0, -2.0]
dofs = ["heave"]
initial_displacement = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
[bodies.geometry]
shape = "sphere"
radius = 5.0
panel_size = 1.0
"""


def _sphere_scenario(tmp_path: Path, depth: str = "inf", fk: str = "false") -> Path:
    path = tmp_path / "sphere.toml"
    path.write_text(SPHERE.format(depth=depth, database=(FILES / "sphere_matlab_ss.h5").as_posix(), fk=fk))
    return path


def test_sphere_file_as_bemio_writes_it_runs(tmp_path) -> None:
    """Acceptance: the sphere database with NaN Froude-Krylov and scattering groups runs a heave decay."""
    from orchestrator.cosim.simulation import run_scenario
    from orchestrator.scenario import load_scenario

    result = run_scenario(load_scenario(_sphere_scenario(tmp_path)), tmp_path / "out.h5", in_process=True,
                          progress=False)
    with h5py.File(tmp_path / "out.h5") as f:
        heave = f["bodies/sphere/displacement"][:, 2]
    assert abs(heave[0] - 1.0) < 1e-9 and np.all(np.isfinite(heave)) and abs(heave).max() <= 1.0 + 1e-9
    assert heave.min() < -0.1  # it oscillates through equilibrium
    assert result is not None


def test_parts_are_checked_only_when_the_scene_uses_them(tmp_path) -> None:
    from orchestrator.errors import ScenarioError
    from orchestrator.scenario import load_scenario
    from orchestrator.scene.database import load_database

    with pytest.raises(ScenarioError) as info:
        load_database(load_scenario(_sphere_scenario(tmp_path, fk="true")), log=None)
    text = str(info.value)
    assert "nonlinear_froude_krylov" in text and "sphere_matlab_ss.h5" in text and "non-finite" in text
    assert "Set hydro.nonlinear_froude_krylov = false" in text


def test_water_depth_of_the_database_is_checked(tmp_path) -> None:
    """A finite-depth database under a deep-water scenario (and the reverse) is refused with the fix; the command
    line says it in one paragraph with exit status 2."""
    from orchestrator.errors import ScenarioError
    from orchestrator.scenario import load_scenario
    from orchestrator.scene.database import load_database

    with pytest.raises(ScenarioError, match=r"environment.water_depth = 200 m but .* water depth of inf m.*"
                                            r"Set environment.water_depth = inf"):
        load_database(load_scenario(_sphere_scenario(tmp_path, depth="200.0")), log=None)
    text = SPHERE.format(depth="inf", database=(FILES / "two_cylinders_matlab.h5").as_posix(), fk="false")
    text = text.replace('name = "sphere"', 'name = "fore"').replace("rho = 1000.0", "rho = 1025.0")
    text = text.replace("cg = [0.0, 0.0, -2.0]", "cg = [-2.0, 0.0, -0.5]")
    (tmp_path / "deep.toml").write_text(text)
    proc = subprocess.run([sys.executable, "-m", "wec_cosim.cli", "rao", str(tmp_path / "deep.toml"), "--out",
                           str(tmp_path / "r.h5")], capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 2, proc.stderr
    assert "water depth of 30 m" in proc.stderr and "Set environment.water_depth = 30" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_hydro_export_writes_what_wec_sim_reads(tmp_path) -> None:
    """`wec-cosim hydro SCENARIO --export F.h5`: the cylinder's database with the groups, readable by us."""
    out = tmp_path / "cylinder_wecsim.h5"
    proc = subprocess.run([sys.executable, "-m", "wec_cosim.cli", "hydro", str(SCENARIOS / "cylinder_regular.toml"),
                           "--export", str(out)], capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    hdb, groups = read_bemio(out), read_wec_sim_groups(out)
    expected = impulse_response(hdb.omega, hdb.radiation_damping, groups.t)
    np.testing.assert_allclose(groups.kernel, expected, rtol=0, atol=1e-9 * np.abs(expected).max())
    heave = groups.state_space_response(groups.t)[:, 2, 2]
    assert np.linalg.norm(heave - expected[:, 2, 2]) < 0.05 * np.linalg.norm(expected[:, 2, 2])
