"""The sweep file (HDF5): every case's parameters, status, summary and optional time series.

Only the client process writes it, one case at a time (open, write, close), so the file is
consistent whatever the workers do and between any two cases. A case is written into
``/cases/<id>.part`` and renamed to ``/cases/<id>`` once complete: a group without the suffix is a
finished case, and a stopped sweep leaves at most one partial group, removed when it is opened again.

Layout (see docs/sweeps.md):

* root attributes: ``format`` = ``wec-cosim sweep``, ``format_version``, ``scenario`` (the scenario
  file's text), ``scenario_file``, ``base_scenario`` (JSON: every key outside ``[sweep]`` as the cases
  used it), ``fingerprint`` (its hash), ``method``,
  ``seeds``, ``transient``, ``axes`` (JSON: key, values, unit of each axis), ``cases`` (number of
  cases of the current grid), ``sessions`` (how many times the sweep was started), ``status``;
* ``/cases/<id>``: attributes ``params`` (JSON [[key, value], ...]), ``index`` (grid position),
  ``seed_index``, ``seed`` (-1: none derived), ``status`` (``ok`` or ``failed``), ``error``,
  ``wall_time`` (s), ``worker``, ``host``, ``pid``, ``session``, ``finished`` (UTC, ISO 8601); datasets:
  the summary (``ptos/<p>/mean_power``...) and, with ``sweep.time_series``, ``series/...`` (the results
  file's time, displacements, PTO force and power, wave elevation, joint coordinates and reactions);
* ``/matrices``: the assembled grid (:mod:`wec_cosim.sweeps.matrices`).
"""

from __future__ import annotations

import json
import time
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from orchestrator.errors import WecCosimError

from .case import CaseResult
from .grid import Case, SweepPlan, base_json
from .summary import UNITS

FORMAT = "wec-cosim sweep"
FORMAT_VERSION = 1
PART = ".part"


def is_sweep_file(f: h5py.File) -> bool:
    return f.attrs.get("format") == FORMAT


class SweepStore:
    """The sweep file of one plan: what is done, and the writing of each finished case."""

    def __init__(self, path: Path, plan: SweepPlan, session: int) -> None:
        self.path = path
        self.plan = plan
        self.session = session
        self.duplicates = 0

    @classmethod
    def open(cls, path: str | Path, plan: SweepPlan, lock_timeout: float = 60.0) -> SweepStore:
        """Create the file, or open an earlier one of the same scene to continue it (its cases are kept)."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        mode = "a" if path.exists() else "w"
        store = cls(path, plan, 1)
        with store.open_file(mode, lock_timeout) as f:
            if mode == "a":
                _check_same_scene(f, path, plan)
            sessions = int(f.attrs.get("sessions", 0)) + 1
            cases = f.require_group("cases")
            for name in [n for n in cases if n.endswith(PART)]:
                del cases[name]
            f.attrs.update({
                "format": FORMAT, "format_version": FORMAT_VERSION, "scenario": plan.scenario.text,
                "base_scenario": base_json(plan.scenario),
                "scenario_file": str(Path(plan.scenario.file).resolve()), "fingerprint": plan.fingerprint,
                "method": plan.method, "seeds": plan.seeds,
                "transient": -1.0 if plan.transient is None else plan.transient,
                "time_series": plan.time_series, "axes": json.dumps(axes_json(plan)), "cases": len(plan.cases),
                "sessions": sessions, "status": "running"})
        store.session = sessions
        return store

    def statuses(self) -> dict[str, str]:
        """Case id -> ``ok`` or ``failed`` for every finished case in the file."""
        with self.open_file("r") as f:
            return {name: g.attrs["status"] for name, g in f["cases"].items() if not name.endswith(PART)}

    def write(self, case: Case, result: CaseResult) -> bool:
        """Record a finished case; False (nothing written) if the file already holds it."""
        with self.open_file("a") as f:
            cases = f["cases"]
            if case.id in cases:
                if cases[case.id].attrs["status"] == "ok" or not result.ok:
                    self.duplicates += 1
                    return False
                del cases[case.id]  # a failed case run again with --retry-failed
            name = case.id + PART
            if name in cases:
                del cases[name]
            g = cases.create_group(name)
            g.attrs.update({
                "params": json.dumps([list(p) for p in case.params]), "index": np.array(case.index, dtype=int),
                "label": case.label(), "seed_index": case.seed_index, "seed": -1 if case.seed is None else case.seed,
                "status": result.status, "error": result.error, "wall_time": result.wall_time,
                "worker": result.worker, "host": result.host, "pid": result.pid, "session": self.session,
                "finished": datetime.now(UTC).isoformat(timespec="seconds")})
            for key, value in result.summary.items():
                ds = g.create_dataset(key, data=value)
                ds.attrs["unit"] = UNITS.get(key.rsplit("/", 1)[-1], "")
            for key, value in result.series.items():
                g.create_dataset(f"series/{key}", data=value, compression="gzip", compression_opts=4)
            cases.move(name, case.id)
        return True

    def finish(self, status: str) -> None:
        with self.open_file("a") as f:
            f.attrs["status"] = status

    def open_file(self, mode: str, lock_timeout: float = 60.0) -> h5py.File:
        """Open the file, waiting while another program (a reader) holds its lock."""
        deadline = time.monotonic() + lock_timeout
        while True:
            try:
                return h5py.File(self.path, mode, libver="latest")
            except OSError as exc:
                locked = "lock" in str(exc).lower()
                if not locked or time.monotonic() > deadline:
                    raise WecCosimError(f"sweep file {self.path}: cannot open it for writing ({exc})"
                                        + ("; another program holds it open" if locked else "")) from None
                time.sleep(0.2)


def _check_same_scene(f: h5py.File, path: Path, plan: SweepPlan) -> None:
    if not is_sweep_file(f):
        raise WecCosimError(f"{path} exists and is not a wec-cosim sweep file; choose another --out")
    if f.attrs.get("fingerprint") != plan.fingerprint:
        raise WecCosimError(
            f"{path} holds a sweep of a different scene ({f.attrs.get('scenario_file')}): the scenario outside "
            "[sweep] has changed since its cases were computed. Keep both: choose another --out (or delete the "
            "file to start again)")


def axes_json(plan: SweepPlan) -> list[dict[str, Any]]:
    return [{"key": a.key, "values": list(a.values), "unit": a.unit} for a in plan.axes]


def open_sweep_file(path: str | Path) -> h5py.File:
    """Open a sweep file to read, with a clear error for a missing, unreadable or foreign file."""
    path = Path(path)
    if not path.is_file():
        raise WecCosimError(f"sweep file {path} does not exist")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise WecCosimError(f"{path} is not a readable HDF5 file ({exc})") from None
    if not is_sweep_file(f):
        f.close()
        raise WecCosimError(f"{path} is not a wec-cosim sweep file")
    return f
