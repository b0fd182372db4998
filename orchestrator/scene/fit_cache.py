"""The slow, deterministic fits a scene load repeats, kept on disk.

Loading a scene fits A_inf to the database (Ogilvie's relation or the Kramers-Kronig fit,
``hydro.added_mass_inf``): an impulse response on a fine time grid and its transforms, 0.4-5 s per
scene on this project's scenarios, at every run, resume, sweep case and test. The result depends only
on the database's arrays, a few settings and the code that computes it, so it is stored once in
``$WEC_COSIM_CACHE/fits`` (default ``~/.cache/wec-cosim/fits``) under a key that hashes all three (the
code: the computing module and every toolkit module it imports, as for the compiled kernels,
:func:`fmu_base._jit.source_stamp`). Another database, setting or version of the code is another key;
nothing is ever reused across them.

Files are ``.npz`` archives of plain arrays read with ``allow_pickle=False`` (a cache file is data,
never code). A file that cannot be read is computed again and replaced; a cache folder that cannot be
written leaves the result uncached, never fails the run.
"""

from __future__ import annotations

import hashlib
import os
import zipfile
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from fmu_base._jit import cache_base, source_stamp


def cache_root() -> Path:
    """``$WEC_COSIM_CACHE/fits`` (default ``~/.cache/wec-cosim/fits``)."""
    return cache_base() / "fits"


def fit_key(kind: str, inputs: Mapping[str, np.ndarray | float], code: str | Path) -> str:
    """Hash of the fit's name, every input (name, dtype, shape and bytes, in name order) and the source stamp
    of the module ``code`` that computes it."""
    digest = hashlib.sha256(f"{kind}\0{source_stamp(code)}\0".encode())
    for name in sorted(inputs):
        value = np.ascontiguousarray(inputs[name])
        if value.dtype.hasobject:
            raise TypeError(f"fit input {name!r} is not numeric: {inputs[name]!r}")
        digest.update(f"{name}\0{value.dtype.str}\0{value.shape}\0".encode())
        digest.update(value.tobytes())
    return digest.hexdigest()[:32]


def cached_fit(kind: str, inputs: Mapping[str, np.ndarray | float], code: str | Path,
               compute: Callable[[], Mapping[str, np.ndarray | float]]) -> dict[str, np.ndarray]:
    """``compute()`` (named arrays) for these ``inputs``, from the cache when an earlier run stored it."""
    path = cache_root() / f"{kind}-{fit_key(kind, inputs, code)}.npz"
    try:
        with np.load(path, allow_pickle=False) as stored:
            return {name: stored[name] for name in stored.files}
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):  # absent, unreadable, corrupt
        pass
    result = {name: np.asarray(value) for name, value in compute().items()}
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        part = path.with_name(f"{path.stem}.{os.getpid()}.part.npz")
        np.savez(part, **result)
        os.replace(part, path)  # whole file or none: a reader never sees half of it
    except OSError:
        pass
    return result
