"""Imported wave data: elevation time series (CSV, HDF5) and spectra (CSV).

Elevation record: uniformly sampled elevation at the world origin. Simulation time 0 is the
record's first sample. CSV: a header row naming the columns ``t`` (s) and ``eta`` (m), comma
separated, ``#`` comments allowed. HDF5: datasets ``t`` and ``eta`` (names configurable).

As wave components (for frequency-domain superposition) the record is one period of a Fourier
series: component k of the real FFT, at omega_k = 2 pi k / (N dt), k = 1 .. N/2 (the mean is
removed; the Nyquist line is halved). At the samples the component sum reproduces the record to
round-off; outside [0, N dt) it repeats. Components above ``omega_max`` can be dropped (a
low-pass filter of the elevation).

Spectrum file (CSV): header ``omega,S`` (rad/s, m^2 s/rad) or ``f,S`` (Hz, m^2/Hz; converted by
S(omega) = S(f) / (2 pi)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .hdb import HydroDatabaseError
from .waves import WaveComponents


class WaveDataError(HydroDatabaseError):
    """An imported wave file is missing or malformed; the message names the file and the problem."""


@dataclass(frozen=True)
class ElevationRecord:
    """Uniformly sampled elevation eta (m) at times t0 + j dt (s)."""

    dt: float
    eta: np.ndarray
    source: str = ""

    @property
    def duration(self) -> float:
        """Length of one period of the record, N dt (s)."""
        return self.dt * len(self.eta)

    def times(self) -> np.ndarray:
        return np.arange(len(self.eta)) * self.dt

    def __call__(self, t: float | np.ndarray) -> float | np.ndarray:
        """Elevation at ``t`` (s from the first sample) by linear interpolation, periodic extension."""
        n = len(self.eta)
        tt = np.asarray(t, dtype=float) / self.dt
        j = np.floor(tt)
        frac = tt - j
        j0 = j.astype(np.int64) % n
        value = (1 - frac) * self.eta[j0] + frac * self.eta[(j0 + 1) % n]
        return float(value) if np.ndim(t) == 0 else value

    def components(self, omega_max: float = math.inf, heading: float = 0.0) -> WaveComponents:
        """The record as Fourier components (module docstring)."""
        n = len(self.eta)
        spectrum = np.fft.rfft(self.eta - np.mean(self.eta))
        k = np.arange(len(spectrum))
        amplitude = 2 * np.abs(spectrum) / n
        if n % 2 == 0:
            amplitude[-1] /= 2
        omega = 2 * math.pi * k / (n * self.dt)
        keep = (k > 0) & (omega <= omega_max) & (amplitude > 0)
        return WaveComponents(omega=omega[keep], amplitude=amplitude[keep], phase=np.angle(spectrum[keep]),
                              heading=heading)


def read_elevation(path: str | Path, *, time_dataset: str = "t", elevation_dataset: str = "eta") -> ElevationRecord:
    """Read an elevation record from ``.csv`` or ``.h5``/``.hdf5`` (module docstring)."""
    path = Path(path)
    if not path.is_file():
        raise WaveDataError(f"wave elevation file {path} does not exist")
    if path.suffix.lower() in (".h5", ".hdf5"):
        t, eta = _read_h5(path, time_dataset, elevation_dataset)
    else:
        columns = _read_csv(path, {"t", "eta"})
        t, eta = columns["t"], columns["eta"]
    return _uniform_record(path, t, eta)


def read_spectrum(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """Read a spectrum table; returns omega (rad/s) and S (m^2 s/rad)."""
    path = Path(path)
    if not path.is_file():
        raise WaveDataError(f"wave spectrum file {path} does not exist")
    columns = _read_csv(path, None)
    if "S" not in columns or not ({"omega", "f"} & set(columns)):
        raise WaveDataError(f"{path}: the header must name the columns omega,S (rad/s, m^2 s/rad) or f,S "
                            f"(Hz, m^2/Hz); found {', '.join(columns)}")
    if "omega" in columns:
        omega, density = columns["omega"], columns["S"]
    else:
        omega, density = 2 * math.pi * columns["f"], columns["S"] / (2 * math.pi)
    if len(omega) < 2 or np.any(np.diff(omega) <= 0) or omega[0] < 0:
        raise WaveDataError(f"{path}: frequencies must be non-negative and strictly increasing (at least two rows)")
    if np.any(density < 0):
        row = int(np.argmax(density < 0))
        raise WaveDataError(f"{path}: spectral density is negative in data row {row + 1}")
    return omega, density


def _read_csv(path: Path, required: set[str] | None) -> dict[str, np.ndarray]:
    lines = [ln.split("#")[0].strip() for ln in path.read_text(errors="replace").splitlines()]
    rows = [(i + 1, ln) for i, ln in enumerate(lines) if ln]
    if not rows:
        raise WaveDataError(f"{path}: the file is empty")
    header = [h.strip() for h in rows[0][1].split(",")]
    if required is not None and not required <= set(header):
        raise WaveDataError(f"{path}: the header row must name the columns {', '.join(sorted(required))} "
                            f"(found {', '.join(header)})")
    values = []
    for number, line in rows[1:]:
        parts = line.split(",")
        if len(parts) != len(header):
            raise WaveDataError(f"{path}:{number}: {len(parts)} values, expected {len(header)}")
        try:
            row = [float(p) for p in parts]
        except ValueError:
            raise WaveDataError(f"{path}:{number}: not a number in {line!r}") from None
        if not all(math.isfinite(v) for v in row):
            raise WaveDataError(f"{path}:{number}: non-finite value in {line!r}")
        values.append(row)
    if not values:
        raise WaveDataError(f"{path}: no data rows after the header")
    data = np.array(values)
    return {name: data[:, i] for i, name in enumerate(header)}


def _read_h5(path: Path, time_dataset: str, elevation_dataset: str) -> tuple[np.ndarray, np.ndarray]:
    import h5py

    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise WaveDataError(f"{path} is not a readable HDF5 file ({exc})") from None
    with f:
        out = []
        for name in (time_dataset, elevation_dataset):
            if name not in f:
                raise WaveDataError(f"{path}: missing dataset {name!r} (datasets: {', '.join(f)})")
            out.append(np.asarray(f[name][()], dtype=float).ravel())
    t, eta = out
    if len(t) != len(eta):
        raise WaveDataError(f"{path}: {time_dataset} has {len(t)} values but {elevation_dataset} has {len(eta)}")
    bad = ~np.isfinite(eta)
    if bad.any():
        raise WaveDataError(f"{path}: {elevation_dataset} is not finite at sample {int(np.argmax(bad))}")
    return t, eta


def _uniform_record(path: Path, t: np.ndarray, eta: np.ndarray) -> ElevationRecord:
    if len(t) < 4:
        raise WaveDataError(f"{path}: an elevation record needs at least four samples")
    steps = np.diff(t)
    dt = float(np.median(steps))
    if not dt > 0:
        raise WaveDataError(f"{path}: times must increase")
    off = np.flatnonzero(np.abs(steps - dt) > 1e-6 * dt)
    if len(off):
        j = int(off[0])
        raise WaveDataError(f"{path}: the record must be uniformly sampled (step {dt:g} s) but the step from "
                            f"t = {t[j]:g} s to {t[j + 1]:g} s is {steps[j]:g} s")
    return ElevationRecord(dt=dt, eta=np.asarray(eta, dtype=float), source=str(path))
