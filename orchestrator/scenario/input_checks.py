"""Checks of a scenario that guard the machine rather than the physics, made before any work starts.

* scenario files: text, UTF-8, not an HDF5 file passed by mistake, of a sane size and nesting;
* derived sizes: every array a scenario key makes the tools allocate (time steps, impulse-response
  samples, frequency grids, wave components, harmonics, panels of a primitive mesh) is bounded, and
  the error names the key to change;
* files the scenario names are read now (elevation records, spectra), so their errors name the
  user's file and key, not a copy inside an FMU;
* output paths: checked for writability before any scene is built (see :func:`check_output`).

Every error is a :class:`~orchestrator.errors.ScenarioError` (or ``WecCosimError`` for an output
path) naming the file and the key, and saying what to change.
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

from hydro_fmu.meshes import MAX_WETTED_PANELS
from orchestrator.errors import ScenarioError, WecCosimError

MAX_SCENARIO_BYTES = 4 * 1024 * 1024
MAX_NESTING = 64
MAX_STEPS = 50_000_000  # macro steps of a run
MAX_KERNEL_SAMPLES = 2_000_000  # radiation or excitation impulse-response samples
MAX_BEM_FREQUENCIES = 2_000  # BEM solves
MAX_GRID = 1_000_000  # any other frequency grid (RAO, impulse-response transform)
MAX_COMPONENTS = 200_000  # wave components x directions
MAX_HARMONICS = 2_000
MAX_PANELS = MAX_WETTED_PANELS  # wetted panels of a body for Capytaine (primitive or mesh file)
MAX_SWEEP_POINTS = 100_000  # cases of a sweep (checked by wec_cosim.sweeps.grid.plan_sweep)
MAX_SEED = 2**31 - 1
NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.+-]{0,99}$")


# ----------------------------------------------------------------------------------------- the file
def read_scenario_text(path: Path) -> str:
    """The text of a scenario file, or a ScenarioError saying why it is not one."""
    if path.is_dir():
        raise ScenarioError(f"scenario file {path} is a directory; give the .toml file")
    if not path.is_file():
        raise ScenarioError(f"scenario file {path} does not exist")
    try:
        size = path.stat().st_size
        if size > MAX_SCENARIO_BYTES:
            raise ScenarioError(f"{path}: {size} bytes is not a scenario file (a scenario is a small TOML text "
                                f"file, at most {MAX_SCENARIO_BYTES // 1024} kB)")
        data = path.read_bytes()
    except OSError as exc:
        raise ScenarioError(f"scenario file {path} cannot be read: {exc.strerror or exc}") from None
    if data.startswith(b"\x89HDF"):
        raise ScenarioError(f"{path} is an HDF5 file (results or database), not a scenario; give the .toml file")
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise ScenarioError(f"{path} is UTF-16 text; TOML scenario files must be UTF-8: save it as UTF-8")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"{path} is not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start}); a "
                            "scenario is a TOML file in UTF-8: save it as UTF-8") from None
    if "\x00" in text:
        raise ScenarioError(f"{path} holds a NUL byte (offset {text.index(chr(0))}): not a text file")
    return text.removeprefix("\ufeff")


def check_nesting(text: str, path: Path) -> None:
    """Refuse arrays or inline tables nested deeper than any scenario needs (before the TOML parser recurses)."""
    depth = deepest = 0
    in_string = None
    i = 0
    while i < len(text):
        c = text[i]
        if in_string:
            if c == "\\" and in_string == '"':
                i += 2
                continue
            if c == in_string:
                in_string = None
        elif c in "\"'":
            in_string = c
        elif c == "#":
            j = text.find("\n", i)
            i = len(text) if j < 0 else j
            continue
        elif c in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif c in "]}":
            depth -= 1
        i += 1
        if deepest > MAX_NESTING:
            line = text.count("\n", 0, i) + 1
            raise ScenarioError(f"{path}:{line}: arrays or tables nested more than {MAX_NESTING} deep; a scenario "
                                "needs at most 3 levels")


# ---------------------------------------------------------------------------------------- the values
def check_limits(s) -> None:  # noqa: ANN001 - a Scenario (import cycle)
    """Bound every derived size (module docstring)."""
    f, sim, h, w = str(s.file), s.simulation, s.hydro, s.waves
    if s.name and not NAME.match(s.name):
        raise ScenarioError(f"{f}: name {s.name!r} must be 1-100 letters, digits, '_', '-', '.' or '+', not starting "
                            "with '.' or '-' (it names the results file results/<name>.h5 and the FMUs)")
    steps = sim.duration / sim.step
    if steps > MAX_STEPS:
        raise ScenarioError(f"{f}: simulation.step = {sim.step:g} s makes {steps:.3g} macro steps over the duration "
                            f"of {sim.duration:g} s (at most {MAX_STEPS:.0e}); increase simulation.step or reduce "
                            "simulation.duration")
    for key, length in (("hydro.irf_duration", h.irf_duration),
                        ("hydro.excitation_irf_duration", 2 * h.excitation_irf_duration)):
        if length / sim.step > MAX_KERNEL_SAMPLES:
            raise ScenarioError(f"{f}: {key} = {length:g} s makes {length / sim.step:.3g} impulse-response samples "
                                f"at simulation.step = {sim.step:g} s (at most {MAX_KERNEL_SAMPLES:.0e}); reduce {key}")
    n_bem = sum(_grid_size(g) for g in [h.omega, *h.omega_refine])
    if n_bem > MAX_BEM_FREQUENCIES:
        raise ScenarioError(f"{f}: hydro.omega (with omega_refine) gives {n_bem:.3g} BEM frequencies (at most "
                            f"{MAX_BEM_FREQUENCIES}, each a Capytaine solve); increase hydro.omega.step")
    if h.irf_d_omega > 0:
        n = max(h.omega.stop, 2 * math.pi / sim.step) / h.irf_d_omega
        if n > MAX_GRID:
            raise ScenarioError(f"{f}: hydro.irf_d_omega = {h.irf_d_omega:g} rad/s makes {n:.3g} frequencies in the "
                                f"impulse-response transform (at most {MAX_GRID:.0e}); increase hydro.irf_d_omega "
                                "(or 0 for the database's grid)")
    if s.rao.omega is not None and _grid_size(s.rao.omega) > MAX_GRID:
        raise ScenarioError(f"{f}: rao.omega gives {_grid_size(s.rao.omega):.3g} frequencies (at most "
                            f"{MAX_GRID:.0e}); increase rao.omega.step")
    if s.steady.harmonics > MAX_HARMONICS:
        raise ScenarioError(f"{f}: steady.harmonics = {s.steady.harmonics} (at most {MAX_HARMONICS}); reduce it")
    if w.seed > MAX_SEED:
        raise ScenarioError(f"{f}: waves.seed = {w.seed} is too large; use a seed from 0 to {MAX_SEED}")
    if w.kind == "irregular":
        _check_components(s, f)
    _check_panels(s, f)


def _grid_size(g) -> float:  # noqa: ANN001 - FrequencyGrid
    return (g.stop - g.start) / g.step + 1


def _check_components(s, f: str) -> None:  # noqa: ANN001
    w = s.waves
    directions = w.n_directions if w.spreading_s > 0 else 1
    if w.discretisation == "equal_energy":
        n = w.n_components
        key = "waves.n_components"
    else:
        repeat = w.repeat_period or s.simulation.duration
        omega_p = 2 * math.pi / w.tp if w.tp > 0 else 0.4 * math.sqrt(s.environment.g / max(w.hs, 1e-9))
        top = w.omega_max or 6 * omega_p
        n = (top - w.omega_min) * repeat / (2 * math.pi) if w.spectrum != "file" else 0
        key = "waves.repeat_period (default the duration)"
    if n * directions > MAX_COMPONENTS:
        raise ScenarioError(f"{f}: the irregular sea would have {n * directions:.3g} wave components "
                            f"({directions} direction(s)); at most {MAX_COMPONENTS:.0e}: reduce {key}"
                            + (" or waves.n_directions" if directions > 1 else ""))


def _check_panels(s, f: str) -> None:  # noqa: ANN001
    """Primitive meshes: estimated panel count from the wetted area (before a Capytaine recompute)."""
    if s.hydro.database:
        return
    for i, b in enumerate(s.bodies):
        g = b.geometry
        if g is not None and g.shape == "mesh" and g.mesh_file and s.resolve(g.mesh_file).is_file():
            from hydro_fmu.hdb import HydroDatabaseError
            from hydro_fmu.meshes import check_face_count

            try:  # counted from the file's header or lines, before anything reads the mesh
                check_face_count(s.resolve(g.mesh_file))
            except HydroDatabaseError as exc:
                raise ScenarioError(f"{f}: bodies[{i}].geometry.mesh_file: {exc}") from None
        if g is None or g.shape == "mesh":
            continue
        if g.shape == "vertical_cylinder":
            area = 2 * math.pi * g.radius * g.draft + 2 * math.pi * g.radius**2
        elif g.shape == "sphere":
            area = 3 * math.pi * g.radius**2
        elif g.shape == "axisymmetric":  # the surface of revolution of the profile
            area = sum(math.pi * (a[0] + b[0]) * math.hypot(b[0] - a[0], b[1] - a[1])
                       for a, b in zip(g.profile[:-1], g.profile[1:], strict=False))
        else:
            length, width, height = g.size
            area = 2 * (length * width + length * height + width * height)
        panels = area / g.panel_size**2
        if panels > MAX_PANELS:
            raise ScenarioError(f"{f}: bodies[{i}] ({b.name}): the geometry with panel_size = {g.panel_size:g} m "
                                f"needs about {panels:.3g} panels (at most {MAX_PANELS}); increase "
                                f"bodies[{i}].geometry.panel_size or check the dimensions (m)")


# ----------------------------------------------------------------------------------------- the files
def check_files(s) -> None:  # noqa: ANN001
    """Read the data files the scenario names (elevation record, spectrum) and check the cache folder."""
    from hydro_fmu.wave_records import WaveDataError, read_elevation, read_spectrum

    f, w, h = str(s.file), s.waves, s.hydro
    try:
        if w.kind == "elevation" and w.elevation_file:
            read_elevation(s.resolve(w.elevation_file), time_dataset=w.time_dataset,
                           elevation_dataset=w.elevation_dataset)
        if w.kind == "irregular" and w.spectrum == "file" and w.spectrum_file:
            read_spectrum(s.resolve(w.spectrum_file))
    except WaveDataError as exc:
        key = "waves.elevation_file" if w.kind == "elevation" else "waves.spectrum_file"
        raise ScenarioError(f"{f}: {key}: {exc}") from None
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        key = "waves.elevation_file" if w.kind == "elevation" else "waves.spectrum_file"
        raise ScenarioError(f"{f}: {key}: the file cannot be read ({type(exc).__name__}: {exc})") from None
    if not h.database:
        cache = s.resolve(h.cache_dir)
        probe = cache
        while not probe.exists() and probe != probe.parent:
            probe = probe.parent
        if probe.exists() and not probe.is_dir():
            raise ScenarioError(f"{f}: hydro.cache_dir: {probe} is a file, not a folder; name a folder for the "
                                "computed hydrodynamic databases")


ENDPOINT = re.compile(r"^(tcp|udp|tls|quic|ws)/(\[[0-9a-fA-F:.]+\]|[A-Za-z0-9_.-]+):(\d{1,5})$")


def check_control(s) -> None:  # noqa: ANN001
    """Zenoh endpoints and configuration file of a controlled run."""
    c, f = s.control, str(s.file)
    if c.zenoh_config:
        path = s.resolve(c.zenoh_config)
        if not path.is_file():
            raise ScenarioError(f"{f}: control.zenoh_config: file {path} does not exist")
        try:
            import zenoh

            zenoh.Config.from_file(str(path))
        except Exception as exc:  # noqa: BLE001 - zenoh raises its own error type for any bad file
            text = " ".join(str(exc).split())[:300]
            raise ScenarioError(f"{f}: control.zenoh_config: {path} is not a valid zenoh configuration ({text})") \
                from None
        return
    if not c.endpoints:
        raise ScenarioError(f"{f}: control.endpoints is empty; give at least one endpoint such as "
                            "'tcp/127.0.0.1:7447' (or remove the key for that default)")
    for i, endpoint in enumerate(c.endpoints):
        m = ENDPOINT.match(endpoint)
        if not m or not 1 <= int(m.group(3)) <= 65535:
            raise ScenarioError(f"{f}: control.endpoints[{i}]: {endpoint!r} is not a zenoh endpoint "
                                "'<protocol>/<host>:<port>' (e.g. 'tcp/127.0.0.1:7447', port 1-65535)")


# ---------------------------------------------------------------------------------------- the outputs
def check_output(path: Path, key: str, *, kind: str = "hdf5") -> Path:
    """Refuse, before any work, an output path that cannot be written or would destroy a foreign file.

    ``key`` names where the path came from (``--out`` or ``simulation.output``); ``kind`` is ``hdf5``
    (an existing file is replaced only if it is an HDF5 file), ``file`` (any regular file) or ``dir``.
    """
    path = Path(path)
    text = str(path)
    if not text or "\x00" in text:
        raise WecCosimError(f"{key}: {text!r} is not a usable path")
    try:
        limit = os.pathconf("/", "PC_NAME_MAX")
    except (OSError, ValueError):
        limit = 255
    too_long = [p for p in path.parts if len(p.encode()) > limit]
    if too_long or len(text.encode()) > 4000:
        raise WecCosimError(f"{key}: {path} is too long for the file system (a name of at most {limit} bytes); "
                            "choose a shorter path")
    if kind == "dir":
        if path.exists() and not path.is_dir():
            raise WecCosimError(f"{key}: {path} is a file, not a folder; choose a folder")
        folder = path
    else:
        if path.is_dir():
            raise WecCosimError(f"{key}: {path} is a folder; give a file name (e.g. {path / 'results.h5'})")
        if path.exists() and not path.is_file():
            raise WecCosimError(f"{key}: {path} is not a regular file (a device or pipe); give a file name")
        if kind == "hdf5" and path.is_file() and path.stat().st_size > 0:
            with open(path, "rb") as fh:
                if fh.read(8) != b"\x89HDF\r\n\x1a\n":
                    raise WecCosimError(f"{key}: {path} exists and is not an HDF5 file; it is not overwritten: "
                                        "choose another name or remove it")
        folder = path.parent
    probe = folder
    while not probe.exists() and probe != probe.parent:
        probe = probe.parent
    if not probe.is_dir():
        raise WecCosimError(f"{key}: {probe} is a file, so {path} cannot be created under it; choose another path")
    if not os.access(probe, os.W_OK | os.X_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise WecCosimError(f"{key}: {path if path.exists() else probe} is not writable; choose another path")
    return path


def require_room(path: Path, nbytes: int) -> None:
    """Refuse (an ``OSError``: ENOSPC or EFBIG, naming ``path``) to write a file of about ``nbytes`` at ``path`` when
    its disk has less free space or the process's file-size limit (``ulimit -f``) is smaller: an HDF5 file whose
    write fails half-way cannot be closed, and HDF5's exit handler may then crash the process."""
    import errno
    import resource
    import shutil

    path = Path(path)
    size = path.stat().st_size if path.exists() else 0
    limit = resource.getrlimit(resource.RLIMIT_FSIZE)[0]
    if limit != resource.RLIM_INFINITY and size + nbytes > limit:
        raise OSError(errno.EFBIG, f"file size limit of {limit} bytes reached", str(path))
    folder = path.parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if shutil.disk_usage(folder).free < nbytes:
        raise OSError(errno.ENOSPC, "no space left on the device", str(path))
