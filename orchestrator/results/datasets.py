"""Results, RAO and steady-state files as labelled :class:`xarray.Dataset` objects, and back.

The HDF5 files keep one dataset per body, PTO and joint (``docs/results.md``); the datasets here stack them along
named dimensions, the way Capytaine and WecOptTool users work:

========================  =====================================================================================
dimension                 labels
========================  =====================================================================================
``time``                  s (results files)
``omega``                 rad/s (RAO and steady-state files)
``body``                  body names (scenario order); coordinate ``hydro`` (the body has hydrodynamic forces)
``dof``                   surge, sway, heave, roll, pitch, yaw
``pto``                   PTO names
``joint``                 joint names (reactions)
``coordinate``            joint coordinates ``NAME[k]`` (k from 1, as the FMU's ``NAME.coordinate[k]``), with the
                          coordinates ``coordinate_joint`` and ``coordinate_name`` (``angle``, ``displacement``...)
``axis``                  x, y, z (world frame)
``load``                  Fx, Fy, Fz, Mx, My, Mz (reactions in the frequency domain)
``line``                  mooring lines (``catenary`` force elements)
========================  =====================================================================================

Every variable has the attributes ``long_name`` and ``units`` (SI, angles in radians); where the unit changes along
a dimension (metres for surge, radians for pitch; N for a linear PTO, N m for a rotary one) ``units`` names them
all (``"m or rad"``) and ``units_by_<dimension>`` lists the unit of each label. The file's root attributes (the
scenario's text, settings, versions, status...) are the dataset's attributes, unchanged (JSON stays text).

A results file read with :func:`results_dataset` and written with :func:`write_results` holds the same datasets and
attributes again, and reading that file gives an identical dataset. :func:`to_netcdf` writes NetCDF-4 that
``xarray.open_dataset`` reads with the same values, units and names (complex variables as ``<name>_real`` and
``<name>_imag``: :func:`open_netcdf` joins them again). :func:`to_pandas` gives a table indexed by time (or
frequency), one column per labelled series, for MHKiT and pandas users.

xarray and pandas are imported when a function here is called, not with this module.
"""

from __future__ import annotations

import json
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import h5py
import numpy as np

from orchestrator.errors import WecCosimError
from orchestrator.scenario import DOFS

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    import xarray as xr

    from orchestrator.scenario import Scenario

AXES = ("x", "y", "z")
LOADS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
DOF_UNITS = ("m", "m", "m", "rad", "rad", "rad")
LOAD_UNITS = ("N", "N", "N", "N m", "N m", "N m")

ENERGY = {
    "kinetic": "multibody kinetic energy (with the infinite-frequency added mass)",
    "potential": "multibody potential energy (gravity, buoyancy, springs, PTO stiffness, ropes)",
    "dissipated": "energy dissipated in the multibody model (PTO laws, dampers, ropes)",
    "external_work": "work of the external forces on the multibody model",
    "pto": "energy absorbed by the PTOs (the part of the dissipated energy they convert)",
    "balance": "multibody energy balance (zero for exact solutions)",
    "excitation_work": "work of the wave excitation force on the bodies",
    "radiation_work": "work of the radiation memory force on the bodies",
    "hydrostatic_work": "work of the hydrostatic force on the bodies",
    "viscous_work": "work of the viscous drag force on the bodies",
    "wave_balance": "wave-to-wire balance: work in - (PTO + radiated + dissipated + stored)",
}


def _xr():
    import xarray as xr

    return xr


def _attrs(long_name: str, units: str | list[str], by: str | None = None) -> dict[str, Any]:
    """``long_name`` and ``units``; a list of units (one per label of dimension ``by``) becomes ``units`` naming
    the distinct ones and ``units_by_<by>``."""
    if isinstance(units, str):
        return {"long_name": long_name, "units": units}
    distinct = list(dict.fromkeys(u for u in units if u))
    out: dict[str, Any] = {"long_name": long_name, "units": " or ".join(distinct)}
    if len(distinct) > 1 or len(distinct) < len(units):
        out[f"units_by_{by}"] = list(units)
    return out


def _text(value: Any) -> str:
    return value.decode() if isinstance(value, bytes) else str(value)


def stored_scenario(attrs: Any, filename: str = "") -> Scenario | None:
    """The scenario a file records (its ``scenario`` attribute), converted by the schema without the checks that
    need its files; None if there is none or it does not load."""
    from orchestrator.errors import ScenarioError
    from orchestrator.scenario import Scenario, schema

    try:
        return schema.load(Scenario, tomllib.loads(_text(attrs["scenario"])), filename)
    except (KeyError, ValueError, TypeError, ScenarioError, tomllib.TOMLDecodeError):
        return None


def _ordered(names: list[str], preferred: list[str]) -> list[str]:
    """``names`` in the order of ``preferred`` (the scenario's), the others after in their own order."""
    return [n for n in preferred if n in names] + [n for n in names if n not in preferred]


def pto_force_unit(scenario: Scenario | None, name: str) -> str:
    """N for a PTO on a translation (or between two points), N m on a rotation."""
    if scenario is None:
        return "N or N m"
    from mbd_fmu.joints import JOINT_COORDINATE_UNITS

    p = next((p for p in scenario.ptos if p.name == name), None)
    if p is None:
        return "N or N m"
    if p.joint:
        j = next((j for j in scenario.joints if j.name == p.joint), None)
        units = JOINT_COORDINATE_UNITS.get(j.kind, []) if j is not None else []
        k = p.joint_coordinate - 1
        return ("N m" if units[k][0] == "rad" else "N") if k < len(units) else "N or N m"
    if p.point:
        return "N"
    return "N m" if p.dof in ("roll", "pitch", "yaw") else "N"


def key_unit(scenario: Scenario | None, key: str, unit: str) -> str:
    """The unit of scenario key ``key`` for this scene: of a schema unit that names both ("N s/m or N m s/rad"),
    the translational one for a PTO on a translation, the rotational one for a PTO on a rotation."""
    parts = unit.split(" or ")
    name = key.split(".")
    if len(parts) != 2 or len(name) != 3 or name[0] != "ptos":
        return unit
    force = pto_force_unit(scenario, name[1])
    return parts[0] if force == "N" else parts[1] if force == "N m" else unit


def joint_coordinate_labels(scenario: Scenario | None, joint: str, count: int) -> list[tuple[str, str, str]]:
    """(label ``NAME[k]``, coordinate name, unit) of a joint's ``count`` coordinates."""
    from mbd_fmu.joints import JOINT_COORDINATE_NAMES, JOINT_COORDINATE_UNITS

    kind = None
    if scenario is not None:
        kind = next((j.kind for j in scenario.joints if j.name == joint), None)
    names = JOINT_COORDINATE_NAMES.get(kind, []) if kind else []
    units = [u for u, _ in JOINT_COORDINATE_UNITS.get(kind, [])] if kind else []
    return [(f"{joint}[{k + 1}]", names[k] if k < len(names) else str(k + 1), units[k] if k < len(units) else "")
            for k in range(count)]


def _rate_unit(unit: str) -> str:
    return f"{unit}/s" if unit else ""


# ----------------------------------------------------------------------------- results files
def _read_file(path: Path) -> tuple[dict[str, np.ndarray], dict[str, dict], dict[str, Any], list[str]]:
    """Datasets (time series cut to the rows they all hold), their attributes, root attributes, and the order of
    the datasets in the file."""
    from .results_file import read_results

    data = read_results(path)
    data.pop("attrs")
    with h5py.File(path, "r", swmr=True) as f:
        attrs = {k: v for k, v in f.attrs.items()}
        ds_attrs = {name: dict(f[name].attrs) for name in data}
    return data, ds_attrs, attrs, list(data)


def _group_names(data: dict[str, Any], group: str, leaf: str) -> list[str]:
    return [k.split("/")[1] for k in data if k.startswith(group + "/") and k.endswith("/" + leaf)
            and k.count("/") == 2]


def results_dataset(path: str | Path) -> xr.Dataset:
    """A results file of ``wec-cosim run`` as an :class:`xarray.Dataset` (module docstring)."""
    path = Path(path)
    if not path.is_file():
        raise WecCosimError(f"results file {path} does not exist")
    try:
        data, ds_attrs, attrs, _ = _read_file(path)
    except OSError as exc:
        raise WecCosimError(f"{path} is not a readable HDF5 file ({exc})") from None
    if "time" not in data:
        raise WecCosimError(f"{path} is not a results file of `wec-cosim run` (no /time); RAO, steady-state and "
                            "sweep files are read by open_dataset")
    return _results_from(data, ds_attrs, attrs, str(path))


def _results_from(data: dict[str, np.ndarray], ds_attrs: dict[str, dict], attrs: dict[str, Any],
                  filename: str) -> xr.Dataset:
    xr = _xr()
    scenario = stored_scenario(attrs, filename)
    used: set[str] = {"time"}
    t = data["time"]
    coords: dict[str, Any] = {"time": ("time", t, _attrs("time", "s"))}
    variables: dict[str, Any] = {}

    bodies = _ordered(sorted({k.split("/")[1] for k in data if k.startswith("bodies/")}),
                      [b.name for b in scenario.bodies] if scenario else [])
    if bodies:
        coords["body"] = ("body", bodies, {"long_name": "body"})
        coords["dof"] = ("dof", list(DOFS), {"long_name": "degree of freedom (world axes)"})
        hydro = [f"bodies/{b}/hydro_force" in data for b in bodies]
        coords["hydro"] = ("body", hydro, {"long_name": "the body has hydrodynamic forces"})
        for key, long_name, units in (
                ("displacement", "displacement from equilibrium about the centre of gravity (world frame)", DOF_UNITS),
                ("velocity", "velocity (world frame)", [f"{u}/s" for u in DOF_UNITS]),
                ("hydro_force", "hydrodynamic force and moment about the centre of gravity (world frame): "
                                "excitation, radiation memory, hydrostatics, drag", LOAD_UNITS)):
            paths = [f"bodies/{b}/{key}" for b in bodies]
            if not any(p in data for p in paths):
                continue
            stack = np.stack([data[p] if p in data else np.full((len(t), 6), np.nan) for p in paths], axis=1)
            used.update(p for p in paths if p in data)
            variables[key] = (("time", "body", "dof"), stack, _attrs(long_name, list(units), "dof"))

    ptos = _ordered(_group_names(data, "ptos", "power"), [p.name for p in scenario.ptos] if scenario else [])
    if ptos:
        coords["pto"] = ("pto", ptos, {"long_name": "power take-off"})
        forces = [f"ptos/{p}/force" for p in ptos]
        if all(f in data for f in forces):
            variables["pto_force"] = (("time", "pto"), np.stack([data[f] for f in forces], axis=1),
                                      _attrs("PTO force on the body (N, or N m on a rotation)",
                                             [pto_force_unit(scenario, p) for p in ptos], "pto"))
            used.update(forces)
        variables["pto_power"] = (("time", "pto"), np.stack([data[f"ptos/{p}/power"] for p in ptos], axis=1),
                                  _attrs("power absorbed by the PTO", "W"))
        used.update(f"ptos/{p}/power" for p in ptos)

    if "wave/elevation" in data:
        variables["wave_elevation"] = (("time",), data["wave/elevation"],
                                       _attrs("incident wave elevation at the world origin", "m"))
        used.add("wave/elevation")

    joints = _ordered(_group_names(data, "joints", "force"), [j.name for j in scenario.joints] if scenario else [])
    if joints:
        coords["joint"] = ("joint", joints, {"long_name": "joint"})
        coords["axis"] = ("axis", list(AXES), {"long_name": "world axis"})
        for key, long_name, unit in (("force", "joint reaction force on body 2 from body 1 (world frame)", "N"),
                                     ("moment", "joint reaction moment on body 2 from body 1 about the joint point "
                                                "(world frame)", "N m")):
            paths = [f"joints/{j}/{key}" for j in joints]
            variables[f"joint_{key}"] = (("time", "joint", "axis"), np.stack([data[p] for p in paths], axis=1),
                                         _attrs(long_name, unit))
            used.update(paths)
        labels: list[tuple[str, str, str]] = []
        columns: dict[str, list[np.ndarray]] = {"coordinate": [], "rate": []}
        for j in joints:
            if f"joints/{j}/coordinate" not in data:
                continue
            q = np.asarray(data[f"joints/{j}/coordinate"]).reshape(len(t), -1)
            labels += joint_coordinate_labels(scenario, j, q.shape[1])
            columns["coordinate"].append(q)
            columns["rate"].append(np.asarray(data[f"joints/{j}/rate"]).reshape(len(t), -1))
            used.update((f"joints/{j}/coordinate", f"joints/{j}/rate"))
        if labels:
            coords["coordinate"] = ("coordinate", [lab for lab, _, _ in labels], {"long_name": "joint coordinate"})
            coords["coordinate_joint"] = ("coordinate", [lab.rpartition("[")[0] for lab, _, _ in labels],
                                          {"long_name": "joint of the coordinate"})
            coords["coordinate_name"] = ("coordinate", [name for _, name, _ in labels],
                                         {"long_name": "name of the coordinate in its joint"})
            units = [u for _, _, u in labels]
            variables["joint_coordinate"] = (("time", "coordinate"), np.concatenate(columns["coordinate"], axis=1),
                                             _attrs("joint coordinate (relative displacement or angle)", units,
                                                    "coordinate"))
            variables["joint_rate"] = (("time", "coordinate"), np.concatenate(columns["rate"], axis=1),
                                       _attrs("joint coordinate rate", [_rate_unit(u) for u in units], "coordinate"))

    lines = _ordered(_group_names(data, "forces", "force"), [e.name for e in scenario.forces] if scenario else [])
    if lines:
        coords["line"] = ("line", lines, {"long_name": "mooring line"})
        coords.setdefault("axis", ("axis", list(AXES), {"long_name": "world axis"}))
        variables["line_force"] = (("time", "line", "axis"),
                                   np.stack([data[f"forces/{n}/force"] for n in lines], axis=1),
                                   _attrs("mooring line force on its body at the fairlead (world frame)", "N"))
        used.update(f"forces/{n}/force" for n in lines)

    for name in [k for k in data if k.startswith("energy/") and k.count("/") == 1]:
        term = name.split("/")[1]
        variables[f"energy_{term}"] = (("time",), data[name], _attrs(ENERGY.get(term, f"energy: {term}"), "J"))
        used.add(name)
    if "mbd/constraint_violation" in data:
        variables["constraint_violation"] = (("time",), data["mbd/constraint_violation"],
                                             _attrs("largest constraint residual", "m"))
        used.add("mbd/constraint_violation")

    for name in [k for k in data if k not in used]:  # anything else (control series...), by its path
        var = name.replace("/", "_")
        value = np.asarray(data[name])
        dims = ("time",) + tuple(f"{var}_{i}" for i in range(1, value.ndim)) if len(value) == len(t) and \
            value.ndim >= 1 else tuple(f"{var}_{i}" for i in range(value.ndim))
        unit = _text(ds_attrs.get(name, {}).get("unit", ""))
        variables[var] = (dims, value, {"long_name": name, "units": unit, "hdf5_path": name})
    return xr.Dataset(variables, coords=coords, attrs=dict(attrs))


def write_results(ds: xr.Dataset, path: str | Path) -> Path:
    """Write a dataset of :func:`results_dataset` as a results file (the layout of ``wec-cosim run``: every
    series extendable, the dataset's attributes as the root attributes); returns the path."""
    path = Path(path)
    series = results_paths(ds)
    path.parent.mkdir(parents=True, exist_ok=True)
    with h5py.File(path, "w", libver="latest") as f:
        for key, value in ds.attrs.items():
            f.attrs[key] = json.dumps(value) if isinstance(value, (dict, list)) else value
        for name, value in series.items():
            value = np.asarray(value)
            extendable = value.ndim >= 1 and len(value) == ds.sizes.get("time", -1)
            f.create_dataset(name, data=value, maxshape=(None,) + value.shape[1:] if extendable else None,
                             chunks=(max(1, min(len(value), 1024)),) + value.shape[1:] if extendable else None)
    return path


def results_paths(ds: xr.Dataset) -> dict[str, np.ndarray]:
    """The results file's datasets (path -> array) that a dataset of :func:`results_dataset` holds."""
    out: dict[str, np.ndarray] = {"time": ds["time"].values}
    bodies = [str(b) for b in ds["body"].values] if "body" in ds.coords else []
    hydro = ds["hydro"].values if "hydro" in ds.coords else [True] * len(bodies)
    for key in ("displacement", "velocity", "hydro_force"):
        if key in ds:
            for i, b in enumerate(bodies):
                if key != "hydro_force" or hydro[i]:
                    out[f"bodies/{b}/{key}"] = ds[key].transpose("time", "body", "dof").values[:, i, :]
    for key, leaf in (("pto_force", "force"), ("pto_power", "power")):
        if key in ds:
            for i, p in enumerate(ds["pto"].values):
                out[f"ptos/{p}/{leaf}"] = ds[key].transpose("time", "pto").values[:, i]
    if "wave_elevation" in ds:
        out["wave/elevation"] = ds["wave_elevation"].values
    for key in ("force", "moment"):
        if f"joint_{key}" in ds:
            for i, j in enumerate(ds["joint"].values):
                out[f"joints/{j}/{key}"] = ds[f"joint_{key}"].transpose("time", "joint", "axis").values[:, i, :]
    if "joint_coordinate" in ds:
        owners = [str(j) for j in ds["coordinate_joint"].values]
        for key in ("coordinate", "rate"):
            values = ds[f"joint_{key}"].transpose("time", "coordinate").values
            for j in dict.fromkeys(owners):
                out[f"joints/{j}/{key}"] = values[:, [k for k, o in enumerate(owners) if o == j]]
    if "line_force" in ds:
        for i, n in enumerate(ds["line"].values):
            out[f"forces/{n}/force"] = ds["line_force"].transpose("time", "line", "axis").values[:, i, :]
    for name in ds.data_vars:
        if str(name).startswith("energy_"):
            out[f"energy/{str(name)[len('energy_'):]}"] = ds[name].values
        elif name == "constraint_violation":
            out["mbd/constraint_violation"] = ds[name].values
        elif "hdf5_path" in ds[name].attrs:
            out[str(ds[name].attrs["hdf5_path"])] = ds[name].values
    return out


# ----------------------------------------------------------------------------- RAO and steady-state files
def _names(group: h5py.Group | None, leaf: str, preferred: list[str]) -> list[str]:
    if group is None:
        return []
    return _ordered([n for n in group if leaf in group[n]], preferred)


def _coordinate_labels(f: h5py.Group, joints: list[str], key: str, scenario: Scenario | None) -> list[tuple]:
    labels = []
    for j in joints:
        ds = f[f"joints/{j}/{key}"]
        stored = [_text(c) for c in ds.attrs.get("coordinates", [])]
        for lab, name, unit in joint_coordinate_labels(scenario, j, ds.shape[-1]):
            k = int(lab.rpartition("[")[2][:-1]) - 1
            labels.append((lab, stored[k] if k < len(stored) else name, unit, j))
    return labels


def _coordinate_coords(labels: list[tuple]) -> dict[str, Any]:
    return {"coordinate": ("coordinate", [lab[0] for lab in labels], {"long_name": "joint coordinate"}),
            "coordinate_joint": ("coordinate", [lab[3] for lab in labels], {"long_name": "joint of the coordinate"}),
            "coordinate_name": ("coordinate", [lab[1] for lab in labels],
                                {"long_name": "name of the coordinate in its joint"})}


def rao_dataset(path: str | Path) -> xr.Dataset:
    """A RAO file of ``wec-cosim rao`` as an :class:`xarray.Dataset`: complex responses per metre of wave amplitude
    (``exp(+i omega t)`` convention) on ``omega``; a heading sweep along ``heading``; the irregular-sea statistics
    with the prefix ``irregular_``."""
    xr = _xr()
    with h5py.File(path, "r") as f:
        attrs = dict(f.attrs)
        scenario = stored_scenario(attrs, str(path))
        omega = f["omega"][()]
        coords: dict[str, Any] = {"omega": ("omega", omega, _attrs("wave frequency", "rad/s"))}
        variables: dict[str, Any] = {}
        bodies = _names(f.get("bodies"), "rao", [b.name for b in scenario.bodies] if scenario else [])
        rao_units = [f"{u}/m" for u in DOF_UNITS]
        if bodies:
            coords["body"] = ("body", bodies, {"long_name": "body"})
            coords["dof"] = ("dof", list(DOFS), {"long_name": "degree of freedom (world axes)"})
            variables["body_rao"] = (("omega", "body", "dof"), np.stack([f[f"bodies/{b}/rao"][()] for b in bodies],
                                                                        axis=1),
                                     _attrs("body response per metre of wave amplitude (complex, exp(+i omega t))",
                                            rao_units, "dof"))
        ptos = _names(f.get("ptos"), "mean_power", [p.name for p in scenario.ptos] if scenario else [])
        if ptos:
            coords["pto"] = ("pto", ptos, {"long_name": "power take-off"})
            variables["pto_mean_power"] = (("omega", "pto"), np.stack([f[f"ptos/{p}/mean_power"][()] for p in ptos],
                                                                      axis=1),
                                           _attrs("mean absorbed power per m^2 of wave amplitude", "W/m^2"))
            if all(f"ptos/{p}/capture_width" in f for p in ptos):
                variables["pto_capture_width"] = (("omega", "pto"),
                                                  np.stack([f[f"ptos/{p}/capture_width"][()] for p in ptos], axis=1),
                                                  _attrs("capture width (mean power over incident power per metre "
                                                         "of crest)", "m"))
        if "incident_power" in f:
            variables["incident_power"] = (("omega",), f["incident_power"][()],
                                           _attrs("incident wave power per metre of crest per m^2 of wave amplitude",
                                                  "W/m^3"))
        joints = _names(f.get("joints"), "rao", [j.name for j in scenario.joints] if scenario else [])
        if joints:
            labels = _coordinate_labels(f, joints, "rao", scenario)
            if labels:
                coords.update(_coordinate_coords(labels))
                variables["joint_rao"] = (("omega", "coordinate"),
                                          np.concatenate([f[f"joints/{j}/rao"][()] for j in joints], axis=1),
                                          _attrs("joint coordinate response per metre of wave amplitude (complex)",
                                                 [f"{lab[2]}/m" if lab[2] else "" for lab in labels], "coordinate"))
            reactions = [j for j in joints if f"joints/{j}/reaction" in f]
            if reactions:
                coords["joint"] = ("joint", reactions, {"long_name": "joint"})
                coords["load"] = ("load", list(LOADS), {"long_name": "force and moment components (world frame)"})
                variables["joint_reaction"] = (
                    ("omega", "joint", "load"), np.stack([f[f"joints/{j}/reaction"][()] for j in reactions], axis=1),
                    _attrs("joint reaction on body 2 from body 1 per metre of wave amplitude, moment about the joint "
                           "point (complex)", [f"{u}/m" for u in LOAD_UNITS], "load"))
        if "heading_sweep" in f:
            g = f["heading_sweep"]
            coords["heading"] = ("heading", g["headings_deg"][()], _attrs("wave heading", "deg"))
            if bodies and "bodies" in g:
                variables["body_rao_by_heading"] = (
                    ("heading", "omega", "body", "dof"), np.stack([g[f"bodies/{b}/rao"][()] for b in bodies], axis=2),
                    _attrs("body response per metre of wave amplitude at each heading (complex)", rao_units, "dof"))
            if ptos and "ptos" in g:
                variables["pto_mean_power_by_heading"] = (
                    ("heading", "omega", "pto"), np.stack([g[f"ptos/{p}/mean_power"][()] for p in ptos], axis=2),
                    _attrs("mean absorbed power per m^2 of wave amplitude at each heading", "W/m^2"))
            if joints and "joints" in g and "coordinate" in coords:
                variables["joint_rao_by_heading"] = (
                    ("heading", "omega", "coordinate"),
                    np.concatenate([g[f"joints/{j}/rao"][()] for j in joints], axis=2),
                    dict(variables["joint_rao"][2], long_name="joint coordinate response per metre of wave "
                                                             "amplitude at each heading (complex)"))
        if "irregular" in f:
            g = f["irregular"]
            variables["irregular_wave_spectrum"] = (("omega",), g["wave_spectrum"][()],
                                                    _attrs("wave elevation spectrum of the scenario's sea",
                                                           "m^2 s/rad"))
            for key, value in g.attrs.items():
                attrs[f"irregular_{key}"] = value
            if bodies and "bodies" in g:
                spectrum = np.full((len(omega), len(bodies), 6), np.nan)
                significant = np.full((len(bodies), 6), np.nan)
                for i, b in enumerate(bodies):
                    cols = [DOFS.index(_text(d)) for d in g[f"bodies/{b}"].attrs["dofs"]]
                    spectrum[:, i, cols] = g[f"bodies/{b}/response_spectrum"][()]
                    significant[i, cols] = g[f"bodies/{b}/significant_response"][()]
                variables["irregular_response_spectrum"] = (
                    ("omega", "body", "dof"), spectrum,
                    _attrs("response spectrum in the scenario's sea", [f"{u}^2 s/rad" for u in DOF_UNITS], "dof"))
                variables["irregular_significant_response"] = (
                    ("body", "dof"), significant,
                    _attrs("significant response (4 sqrt(m0)) in the scenario's sea", list(DOF_UNITS), "dof"))
            if ptos and "ptos" in g:
                variables["irregular_mean_power"] = (("pto",), np.array([g[f"ptos/{p}/mean_power"][()] for p in ptos]),
                                                     _attrs("mean absorbed power in the scenario's sea", "W"))
    return xr.Dataset(variables, coords=coords, attrs=attrs)


def steady_dataset(path: str | Path) -> xr.Dataset:
    """A steady-state file of ``wec-cosim steady`` as an :class:`xarray.Dataset`: one entry per wave period along
    ``period`` (s); harmonics k = 0..N (complex amplitudes of exp(+i k omega t)); one synthesised period along
    ``sample`` (its times in ``period_time``); the solver's report per period."""
    xr = _xr()
    with h5py.File(path, "r") as f:
        attrs = dict(f.attrs)
        scenario = stored_scenario(attrs, str(path))
        groups = [f[f"periods/{k}"] for k in sorted(f["periods"], key=int)]
        omega = np.array([g.attrs["omega"] for g in groups])
        coords: dict[str, Any] = {"period": ("period", 2 * np.pi / omega, _attrs("wave period", "s")),
                                  "omega": ("period", omega, _attrs("wave frequency", "rad/s"))}
        variables: dict[str, Any] = {}
        n = max(int(g.attrs["harmonics"]) for g in groups)
        coords["harmonic"] = ("harmonic", np.arange(n + 1), {"long_name": "harmonic k of exp(+i k omega t)"})
        samples = max(len(g["time"]) for g in groups)
        coords["period_time"] = (("period", "sample"), _padded([g["time"][()] for g in groups], samples),
                                 _attrs("time within the period", "s"))
        for key, long_name, unit in (("amplitude", "wave amplitude", "m"), ("residual", "solver residual", ""),
                                     ("evaluations", "solver evaluations", ""),
                                     ("wall_time", "solver wall time", "s"),
                                     ("incident_power", "incident wave power per metre of crest", "W/m")):
            variables[key] = (("period",), np.array([g.attrs[key] for g in groups]), _attrs(long_name, unit))
        variables["converged"] = (("period",), np.array([bool(g.attrs["converged"]) for g in groups]),
                                  {"long_name": "the solver converged"})
        variables["message"] = (("period",), np.array([_text(g.attrs["message"]) for g in groups]),
                                {"long_name": "the solver's message"})
        first = groups[0]
        bodies = _names(first.get("bodies"), "harmonics", [b.name for b in scenario.bodies] if scenario else [])
        if bodies:
            coords["body"] = ("body", bodies, {"long_name": "body"})
            coords["dof"] = ("dof", list(DOFS), {"long_name": "degree of freedom (world axes)"})
            variables["body_harmonics"] = (
                ("period", "harmonic", "body", "dof"),
                _per_period(groups, "bodies/{}/harmonics", bodies, n + 1),
                _attrs("body motion harmonics (complex)", list(DOF_UNITS), "dof"))
            variables["body_one_period"] = (
                ("period", "sample", "body", "dof"),
                _per_period(groups, "bodies/{}/one_period", bodies, samples),
                _attrs("body motion over one period", list(DOF_UNITS), "dof"))
        ptos = _names(first.get("ptos"), "mean_power", [p.name for p in scenario.ptos] if scenario else [])
        if ptos:
            coords["pto"] = ("pto", ptos, {"long_name": "power take-off"})
            variables["pto_mean_power"] = (("period", "pto"),
                                           np.array([[g[f"ptos/{p}/mean_power"][()] for p in ptos] for g in groups]),
                                           _attrs("mean absorbed power", "W"))
            variables["pto_capture_width"] = (("period", "pto"),
                                              np.array([[g[f"ptos/{p}"].attrs["capture_width"] for p in ptos]
                                                        for g in groups]), _attrs("capture width", "m"))
        joints = _names(first.get("joints"), "harmonics", [j.name for j in scenario.joints] if scenario else [])
        if joints:
            labels = _coordinate_labels(first, joints, "harmonics", scenario)
            if labels:
                coords.update(_coordinate_coords(labels))
                variables["joint_harmonics"] = (
                    ("period", "harmonic", "coordinate"),
                    _per_period(groups, "joints/{}/harmonics", joints, n + 1, join=np.concatenate),
                    _attrs("joint coordinate harmonics (complex)", [lab[2] for lab in labels], "coordinate"))
            coords["joint"] = ("joint", joints, {"long_name": "joint"})
            coords["load"] = ("load", list(LOADS), {"long_name": "force and moment components (world frame)"})
            variables["joint_reaction_harmonics"] = (
                ("period", "harmonic", "joint", "load"),
                _per_period(groups, "joints/{}/reaction_harmonics", joints, n + 1),
                _attrs("joint reaction harmonics on body 2 from body 1, moment about the joint point (complex)",
                       list(LOAD_UNITS), "load"))
    return xr.Dataset(variables, coords=coords, attrs=attrs)


def _per_period(groups: list[h5py.Group], path: str, names: list[str], length: int,
                join: Callable[..., np.ndarray] = np.stack) -> np.ndarray:
    """``path.format(name)`` of every group (wave period) and name, each padded to ``length`` rows: (period, rows,
    name, ...) with ``np.stack``, names' columns side by side with ``np.concatenate``."""
    return np.stack([join([_padded(g[path.format(name)][()], length) for name in names], axis=1) for g in groups])


def _padded(values: np.ndarray | list, length: int) -> np.ndarray:
    """Rows of ``values`` (or each array of a list, stacked) padded with NaN to ``length``."""
    if isinstance(values, list):
        return np.stack([_padded(v, length) for v in values])
    values = np.asarray(values)
    if len(values) == length:
        return values
    out = np.full((length,) + values.shape[1:], np.nan, dtype=np.result_type(values.dtype, float))
    out[: len(values)] = values
    return out


# ----------------------------------------------------------------------------- any file, NetCDF, pandas
def file_kind(path: str | Path) -> str:
    """``results``, ``rao``, ``steady``, ``sweep`` or ``netcdf``: what kind of file ``path`` is."""
    path = Path(path)
    if not path.is_file():
        raise WecCosimError(f"file {path} does not exist")
    try:
        with h5py.File(path, "r", swmr=True) as f:
            if f.attrs.get("format") == "wec-cosim sweep":
                return "sweep"
            if "omega" in f:
                return "rao"
            if "periods" in f:
                return "steady"
            if "time" in f:
                return "results"
            if "_NCProperties" in f.attrs or "wec_cosim_kind" in f.attrs:
                return "netcdf"
    except OSError as exc:
        raise WecCosimError(f"{path} is not a readable HDF5 file ({exc})") from None
    raise WecCosimError(f"{path} is neither a results file (/time), a RAO file (/omega), a steady-state file "
                        "(/periods), a sweep file nor a NetCDF export of one")


READERS: dict[str, Callable[[str | Path], Any]] = {
    "results": results_dataset, "rao": rao_dataset, "steady": steady_dataset}


def to_netcdf(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``ds`` as NetCDF-4 (``xarray.open_dataset`` reads it; complex variables as ``<name>_real`` and
    ``<name>_imag``, which :func:`open_netcdf` joins again); returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    out = ds.copy()
    for name in list(out.data_vars):
        if np.iscomplexobj(out[name].values):
            var = out[name]
            for part, values in (("real", var.real), ("imag", var.imag)):
                out[f"{name}_{part}"] = values.assign_attrs(var.attrs, complex_part=part)
            out = out.drop_vars(name)
    out.attrs = _netcdf_attrs(out.attrs)
    for name in out.variables:
        out[name].attrs = _netcdf_attrs(out[name].attrs)
    out.to_netcdf(path, engine="h5netcdf")
    return path


def _netcdf_attrs(attrs: dict[str, Any]) -> dict[str, Any]:
    """Attributes NetCDF can hold: booleans as 0 or 1, dictionaries as JSON."""
    return {k: int(v) if isinstance(v, (bool, np.bool_)) else json.dumps(v) if isinstance(v, dict) else v
            for k, v in attrs.items()}


def open_netcdf(path: str | Path) -> xr.Dataset:
    """A NetCDF file of :func:`to_netcdf` read back, complex variables joined (loaded into memory, file closed)."""
    xr = _xr()
    with xr.open_dataset(path, engine="h5netcdf") as opened:
        ds = opened.load()
    for name in [n for n in ds.data_vars if str(n).endswith("_real") and ds[n].attrs.get("complex_part") == "real"]:
        base = str(name)[: -len("_real")]
        if f"{base}_imag" in ds:
            attrs = {k: v for k, v in ds[name].attrs.items() if k != "complex_part"}
            ds[base] = (ds[name] + 1j * ds[f"{base}_imag"]).assign_attrs(attrs)
            ds = ds.drop_vars([name, f"{base}_imag"])
    return ds


def to_pandas(ds: xr.Dataset, index: str | None = None) -> pd.DataFrame:
    """A table of ``ds``: one row per label of ``index`` (default ``time``, else ``omega``, else ``period``), one
    column per labelled series (``displacement[float,heave]``, ``pto_power[pto]``, ``wave_elevation``); the units
    of the columns in ``DataFrame.attrs["units"]``. Variables without the index dimension are left out."""
    import pandas as pd

    index = index or next((d for d in ("time", "omega", "period") if d in ds.dims), None)
    if index is None:
        raise WecCosimError(f"to_pandas: the dataset has none of the dimensions time, omega, period (it has "
                            f"{', '.join(map(str, ds.dims))}); give index=")
    columns: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    for name, var in ds.data_vars.items():
        if index not in var.dims:
            continue
        others = [d for d in var.dims if d != index]
        values = var.transpose(index, *others).values.reshape(var.sizes[index], -1)
        labels = [tuple(str(ds[d].values[k]) if d in ds.coords else str(k) for d, k in zip(others, idx, strict=True))
                  for idx in np.ndindex(*[var.sizes[d] for d in others])]
        for col, label in enumerate(labels):
            key = f"{name}[{','.join(label)}]" if label else str(name)
            columns[key] = values[:, col]
            units[key] = _column_unit(var, others, label)
    frame = pd.DataFrame(columns, index=pd.Index(ds[index].values, name=index))
    frame.attrs["units"] = units
    return frame


def _column_unit(var: xr.DataArray, dims: list[str], label: tuple[str, ...]) -> str:
    for dim, lab in zip(dims, label, strict=True):
        by = var.attrs.get(f"units_by_{dim}")
        if by is not None:
            labels = [str(v) for v in var[dim].values] if dim in var.coords else []
            if lab in labels:
                return str(list(by)[labels.index(lab)])
    return str(var.attrs.get("units", ""))
