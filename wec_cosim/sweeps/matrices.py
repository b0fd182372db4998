"""Matrices of a sweep: every summary quantity on the grid (seeds combined), e.g. the power matrix.

``/matrices`` in the sweep file, rebuilt from the finished cases at the end of every session
(complete or not: a cell without a finished case is NaN):

* ``axes/<i>``: the values of axis i (attributes ``key``, ``unit``); root attribute ``keys``;
* for every summary path (``ptos/<p>/mean_power``, ``bodies/<b>/significant``...), an array of
  the grid's shape (times the quantity's own shape): the mean over a cell's seeds for means and
  significant values, the largest for maxima;
* ``ptos/<p>/mean_power_std``: standard deviation of the mean power over the seeds (NaN with one);
* ``mean_power`` (W): the sum over the PTOs (the device's power matrix), ``mean_power_std`` its standard
  deviation over the seeds; ``capture_width`` (m): it
  over the incident power per metre of crest; ``ptos/<p>/capture_width`` the same per PTO;
* ``seeds_done`` and ``failed``: finished and failed cases per cell.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import h5py
import numpy as np

from .grid import SweepPlan
from .store import SweepStore
from .summary import UNITS

LARGEST = ("max_power", "maximum", "max_force", "max_moment")


def assemble(store: SweepStore) -> None:
    """Write ``/matrices`` for the store's plan from the finished cases in the file."""
    plan = store.plan
    with store.open_file("a") as f:
        if "matrices" in f:
            del f["matrices"]
        m = f.create_group("matrices")
        m.attrs["keys"] = json.dumps([a.key for a in plan.axes])
        for i, axis in enumerate(plan.axes):
            values = list(axis.values)
            data = np.array(values, dtype=h5py.string_dtype()) if isinstance(values[0], str) else np.array(values)
            ds = m.create_dataset(f"axes/{i}", data=data)
            ds.attrs.update(key=axis.key, unit=axis.unit)
        for path, value in cell_statistics(f["cases"], plan).items():
            ds = m.create_dataset(path, data=value)
            ds.attrs["unit"] = UNITS.get(path.rsplit("/", 1)[-1], "m" if path.endswith("capture_width") else "")


def cell_statistics(cases: h5py.Group, plan: SweepPlan) -> dict[str, np.ndarray]:
    """Every quantity on the grid, seeds combined (module docstring)."""
    shape = plan.shape
    done = np.zeros(shape, dtype=int)
    failed = np.zeros(shape, dtype=int)
    samples: dict[str, dict[tuple, list]] = {}
    for case in plan.cases:
        g = cases.get(case.id)
        if g is None:
            continue
        if g.attrs["status"] != "ok":
            failed[case.index] += 1
            continue
        done[case.index] += 1
        g.visititems(lambda name, obj, idx=case.index: _collect(samples, name, obj, idx))
    out: dict[str, np.ndarray] = {"seeds_done": done, "failed": failed}
    for path, cells in samples.items():
        inner = np.shape(next(iter(cells.values()))[0])
        largest = path.rsplit("/", 1)[-1] in LARGEST
        grid = np.full(shape + inner, np.nan)
        std = np.full(shape, np.nan)
        for idx, values in cells.items():
            stack = np.array(values)
            grid[idx] = np.max(stack, axis=0) if largest else np.mean(stack, axis=0)
            if len(values) > 1 and not inner:
                std[idx] = np.std(stack, ddof=1)
        out[path] = grid
        if path.endswith("/mean_power"):
            out[path + "_std"] = std
    ptos = [p.name for p in plan.scenario.ptos if f"ptos/{p.name}/mean_power" in out]
    if ptos:
        out["mean_power"] = sum(out[f"ptos/{p}/mean_power"] for p in ptos)
        out["mean_power_std"] = np.full(shape, np.nan)
        for idx in samples[f"ptos/{ptos[0]}/mean_power"]:
            totals = np.sum([samples[f"ptos/{p}/mean_power"][idx] for p in ptos], axis=0)
            if len(totals) > 1:
                out["mean_power_std"][idx] = np.std(totals, ddof=1)
        if "incident_power" in out:
            with np.errstate(invalid="ignore", divide="ignore"):
                out["capture_width"] = out["mean_power"] / out["incident_power"]
                for p in ptos:
                    out[f"ptos/{p}/capture_width"] = out[f"ptos/{p}/mean_power"] / out["incident_power"]
    return out


def _collect(samples: dict, name: str, obj, index: tuple) -> None:
    if isinstance(obj, h5py.Dataset) and not name.startswith("series/"):
        samples.setdefault(name, {}).setdefault(index, []).append(obj[()])


@dataclass
class Matrices:
    """The ``/matrices`` group read back: axes (key, unit, values) and quantities."""

    keys: list[str]
    units: list[str]
    values: list[np.ndarray]
    data: dict[str, np.ndarray]

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(v) for v in self.values)


def read_matrices(f: h5py.File) -> Matrices:
    m = f["matrices"]
    keys = json.loads(m.attrs["keys"])
    axes = [m[f"axes/{i}"] for i in range(len(keys))]
    values = [a.asstr()[()] if h5py.check_string_dtype(a.dtype) else a[()] for a in axes]
    data: dict[str, np.ndarray] = {}
    m.visititems(lambda name, obj: data.__setitem__(name, obj[()])
                 if isinstance(obj, h5py.Dataset) and not name.startswith("axes/") else None)
    return Matrices(keys, [a.attrs["unit"] for a in axes], values, data)
