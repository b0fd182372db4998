"""Floating hemisphere in heave against Hulme's (1982) multipole solution (acceptance test).

Reference: :mod:`tests.multipole_hemisphere` reproduces Hulme's method (Havelock's wave source
and wave-free multipoles; no panels); its damping agrees with the energy radiated by the source
term to 1e-5, and its added mass tends to 0.5 as K a grows (the infinite-frequency limit of a
hemisphere: half a sphere's added mass). The Capytaine databases (``method = "direct"``, lid on the
waterplane) are computed by our front end and cached in ``scenarios/hydro_cache``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydro_fmu.bem import BemBody, BemSettings, BodyGeometry, cached_database

from .conftest import SCENARIOS
from .multipole_hemisphere import hemisphere_heave

KA = (0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0)
RADIUS, RHO, G = 1.0, 1000.0, 9.81
PANELS = (0.16, 0.08)  # sphere meshes of 20 x 40 and 40 x 80 panels (400 and 1600 below water)


@pytest.fixture(scope="module")
def reference() -> np.ndarray:
    return np.array([hemisphere_heave(ka)[:2] for ka in KA])


def hemisphere_database(panel_size: float):
    body = BemBody("hemisphere", BodyGeometry("sphere", radius=RADIUS, panel_size=panel_size), (0.0, 0.0, 0.0))
    omega = tuple(round(math.sqrt(ka * G / RADIUS), 12) for ka in KA)
    settings = BemSettings(omega=omega, rho=RHO, g=G, method="direct")
    hdb, _, _ = cached_database([body], settings, SCENARIOS / "hydro_cache")
    volume = 2.0 / 3.0 * math.pi * RADIUS**3
    mu = hdb.added_mass[:, 2, 2] / (RHO * volume)
    lam = hdb.radiation_damping[:, 2, 2] / (RHO * volume * hdb.omega)
    return np.stack([mu, lam], axis=1)


def test_reference_is_converged_and_conserves_energy() -> None:
    for ka in (0.2, 1.0, 2.0):
        mu, lam, lam_energy = hemisphere_heave(ka)
        mu2, lam2, _ = hemisphere_heave(ka, n_multipoles=16, n_points=64)
        assert abs(mu - mu2) < 1e-5 and abs(lam - lam2) < 1e-5  # multipole series converged
        assert lam == pytest.approx(lam_energy, rel=1e-4)  # pressure integral = radiated power
    assert hemisphere_heave(30.0)[0] == pytest.approx(0.5, abs=0.02)  # infinite-frequency limit
    assert hemisphere_heave(0.01)[1] == pytest.approx(0.75 * math.pi * 0.01, rel=0.05)  # long waves: 3 pi Ka / 4


def test_heave_added_mass_and_damping_within_two_percent(reference) -> None:
    fine = hemisphere_database(PANELS[1])
    error = np.abs(fine / reference - 1)
    assert error.max() < 0.02, np.round(100 * error, 2)


def test_bem_error_shrinks_with_the_panel_size(reference) -> None:
    """Halving the panel size divides the error by about four (second order)."""
    errors = [np.abs(hemisphere_database(p) / reference - 1).max(axis=0) for p in PANELS]
    order = np.log2(errors[0] / errors[1])
    assert np.all(order > 1.3), (errors, order)
