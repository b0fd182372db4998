"""Sea states: spectra, random-phase realisation, spreading, imported records and spectra."""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from hydro_fmu import spectra
from hydro_fmu.sea import SeaSpec, build_sea
from hydro_fmu.wave_records import WaveDataError, read_elevation, read_spectrum
from hydro_fmu.waves import group_velocity, wavenumber

RHO, G = 1025.0, 9.81
THREE_HOURS = 10800.0


def test_bretschneider_has_the_closed_form_moments() -> None:
    """S = (5/16) Hs^2 wp^4 w^-5 exp(-5/4 (wp/w)^4): m0 = Hs^2/16, m_-1 = (Hs^2/16) (5/4)^(-1/4)
    Gamma(5/4) / wp (substitute u = (5/4)(wp/w)^4), and the maximum is at wp."""
    hs, tp = 2.5, 9.0
    wp = 2 * math.pi / tp
    s = spectra.bretschneider(hs, tp)
    w = np.linspace(1e-3, 40.0, 400_001)
    m0 = np.trapezoid(s(w), w)
    m_1 = np.trapezoid(s(w) / w, w)
    assert m0 == pytest.approx(hs**2 / 16, rel=1e-6)
    assert m_1 == pytest.approx(hs**2 / 16 * (5 / 4) ** -0.25 * math.gamma(1.25) / wp, rel=1e-6)
    assert w[np.argmax(s(w))] == pytest.approx(wp, abs=1e-3)


@pytest.mark.parametrize("gamma", [1.0, 3.3, 7.0])
def test_jonswap_peaks_at_tp_and_integrates_to_hs(gamma) -> None:
    hs, tp = 2.0, 8.0
    s = spectra.jonswap(hs, tp, gamma)
    w = np.linspace(1e-3, 60.0, 600_001)
    assert 4 * math.sqrt(np.trapezoid(s(w), w)) == pytest.approx(hs, rel=1e-6)
    assert w[np.argmax(s(w))] == pytest.approx(2 * math.pi / tp, abs=1e-3)
    if gamma > 1:  # the peak enhancement: S(wp) = gamma * C(gamma) * S_PM(wp)
        wp = np.array([2 * math.pi / tp])
        ratio = s(wp)[0] / spectra.bretschneider(hs, tp)(wp)[0]
        assert ratio == pytest.approx(gamma * spectra.jonswap_normalisation(gamma), rel=1e-9)


def three_hour_record(discretisation: str, dt: float = 0.5):
    spec = SeaSpec(kind="irregular", spectrum="jonswap", hs=2.0, tp=8.0, gamma=3.3, discretisation=discretisation,
                   repeat_period=THREE_HOURS, n_components=2000, seed=11)
    sea = build_sea(spec)
    t = np.arange(0.0, THREE_HOURS, dt)
    return spec, sea, t, sea.elevation(t)


def test_three_hour_jonswap_record_reproduces_hs_tp_and_power() -> None:
    """Acceptance: Hs = 4 std(eta) and Tp (periodogram peak) of the realised record within 1 %; the
    incident power per metre rho g^2 Hs^2 Te / (64 pi) from the record's Hs and Te equals the power
    carried by the components (sum rho g a^2/2 c_g) and that of the continuous spectrum
    (rho g^2 m_-1 / 2, deep water) within 1 %."""
    spec, sea, t, eta = three_hour_record("equal_frequency")
    stats = spectra.record_statistics(t, eta)
    assert stats["hs"] == pytest.approx(spec.hs, rel=0.01)
    assert stats["tp"] == pytest.approx(spec.tp, rel=0.01)
    power = spectra.deep_water_power(stats["hs"], stats["te"], RHO, G)
    assert power == pytest.approx(spectra.component_power(sea.components, RHO, G), rel=0.01)
    m_1 = spectra.moment(spectra.jonswap(spec.hs, spec.tp, spec.gamma), -1, 1e-3, 60.0)
    assert power == pytest.approx(RHO * G**2 * m_1 / 2, rel=0.01)


def test_equal_energy_record_reproduces_hs_and_power() -> None:
    """Equal-energy components do not repeat; the record's Hs and power still match (Tp from a raw
    periodogram of a non-repeating record is noisy, so it is not claimed here)."""
    spec, sea, t, eta = three_hour_record("equal_energy")
    stats = spectra.record_statistics(t, eta)
    assert stats["hs"] == pytest.approx(spec.hs, rel=0.01)
    m_1 = spectra.moment(spectra.jonswap(spec.hs, spec.tp, spec.gamma), -1, 1e-3, 60.0)
    assert spectra.deep_water_power(stats["hs"], stats["te"], RHO, G) == pytest.approx(RHO * G**2 * m_1 / 2, rel=0.02)
    assert len(sea.components.omega) == 2000 and np.ptp(sea.components.amplitude) == 0  # equal energy


def test_record_does_not_drift_over_three_hours() -> None:
    """An equal-frequency sea repeats exactly after its repeat period: the elevation three hours on
    (block evaluation, and one time at a time as the FMU does) equals the first minutes'."""
    _, sea, t, eta = three_hour_record("equal_frequency")
    first = t[:1200]
    np.testing.assert_allclose(sea.elevation(first + THREE_HOURS), eta[:1200], atol=1e-9)
    np.testing.assert_allclose([sea.elevation(float(x) + THREE_HOURS) for x in first[::97]], eta[:1200:97],
                               atol=1e-9)


def test_same_seed_same_sea_and_the_phases_are_pcg64() -> None:
    spec = SeaSpec(kind="irregular", spectrum="pierson_moskowitz", hs=1.5, tp=7.0, discretisation="equal_energy",
                   n_components=50, seed=2024)
    a, b = build_sea(spec), build_sea(spec)
    np.testing.assert_array_equal(a.components.phase, b.components.phase)
    other = build_sea(SeaSpec(**{**spec.to_json(), "seed": 2025}))
    assert not np.allclose(other.components.phase, a.components.phase)
    # Documented contract: phases are Generator(PCG64(seed)).random() * 2 pi, in frequency order.
    expected = np.random.Generator(np.random.PCG64(2024)).random(50) * 2 * math.pi
    np.testing.assert_array_equal(a.components.phase, expected)


def test_fully_developed_pierson_moskowitz_peak() -> None:
    """Without tp, omega_p = 0.4 sqrt(g / Hs) (fully developed sea)."""
    spec = SeaSpec(kind="irregular", spectrum="pierson_moskowitz", hs=4.0, seed=1, repeat_period=2000.0)
    assert spec.peak_period() == pytest.approx(2 * math.pi / (0.4 * math.sqrt(G / 4.0)))


def test_cos_2s_spreading_distribution() -> None:
    """D integrates to one, and the mean of cos(theta - theta_0) over D is s / (s + 1) (closed form)."""
    for s in (1.0, 4.0, 15.0):
        x = np.linspace(-math.pi, math.pi, 200_001)
        d = spectra.spreading_function(x, s)
        assert np.trapezoid(d, x) == pytest.approx(1.0, rel=1e-8)
        directions = spectra.spreading_directions(s, 201, heading=0.3)
        assert np.mean(np.cos(directions - 0.3)) == pytest.approx(s / (s + 1), rel=2e-3)


def test_spread_sea_keeps_the_energy() -> None:
    spec = SeaSpec(kind="irregular", spectrum="jonswap", hs=2.0, tp=8.0, discretisation="equal_energy",
                   n_components=100, spreading_s=4.0, n_directions=9, heading=math.radians(30))
    sea = build_sea(spec)
    assert len(sea.components.omega) == 900 and not sea.components.unidirectional
    m0 = np.sum(sea.components.amplitude**2) / 2
    lo, hi = 0.5 * 2 * math.pi / 8, 6 * 2 * math.pi / 8
    assert m0 == pytest.approx(spectra.moment(spectra.jonswap(2.0, 8.0), 0, lo, hi), rel=1e-4)


def test_dispersion_and_group_velocity() -> None:
    """omega^2 = g k tanh(k h); c_g -> g / (2 omega) in deep water and sqrt(g h) in shallow water."""
    w = np.array([0.3, 1.0, 2.0])
    k = wavenumber(w, 20.0, G)
    np.testing.assert_allclose(G * k * np.tanh(k * 20.0), w**2, rtol=1e-12)
    np.testing.assert_allclose(group_velocity(w, math.inf, G), G / (2 * w))
    assert group_velocity(np.array([1e-3]), 5.0, G)[0] == pytest.approx(math.sqrt(G * 5.0), rel=1e-5)


# ---------------------------------------------------------------------- imported data
def jonswap_record(dt: float = 0.1, duration: float = 600.0):
    sea = build_sea(SeaSpec(kind="irregular", hs=1.0, tp=6.0, discretisation="equal_energy", n_components=150, seed=5))
    t = np.arange(0.0, duration, dt)
    return t, sea.elevation(t)


def test_elevation_record_round_trip_csv_and_hdf5(tmp_path) -> None:
    t, eta = jonswap_record()
    csv = tmp_path / "eta.csv"
    rows = "\n".join(f"{a:.17g},{b:.17g}" for a, b in zip(t, eta, strict=True))
    csv.write_text("# measured at the origin\nt,eta\n" + rows)
    h5 = tmp_path / "eta.h5"
    with h5py.File(h5, "w") as f:
        f["time"], f["elevation"] = t, eta
    a = read_elevation(csv)
    b = read_elevation(h5, time_dataset="time", elevation_dataset="elevation")
    np.testing.assert_array_equal(a.eta, eta)
    np.testing.assert_array_equal(b.eta, eta)
    assert a.dt == pytest.approx(0.1)
    # As Fourier components the record is reproduced at its samples (one period of a Fourier series).
    comps = a.components()
    np.testing.assert_allclose(comps.elevation(t), eta - eta.mean(), atol=1e-10 * np.abs(eta).max())
    assert a(t[123] + 0.05) == pytest.approx(0.5 * (eta[123] + eta[124]))  # linear between samples


@pytest.mark.parametrize("text, fragment", [
    ("t,eta\n0,0\n0.1,0.1\n0.3,0\n0.4,0.2\n", "uniformly sampled"),
    ("a,b,c\n0,0,0\n0.1,0,1\n", "does not name the time column"),
    ("0 0 1\n0.1 0 1\n", "3 columns and no header row"),
    ("t eta\n0 0\n0.1\n", "1 values, expected 2"),
    ("t,eta\n0,0\n0.1,nan\n0.2,0\n0.3,0\n", "non-finite"),
    ("t,eta\n0,0\n0.1,abc\n", "not a number"),
    ("t,eta\n", "no data rows"),
])
def test_malformed_elevation_records_are_named(tmp_path, text, fragment) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(WaveDataError, match=fragment) as info:
        read_elevation(path)
    assert str(path) in str(info.value)


def test_imported_spectrum_in_hertz_gives_the_same_sea(tmp_path) -> None:
    """A JONSWAP tabulated per Hz (S_f = 2 pi S_omega) realises the same components as the formula."""
    s = spectra.jonswap(1.5, 7.0)
    f = np.linspace(0.01, 1.0, 4000)
    path = tmp_path / "spec.csv"
    path.write_text("f,S\n" + "\n".join(f"{a:.17g},{b:.17g}" for a, b in zip(f, 2 * math.pi * s(2 * math.pi * f),
                                                                         strict=True)))
    omega, density = read_spectrum(path)
    np.testing.assert_allclose(density, s(omega), rtol=1e-12)
    common = dict(kind="irregular", discretisation="equal_frequency", repeat_period=600.0, omega_min=0.5,
                  omega_max=4.0, seed=3)
    tab = build_sea(SeaSpec(spectrum="file", spectrum_file=str(path), **common)).components
    ref = build_sea(SeaSpec(spectrum="jonswap", hs=1.5, tp=7.0, **common)).components
    np.testing.assert_allclose(tab.amplitude, ref.amplitude, rtol=2e-3)  # linear interpolation of the table
    np.testing.assert_array_equal(tab.phase, ref.phase)


def test_phasor_clock_matches_the_exponential_over_long_and_uneven_runs() -> None:
    """The rotation shortcut of the excitation sum stays within 32 times the round-off of omega t
    itself (about 2e-16 * 4 rad/s * 2000 s = 2e-12 here): 20 000 steps of 0.1 s, then uneven steps and
    repeated times."""
    from hydro_fmu.waves import PhasorClock

    omega = np.linspace(0.3, 4.0, 500)
    clock = PhasorClock(omega)
    times = list(np.arange(20_000) * 0.1) + [2000.05, 2000.05, 2000.3, 2001.0, 2001.7, 2001.7, 2002.4]
    worst = 0.0
    for t in times:
        worst = max(worst, float(np.abs(clock(t) - np.exp(1j * omega * t)).max()))
    assert worst < 32 * 2.2e-16 * omega.max() * times[-1]
