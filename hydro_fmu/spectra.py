"""Wave spectra, their discretisation into random-phase components, and directional spreading.

Spectra are one-sided, in angular frequency: S(omega) in m^2 s/rad, with m_n = int omega^n S
domega, Hs = 4 sqrt(m0), Te = 2 pi m_{-1} / m0 (energy period), Tp = 2 pi / omega_p.

* JONSWAP: S = C(gamma) (5/16) Hs^2 omega_p^4 omega^-5 exp(-5/4 (omega_p/omega)^4) gamma^r,
  r = exp(-(omega - omega_p)^2 / (2 sigma^2 omega_p^2)), sigma = 0.07 below omega_p, 0.09 above.
  C(gamma) makes 4 sqrt(m0) = Hs exactly: it is computed by quadrature (not the 1 - 0.287 ln gamma
  approximation, which is 1-2 % off for gamma far from 3.3).
* Bretschneider (two-parameter Pierson-Moskowitz): JONSWAP with gamma = 1 (C = 1 exactly).
* Pierson-Moskowitz (fully developed, one parameter): Bretschneider with omega_p = 0.4 sqrt(g/Hs)
  unless Tp is given.
* A tabulated spectrum (from a file), linearly interpolated and zero outside its range.

Discretisation into components ``a_k cos(omega_k t + phi_k)`` with phases uniformly random from a
``numpy.random.Generator(PCG64(seed))`` (``Generator.random``: 53-bit doubles of the PCG64 stream,
the same on every machine for a given seed):

* ``equal_frequency``: omega_k = k d_omega (integer multiples, so the sea repeats exactly after
  2 pi / d_omega: choose that at least the simulated time); a_k = sqrt(2 S(omega_k) d_omega).
  A record of whole repeat periods has variance sum a_k^2 / 2 exactly.
* ``equal_energy``: N bins of equal m0 between omega_min and omega_max; omega_k is the bin's
  median frequency (the inverse cumulative spectrum at the bin middle); a_k = sqrt(2 m0 / N).
  The sea does not repeat, and each component carries the same energy.

Directional spreading (cos-2s): D(theta) = G(s) cos^(2s)((theta - theta_0)/2), G(s) =
Gamma(s + 1) / (2 sqrt(pi) Gamma(s + 1/2)); M directions at the quantiles of D (equal weight
1/M each), every (frequency, direction) pair a component of amplitude a_k / sqrt(M) with its
own random phase.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.special import gammaln

from .waves import WaveComponents

Spectrum = Callable[[np.ndarray], np.ndarray]
DISCRETISATIONS = ("equal_frequency", "equal_energy")


def _jonswap_shape(omega: np.ndarray, omega_p: float, gamma: float) -> np.ndarray:
    """Unnormalised JONSWAP shape for Hs = 1 (PM part times peak enhancement)."""
    w = np.asarray(omega, dtype=float)
    out = np.zeros_like(w)
    pos = w > 0
    wp = w[pos]
    pm = (5.0 / 16.0) * omega_p**4 * wp**-5 * np.exp(-1.25 * (omega_p / wp) ** 4)
    if gamma != 1.0:
        sigma = np.where(wp <= omega_p, 0.07, 0.09)
        pm = pm * gamma ** np.exp(-((wp - omega_p) ** 2) / (2 * sigma**2 * omega_p**2))
    out[pos] = pm
    return out


def jonswap_normalisation(gamma: float) -> float:
    """C(gamma) such that the JONSWAP spectrum has 4 sqrt(m0) = Hs (quadrature to ~1e-10)."""
    if gamma == 1.0:
        return 1.0
    # Shape in omega / omega_p: integrate on a fine grid (the integrand vanishes at both ends).
    x = np.linspace(1e-3, 40.0, 400_001)
    m0 = np.trapezoid(_jonswap_shape(x, 1.0, gamma), x)
    return float(1.0 / (16.0 * m0))


def jonswap(hs: float, tp: float, gamma: float = 3.3) -> Spectrum:
    """JONSWAP spectrum S(omega) (m^2 s/rad) with significant wave height ``hs`` (m) and peak period ``tp`` (s)."""
    if not (hs >= 0 and tp > 0 and gamma >= 1):
        raise ValueError(f"JONSWAP needs hs >= 0, tp > 0 and gamma >= 1 (got {hs}, {tp}, {gamma})")
    omega_p = 2 * math.pi / tp
    scale = hs**2 * jonswap_normalisation(gamma)
    return lambda omega: scale * _jonswap_shape(omega, omega_p, gamma)


def bretschneider(hs: float, tp: float) -> Spectrum:
    """Two-parameter Pierson-Moskowitz (Bretschneider) spectrum."""
    return jonswap(hs, tp, 1.0)


def pierson_moskowitz_peak_period(hs: float, g: float = 9.81) -> float:
    """Peak period of a fully developed sea of height ``hs``: omega_p = 0.4 sqrt(g / hs)."""
    return 2 * math.pi / (0.4 * math.sqrt(g / hs))


def tabulated(omega: np.ndarray, density: np.ndarray) -> Spectrum:
    """Spectrum interpolated linearly from a table (rad/s, m^2 s/rad), zero outside the table."""
    omega = np.asarray(omega, dtype=float)
    density = np.asarray(density, dtype=float)
    return lambda w: np.interp(w, omega, density, left=0.0, right=0.0)


def moment(spectrum: Spectrum, n: int, omega_min: float, omega_max: float, points: int = 200_001) -> float:
    """Spectral moment m_n = int omega^n S domega over [omega_min, omega_max] (trapezoidal, fine grid)."""
    w = np.linspace(max(omega_min, 1e-9), omega_max, points)
    return float(np.trapezoid(w**n * spectrum(w), w))


@dataclass(frozen=True)
class Discretisation:
    """How to turn a spectrum into components.

    Attributes:
        method: ``equal_frequency`` or ``equal_energy``.
        omega_min, omega_max: frequency range (rad/s).
        repeat_period: equal frequency: the sea repeats after this time (s); d_omega = 2 pi / it.
        n_components: equal energy: number of components.
        seed: seed of the random phases.
    """

    method: str
    omega_min: float
    omega_max: float
    repeat_period: float = 0.0
    n_components: int = 0
    seed: int = 0

    def __post_init__(self) -> None:
        if self.method not in DISCRETISATIONS:
            raise ValueError(f"discretisation must be one of {DISCRETISATIONS}, not {self.method!r}")
        if not (0 <= self.omega_min < self.omega_max):
            raise ValueError(f"frequency range [{self.omega_min}, {self.omega_max}] rad/s is empty")
        if self.method == "equal_frequency" and not self.repeat_period > 0:
            raise ValueError("equal-frequency discretisation needs a positive repeat period")
        if self.method == "equal_energy" and self.n_components < 1:
            raise ValueError("equal-energy discretisation needs at least one component")


def discretise(spectrum: Spectrum, d: Discretisation) -> tuple[np.ndarray, np.ndarray, np.random.Generator]:
    """Frequencies (rad/s) and amplitudes (m) of the components, and the generator for the phases."""
    rng = np.random.Generator(np.random.PCG64(d.seed))
    if d.method == "equal_frequency":
        dw = 2 * math.pi / d.repeat_period
        k = np.arange(max(1, math.ceil(d.omega_min / dw - 1e-9)), math.floor(d.omega_max / dw + 1e-9) + 1)
        omega = k * dw
        amplitude = np.sqrt(2 * spectrum(omega) * dw)
    else:
        w = np.linspace(max(d.omega_min, 1e-9), d.omega_max, 200_001)
        s = spectrum(w)
        cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (s[1:] + s[:-1]) * np.diff(w))])
        m0 = cumulative[-1]
        if m0 <= 0:
            raise ValueError("the spectrum has no energy in the frequency range")
        targets = (np.arange(d.n_components) + 0.5) / d.n_components * m0
        omega = np.interp(targets, cumulative, w)
        amplitude = np.full(d.n_components, math.sqrt(2 * m0 / d.n_components))
    return omega, amplitude, rng


def held_variance(spectrum: Spectrum, d: Discretisation) -> float:
    """The variance of the discretised components over the spectrum's variance in ``[omega_min, omega_max]``
    (1 for a discretisation that keeps the sea's energy; equal energy keeps it by construction). An equal-frequency
    step 2 pi / repeat_period wider than the spectrum's peak leaves few or no components: 0 is still water."""
    w = np.linspace(max(d.omega_min, 1e-9), d.omega_max, 20_001)
    m0 = float(np.trapezoid(spectrum(w), w))
    if m0 <= 0:
        return 1.0
    _, amplitude, _ = discretise(spectrum, d)
    return float(np.sum(amplitude**2) / 2 / m0)


def spreading_directions(s: float, n: int, heading: float) -> np.ndarray:
    """``n`` equal-weight directions (rad) of the cos-2s distribution about ``heading``.

    Direction m is the quantile (m + 1/2)/n of D(theta) = G(s) cos^(2s)((theta - heading)/2) on
    (heading - pi, heading + pi), found from its cumulative distribution on a fine grid.
    """
    if n < 1 or s <= 0:
        raise ValueError(f"spreading needs s > 0 and at least one direction (got s = {s}, n = {n})")
    x = np.linspace(-math.pi, math.pi, 100_001)
    density = spreading_function(x, s)
    cdf = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(x))])
    cdf /= cdf[-1]
    return heading + np.interp((np.arange(n) + 0.5) / n, cdf, x)


def spreading_function(dtheta: np.ndarray, s: float) -> np.ndarray:
    """cos-2s spreading D(dtheta) = G(s) cos^(2s)(dtheta / 2) (1/rad; integrates to 1 over 2 pi)."""
    log_g = gammaln(s + 1) - gammaln(s + 0.5) - math.log(2 * math.sqrt(math.pi))
    return math.exp(log_g) * np.abs(np.cos(np.asarray(dtheta) / 2)) ** (2 * s)


def irregular_sea(
    spectrum: Spectrum,
    discretisation: Discretisation,
    heading: float = 0.0,
    spreading_s: float = 0.0,
    n_directions: int = 1,
) -> WaveComponents:
    """Random-phase components of a sea (unidirectional unless ``spreading_s`` > 0).

    Phases: ``Generator(PCG64(seed)).random(K) * 2 pi`` for the K components in order of
    frequency (and direction within a frequency).
    """
    omega, amplitude, rng = discretise(spectrum, discretisation)
    if spreading_s > 0 and n_directions > 1:
        directions = spreading_directions(spreading_s, n_directions, heading)
        omega = np.repeat(omega, n_directions)
        amplitude = np.repeat(amplitude, n_directions) / math.sqrt(n_directions)
        headings = np.tile(directions, len(omega) // n_directions)
    else:
        headings = np.full(len(omega), float(heading))
    keep = amplitude > 0
    phase = rng.random(len(omega)) * 2 * math.pi
    return WaveComponents(omega=omega[keep], amplitude=amplitude[keep], phase=phase[keep], heading=headings[keep])


# ---------------------------------------------------------------------- analysis of a record
def record_statistics(t: np.ndarray, eta: np.ndarray) -> dict[str, float]:
    """Hs, Tp, Te and the moments of a uniformly sampled elevation record, from its periodogram.

    Hs = 4 std(eta); the one-sided periodogram S_k = |FFT_k|^2 2 dt / (2 pi N) at omega_k =
    2 pi k / (N dt) gives m0, m_{-1} (Te = 2 pi m_{-1} / m0) and Tp = 2 pi / omega at the
    periodogram's maximum. With a record of whole repeat periods of an equal-frequency sea the
    periodogram lines fall exactly on the components.
    """
    t = np.asarray(t, dtype=float)
    eta = np.asarray(eta, dtype=float) - np.mean(eta)
    n = len(eta)
    dt = float(t[1] - t[0])
    spectrum = np.abs(np.fft.rfft(eta)) ** 2 * 2 * dt / (2 * math.pi * n)
    spectrum[0] = 0.0
    if n % 2 == 0:
        spectrum[-1] /= 2
    omega = 2 * math.pi * np.fft.rfftfreq(n, dt)
    d_omega = omega[1]
    m0 = float(np.sum(spectrum) * d_omega)
    m_1 = float(np.sum(spectrum[1:] / omega[1:]) * d_omega)
    peak = int(np.argmax(spectrum))
    return {
        "hs": 4 * float(np.std(eta)),
        "hm0": 4 * math.sqrt(m0),
        "tp": 2 * math.pi / omega[peak],
        "te": 2 * math.pi * m_1 / m0,
        "m0": m0,
    }


def deep_water_power(hs: float, te: float, rho: float = 1025.0, g: float = 9.81) -> float:
    """Incident wave power per metre of crest in deep water, rho g^2 Hs^2 Te / (64 pi) (W/m)."""
    return rho * g**2 * hs**2 * te / (64 * math.pi)


def component_power(waves: WaveComponents, rho: float = 1025.0, g: float = 9.81,
                    water_depth: float = math.inf) -> float:
    """Incident power per metre of crest of a sum of components: sum rho g a^2/2 c_g(omega) (W/m)."""
    from .waves import group_velocity

    cg = group_velocity(waves.omega, water_depth, g)
    return float(np.sum(rho * g * waves.amplitude**2 / 2 * cg))
