"""Read and write WEC-Sim BEMIO HDF5 files (the layout WEC-Sim and HydroChrono read).

Layout, as seen from h5py (row-major; WEC-Sim's MATLAB writer produces the same index order):

``/simulation_parameters``
    ``w`` (Nw,) rad/s, ``T`` (Nw,) s, ``wave_dir`` (Nh,) deg, ``water_depth`` m (``inf`` for deep
    water), ``rho`` kg/m^3, ``g`` m/s^2, ``scaled`` (0).
``/bem_data/code``
    name of the BEM code.
``/body<i>/properties``
    ``name``, ``body_number``, ``cg`` (3,), ``cb`` (3,), ``disp_vol``, ``dof`` (6),
    ``dof_start``, ``dof_end`` (1-based rows of this body in the 6N system).
``/body<i>/hydro_coeffs``
    ``linear_restoring_stiffness`` (6, 6) / (rho g);
    ``added_mass/all`` (6, 6N, Nw) / rho; ``added_mass/inf_freq`` (6, 6N) / rho;
    ``radiation_damping/all`` (6, 6N, Nw) / (rho omega);
    ``excitation/{re,im,mag,phase}`` (6, Nh, Nw) / (rho g), and the same under
    ``excitation/froude-krylov`` and ``excitation/scattering``.

Normalisations are those of WEC-Sim's ``normalizeBEM``; reading undoes them. Complex
amplitudes use WEC-Sim's ``exp(+i omega t)`` convention, as :mod:`hydro_fmu.hdb` does.

Both BEMIO writers are read: the MATLAB ``writeBEMIOH5`` (scalars stored as (1, 1), vectors as (N, 1),
strings as variable-length arrays, attributes ``units``) and the older Python ``bemio`` ``write_hdf5``
(no ``dof``/``dof_start``/``dof_end``, ``water_depth`` may be the string ``infinite``, extra
``components`` groups, which are ignored). The ``froude-krylov`` and ``scattering`` parts are optional: a
file without them, or with NaN in them (BEMIO fills them with NaN when the BEM run did not compute them),
reads without them, and ``extra["excitation_parts"]`` says why; a scene that needs them says so then. The
impulse-response and state-space groups (:mod:`hydro_fmu.bemio_groups`) are optional too, and written
on request (``write_bemio(..., wec_sim_groups=True)``).
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

from .hdb import HydroDatabase, HydroDatabaseError
from .hdf5_reading import CheckedFile

EXCITATION_PARTS = "excitation_parts"  # HydroDatabase.extra key: why the Froude-Krylov/diffraction parts are absent


def write_bemio(hdb: HydroDatabase, path: str | Path, code: str = "", *, wec_sim_groups: bool = False) -> Path:
    """Write ``hdb`` as a BEMIO HDF5 file; returns the path. ``wec_sim_groups``: add the radiation impulse
    response, its per-entry state-space realisation and the excitation impulse response that WEC-Sim's body class
    reads (:mod:`hydro_fmu.bemio_groups`; a few seconds of fitting)."""
    path = Path(path)
    realisation = None
    if wec_sim_groups:
        from .bemio_groups import realise

        realisation = realise(hdb)
    path.parent.mkdir(parents=True, exist_ok=True)
    rho, g, w = hdb.rho, hdb.g, hdb.omega
    n = hdb.n_dofs
    with h5py.File(path, "w") as f:
        sp = f.create_group("simulation_parameters")
        _dataset(sp, "w", w, "Wave frequencies", "rad/s")
        _dataset(sp, "T", 2 * np.pi / w, "Wave periods", "s")
        _dataset(sp, "wave_dir", np.degrees(hdb.headings), "Wave direction", "deg")
        _dataset(sp, "water_depth", float(hdb.water_depth), "Water depth", "m")
        _dataset(sp, "rho", float(rho), "Water density", "kg/m^3")
        _dataset(sp, "g", float(g), "Gravitational acceleration", "m/s^2")
        _dataset(sp, "scaled", 0, "0: coefficients normalised by rho, rho*omega and rho*g", "")
        f.create_group("bem_data").create_dataset("code", data=code or hdb.source or "wec-cosim")
        for b, name in enumerate(hdb.body_names):
            rows = slice(6 * b, 6 * b + 6)
            grp = f.create_group(f"body{b + 1}")
            props = grp.create_group("properties")
            props.create_dataset("name", data=name)
            _dataset(props, "body_number", b + 1, "Number of rigid body from the BEM simulation", "")
            _dataset(props, "cg", hdb.cg[b], "Center of gravity", "m")
            _dataset(props, "cb", hdb.cb[b], "Center of buoyancy", "m")
            _dataset(props, "disp_vol", float(hdb.displaced_volume[b]), "Displaced volume", "m^3")
            _dataset(props, "dof", 6, "Degrees of freedom", "")
            _dataset(props, "dof_start", 6 * b + 1, "First DOF of this body (1-based)", "")
            _dataset(props, "dof_end", 6 * b + 6, "Last DOF of this body (1-based)", "")
            hc = grp.create_group("hydro_coeffs")
            _dataset(hc, "linear_restoring_stiffness", hdb.hydrostatic_stiffness[b] / (rho * g),
                     "Hydrostatic stiffness matrix", "")
            am = hc.create_group("added_mass")
            _dataset(am, "all", np.transpose(hdb.added_mass[:, rows, :], (1, 2, 0)) / rho,
                     "Added mass", "kg-m^2 (rotation); kg (translation)")
            _dataset(am, "inf_freq", hdb.added_mass_inf[rows, :] / rho,
                     "Infinite frequency added mass", "kg-m^2 (rotation); kg (translation)")
            rd = hc.create_group("radiation_damping")
            _dataset(rd, "all", np.transpose(hdb.radiation_damping[:, rows, :], (1, 2, 0)) / (rho * w),
                     "Radiation damping", "N-s/m (translation); N-m-s/rad (rotation)")
            ex = hc.create_group("excitation")
            _write_complex(ex, hdb.excitation[:, :, rows], rho * g, "Excitation force")
            if hdb.froude_krylov is not None:
                _write_complex(ex.create_group("froude-krylov"), hdb.froude_krylov[:, :, rows], rho * g,
                               "Froude-Krylov force")
            if hdb.diffraction is not None:
                _write_complex(ex.create_group("scattering"), hdb.diffraction[:, :, rows], rho * g,
                               "Scattering (diffraction) force")
            if realisation is not None:
                from .bemio_groups import write_radiation_groups

                write_radiation_groups(hc, hdb, rows, realisation, _dataset)
        assert n == 6 * hdb.n_bodies
    return path


def read_bemio(path: str | Path) -> HydroDatabase:
    """Read a BEMIO HDF5 file (written by WEC-Sim's BEMIO, HydroChrono tools or this package)."""
    path = Path(path)
    if not path.is_file():
        raise HydroDatabaseError(f"hydrodynamic database file {path} does not exist")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise HydroDatabaseError(f"{path} is not a readable HDF5 file ({exc})") from None
    checked = CheckedFile(f, path, "a BEMIO hydrodynamic database", HydroDatabaseError,
                          fix="write the database again (BEMIO, Capytaine or `wec-cosim hydro`)")
    with f, checked.guard():
        return _read(f, path, checked)


def read_wec_sim_groups(path: str | Path):
    """The impulse-response and state-space groups of a BEMIO file, SI units
    (:class:`hydro_fmu.bemio_groups.RadiationGroups`; fields None where the file has no such group)."""
    from .bemio_groups import read_radiation_groups

    hdb = read_bemio(path)
    with h5py.File(path, "r") as f:
        bodies = sorted((k for k in f if k.startswith("body") and k[4:].isdigit()), key=lambda k: int(k[4:]))
        return read_radiation_groups(f, bodies, hdb.n_dofs, len(hdb.headings), hdb.rho, hdb.g,
                                     lambda value, shape, what: _shaped(value, shape, Path(path), what))


def _read(f: h5py.File, path: Path, checked: CheckedFile) -> HydroDatabase:
    need = checked.numbers  # every group and dataset checked before use (hydro_fmu.hdf5_reading)
    if not checked.has(f, "simulation_parameters"):
        raise HydroDatabaseError(f"{path}: /simulation_parameters is missing: not a BEMIO hydrodynamic database "
                                 "(WEC-Sim's layout); give a BEMIO file as hydro.database")
    sp = checked.group(f, "simulation_parameters")
    w = need(sp, "w").ravel()
    headings = np.radians(need(sp, "wave_dir").ravel())
    depth = checked.scalar(sp, "water_depth")
    rho = checked.scalar(sp, "rho") if checked.has(sp, "rho") else 1000.0
    g = checked.scalar(sp, "g") if checked.has(sp, "g") else 9.81
    bodies = sorted((k for k in f if k.startswith("body") and k[4:].isdigit()), key=lambda k: int(k[4:]))
    if not bodies:
        raise HydroDatabaseError(f"{path}: /body1 is missing (no /body<i> groups): a BEMIO database holds one group "
                                 "per body; write the database again")
    nb, nw, nh = len(bodies), len(w), len(headings)
    n = 6 * nb
    A = np.zeros((nw, n, n))
    B = np.zeros((nw, n, n))
    Ainf = np.zeros((n, n))
    X = np.zeros((nh, nw, n), complex)
    FK = np.zeros((nh, nw, n), complex)
    DF = np.zeros((nh, nw, n), complex)
    parts_note = ""
    C = np.zeros((nb, 6, 6))
    cg, cb, vol, names = np.zeros((nb, 3)), np.zeros((nb, 3)), np.zeros(nb), []
    for b, key in enumerate(bodies):
        grp = checked.group(f, key)
        props, hc = checked.group(grp, "properties"), checked.group(grp, "hydro_coeffs")
        dof = int(checked.scalar(props, "dof")) if checked.has(props, "dof") else 6
        if dof != 6:
            raise HydroDatabaseError(
                f"{path}: {key} has {dof} degrees of freedom; only rigid bodies (6) are supported"
            )
        name = checked.text(props, "name").strip().rstrip("\x00")
        names.append(name if name not in names else f"{name}_{b + 1}")
        cg[b] = _shaped(need(props, "cg", 3), (3,), path, f"{key} cg")
        cb[b] = _shaped(need(props, "cb", 3), (3,), path, f"{key} cb")
        vol[b] = checked.scalar(props, "disp_vol")
        rows = slice(6 * b, 6 * b + 6)
        am, rd = checked.group(hc, "added_mass"), checked.group(hc, "radiation_damping")
        C[b] = _shaped(need(hc, "linear_restoring_stiffness", 36), (6, 6), path, f"{key} stiffness") * rho * g
        A[:, rows, :] = np.transpose(
            _shaped(need(am, "all", 6 * n * nw), (6, n, nw), path, f"{key} added_mass/all"), (2, 0, 1)) * rho
        Ainf[rows, :] = _shaped(need(am, "inf_freq", 6 * n), (6, n), path, f"{key} inf_freq") * rho
        B[:, rows, :] = np.transpose(
            _shaped(need(rd, "all", 6 * n * nw), (6, n, nw), path, f"{key} radiation_damping/all"),
            (2, 0, 1)) * rho * w[:, None, None]
        ex = checked.group(hc, "excitation")
        X[:, :, rows] = _read_complex(checked, ex, path, key, (6, nh, nw)) * rho * g
        for part, table in (("froude-krylov", FK), ("scattering", DF)):
            if not (checked.has(ex, part) and checked.has(checked.group(ex, part), "re")):
                parts_note = parts_note or f"{path} has no {ex.name}/{part} group"
                continue
            table[:, :, rows] = _read_complex(checked, checked.group(ex, part), path, key, (6, nh, nw)) * rho * g
            bad = int(np.sum(~np.isfinite(table[:, :, rows])))
            if bad:
                parts_note = parts_note or (f"{path}: {ex.name}/{part} has {bad} non-finite values (BEMIO writes NaN "
                                            "where the BEM run did not compute a part)")
    order = np.argsort(w)
    code = ""
    if checked.has(f, "bem_data") and checked.has(bem := checked.group(f, "bem_data"), "code"):
        code = checked.text(bem, "code")
    return HydroDatabase(
        body_names=names,
        omega=w[order],
        added_mass=A[order],
        radiation_damping=B[order],
        added_mass_inf=Ainf,
        headings=headings,
        excitation=X[:, order],
        froude_krylov=None if parts_note else FK[:, order],
        diffraction=None if parts_note else DF[:, order],
        hydrostatic_stiffness=C,
        cg=cg,
        cb=cb,
        displaced_volume=vol,
        rho=rho,
        g=g,
        water_depth=float(depth),
        source=f"{path}" + (f" ({code})" if code else ""),
        extra={EXCITATION_PARTS: parts_note} if parts_note else {},
    )


def _dataset(group: h5py.Group, name: str, data: object, description: str, unit: str) -> None:
    ds = group.create_dataset(name, data=data)
    ds.attrs["description"] = description
    ds.attrs["unit"] = unit


def _write_complex(group: h5py.Group, values: np.ndarray, scale: float, description: str) -> None:
    """``values`` (Nh, Nw, 6) complex -> re/im/mag/phase datasets (6, Nh, Nw) divided by ``scale``."""
    v = np.transpose(values, (2, 0, 1)) / scale
    _dataset(group, "re", v.real, f"Real part of {description}", "")
    _dataset(group, "im", v.imag, f"Imaginary part of {description}", "")
    _dataset(group, "mag", np.abs(v), f"Magnitude of {description}", "")
    _dataset(group, "phase", np.angle(v), f"Phase of {description}", "rad")


def _read_complex(checked: CheckedFile, group: h5py.Group, path: Path, key: str,
                  shape: tuple[int, int, int]) -> np.ndarray:
    size = int(np.prod(shape))
    re = _shaped(checked.numbers(group, "re", size), shape, path, f"{group.name}/re")
    im = _shaped(checked.numbers(group, "im", size), shape, path, f"{group.name}/im")
    return np.transpose(re + 1j * im, (1, 2, 0))


def _shaped(value: np.ndarray, shape: tuple[int, ...], path: Path, what: str) -> np.ndarray:
    """``value`` with shape ``shape``; accepts the reversed order MATLAB writers sometimes leave."""
    value = np.asarray(value, dtype=float)
    if value.shape == shape:
        return value
    if value.shape == shape[::-1]:
        return value.transpose()
    if value.size == int(np.prod(shape)) and 1 in value.shape:
        return value.reshape(shape)
    raise HydroDatabaseError(f"{path}: {what} has shape {value.shape}, expected {shape}")
