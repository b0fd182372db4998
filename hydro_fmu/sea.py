"""A sea state from its specification: regular, irregular (spectrum), imported elevation or still.

:class:`SeaSpec` is the plain, JSON-serialisable description that the scenario resolves and the
hydro FMU carries in its resources; :func:`build_sea` turns it into a :class:`Sea`: the wave
components (for excitation by frequency-domain superposition) and the elevation at the world
origin (the record itself for an imported elevation, else the component sum), both ramped.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from . import spectra
from .wave_records import ElevationRecord, read_elevation, read_spectrum
from .waves import Ramp, WaveComponents, regular_wave, still_water

KINDS = ("still", "regular", "irregular", "elevation")
SPECTRA = ("jonswap", "pierson_moskowitz", "bretschneider", "file")


@dataclass(frozen=True)
class SeaSpec:
    """What sea to make (SI units, angles in rad). Only the fields of ``kind`` matter.

    Attributes:
        kind: ``still``, ``regular``, ``irregular`` or ``elevation``.
        height, period, phase: regular wave (m crest to trough, s, rad at the origin).
        heading: main direction of propagation (rad, 0 = towards +x).
        ramp_time: half-cosine start-up ramp (s), 0 for none.
        spectrum: ``jonswap``, ``pierson_moskowitz``, ``bretschneider`` or ``file``.
        hs, tp, gamma: significant height (m), peak period (s; 0 = fully developed for
            Pierson-Moskowitz), JONSWAP peak enhancement.
        spectrum_file: CSV table (see :mod:`hydro_fmu.wave_records`).
        discretisation, repeat_period, n_components, omega_min, omega_max, seed: see
            :class:`hydro_fmu.spectra.Discretisation` (omega_max also low-passes a record).
        spreading_s, n_directions: cos-2s spreading exponent (0 = unidirectional), directions.
        elevation_file, time_dataset, elevation_dataset: imported elevation record.
        g: gravity (m/s^2), for the fully developed Pierson-Moskowitz peak period.
    """

    kind: str = "still"
    height: float = 0.0
    period: float = 0.0
    phase: float = 0.0
    heading: float = 0.0
    ramp_time: float = 0.0
    spectrum: str = "jonswap"
    hs: float = 0.0
    tp: float = 0.0
    gamma: float = 3.3
    spectrum_file: str = ""
    discretisation: str = "equal_frequency"
    repeat_period: float = 0.0
    n_components: int = 200
    omega_min: float = 0.0
    omega_max: float = 0.0
    seed: int = 0
    spreading_s: float = 0.0
    n_directions: int = 1
    elevation_file: str = ""
    time_dataset: str = "t"
    elevation_dataset: str = "eta"
    g: float = 9.81

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"unknown wave kind {self.kind!r}; expected one of {', '.join(KINDS)}")
        if self.kind == "irregular" and self.spectrum not in SPECTRA:
            raise ValueError(f"unknown spectrum {self.spectrum!r}; expected one of {', '.join(SPECTRA)}")

    def to_json(self) -> dict:
        return asdict(self)

    @classmethod
    def from_json(cls, data: dict) -> SeaSpec:
        return cls(**data)

    def with_files(self, folder: str | Path) -> SeaSpec:
        """The same spec with its file names taken relative to ``folder`` (FMU resources)."""
        changes = {}
        for key in ("spectrum_file", "elevation_file"):
            name = getattr(self, key)
            if name and not Path(name).is_absolute():
                changes[key] = str(Path(folder) / name)
        return SeaSpec(**{**asdict(self), **changes})

    def peak_period(self) -> float:
        """Tp (s) of a parametric spectrum (fully developed sea for Pierson-Moskowitz without tp)."""
        if self.spectrum == "pierson_moskowitz" and self.tp <= 0:
            return spectra.pierson_moskowitz_peak_period(self.hs, self.g)
        return self.tp


@dataclass
class Sea:
    """Wave components and the elevation at the world origin of one sea state."""

    components: WaveComponents
    ramp: Ramp
    record: ElevationRecord | None = None

    def unramped_elevation(self, t: float | np.ndarray) -> float | np.ndarray:
        """Incident elevation at the world origin (m) without the ramp: the record if imported."""
        return self.components.elevation(t) if self.record is None else self.record(t)

    def elevation(self, t: float | np.ndarray) -> float | np.ndarray:
        """Incident elevation at the world origin (m), ramped."""
        return self.unramped_elevation(t) * self.ramp(t if np.ndim(t) else float(t))


def build_sea(spec: SeaSpec) -> Sea:
    """Realise ``spec`` (files are read from the paths in it)."""
    ramp = Ramp(spec.ramp_time)
    if spec.kind == "still":
        return Sea(still_water(), ramp)
    if spec.kind == "regular":
        return Sea(regular_wave(spec.height, spec.period, spec.phase, spec.heading), ramp)
    if spec.kind == "elevation":
        record = read_elevation(spec.elevation_file, time_dataset=spec.time_dataset,
                                elevation_dataset=spec.elevation_dataset)
        omega_max = spec.omega_max if spec.omega_max > 0 else math.inf
        return Sea(record.components(omega_max, spec.heading), ramp, record)
    return Sea(spectra.irregular_sea(sea_spectrum(spec), discretisation(spec), spec.heading,
                                     spec.spreading_s, spec.n_directions), ramp)


def sea_spectrum(spec: SeaSpec) -> spectra.Spectrum:
    """S(omega) of an irregular sea."""
    if spec.spectrum == "file":
        return spectra.tabulated(*read_spectrum(spec.spectrum_file))
    if spec.spectrum == "jonswap":
        return spectra.jonswap(spec.hs, spec.tp, spec.gamma)
    return spectra.bretschneider(spec.hs, spec.peak_period())


def frequency_range(spec: SeaSpec) -> tuple[float, float]:
    """The discretised range: the spec's, else [0.5, 6] omega_p (all but ~0.1 % of the energy of a
    Bretschneider spectrum, whose energy above c omega_p is about 1.25 / c^4) or the file's range."""
    if spec.spectrum == "file":
        omega, _ = read_spectrum(spec.spectrum_file)
        lo, hi = float(omega[0]), float(omega[-1])
    else:
        wp = 2 * math.pi / spec.peak_period()
        lo, hi = 0.5 * wp, 6.0 * wp
    return (spec.omega_min if spec.omega_min > 0 else lo, spec.omega_max if spec.omega_max > 0 else hi)


def discretisation(spec: SeaSpec) -> spectra.Discretisation:
    lo, hi = frequency_range(spec)
    return spectra.Discretisation(spec.discretisation, lo, hi, repeat_period=spec.repeat_period,
                                  n_components=spec.n_components, seed=spec.seed)
