"""Make the BEMIO files of this folder (README.md): Capytaine 3.0 databases written with h5py in the layouts of
WEC-Sim's MATLAB BEMIO writer (``writeBEMIOH5``) and of the older Python ``bemio`` package (``write_hdf5``).

    python scenarios/data/bemio/make_files.py          # about two minutes on two cores

No file written by either writer could be had here, so these are synthesised: the coefficients are ours
(Capytaine, :mod:`hydro_fmu.bem`), the groups, dataset names, shapes, index orders, normalisations, string and
scalar storage and attributes follow each writer as described in README.md.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import h5py
import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[2]))

from hydro_fmu.bem import BemBody, BemSettings, BodyGeometry, compute_database, frequency_grid  # noqa: E402
from hydro_fmu.bemio_groups import realise  # noqa: E402
from hydro_fmu.hdb import HydroDatabase  # noqa: E402

STRING = h5py.string_dtype("utf-8")


# ---------------------------------------------------------------------- MATLAB writeBEMIOH5 layout
def _matlab(group: h5py.Group, name: str, value: object, description: str, units: str) -> None:
    """One dataset as MATLAB's h5create/h5write leave it: double, at least two dimensions, the dimensions reversed
    (a 1 x N row vector reads (N, 1), a scalar (1, 1)); strings variable-length, (1, 1)."""
    if isinstance(value, str):
        ds = group.create_dataset(name, data=np.array([[value]], dtype=object), dtype=STRING)
    else:
        arr = np.asarray(value, dtype=float)
        if arr.ndim == 0:
            arr = arr.reshape(1, 1)
        elif arr.ndim == 1:
            arr = arr.reshape(-1, 1)
        ds = group.create_dataset(name, data=arr)
    ds.attrs["description"] = description
    ds.attrs["units"] = units


def write_matlab_layout(hdb: HydroDatabase, path: Path, *, groups: bool, parts: str = "nan") -> None:
    """``parts``: ``nan`` writes the Froude-Krylov and scattering groups filled with NaN (BEMIO does so when the
    BEM run did not compute them), ``values`` the real parts, ``none`` no such groups."""
    rho, g, w, n = hdb.rho, hdb.g, hdb.omega, hdb.n_dofs
    real = realise(hdb) if groups else None
    with h5py.File(path, "w") as f:
        for b, name in enumerate(hdb.body_names):
            rows = slice(6 * b, 6 * b + 6)
            props = f.create_group(f"body{b + 1}/properties")
            _matlab(props, "name", name, "Name of rigid body", "")
            _matlab(props, "body_number", b + 1, "Number of rigid body from the BEM simulation", "")
            _matlab(props, "cg", hdb.cg[b], "Center of gravity", "m")
            _matlab(props, "cb", hdb.cb[b], "Center of buoyancy", "m")
            _matlab(props, "disp_vol", hdb.displaced_volume[b], "Displaced volume", "m^3")
            _matlab(props, "dof", 6, "Degrees of freedom", "")
            _matlab(props, "dof_start", 6 * b + 1, "Degrees of freedom", "")
            _matlab(props, "dof_end", 6 * b + 6, "Degrees of freedom", "")
            hc = f.create_group(f"body{b + 1}/hydro_coeffs")
            _matlab(hc, "linear_restoring_stiffness", hdb.hydrostatic_stiffness[b] / (rho * g),
                    "Hydrostatic stiffness matrix", "")
            ex = hc.create_group("excitation")
            _complex(ex, hdb.excitation[:, :, rows] / (rho * g), _matlab, "excitation force")
            for part, table in (("froude-krylov", hdb.froude_krylov), ("scattering", hdb.diffraction)):
                if parts == "none":
                    continue
                values = table[:, :, rows] / (rho * g) if parts == "values" else np.full(
                    hdb.excitation[:, :, rows].shape, np.nan + 1j * np.nan)
                _complex(ex.create_group(part), values, _matlab, f"{part} force")
            am = hc.create_group("added_mass")
            _matlab(am, "all", np.transpose(hdb.added_mass[:, rows, :], (1, 2, 0)) / rho, "Added mass",
                    "kg-m^2 (rotation); kg (translation)")
            _matlab(am, "inf_freq", hdb.added_mass_inf[rows, :] / rho, "Infinite frequency added mass",
                    "kg-m^2 (rotation); kg (translation)")
            rd = hc.create_group("radiation_damping")
            _matlab(rd, "all", np.transpose(hdb.radiation_damping[:, rows, :], (1, 2, 0)) / (rho * w),
                    "Radiation damping", "N-s/m (translation); N-m-s/rad (rotation)")
            if real is not None:
                irf = rd.create_group("impulse_response_fun")
                _matlab(irf, "K", np.transpose(real.kernel[:, rows, :], (1, 2, 0)) / rho, "Impulse response function",
                        "")
                _matlab(irf, "t", real.t, "Time", "s")
                _matlab(irf, "w", w, "Frequency", "rad/s")
                ss = rd.create_group("state_space")
                _matlab(ss, "it", real.order[rows], "Order of state space realization", "")
                _matlab(ss.create_group("A"), "all", real.a[rows], "State Space A Coefficient", "")
                _matlab(ss.create_group("B"), "all", real.b[rows], "State Space B Coefficient", "")
                _matlab(ss.create_group("C"), "all", real.c[rows] / rho, "State Space C Coefficient", "")
                _matlab(ss.create_group("D"), "all", np.zeros((6, n)), "State Space D Coefficient", "")
                exirf = ex.create_group("impulse_response_fun")
                _matlab(exirf, "f", np.transpose(real.ex_kernel[:, :, rows], (2, 0, 1)) / (rho * g),
                        "Impulse response function", "")
                _matlab(exirf, "t", real.ex_t, "Time", "s")
                _matlab(exirf, "w", w, "Frequency", "rad/s")
        sp = f.create_group("simulation_parameters")
        _matlab(sp, "scaled", 0, "Data is scaled", "")
        _matlab(sp, "wave_dir", np.degrees(hdb.headings), "Wave direction", "deg")
        _matlab(sp, "water_depth", hdb.water_depth, "Water depth", "m")
        _matlab(sp, "w", w, "Wave frequencies", "rad/s")
        _matlab(sp, "T", 2 * np.pi / w, "Wave periods", "s")
        _matlab(sp, "g", g, "Gravitational acceleration", "m/s^2")
        _matlab(sp, "rho", rho, "Water density", "kg/m^3")
        _matlab(f.create_group("bem_data"), "code", "CAPYTAINE", "BEM code", "")


def _complex(group: h5py.Group, values: np.ndarray, write, what: str) -> None:
    """(Nh, Nw, 6) complex, normalised -> re, im, mag, phase (6, Nh, Nw)."""
    v = np.transpose(values, (2, 0, 1))
    write(group, "re", v.real, f"Real component of {what}", "")
    write(group, "im", v.imag, f"Imaginary component of {what}", "")
    write(group, "mag", np.abs(v), f"Magnitude of {what}", "")
    write(group, "phase", np.angle(v), f"Phase angle of {what}", "rad")


# ---------------------------------------------------------------------- Python bemio write_hdf5 layout
def _python(group: h5py.Group, name: str, value: object, description: str, units: str) -> None:
    """One dataset as h5py's create_dataset(data=...) leaves numpy data: shapes as they are, scalars (), Python
    strings variable-length scalars; attributes ``units`` and ``description``."""
    ds = group.create_dataset(name, data=value)
    ds.attrs["units"] = units
    ds.attrs["description"] = description


def write_python_layout(hdb: HydroDatabase, path: Path, *, groups: bool) -> None:
    """Per body the properties (no dof/dof_start/dof_end), the coefficient arrays and bemio's per-entry
    ``components`` tables ([T, value] columns); deep water as the string ``infinite``."""
    rho, g, w, n = hdb.rho, hdb.g, hdb.omega, hdb.n_dofs
    period = 2 * np.pi / w
    real = realise(hdb, duration=20.0, step=0.1) if groups else None
    with h5py.File(path, "w") as f:
        for b, name in enumerate(hdb.body_names):
            rows = slice(6 * b, 6 * b + 6)
            key = f"body{b + 1}"
            props = f.create_group(f"{key}/properties")
            _python(props, "cg", hdb.cg[b], "Center of gravity", "m")
            _python(props, "cb", hdb.cb[b], "Center of buoyancy", "m")
            _python(props, "disp_vol", float(hdb.displaced_volume[b]), "Displaced volume", "m^3")
            _python(props, "name", name, "Name of rigid body", "")
            _python(props, "body_number", b, "Number of rigid body from the BEM simulation", "")
            hc = f.create_group(f"{key}/hydro_coeffs")
            if real is not None:
                irf = hc.create_group("radiation_damping/impulse_response_fun")
                kernel = np.transpose(real.kernel[:, rows, :], (1, 2, 0)) / rho
                _python(irf, "K", kernel, "Impulse response function", "")
                _python(irf, "t", real.t, "Time vector for the impulse response function", "s")
                _python(irf, "w", w, "Interpolated frequencies used to compute the impulse response function", "s")
                for m in range(6):
                    for k in range(n):
                        _python(irf, f"components/K/{m + 1}_{k + 1}", np.column_stack([real.t, kernel[m, k]]),
                                "Components of the IRF", "")
                ss = hc.create_group("radiation_damping/state_space")
                _python(ss, "A/all", real.a[rows], "State space A matrix", "")
                _python(ss, "B/all", real.b[rows], "State space B matrix", "")
                _python(ss, "C/all", real.c[rows] / rho, "State space C matrix", "")
                _python(ss, "D/all", np.zeros((6, n, 1)), "State space D matrix", "")
                _python(ss, "it", real.order[rows], "Order of state space realization", "")
                _python(ss, "r2t", np.ones((6, n)), "State space R^2 fit", "")
            _python(hc, "linear_restoring_stiffness", hdb.hydrostatic_stiffness[b] / (rho * g),
                    "Hydrostatic stiffness", "")
            ex = hc.create_group("excitation")
            norm = np.transpose(hdb.excitation[:, :, rows], (2, 0, 1)) / (rho * g)
            for part, value, unit in (("mag", np.abs(norm), ""), ("phase", np.angle(norm), "rad"),
                                      ("re", norm.real, ""), ("im", norm.imag, "")):
                _python(ex, part, value, f"{part} of excitation force", unit)
                for m in range(6):
                    for h in range(len(hdb.headings)):
                        _python(ex, f"components/{part}/{m + 1}_{h + 1}", np.column_stack([period, value[m, h]]),
                                f"{part} of excitation force", unit)
            for part, table in (("scattering", hdb.diffraction), ("froude-krylov", hdb.froude_krylov)):
                v = np.transpose(table[:, :, rows], (2, 0, 1)) / (rho * g)
                for comp, value in (("mag", np.abs(v)), ("phase", np.angle(v)), ("re", v.real), ("im", v.imag)):
                    _python(ex, f"{part}/{comp}", value, f"{comp} of {part} force", "")
            am = np.transpose(hdb.added_mass[:, rows, :], (1, 2, 0)) / rho
            rd = np.transpose(hdb.radiation_damping[:, rows, :], (1, 2, 0)) / (rho * w)
            _python(hc, "added_mass/all", am, "Added mass", "kg-m^2 (rotation); kg (translation)")
            _python(hc, "added_mass/inf_freq", hdb.added_mass_inf[rows, :] / rho, "Infinite frequency added mass",
                    "kg-m^2 (rotation); kg (translation)")
            _python(hc, "radiation_damping/all", rd, "Radiation damping", "N-s/m (translation); N-m-s/rad (rotation)")
            for m in range(6):
                for k in range(n):
                    _python(hc, f"added_mass/components/{m + 1}_{k + 1}", np.column_stack([period, am[m, k]]),
                            "Added mass components as a function of frequency", "")
                    _python(hc, f"radiation_damping/components/{m + 1}_{k + 1}", np.column_stack([period, rd[m, k]]),
                            "Radiation damping components as a function of frequency", "")
        sp = f.create_group("simulation_parameters")
        _python(sp, "scaled", 0, "True: The data is scaled by rho*g, False: The data is not scaled", "")
        _python(sp, "wave_dir", np.degrees(hdb.headings), "Wave direction", "deg")
        depth = "infinite" if math.isinf(hdb.water_depth) else hdb.water_depth
        _python(sp, "water_depth", depth, "Water depth", "m")
        _python(sp, "w", w, "Wave frequencies", "rad/s")
        _python(sp, "T", period, "Wave periods", "s")
        _python(sp, "g", g, "Gravitational acceleration", "m/s^2")
        _python(sp, "rho", rho, "Water density", "kg/m^3")
        f.create_dataset("bem_data/code", data="NEMOH")


# ---------------------------------------------------------------------- the databases
def sphere() -> HydroDatabase:
    """The OES Task 10 sphere: radius 5 m, centre on the still water level (half submerged), cg 2 m below it,
    fresh water (rho = 1000 kg/m^3, so the displaced mass is the published 261.8 t), deep water."""
    body = BemBody("sphere", BodyGeometry(shape="sphere", radius=5.0, panel_size=0.45), (0.0, 0.0, -2.0))
    settings = BemSettings(omega=frequency_grid(0.05, 5.0, 0.05), headings_deg=(0.0,), rho=1000.0, g=9.81)
    return compute_database([body], settings)


def two_cylinders() -> HydroDatabase:
    """Two small floating cylinders (radius 1 m, draft 1 m, 4 m apart), 12 frequencies, 2 headings, 30 m deep."""
    bodies = [BemBody(name, BodyGeometry(shape="vertical_cylinder", radius=1.0, draft=1.0, panel_size=0.4,
                                         position=(x, 0.0, 0.0)), (x, 0.0, -0.5))
              for name, x in (("fore", -2.0), ("aft", 2.0))]
    settings = BemSettings(omega=frequency_grid(0.3, 3.6, 0.3), headings_deg=(0.0, 30.0), rho=1025.0, g=9.81,
                           water_depth=30.0)
    return compute_database(bodies, settings)


def one_cylinder(deep: bool) -> HydroDatabase:
    """One small floating cylinder (radius 1 m, draft 1 m), 12 frequencies, one heading."""
    body = BemBody("buoy", BodyGeometry(shape="vertical_cylinder", radius=1.0, draft=1.0, panel_size=0.4),
                   (0.0, 0.0, -0.5))
    settings = BemSettings(omega=frequency_grid(0.3, 3.6, 0.3), headings_deg=(0.0,), rho=1025.0, g=9.81,
                           water_depth=math.inf if deep else 30.0)
    return compute_database([body], settings)


def main() -> None:
    cyl = one_cylinder(deep=True)
    pair = two_cylinders()
    write_matlab_layout(sphere(), HERE / "sphere_matlab_ss.h5", groups=True, parts="nan")
    write_matlab_layout(pair, HERE / "two_cylinders_matlab.h5", groups=False, parts="values")
    write_python_layout(cyl, HERE / "buoy_python_ss.h5", groups=True)
    write_python_layout(pair, HERE / "two_cylinders_python.h5", groups=False)
    for p in sorted(HERE.glob("*.h5")):
        print(f"{p.name}: {p.stat().st_size / 1024:.0f} KiB")


if __name__ == "__main__":
    main()
