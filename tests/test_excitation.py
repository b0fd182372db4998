"""Wave excitation: superposition against the non-causal impulse-response convolution of seed 000,
heading interpolation, and the excitation impulse response's own properties."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydro_fmu.bemio import read_bemio
from hydro_fmu.excitation import ExcitationConvolution, ExcitationForce, excitation_impulse_response
from hydro_fmu.hdb import HydroDatabaseError
from hydro_fmu.sea import SeaSpec, build_sea
from hydro_fmu.waves import Ramp

from .conftest import SCENARIOS

CYLINDER_DB = SCENARIOS / "hydro_cache" / "float-24c657d2983c3078.h5"
TWO_BODY_DB = SCENARIOS / "hydro_cache" / "fore-aft-9770cca4a4f9ef4e.h5"


@pytest.fixture(scope="module")
def cylinder():
    return read_bemio(CYLINDER_DB)


@pytest.fixture(scope="module")
def record_file(tmp_path_factory):
    """A 600 s elevation record sampled at 0.1 s, written as CSV (the imported-record path)."""
    sea = build_sea(SeaSpec(kind="irregular", hs=2.0, tp=7.0, discretisation="equal_energy", n_components=300,
                            seed=3))
    t = np.arange(0.0, 600.0, 0.1)
    path = tmp_path_factory.mktemp("record") / "eta.csv"
    path.write_text("t,eta\n" + "\n".join(f"{a:.17g},{b:.17g}" for a, b in zip(t, sea.elevation(t), strict=True)))
    return path


def excitation_pair(hdb, path, duration: float, dt: float = 0.1):
    sea = build_sea(SeaSpec(kind="elevation", elevation_file=str(path)))
    dofs = np.arange(6)
    superposition = ExcitationForce(hdb, sea.components, dofs, Ramp())
    convolution = ExcitationConvolution(hdb, dofs, 0.0, sea.record, duration, dt, Ramp())
    times = np.arange(100.0, 500.0, 0.7)
    a = np.array([superposition(t) for t in times])
    b = np.array([convolution(t) for t in times])
    return np.sqrt(np.mean((a - b) ** 2, axis=0)) / np.sqrt(np.mean(a**2, axis=0))


def test_superposition_and_convolution_agree_on_an_imported_record(cylinder, record_file) -> None:
    """Acceptance: on an imported elevation record the two methods give the same surge, heave and
    pitch excitation within 0.5 % (RMS), and the difference shrinks as the kernel lengthens."""
    errors = {T: excitation_pair(cylinder, record_file, T)[[0, 2, 4]] for T in (10.0, 40.0)}
    assert np.all(errors[40.0] < 0.005), errors
    assert np.all(errors[40.0] < errors[10.0]), errors


def test_excitation_kernel_is_non_causal_and_transforms_back(cylinder) -> None:
    """K_ex is nonzero before tau = 0 (the wave reaches the body's sides before the origin), and its
    Fourier transform gives back X(omega) at the database frequencies."""
    tau = np.arange(-60.0, 60.0 + 1e-9, 0.05)
    k = excitation_impulse_response(cylinder, 0.0, np.array([0, 2]), tau)
    surge = k[:, 0]
    assert np.abs(surge[tau < -1.0]).max() > 0.05 * np.abs(surge).max()
    w = np.array([0.4, 0.8, 1.2])
    weights = np.full(len(tau), 0.05)
    weights[[0, -1]] = 0.025
    back = (np.exp(-1j * np.outer(w, tau)) * weights) @ k
    _, _, X = cylinder.interpolate(w)
    np.testing.assert_allclose(back, X[:, [0, 2]], rtol=0.01, atol=0.002 * np.abs(X[:, [0, 2]]).max())


def test_heading_interpolation_and_range() -> None:
    hdb = read_bemio(TWO_BODY_DB)
    w = hdb.omega[10:13]
    x0 = hdb.excitation_at(w, 0.0)
    x45 = hdb.excitation_at(w, math.radians(45.0))
    mid = hdb.excitation_at(w, math.radians(22.5))
    np.testing.assert_allclose(x0, hdb.excitation[0, 10:13])
    np.testing.assert_allclose(mid, 0.5 * (x0 + x45))
    # The eight headings cover the circle: 337.5 deg lies between 315 and 0 (360).
    wrap = hdb.excitation_at(w, math.radians(-22.5))
    np.testing.assert_allclose(wrap, 0.5 * (hdb.excitation[7, 10:13] + x0))
    single = read_bemio(CYLINDER_DB)
    with pytest.raises(HydroDatabaseError, match="outside the tabulated headings"):
        single.excitation_at(w, math.radians(10.0))


def test_two_body_excitation_is_symmetric_in_heading() -> None:
    """Two equal cylinders on the x axis, one at +x and one at -x: the wave from 0 deg on the fore body is
    the wave from 180 deg on the aft body, mirrored (surge sign flips, heave equal) up to the phase of
    the incident wave at each body, exp(+-i k x_b) (deep water, exp(+i w t) convention)."""
    hdb = read_bemio(TWO_BODY_DB)
    w = hdb.omega[5:40]
    k = w**2 / hdb.g
    fore_0 = hdb.excitation_at(w, 0.0)[:, 2] * np.exp(1j * k * 4.0)  # referred to the body's own centre
    aft_180 = hdb.excitation_at(w, math.pi)[:, 8] * np.exp(1j * k * 4.0)
    np.testing.assert_allclose(aft_180, fore_0, rtol=0.02, atol=0.01 * np.abs(fore_0).max())
