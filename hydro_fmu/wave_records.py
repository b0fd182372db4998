"""Imported wave data: elevation time series (text, WEC-Sim .mat, HDF5) and spectra (CSV).

Elevation record: uniformly sampled elevation at the world origin. Simulation time 0 is the
record's first sample. The forms read, detected from the file (:attr:`ElevationRecord.form` names
the one found, and the run's summary prints it):

* text, two columns (time in s, elevation in m), separated by whitespace, commas or semicolons;
  lines starting with ``%`` or ``#`` are comments (what MATLAB, WEC-Sim and most wave codes write),
  and so is anything after ``%`` or ``#`` on a line; an optional header row of column names;
* text with more columns: a header row must name the time column (``t``, ``time``) and the
  elevation column (``eta``, ``elevation``, ``wave_elevation``); units in brackets are allowed
  (``time [s]``, ``eta (m)``);
* WEC-Sim's ``etaImport``/``elevationImport`` file: a MATLAB ``.mat`` file holding one N x 2 array
  [time, elevation] (MATLAB 5 files through scipy, MATLAB 7.3 files through h5py); with several
  arrays, the one named ``etaData``, ``elevationData``, ``eta`` or ``data``;
* HDF5: datasets ``t`` and ``eta`` (names configurable).

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
import re
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
    form: str = ""  # the file's form as detected, e.g. "two columns, whitespace-separated, 3 comment lines"

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
    """Read an elevation record in any of the forms of the module docstring."""
    path = Path(path)
    if not path.is_file():
        raise WaveDataError(f"wave elevation file {path} does not exist")
    suffix = path.suffix.lower()
    if suffix in (".h5", ".hdf5"):
        t, eta = _read_h5(path, time_dataset, elevation_dataset)
        form = f"HDF5, datasets {time_dataset} and {elevation_dataset}"
    elif suffix == ".mat":
        t, eta, form = _read_mat(path)
    else:
        t, eta, form = _read_columns(path)
    record = _uniform_record(path, t, eta)
    return ElevationRecord(dt=record.dt, eta=record.eta, source=record.source, form=form)


TIME_NAMES = ("t", "time", "times", "time_s")
ELEVATION_NAMES = ("eta", "elevation", "wave_elevation", "surface_elevation", "eta_m", "wave")
MAT_NAMES = ("etaData", "elevationData", "eta", "data")
_SEPARATORS = {",": "comma", ";": "semicolon", None: "whitespace"}


def _column_name(text: str) -> str:
    """A header cell without units and quotes, lower case: 'Time [s]' -> 'time'."""
    text = re.sub(r"[\[(].*?[\])]", "", text).strip().strip("\"'").strip().lower()
    return re.sub(r"[\s\-]+", "_", text)


def _read_columns(path: Path) -> tuple[np.ndarray, np.ndarray, str]:
    """Time and elevation from a text table (module docstring), and the form found."""
    try:
        raw = path.read_text(encoding="utf-8-sig", errors="strict").splitlines()
    except UnicodeDecodeError:
        raise WaveDataError(f"{path}: not a text file (not UTF-8); an elevation record is a text table of time and "
                            "elevation, a WEC-Sim .mat file or an HDF5 file (.h5)") from None
    comments, rows = 0, []
    for number, line in enumerate(raw, start=1):
        stripped = line.strip()
        if stripped[:1] in ("%", "#"):
            comments += 1
            continue
        stripped = stripped.split("#")[0].split("%")[0].strip()
        if stripped:
            rows.append((number, stripped))
    if not rows:
        raise WaveDataError(f"{path}: the file is empty (no data rows, only blank or comment lines)")
    first = rows[0][1]
    sep = "," if "," in first else ";" if ";" in first else None
    split = (lambda text: [p.strip() for p in text.split(sep)]) if sep else str.split

    def numbers(text: str) -> list[float] | None:
        try:
            return [float(p) for p in split(text)]
        except ValueError:
            return None

    # A header's units in brackets may contain spaces ("Time [s]"): drop them before splitting on whitespace.
    header = None if numbers(first) is not None else split(re.sub(r"\s*[\[(][^\])]*[\])]", "", first))
    data_rows = rows[1:] if header is not None else rows
    width = len(header) if header is not None else len(split(data_rows[0][1])) if data_rows else 0
    if header is not None:
        names = [_column_name(h) for h in header]
        ti = next((i for i, n in enumerate(names) if n in TIME_NAMES), None)
        ei = next((i for i, n in enumerate(names) if n in ELEVATION_NAMES), None)
        if (ti is None or ei is None) and width == 2:
            ti, ei = 0, 1
        elif ti is None or ei is None:
            raise WaveDataError(
                f"{path}:{rows[0][0]}: the header row {first!r} has {width} columns but does not name the time column "
                f"({', '.join(TIME_NAMES)}) and the elevation column ({', '.join(ELEVATION_NAMES)}); name them so, or "
                "keep only two columns: time (s) and elevation (m)")
    elif width == 2:
        ti, ei = 0, 1
    else:
        raise WaveDataError(
            f"{path}:{data_rows[0][0]}: {width} columns and no header row: keep two columns, time (s) and elevation "
            f"(m), or add a header row naming the columns t and eta")
    data = _numeric_rows(path, data_rows, width, split,
                         f" (as in the {'header' if header is not None else 'first row'})")
    form = (f"{'two' if width == 2 else width} columns, {_SEPARATORS[sep]}-separated"
            + (f", header {first!r}" if header is not None else "")
            + (f", {comments} comment line{'s' if comments != 1 else ''}" if comments else ""))
    return data[:, ti], data[:, ei], form


def _read_mat(path: Path) -> tuple[np.ndarray, np.ndarray, str]:
    """WEC-Sim's etaImport file: one N x 2 array [time, elevation] in a MATLAB .mat file."""
    with open(path, "rb") as handle:
        head = handle.read(128)
    arrays: dict[str, np.ndarray] = {}
    if head[:8] == b"\x89HDF\r\n\x1a\n" or b"MATLAB 7.3" in head:
        import h5py

        version = "MATLAB 7.3"
        try:
            with h5py.File(path, "r") as f:
                for name, item in f.items():
                    if isinstance(item, h5py.Dataset) and item.dtype.kind in "fiu":
                        arrays[name] = np.asarray(item[()], dtype=float).T  # MATLAB's column-major order
        except OSError as exc:
            raise WaveDataError(f"{path}: not a readable MATLAB 7.3 (HDF5) file ({exc})") from None
    else:
        from scipy.io import loadmat

        version = "MATLAB 5"
        try:
            content = loadmat(path)
        except Exception as exc:  # noqa: BLE001 - scipy raises several types for damaged files
            raise WaveDataError(f"{path}: not a readable MATLAB .mat file ({exc})") from None
        arrays = {k: np.asarray(v) for k, v in content.items()
                  if not k.startswith("__") and isinstance(v, np.ndarray) and v.dtype.kind in "fiu"}
    pairs = {k: (v if v.shape[1:] == (2,) else v.T) for k, v in arrays.items()
             if v.ndim == 2 and 2 in v.shape and max(v.shape) >= 2}
    if not pairs:
        found = ", ".join(f"{k} {tuple(v.shape)}" for k, v in arrays.items()) or "no numeric arrays"
        raise WaveDataError(f"{path}: a WEC-Sim elevation file holds one N x 2 array [time, elevation]; found {found}")
    name = next((n for n in MAT_NAMES if n in pairs), None)
    if name is None and len(pairs) > 1:
        raise WaveDataError(f"{path}: several N x 2 arrays ({', '.join(pairs)}); name the elevation record "
                            f"{MAT_NAMES[0]} (WEC-Sim's name)")
    name = name or next(iter(pairs))
    table = pairs[name].astype(float)
    bad = ~np.isfinite(table)
    if bad.any():
        raise WaveDataError(f"{path}: {name} is not finite at row {int(np.argwhere(bad)[0][0]) + 1}")
    return table[:, 0], table[:, 1], f"WEC-Sim elevation file ({version} .mat, array {name}, {len(table)} rows)"


def read_spectrum(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """Read a spectrum table; returns omega (rad/s) and S (m^2 s/rad)."""
    path = Path(path)
    if not path.is_file():
        raise WaveDataError(f"wave spectrum file {path} does not exist")
    columns = _read_csv(path)
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


def _read_csv(path: Path) -> dict[str, np.ndarray]:
    """A comma-separated table with a header row of column names (spectrum files)."""
    lines = [ln.split("#")[0].strip() for ln in path.read_text(errors="replace").splitlines()]
    rows = [(i + 1, ln) for i, ln in enumerate(lines) if ln]
    if not rows:
        raise WaveDataError(f"{path}: the file is empty")
    header = [h.strip() for h in rows[0][1].split(",")]
    data = _numeric_rows(path, rows[1:], len(header), lambda line: line.split(","), "")
    return {name: data[:, i] for i, name in enumerate(header)}


def _numeric_rows(path: Path, rows: list[tuple[int, str]], width: int, split, expected: str) -> np.ndarray:
    """The data rows (line number, text) as an array (len(rows), width) of finite numbers; an error names the line
    (``expected``: what the width comes from, for the message)."""
    values = []
    for number, line in rows:
        parts = split(line)
        if len(parts) != width:
            raise WaveDataError(f"{path}:{number}: {len(parts)} values, expected {width}{expected}")
        try:
            row = [float(p) for p in parts]
        except ValueError:
            raise WaveDataError(f"{path}:{number}: not a number in {line!r}") from None
        if not all(math.isfinite(v) for v in row):
            raise WaveDataError(f"{path}:{number}: non-finite value in {line!r}")
        values.append(row)
    if not values:
        raise WaveDataError(f"{path}: no data rows after the header")
    return np.array(values)


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
