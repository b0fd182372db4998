"""Checkpoint files: every FMU state and the master's memory at one instant, for ``wec-cosim resume``.

One file per results file, ``<results>.checkpoint.h5``, replaced atomically at every checkpoint
(written to a temporary name, then renamed), so a crash at any moment leaves either the previous
or the new checkpoint, never half of one. Layout: ``/states/<component>`` the serialised FMU
state (``fmi2SerializeFMUstate`` bytes), ``/master`` the master's and step controller's memory,
both in the data-only layout of :mod:`fmu_base.state_codec` (JSON and raw numeric arrays, never
pickle: reading a checkpoint runs no code from it); attributes ``format`` ("wec-cosim
checkpoint"), ``format_version`` (:data:`FORMAT_VERSION`), ``time`` (s), ``rows`` (rows of the
results file that hold data up to this time), ``steps`` (macro steps taken), and what the checkpoint
belongs to and an integrity check over its data:

* ``scenario``: the SHA-256 of the run's resolved scenario parameters (:func:`scenario_fingerprint`:
  every key after defaults, ``--set`` overrides and ``--duration``), so a checkpoint of another run of the
  same scene (another wave height) is refused on resume;
* ``build``: the build keys of the FMUs that wrote the states (their file names carry the hash of the
  sources, the specification and the data), or of the physics sources for the in-process monolithic mode;
* ``sha256``: the SHA-256 over the states, the master memory, ``time``, ``rows``, ``steps``, ``scenario`` and
  ``build`` (:func:`checkpoint_digest`): a checkpoint changed after it was written (a radiation history scaled,
  ``rows`` set to 0) is refused before any FMU sees it. It is an integrity check, not a signature: a change
  followed by a recomputed digest passes it (the identity and the rows' fit to the results file are checked
  on resume all the same: :mod:`orchestrator.cosim.checkpoint_identity`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from fmu_base import state_codec
from orchestrator.errors import WecCosimError

FORMAT = "wec-cosim checkpoint"
FORMAT_VERSION = 2  # 2: scenario, build and sha256 attributes


def checkpoint_path(results: str | Path) -> Path:
    results = Path(results)
    return results.with_name(results.stem + ".checkpoint.h5")


# [simulation] keys that say where and how often a run writes its files, not what it computes: a resume may differ in
# them (a scenario changed in Python records only what changes the computation).
BOOKKEEPING = ("output", "flush_seconds", "checkpoint_every")


def scenario_fingerprint(scenario: object) -> str:
    """SHA-256 of a scenario's resolved parameters (every key of every section after defaults and overrides but the
    file-writing ones of ``BOOKKEEPING``; not the file's text, its path or comments): two runs with the same
    fingerprint compute the same thing."""
    values = {k: v for k, v in dataclasses.asdict(scenario).items() if not k.startswith("_")}
    for key in BOOKKEEPING:  # where and how often the run writes: not what it computes
        values.get("simulation", {}).pop(key, None)
    return hashlib.sha256(json.dumps(values, sort_keys=True, default=str).encode()).hexdigest()


def checkpoint_digest(states: dict[str, bytes], memory: bytes, numbers: dict[str, float | int],
                      identity: dict[str, str]) -> str:
    """SHA-256 over a checkpoint's data: each component's state (by name), the master memory, the numbers (time,
    rows, steps) and the identity (scenario, build)."""
    h = hashlib.sha256()
    for name in sorted(states):
        blob = bytes(states[name])
        h.update(name.encode() + b"\0" + len(blob).to_bytes(8, "little") + blob)
    h.update(len(memory).to_bytes(8, "little") + memory)
    h.update(json.dumps({k: numbers[k] for k in ("time", "rows", "steps")}, sort_keys=True).encode())
    h.update(json.dumps({k: identity.get(k, "") for k in ("scenario", "build")}, sort_keys=True).encode())
    return h.hexdigest()


def write_checkpoint(path: str | Path, checkpoint: dict, controller_state: dict, *, time: float, rows: int,
                     steps: int, identity: dict[str, str] | None = None) -> None:
    """Write atomically: the old checkpoint stays valid until the new one is complete. ``identity``: the run's
    ``scenario`` fingerprint and ``build`` key (module docstring)."""
    path = Path(path)
    tmp = path.with_name(path.name + f".{os.getpid()}.part")
    try:
        _write(tmp, checkpoint, controller_state, time=time, rows=rows, steps=steps, identity=identity or {})
    except RuntimeError as exc:  # h5py's report of a refused write (disk full)
        from .results_file import write_error

        tmp.unlink(missing_ok=True)
        raise write_error(exc, tmp) from None
    except OSError:
        tmp.unlink(missing_ok=True)
        raise
    os.replace(tmp, path)


def _write(tmp: Path, checkpoint: dict, controller_state: dict, *, time: float, rows: int, steps: int,
           identity: dict[str, str]) -> None:
    states = {name: bytes(blob) for name, blob in checkpoint["states"].items()}
    memory = state_codec.encode({"master": checkpoint["master"], "controller": controller_state})
    numbers = {"time": time, "rows": rows, "steps": steps}
    with h5py.File(tmp, "w") as f:
        for name, blob in states.items():
            f.create_dataset(f"states/{name}", data=np.void(blob))
        f.create_dataset("master", data=np.void(memory))
        f.attrs["format"] = FORMAT
        f.attrs["format_version"] = FORMAT_VERSION
        for key, value in numbers.items():
            f.attrs[key] = value
        for key in ("scenario", "build"):
            f.attrs[key] = identity.get(key, "")
        f.attrs["sha256"] = checkpoint_digest(states, memory, numbers, identity)


def read_checkpoint(path: str | Path) -> dict[str, Any]:
    """``{"checkpoint": {...}, "controller": {...}, "time", "rows", "steps", "identity": {"scenario", "build"}}``,
    its integrity checked (:func:`checkpoint_digest`) before anything is decoded."""
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
            raw = _blob(f, "master")
            out = {key: _number(f, key) for key in ("time", "rows", "steps")}
            identity = {key: str(f.attrs.get(key, "")) for key in ("scenario", "build")}
            stored = str(f.attrs.get("sha256", ""))
        if checkpoint_digest(states, raw, out, identity) != stored:
            raise state_codec.StateFormatError(
                "its data were changed after it was written (the SHA-256 over its states, memory, time, rows and "
                "identity does not match the one it carries)")
        memory = state_codec.decode(raw)
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
    out["identity"] = identity
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
