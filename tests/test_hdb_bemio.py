"""Hydrodynamic database type and the WEC-Sim BEMIO HDF5 layout."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from hydro_fmu.bemio import read_bemio, write_bemio
from hydro_fmu.hdb import HydroDatabase, HydroDatabaseError


def synthetic_database(n_bodies: int = 2, nw: int = 5, nh: int = 2, seed: int = 1) -> HydroDatabase:
    """Random but well-formed coefficients (symmetric A, B) for file-format tests."""
    rng = np.random.default_rng(seed)
    n = 6 * n_bodies

    def sym(k: int) -> np.ndarray:
        m = rng.normal(size=(k, n, n))
        return m + np.transpose(m, (0, 2, 1))

    return HydroDatabase(
        body_names=[f"b{i}" for i in range(n_bodies)],
        omega=np.linspace(0.2, 2.0, nw),
        added_mass=sym(nw) * 1e4,
        radiation_damping=sym(nw) * 1e3,
        added_mass_inf=sym(1)[0] * 1e4,
        headings=np.radians(np.linspace(0, 90, nh)),
        excitation=rng.normal(size=(nh, nw, n)) * 1e5 + 1j * rng.normal(size=(nh, nw, n)) * 1e5,
        froude_krylov=rng.normal(size=(nh, nw, n)) + 1j * rng.normal(size=(nh, nw, n)),
        diffraction=rng.normal(size=(nh, nw, n)) + 1j * rng.normal(size=(nh, nw, n)),
        hydrostatic_stiffness=rng.normal(size=(n_bodies, 6, 6)) * 1e5,
        cg=rng.normal(size=(n_bodies, 3)),
        cb=rng.normal(size=(n_bodies, 3)),
        displaced_volume=rng.uniform(10, 100, n_bodies),
        rho=1025.0,
        g=9.81,
        water_depth=50.0,
    )


def test_round_trip_reproduces_every_array(tmp_path) -> None:
    hdb = synthetic_database()
    back = read_bemio(write_bemio(hdb, tmp_path / "db.h5"))
    for name in ("omega", "added_mass", "radiation_damping", "added_mass_inf", "headings", "excitation",
                 "froude_krylov", "diffraction", "hydrostatic_stiffness", "cg", "cb", "displaced_volume"):
        # Equal up to the round-off of WEC-Sim's normalisation (divide by rho, rho*omega, rho*g, multiply back).
        np.testing.assert_allclose(getattr(back, name), getattr(hdb, name), rtol=1e-14, atol=0, err_msg=name)
    assert back.body_names == hdb.body_names
    assert (back.rho, back.g, back.water_depth) == (hdb.rho, hdb.g, hdb.water_depth)


def test_file_has_wec_sim_names_shapes_and_normalisation(tmp_path) -> None:
    """Dataset names and shapes of WEC-Sim's writeBEMIOH5 (as seen from h5py) for 2 bodies."""
    hdb = synthetic_database(n_bodies=2, nw=5, nh=2)
    path = write_bemio(hdb, tmp_path / "db.h5")
    nw, nh, n = 5, 2, 12
    expected = {
        "simulation_parameters/w": (nw,),
        "simulation_parameters/T": (nw,),
        "simulation_parameters/wave_dir": (nh,),
        "simulation_parameters/water_depth": (),
        "simulation_parameters/rho": (),
        "simulation_parameters/g": (),
        "bem_data/code": (),
    }
    for b in (1, 2):
        expected.update({
            f"body{b}/properties/name": (),
            f"body{b}/properties/body_number": (),
            f"body{b}/properties/cg": (3,),
            f"body{b}/properties/cb": (3,),
            f"body{b}/properties/disp_vol": (),
            f"body{b}/properties/dof": (),
            f"body{b}/properties/dof_start": (),
            f"body{b}/properties/dof_end": (),
            f"body{b}/hydro_coeffs/linear_restoring_stiffness": (6, 6),
            f"body{b}/hydro_coeffs/added_mass/all": (6, n, nw),
            f"body{b}/hydro_coeffs/added_mass/inf_freq": (6, n),
            f"body{b}/hydro_coeffs/radiation_damping/all": (6, n, nw),
        })
        for part in ("", "froude-krylov/", "scattering/"):
            for comp in ("re", "im", "mag", "phase"):
                expected[f"body{b}/hydro_coeffs/excitation/{part}{comp}"] = (6, nh, nw)
    with h5py.File(path) as f:
        for name, shape in expected.items():
            assert name in f, name
            assert f[name].shape == shape, name
        # Normalisations of WEC-Sim's normalizeBEM: A / rho, B / (rho w), excitation and stiffness / (rho g).
        rho, g, w = hdb.rho, hdb.g, hdb.omega
        np.testing.assert_allclose(f["body2/hydro_coeffs/added_mass/all"][1, 7, 3], hdb.added_mass[3, 7, 7] / rho)
        np.testing.assert_allclose(f["body1/hydro_coeffs/radiation_damping/all"][2, 9, 4],
                                   hdb.radiation_damping[4, 2, 9] / (rho * w[4]))
        np.testing.assert_allclose(f["body2/hydro_coeffs/excitation/im"][0, 1, 2],
                                   hdb.excitation[1, 2, 6].imag / (rho * g))
        assert f["body2/properties/dof_start"][()] == 7 and f["body2/properties/dof_end"][()] == 12


def test_missing_and_corrupt_files_are_named(tmp_path) -> None:
    with pytest.raises(HydroDatabaseError, match="does not exist"):
        read_bemio(tmp_path / "nope.h5")
    bad = tmp_path / "bad.h5"
    bad.write_bytes(b"not an hdf5 file")
    with pytest.raises(HydroDatabaseError, match="bad.h5 is not a readable HDF5 file"):
        read_bemio(bad)
    path = write_bemio(synthetic_database(), tmp_path / "db.h5")
    with h5py.File(path, "a") as f:
        del f["body2/hydro_coeffs/added_mass/inf_freq"]
    with pytest.raises(HydroDatabaseError, match="body2/hydro_coeffs/added_mass/inf_freq"):
        read_bemio(path)


def test_non_finite_coefficient_is_located(tmp_path) -> None:
    path = write_bemio(synthetic_database(), tmp_path / "db.h5")
    with h5py.File(path, "a") as f:
        data = f["body2/hydro_coeffs/radiation_damping/all"][()]
        data[4, 4, 1] = np.nan  # body 2, pitch row, second frequency
        f["body2/hydro_coeffs/radiation_damping/all"][...] = data
    with pytest.raises(HydroDatabaseError, match=r"radiation_damping .*body 'b1' pitch, omega = 0.65"):
        read_bemio(path)


def test_interpolation_holds_limits() -> None:
    hdb = synthetic_database(n_bodies=1)
    A, B, X = hdb.interpolate(np.array([hdb.omega[2], 10.0]))
    np.testing.assert_allclose(A[0], hdb.added_mass[2])
    np.testing.assert_allclose(A[1], hdb.added_mass_inf)  # above the grid: A_inf, B = 0, no excitation
    assert not B[1].any() and not X[1].any()


def physical_database(n_bodies: int = 3, nw: int = 6, seed: int = 2) -> HydroDatabase:
    """Symmetric A and positive semi-definite B (what a BEM code produces for a passive body)."""
    hdb = synthetic_database(n_bodies=n_bodies, nw=nw, seed=seed)
    rng = np.random.default_rng(seed)
    n = 6 * n_bodies
    m = rng.normal(size=(nw, n, n))
    hdb.radiation_damping = m @ np.transpose(m, (0, 2, 1)) * 1e3
    hdb.added_mass_inf = hdb.added_mass_inf + hdb.added_mass_inf.T
    return hdb


def test_three_body_round_trip(tmp_path) -> None:
    hdb = physical_database(3)
    back = read_bemio(write_bemio(hdb, tmp_path / "three.h5"))
    np.testing.assert_allclose(back.radiation_damping, hdb.radiation_damping, rtol=1e-14)
    np.testing.assert_allclose(back.added_mass[:, 6:12, 12:18], hdb.added_mass[:, 6:12, 12:18], rtol=1e-14)
    with h5py.File(tmp_path / "three.h5") as f:
        assert f["body3/hydro_coeffs/radiation_damping/all"].shape == (6, 18, 6)
        assert f["body3/properties/dof_start"][()] == 13


def test_physics_checks_name_quantity_body_and_frequency() -> None:
    hdb = physical_database(2)
    assert hdb.check_physics() == []
    hdb.added_mass[3, 2, 8] *= 1.5  # body b0 heave row, body b1 heave column, 4th frequency
    problems = hdb.check_physics()
    assert len(problems) == 1
    assert "added_mass is not symmetric" in problems[0]
    assert "body 'b0' heave" in problems[0] and "body 'b1' heave" in problems[0]
    assert f"omega = {hdb.omega[3]:g} rad/s" in problems[0]
    hdb = physical_database(2)
    hdb.radiation_damping[1, 10, 10] = -abs(hdb.radiation_damping[1]).max()  # b1 pitch: negative damping
    problems = hdb.check_physics()
    assert any("radiation_damping is not positive semi-definite" in p and "body 'b1' pitch" in p for p in problems)
    # Only the degrees of freedom a scene uses are checked.
    assert hdb.check_physics(dofs=np.array([0, 1, 2, 6, 7, 8])) == []


def test_scene_refuses_a_database_that_creates_energy(tmp_path) -> None:
    from orchestrator.scenario import load_scenario
    from orchestrator.scene import load_scene

    from .conftest import SCENARIOS

    hdb = read_bemio(SCENARIOS / "hydro_cache" / "float-24c657d2983c3078.h5")
    hdb.radiation_damping[40, 2, 2] *= -1
    write_bemio(hdb, tmp_path / "bad.h5")
    text = (SCENARIOS / "cylinder_regular.toml").read_text().replace(
        "[hydro]\n", '[hydro]\ndatabase = "bad.h5"\n')
    (tmp_path / "scene.toml").write_text(text)
    with pytest.raises(HydroDatabaseError) as info:
        load_scene(load_scenario(tmp_path / "scene.toml"), log=None)
    message = str(info.value)
    assert "bad.h5" in message and "radiation_damping" in message and "body 'float' heave" in message
