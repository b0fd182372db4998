"""Make the elevation records of this folder (README.md): one known elevation in the forms users bring.

    python scenarios/data/elevation/make_files.py

eta(t) = 0.5 cos(2 pi t / 8) + 0.2 sin(2 pi t / 5 + 0.3) m, sampled every 0.1 s for 40 s (400 samples: the
record repeats seamlessly, both periods divide 40 s), written with 6 decimals in the text forms.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
from scipy.io import savemat

HERE = Path(__file__).resolve().parent


def elevation(t: np.ndarray) -> np.ndarray:
    return 0.5 * np.cos(2 * np.pi * t / 8) + 0.2 * np.sin(2 * np.pi * t / 5 + 0.3)


def main() -> None:
    t = np.round(np.arange(400) * 0.1, 10)
    eta = elevation(t)
    rows = [(f"{a:.1f}", f"{b:.6f}") for a, b in zip(t, eta, strict=True)]
    # Whitespace columns under MATLAB-style % comments (as a MATLAB script's fprintf or WEC-Sim users write them).
    (HERE / "eta_percent_comments.txt").write_text(
        "% wave elevation at the origin\n% column 1: time (s), column 2: elevation (m)\n"
        + "".join(f"{a}\t{b}\n" for a, b in rows))
    # A '#' comment, a whitespace header with units, space-aligned columns.
    (HERE / "eta_header_units.dat").write_text(
        "# elevation record\nTime [s]    Eta [m]\n" + "".join(f"{a:>8}  {b:>10}\n" for a, b in rows))
    # Comma-separated, no header, no comments.
    (HERE / "eta_plain.csv").write_text("".join(f"{a},{b}\n" for a, b in rows))
    # WEC-Sim's etaImport file: a MATLAB 5 .mat file with the N x 2 array etaData = [time, elevation].
    savemat(HERE / "etaData.mat", {"etaData": np.column_stack([t, eta])}, format="5")
    # The same array as MATLAB 7.3 writes it (HDF5 with MATLAB's 512-byte header; arrays stored transposed).
    path = HERE / "etaData_v73.mat"
    with h5py.File(path, "w", userblock_size=512) as f:
        f.create_dataset("etaData", data=np.column_stack([t, eta]).T)
    with open(path, "r+b") as handle:
        handle.write(b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: synthesised with h5py HDF5 schema 1.00 .")


if __name__ == "__main__":
    main()
