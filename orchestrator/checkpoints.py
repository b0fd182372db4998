"""Checkpoint files: every FMU state and the master's memory at one instant, for ``wec-cosim resume``.

One file per results file, ``<results>.checkpoint.h5``, replaced atomically at every checkpoint
(written to a temporary name, then renamed), so a crash at any moment leaves either the previous
or the new checkpoint, never half of one. Layout: ``/states/<component>`` the serialised FMU
state (``fmi2SerializeFMUstate`` bytes), ``/master`` the master's and step controller's memory
(pickled), attributes ``time`` (s), ``rows`` (rows of the results file that hold data up to this
time), ``steps`` (macro steps taken).
"""

from __future__ import annotations

import os
import pickle
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from .errors import WecCosimError


def checkpoint_path(results: str | Path) -> Path:
    results = Path(results)
    return results.with_name(results.stem + ".checkpoint.h5")


def write_checkpoint(path: str | Path, checkpoint: dict, controller_state: dict, *, time: float, rows: int,
                     steps: int) -> None:
    """Write atomically: the old checkpoint stays valid until the new one is complete."""
    path = Path(path)
    tmp = path.with_name(path.name + f".{os.getpid()}.part")
    with h5py.File(tmp, "w") as f:
        for name, blob in checkpoint["states"].items():
            f.create_dataset(f"states/{name}", data=np.void(bytes(blob)))
        memory = {"master": checkpoint["master"], "controller": controller_state}
        f.create_dataset("master", data=np.void(pickle.dumps(memory, protocol=pickle.HIGHEST_PROTOCOL)))
        f.attrs["time"] = time
        f.attrs["rows"] = rows
        f.attrs["steps"] = steps
    os.replace(tmp, path)


def read_checkpoint(path: str | Path) -> dict[str, Any]:
    """``{"checkpoint": {...}, "controller": {...}, "time", "rows", "steps"}``."""
    path = Path(path)
    if not path.is_file():
        raise WecCosimError(
            f"no checkpoint {path}: the run did not reach its first checkpoint; set simulation.checkpoint_every "
            "and run again")
    with h5py.File(path, "r") as f:
        states = {name: f["states"][name][()].tobytes() for name in f["states"]}
        memory = pickle.loads(f["master"][()].tobytes())
        out = {key: f.attrs[key].item() for key in ("time", "rows", "steps")}
    out["checkpoint"] = {"states": states, "master": memory["master"]}
    out["controller"] = memory["controller"]
    return out
