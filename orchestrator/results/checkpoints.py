"""Checkpoint files: every FMU state and the master's memory at one instant, for ``wec-cosim resume``.

One file per results file, ``<results>.checkpoint.h5``, replaced atomically at every checkpoint
(written to a temporary name, then renamed), so a crash at any moment leaves either the previous
or the new checkpoint, never half of one. Layout: ``/states/<component>`` the serialised FMU
state (``fmi2SerializeFMUstate`` bytes), ``/master`` the master's and step controller's memory,
both in the data-only layout of :mod:`fmu_base.state_codec` (JSON and raw numeric arrays, never
pickle: reading a checkpoint runs no code from it); attributes ``format`` ("wec-cosim
checkpoint"), ``format_version`` (:data:`FORMAT_VERSION`), ``time`` (s), ``rows`` (rows of the
results file that hold data up to this time), ``steps`` (macro steps taken).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from fmu_base import state_codec
from orchestrator.errors import WecCosimError

FORMAT = "wec-cosim checkpoint"
FORMAT_VERSION = 1


def checkpoint_path(results: str | Path) -> Path:
    results = Path(results)
    return results.with_name(results.stem + ".checkpoint.h5")


def write_checkpoint(path: str | Path, checkpoint: dict, controller_state: dict, *, time: float, rows: int,
                     steps: int) -> None:
    """Write atomically: the old checkpoint stays valid until the new one is complete."""
    path = Path(path)
    tmp = path.with_name(path.name + f".{os.getpid()}.part")
    try:
        _write(tmp, checkpoint, controller_state, time=time, rows=rows, steps=steps)
    except RuntimeError as exc:  # h5py's report of a refused write (disk full)
        from .results_file import write_error

        tmp.unlink(missing_ok=True)
        raise write_error(exc, tmp) from None
    except OSError:
        tmp.unlink(missing_ok=True)
        raise
    os.replace(tmp, path)


def _write(tmp: Path, checkpoint: dict, controller_state: dict, *, time: float, rows: int, steps: int) -> None:
    with h5py.File(tmp, "w") as f:
        for name, blob in checkpoint["states"].items():
            f.create_dataset(f"states/{name}", data=np.void(bytes(blob)))
        memory = {"master": checkpoint["master"], "controller": controller_state}
        f.create_dataset("master", data=np.void(state_codec.encode(memory)))
        f.attrs["format"] = FORMAT
        f.attrs["format_version"] = FORMAT_VERSION
        f.attrs["time"] = time
        f.attrs["rows"] = rows
        f.attrs["steps"] = steps


def read_checkpoint(path: str | Path) -> dict[str, Any]:
    """``{"checkpoint": {...}, "controller": {...}, "time", "rows", "steps"}``."""
    path = Path(path)
    if not path.is_file():
        raise WecCosimError(
            f"no checkpoint {path}: the run did not reach its first checkpoint; set simulation.checkpoint_every "
            "and run again")
    try:
        with h5py.File(path, "r") as f:
            if f.attrs.get("format") != FORMAT:
                raise state_codec.StateFormatError("it has no 'format' attribute of a wec-cosim checkpoint (a "
                                                   "checkpoint of an older version, or another file)")
            version = f.attrs.get("format_version")
            if version != FORMAT_VERSION:
                raise state_codec.StateFormatError(f"checkpoint format version {version} is not supported (this "
                                                   f"version reads {FORMAT_VERSION})")
            states = {name: _blob(f, f"states/{name}") for name in f["states"]}
            memory = state_codec.decode(_blob(f, "master"))
            out = {key: _number(f, key) for key in ("time", "rows", "steps")}
        if not isinstance(memory, dict) or not {"master", "controller"} <= set(memory):
            raise state_codec.StateFormatError("its master memory lacks the master's or the step controller's state")
        for name, blob in states.items():
            try:
                state_codec.read_layout(blob)  # checked here, before any FMU sees it
            except state_codec.StateFormatError as exc:
                raise state_codec.StateFormatError(f"the state of component {name!r}: {exc}") from None
    except state_codec.StateFormatError as exc:
        raise WecCosimError(f"checkpoint {path} cannot be used: {exc}; run the simulation again") from None
    except (OSError, KeyError, TypeError, ValueError) as exc:
        raise WecCosimError(f"checkpoint {path} is not a readable wec-cosim checkpoint ({type(exc).__name__}: "
                            f"{exc}); run the simulation again") from None
    out["checkpoint"] = {"states": states, "master": memory["master"]}
    out["controller"] = memory["controller"]
    return out


def _blob(f: h5py.File, name: str) -> bytes:
    value = f[name][()]
    if not isinstance(value, np.void):
        raise state_codec.StateFormatError(f"/{name} is not an opaque byte string")
    return value.tobytes()


def _number(f: h5py.File, key: str) -> float | int:
    value = f.attrs[key]
    value = value.item() if hasattr(value, "item") else value
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value != value or value < 0:
        raise state_codec.StateFormatError(f"attribute {key!r} is not a non-negative number")
    return value
