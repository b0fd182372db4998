"""A sweep file's matrices as an :class:`xarray.Dataset`: one dimension per swept key (named by the key, e.g.
``waves.hs``, with its unit), the device's power matrix and capture width, each PTO's mean and largest power
(dimension ``pto``), each body's significant and largest motion (``body``, ``dof``), each joint's largest reaction
(``joint``), the incident power and the number of finished and failed cases per cell. Units and long names as in
:mod:`orchestrator.results.datasets`; the sweep file's root attributes are the dataset's."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import h5py
import numpy as np

from orchestrator.errors import WecCosimError
from orchestrator.results.datasets import DOF_UNITS, key_unit, stored_scenario
from orchestrator.scenario import DOFS

from .matrices import read_matrices

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

# summary leaf -> (variable, long name, unit; None: per DOF)
PER_PTO = {"mean_power": ("pto_mean_power", "mean absorbed power (mean over the seeds)", "W"),
           "mean_power_std": ("pto_mean_power_std", "standard deviation of the mean power over the seeds", "W"),
           "max_power": ("pto_max_power", "largest absorbed power", "W"),
           "capture_width": ("pto_capture_width", "capture width", "m")}
PER_BODY = {"significant": ("significant", "significant motion (4 standard deviations)"),
            "maximum": ("maximum", "largest displacement from equilibrium")}
PER_JOINT = {"max_force": ("joint_max_force", "largest reaction force magnitude", "N"),
             "max_moment": ("joint_max_moment", "largest reaction moment magnitude", "N m")}
DEVICE = {"mean_power": ("device mean power: the power matrix (sum over the PTOs)", "W"),
          "mean_power_std": ("standard deviation of the device's mean power over the seeds", "W"),
          "capture_width": ("device capture width", "m"),
          "incident_power": ("incident wave power per metre of crest", "W/m"),
          "seeds_done": ("finished cases per cell", ""), "failed": ("failed cases per cell", "")}


def sweep_dataset(path: str | Path) -> xr.Dataset:
    """The matrices of a sweep file (module docstring)."""
    import xarray as xr

    path = Path(path)
    with h5py.File(path, "r", swmr=True) as f:
        if "matrices" not in f:
            raise WecCosimError(f"{path} is a sweep file without matrices (no session finished); run the sweep "
                                "again to assemble them")
        m = read_matrices(f)
        attrs = dict(f.attrs)
    scenario = stored_scenario(attrs, str(path))
    dims = list(m.keys)
    coords: dict[str, Any] = {key: (key, values, {"long_name": f"swept key {key}",
                                                  "units": key_unit(scenario, key, unit)})
                              for key, unit, values in zip(m.keys, m.units, m.values, strict=True)}
    variables: dict[str, Any] = {}
    grouped: dict[str, dict[str, dict[str, np.ndarray]]] = {"ptos": {}, "bodies": {}, "joints": {}}
    for name, value in m.data.items():
        parts = name.split("/")
        if len(parts) == 3 and parts[0] in grouped:
            grouped[parts[0]].setdefault(parts[2], {})[parts[1]] = value
        elif name in DEVICE:
            long_name, unit = DEVICE[name]
            variables[name] = (dims, value, {"long_name": long_name, "units": unit})
        else:
            extra = [f"{name.replace('/', '_')}_{i}" for i in range(value.ndim - len(dims))]
            variables[name.replace("/", "_")] = (dims + extra, value, {"long_name": name, "units": ""})
    order = {"ptos": [p.name for p in scenario.ptos] if scenario else [],
             "bodies": [b.name for b in scenario.bodies] if scenario else [],
             "joints": [j.name for j in scenario.joints] if scenario else []}
    labels = {"ptos": "pto", "bodies": "body", "joints": "joint"}
    for group, leaves in grouped.items():
        names = sorted({n for values in leaves.values() for n in values},
                       key=lambda n: order[group].index(n) if n in order[group] else len(order[group]))
        if not names:
            continue
        dim = labels[group]
        coords[dim] = (dim, names, {"long_name": {"pto": "power take-off", "body": "body", "joint": "joint"}[dim]})
        for leaf, values in leaves.items():
            stack = np.stack([values.get(n, np.full_like(next(iter(values.values())), np.nan)) for n in names],
                             axis=len(dims))
            if group == "bodies" and leaf in PER_BODY:
                var, long_name = PER_BODY[leaf]
                coords.setdefault("dof", ("dof", list(DOFS), {"long_name": "degree of freedom (world axes)"}))
                variables[var] = (dims + ["body", "dof"], stack,
                                  {"long_name": long_name, "units": "m or rad", "units_by_dof": list(DOF_UNITS)})
                continue
            table = PER_PTO if group == "ptos" else PER_JOINT if group == "joints" else {}
            var, long_name, unit = table.get(leaf, (f"{dim}_{leaf}", leaf, ""))
            extra = [f"{var}_{i}" for i in range(stack.ndim - len(dims) - 1)]
            variables[var] = (dims + [dim] + extra, stack, {"long_name": long_name, "units": unit})
    return xr.Dataset(variables, coords=coords, attrs=attrs)
