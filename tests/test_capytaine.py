"""Capytaine front end: physics limits, time convention, cache behaviour."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hydro_fmu.bem import BemBody, BemSettings, BodyGeometry, cache_key, cached_database, compute_database
from hydro_fmu.hdb import HydroDatabaseError
from orchestrator.scenario import load_scenario
from orchestrator.scene.database import bem_inputs

from .conftest import SCENARIOS

R, D, RHO, G = 2.0, 2.0, 1025.0, 9.81


@pytest.fixture(scope="module")
def small_cylinder(tmp_path_factory):
    body = BemBody("can", BodyGeometry("vertical_cylinder", radius=R, draft=D, panel_size=0.5), (0.0, 0.0, -1.0))
    settings = BemSettings(omega=(0.05, 1.0, 2.0), headings_deg=(0.0,), rho=RHO, g=G)
    cache = tmp_path_factory.mktemp("bem_cache")
    hdb, path, computed = cached_database([body], settings, cache)
    return body, settings, cache, hdb, path, computed


def test_hydrostatics_and_volume_match_geometry(small_cylinder) -> None:
    *_, hdb, _, computed = small_cylinder
    assert computed
    assert hdb.displaced_volume[0] == pytest.approx(math.pi * R**2 * D, rel=0.015)
    assert hdb.hydrostatic_stiffness[0, 2, 2] == pytest.approx(RHO * G * math.pi * R**2, rel=0.015)
    # Pitch about the cg: rho g (I_wp + V (z_b - z_g)) with I_wp = pi R^4 / 4, z_b = -D/2, z_g = -1.
    c55 = RHO * G * (math.pi * R**4 / 4 + math.pi * R**2 * D * (-D / 2 + 1.0))
    # The waterline is an inscribed 26-gon (I_wp 2 % low) and Capytaine integrates it by quadrature.
    assert hdb.hydrostatic_stiffness[0, 4, 4] == pytest.approx(c55, rel=0.04)


def test_long_wave_limit_and_time_convention(small_cylinder) -> None:
    """At k R << 1 (long waves): the heave excitation tends to rho g A_wp, in phase with the
    elevation; the surge Froude-Krylov force to i k rho g V and the total surge force to
    i k g (rho V + A_11) (G. I. Taylor's long-wave result), leading the elevation by 90 deg in the
    exp(+i w t) convention."""
    *_, hdb, _, _ = small_cylinder
    x = hdb.excitation[0, 0]  # omega = 0.05 rad/s, k R = 5e-4
    k = 0.05**2 / G
    assert x[2] == pytest.approx(hdb.hydrostatic_stiffness[0, 2, 2], rel=0.01)
    assert hdb.froude_krylov[0, 0, 0] == pytest.approx(1j * k * RHO * G * hdb.displaced_volume[0], rel=0.01)
    expected = 1j * k * G * (RHO * hdb.displaced_volume[0] + hdb.added_mass[0, 0, 0])
    assert x[0] == pytest.approx(expected, rel=0.02)


def test_radiation_coefficients_are_physical(small_cylinder) -> None:
    *_, hdb, _, _ = small_cylinder
    for k in range(len(hdb.omega)):
        assert np.all(np.linalg.eigvalsh((hdb.radiation_damping[k] + hdb.radiation_damping[k].T) / 2) > -1e-3 * np.abs(
            hdb.radiation_damping[k]).max())
    assert hdb.added_mass_inf[2, 2] > 0


def test_second_call_hits_the_cache(small_cylinder) -> None:
    body, settings, cache, hdb, path, _ = small_cylinder
    again, path2, computed = cached_database([body], settings, cache)
    assert not computed and path2 == path
    np.testing.assert_array_equal(again.added_mass, hdb.added_mass)
    other = BemSettings(omega=(0.05, 1.0), rho=RHO, g=G)
    assert cache_key([body], other) != cache_key([body], settings)


@pytest.mark.parametrize("name", ["cylinder_regular", "disc_decay", "two_floats", "light_float", "hinge_barge",
                                  "two_cylinders_decay", "cylinder_irregular", "nenuphar", "mathai_assembly"])
def test_bundled_scenarios_ship_their_database(name) -> None:
    """The committed database is the one the scenario asks for: a fresh run needs no BEM solve."""
    scenario = load_scenario(SCENARIOS / f"{name}.toml")
    bodies, settings = bem_inputs(scenario)
    key = cache_key(bodies, settings)
    files = list((SCENARIOS / scenario.hydro.cache_dir).glob(f"*-{key}.h5"))
    assert files, f"no cached database with key {key} for {name}; run `wec-cosim hydro scenarios/{name}.toml`"


def test_mirror_symmetry_solve_equals_the_full_solve() -> None:
    """``symmetry = "xOz"`` solves on half meshes; with no panel crossing y = 0 the discretisation is the same,
    so every coefficient must equal the full solve's to round-off (two bodies: interaction included). Without lids:
    a lid is generated from the half waterline, so its panels differ from the full mesh's lid."""
    bodies = [BemBody("bow", BodyGeometry("box", size=(1.0, 0.5, 0.6), position=(0.0, 0.0, -0.1), panel_size=0.25,
                                          lid=False), (0.0, 0.0, -0.15)),
              BemBody("stern", BodyGeometry("box", size=(1.5, 0.5, 0.3), position=(1.6, 0.0, 0.0), panel_size=0.25,
                                            lid=False), (1.6, 0.0, -0.05))]
    full = compute_database(bodies, BemSettings(omega=(1.0, 4.0), headings_deg=(0.0, 30.0), rho=RHO, g=G))
    half = compute_database(bodies, BemSettings(omega=(1.0, 4.0), headings_deg=(0.0, 30.0), rho=RHO, g=G,
                                                symmetry="xOz"))
    for name in ("added_mass", "radiation_damping", "added_mass_inf", "excitation", "hydrostatic_stiffness"):
        a, b = getattr(full, name), getattr(half, name)
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-7 * np.abs(a).max(), err_msg=name)
    settings = BemSettings(omega=(1.0,))
    assert cache_key(bodies, settings) != cache_key(bodies, dataclasses.replace(settings, symmetry="xOz"))


def test_mirror_symmetry_of_an_asymmetric_body_is_an_error() -> None:
    off_centre = BemBody("float", BodyGeometry("box", size=(1.0, 0.5, 0.6), position=(0.0, 0.3, 0.0),
                                               panel_size=0.25), (0.0, 0.3, -0.1))
    with pytest.raises(HydroDatabaseError, match="'float' is not mirror-symmetric about the plane y = 0"):
        compute_database([off_centre], BemSettings(omega=(1.0,), symmetry="xOz"))
