"""Capytaine front end: body geometry -> hydrodynamic database, cached on disk by content hash.

A body is a primitive (vertical cylinder, sphere, box) or a mesh file (``.obj`` and ``.stl`` read
by :mod:`hydro_fmu.meshes`, other formats by Capytaine: ``.gdf``, ``.dat``...), placed in the world
by a rotation about its origin and a translation. Mesh files are checked before the solve
(:func:`hydro_fmu.meshes.check_mesh`): defects that make Capytaine return NaN stop the run with
the body, file and place named; others are logged as warnings.
The solver runs Capytaine 3.0's ``BEMSolver.fill_dataset`` over a frequency grid and the
headings, plus one radiation solve at infinite frequency for A_inf, with a lid mesh on the
waterplane to remove irregular frequencies. Rotation centres are the bodies' centres of
gravity, so the database follows the BEMIO convention of :mod:`hydro_fmu.hdb`.

Capytaine uses the ``exp(-i omega t)`` convention; excitation is conjugated on the way in.
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from .bem_symmetry import MIRROR_XOZ, check_invariant, rotation_symmetric_system, symmetry_group
from .bemio import read_bemio, write_bemio
from .hdb import HydroDatabase, HydroDatabaseError
from .hydrostatics import hull_hydrostatics
from .meshes import SurfaceMesh, check_mesh, euler_xyz, from_capytaine, read_mesh, to_capytaine
from .prism_mesh import regular_prism_mesh

# Bump when the way a database is computed changes: invalidates every cached file.
BEM_CACHE_VERSION = 1
SHAPES = ("vertical_cylinder", "sphere", "box", "regular_prism", "axisymmetric", "mesh")

_logger = logging.getLogger(__name__)

Progress = Callable[[int, int, float], None]
"""``progress(done, total, omega)``: ``done`` of ``total`` frequencies solved, the last at ``omega`` (rad/s)."""


@dataclass(frozen=True)
class BodyGeometry:
    """Wetted shape of one body in body-local coordinates.

    Attributes:
        shape: ``vertical_cylinder`` (``radius``, ``draft``; local origin on the axis at the
            waterline), ``sphere`` (``radius``; origin at the centre), ``box`` (``size`` =
            length, width, height; origin at the centre), ``regular_prism`` (``sides``, ``radius``
            from the axis to a corner, ``draft``, freeboard equal to the draft; origin on the axis at
            the waterline, a flat side facing +x; :mod:`hydro_fmu.prism_mesh`), ``axisymmetric``
            (``profile``: the generating curve revolved about the local z axis, see
            :func:`mesh_of_revolution`) or ``mesh`` (``mesh_file``; the file's own coordinates).
        position: world coordinates (m) of the local origin.
        rotation_deg: rotation about the local origin, about the fixed x, then y, then z axis (deg).
        profile: ``axisymmetric``: ``(r, z)`` points (m) of the hull's cross-section in a meridian
            half-plane, in order along the hull surface.
        dry_segments: ``axisymmetric``: indices of profile segments in contact with another body
            (e.g. a float's bore sliding on a spar's column): they close the body for its hydrostatics
            (displaced volume, centre of buoyancy, stiffness) but are not wetted, so they are left out
            of the BEM mesh; the neighbour's hull in that stretch is dry too (no water gap, hence no
            gap resonance).
        panel_size: target panel edge (m) for primitives; ignored for mesh files.
        lid: put a lid mesh on the waterplane of a surface-piercing body to remove irregular
            frequencies (not needed for thin discs, whose irregular frequencies are very high).
    """

    shape: str
    radius: float = 0.0
    draft: float = 0.0
    size: tuple[float, float, float] = (0.0, 0.0, 0.0)
    mesh_file: str = ""
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    panel_size: float = 0.5
    lid: bool = True
    rotation_deg: tuple[float, float, float] = (0.0, 0.0, 0.0)
    profile: tuple[tuple[float, float], ...] = ()
    dry_segments: tuple[int, ...] = ()
    sides: int = 0

    def __post_init__(self) -> None:
        if self.shape not in SHAPES:
            raise ValueError(f"unknown shape {self.shape!r}; expected one of {', '.join(SHAPES)}")


@dataclass(frozen=True)
class BemBody:
    """A body for the BEM solver: name, geometry and centre of gravity (world, m)."""

    name: str
    geometry: BodyGeometry
    cg: tuple[float, float, float]


@dataclass(frozen=True)
class BemSettings:
    """Frequency grid, headings and environment of a BEM run.

    Attributes:
        omega: wave frequencies (rad/s), strictly increasing.
        headings_deg: wave headings (deg), 0 = waves towards +x.
        rho, g, water_depth: kg/m^3, m/s^2, m (``inf`` for deep water).
        method: Capytaine boundary-integral formulation, ``indirect`` or ``direct``.
        symmetry: ``none``, or ``xOz``: every body is mirror-symmetric about the plane y = 0, and
            Capytaine solves on half meshes (:func:`reflection_symmetric`). Same discretisation
            except that panels crossing y = 0 are split in two and the lid is generated from the
            half waterline; 2.3 times faster per frequency at 5400 panels
            (``benchmarks/bench_bem_symmetry.py``). ``C<n>``, ``D<n>``: the set of bodies is
            unchanged by a rotation of 360/n deg about z (and, for ``D<n>``, by the mirror about
            y = 0); one solve on a wedge (:mod:`hydro_fmu.bem_symmetry`).
    """

    omega: tuple[float, ...]
    headings_deg: tuple[float, ...] = (0.0,)
    rho: float = 1025.0
    g: float = 9.81
    water_depth: float = math.inf
    method: str = "indirect"
    symmetry: str = "none"
    extra: dict = field(default_factory=dict, compare=False)


def frequency_grid(start: float, stop: float, step: float) -> tuple[float, ...]:
    """Uniform grid ``start, start+step, ... <= stop`` (rad/s), rounded to 1e-12."""
    n = int(math.floor((stop - start) / step + 1e-9)) + 1
    return tuple(round(start + i * step, 12) for i in range(n))


def merged_grid(*grids: tuple[float, ...]) -> tuple[float, ...]:
    """The union of frequency grids, sorted, with frequencies closer than 1e-9 rad/s merged."""
    merged: list[float] = []
    for w in sorted(w for g in grids for w in g):
        if not merged or w - merged[-1] > 1e-9:
            merged.append(w)
    return tuple(merged)


def cache_key(bodies: list[BemBody], settings: BemSettings) -> str:
    """Hash of every input that changes the database (mesh file contents included). Capytaine's version is read
    from the installed distribution's metadata: importing it costs about 0.65 s."""
    from importlib.metadata import version

    items = []
    for body in bodies:
        item = asdict(body)
        if not any(body.geometry.rotation_deg):  # keys of databases made before rotations existed stay valid
            item["geometry"].pop("rotation_deg")
        if not body.geometry.profile:  # nor do profiles change the keys of other shapes
            item["geometry"].pop("profile")
        if not body.geometry.dry_segments:
            item["geometry"].pop("dry_segments")
        if not body.geometry.sides:  # nor those made before regular prisms existed
            item["geometry"].pop("sides")
        if body.geometry.shape == "mesh":
            item["geometry"]["mesh_file"] = _file_digest(Path(body.geometry.mesh_file))
        items.append(item)
    settings_dict = asdict(settings)
    settings_dict.pop("extra")
    if not math.isinf(settings.water_depth):  # the Green function's finite-depth decomposition (_green_function)
        settings_dict["finite_depth_prony"] = "fortran"
    if settings.symmetry == "none":  # keys of databases made before the option existed stay valid
        settings_dict.pop("symmetry")
    payload = {
        "version": BEM_CACHE_VERSION,
        "capytaine": ".".join(version("capytaine").split(".")[:2]),
        "bodies": items,
        "settings": settings_dict,
    }
    text = json.dumps(payload, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def cached_database(
    bodies: list[BemBody],
    settings: BemSettings,
    cache_dir: str | Path,
    *,
    refresh: bool = False,
    log=None,
    progress: Progress | None = None,
) -> tuple[HydroDatabase, Path, bool]:
    """The database for ``bodies``: from ``cache_dir`` if present, else computed and stored.

    Returns ``(database, file, computed)``; ``computed`` is False on a cache hit. ``progress`` is
    called as the solve goes (see :func:`compute_database`); never on a cache hit.
    """
    key = cache_key(bodies, settings)
    stem = "-".join(b.name for b in bodies)
    path = Path(cache_dir) / f"{stem}-{key}.h5"
    if path.is_file() and not refresh:
        hdb = read_bemio(path)
        return hdb, path, False
    hdb = compute_database(bodies, settings, log=log, progress=progress)
    write_bemio(hdb, path, code=hdb.source)
    return read_bemio(path), path, True


def compute_database(bodies: list[BemBody], settings: BemSettings, log=None,
                     progress: Progress | None = None) -> HydroDatabase:
    """Run Capytaine for ``bodies`` (interaction included when several) and return the HDB.

    Mesh-file bodies are checked first (errors raise :class:`HydroDatabaseError`, warnings go
    to ``log``). The problems are solved one frequency at a time (each frequency's radiation and
    diffraction problems together, as Capytaine's ``fill_dataset`` does), and
    ``progress(done, total, omega)`` is called before the first and after every frequency:
    ``total`` is the number of frequencies plus one (the infinite frequency, solved last).
    """
    import capytaine as cpt
    import xarray as xr

    logging.getLogger("capytaine").setLevel(logging.ERROR)  # its per-frequency warnings flood the console
    for body in bodies:
        if body.geometry.shape == "mesh":
            report = check_mesh(body_mesh(body.geometry), body.name, body.cg)
            report.raise_errors()
            for message in report.warnings:
                (log or log_warning)(f"body {body.name!r} (mesh {body.geometry.mesh_file}): {message}")
    order, _ = symmetry_group(settings.symmetry)
    if order > 1:
        system, panels, cpt_bodies = _rotation_symmetric(bodies, settings.symmetry)
    else:
        cpt_bodies = [_floating_body(b, settings.symmetry) for b in bodies]
        system = cpt_bodies[0] if len(cpt_bodies) == 1 else cpt.Multibody(cpt_bodies)
        panels = [cb.mesh.nb_faces for cb in cpt_bodies]
    dofs = list(system.dofs)
    solver = cpt.BEMSolver(green_function=_green_function(settings.water_depth), method=settings.method)
    common = {
        "water_depth": [settings.water_depth],
        "rho": [settings.rho],
        "g": [settings.g],
        "radiating_dof": dofs,
        "influenced_dof": dofs,
    }
    omega = np.asarray(settings.omega, dtype=float)
    headings = np.radians(np.asarray(settings.headings_deg, dtype=float))
    test = xr.Dataset(coords={"omega": omega, "wave_direction": headings, **common})
    report = progress or (lambda done, total, omega: None)
    total = len(omega) + 1
    report(0, total, float(omega[0]) if len(omega) else math.inf)
    try:
        ds = _solve_by_frequency(solver, test, system, lambda k, w: report(k, total, w))
        # Infinite frequency with Capytaine's default Green function: Nemoh's Fortran decomposition returns NaN
        # there (the bottom is still taken into account by the default one in finite depth).
        solver_inf = cpt.BEMSolver(method=settings.method)
        ds_inf = _solve_by_frequency(solver_inf, xr.Dataset(coords={"omega": [np.inf], **common}), system,
                                     lambda k, w: report(total, total, w))
    except Exception as exc:  # Capytaine raises its own types (e.g. GreenFunctionEvaluationError on NaN)
        names = ", ".join(repr(b.name) for b in bodies)
        raise HydroDatabaseError(f"Capytaine failed for bodies {names}: {type(exc).__name__}: {exc}") from None

    def matrix(da: xr.DataArray) -> np.ndarray:
        return da.transpose("omega", "influenced_dof", "radiating_dof").sel(
            influenced_dof=dofs, radiating_dof=dofs).values.squeeze(axis=())

    def forces(da: xr.DataArray) -> np.ndarray:
        # Capytaine exp(-i w t) -> exp(+i w t): complex conjugate.
        return np.conj(da.transpose("wave_direction", "omega", "influenced_dof").sel(influenced_dof=dofs).values)

    # Volume, centre of buoyancy and restoring matrix by the z form of the divergence theorem
    # (hull_hydrostatics): the same as Capytaine's for closed hulls, and right for hulls open along
    # vertical faces where they touch another body (F3OF), where Capytaine's average of the three forms is not.
    statics = [hull_hydrostatics(body_mesh(b.geometry).immersed_part(), b.cg, settings.rho, settings.g)
               for b in bodies]
    hdb = HydroDatabase(
        body_names=[b.name for b in bodies],
        omega=omega,
        added_mass=matrix(ds["added_mass"]),
        radiation_damping=matrix(ds["radiation_damping"]),
        added_mass_inf=matrix(ds_inf["added_mass"])[0],
        headings=headings,
        excitation=forces(ds["excitation_force"]),
        froude_krylov=forces(ds["Froude_Krylov_force"]),
        diffraction=forces(ds["diffraction_force"]),
        hydrostatic_stiffness=np.stack([k for _, _, k in statics]),
        cg=np.array([b.cg for b in bodies], dtype=float),
        cb=np.array([cb for _, cb, _ in statics]),
        displaced_volume=np.array([v for v, _, _ in statics]),
        rho=settings.rho,
        g=settings.g,
        water_depth=settings.water_depth,
        source=f"Capytaine {cpt.__version__} ({settings.method}, "
        + ", ".join(f"{b.name}: {n} panels" for b, n in zip(bodies, panels, strict=True))
        + (f"; symmetry {settings.symmetry}" if settings.symmetry != "none" else "") + ")",
    )
    return hdb


def _green_function(water_depth: float):
    """Capytaine's Delhommeau Green function at finite frequencies; in finite depth with Nemoh's Fortran Prony
    decomposition of the wave term. Capytaine 3.0's default Python decomposition fails below kh of about 0.15
    (every coefficient NaN; e.g. below 0.15 rad/s in 15 m of water, or 0.2 rad/s in the 1.5 m of seed 003's
    tank); the Fortran one converges there and agrees with it to 1e-4 from 0.5 rad/s up in 15 m
    (``docs/mathai_assembly.md``). It returns NaN at infinite frequency, which is solved with the default."""
    import capytaine as cpt

    if math.isinf(water_depth):
        return cpt.Delhommeau()
    return cpt.Delhommeau(finite_depth_prony_decomposition_method="fortran")


def _solve_by_frequency(solver, dataset, system, done) -> object:  # noqa: ANN001 - Capytaine and xarray objects
    """Capytaine's ``fill_dataset`` one frequency at a time: the same problems, solved in the same
    order and assembled the same way, with ``done(k, omega)`` after the k-th frequency."""
    from capytaine.io.xarray import assemble_dataset, problems_from_dataset

    by_omega: dict[float, list] = {}
    for problem in problems_from_dataset(dataset, system):
        by_omega.setdefault(float(problem.omega), []).append(problem)
    results = []
    for k, (w, problems) in enumerate(by_omega.items(), start=1):
        results += solver.solve_all(problems, keep_details=False, progress_bar=False)
        done(k, w)
    return assemble_dataset(results)


def log_warning(message: str) -> None:
    _logger.warning(message)


def body_mesh(geometry: BodyGeometry) -> SurfaceMesh:
    """The whole hull (above and below water) of a body in world coordinates."""
    if geometry.shape == "mesh":
        local = read_mesh(geometry.mesh_file)
    else:
        local = from_capytaine(_primitive_mesh(geometry), geometry.shape)
    return local.transformed(euler_xyz(geometry.rotation_deg), geometry.position)


def _floating_body(body: BemBody, symmetry: str = "none"):
    """Capytaine ``FloatingBody`` for one body: immersed mesh, lid, 6 rigid DOFs about its cg."""
    import capytaine as cpt

    mesh = _mesh(body.geometry)
    if symmetry == "xOz":  # before clipping at the waterline, which may cut panels asymmetrically
        mesh = reflection_symmetric(mesh, body.name)
    immersed = mesh.immersed_part()
    if immersed.nb_faces == 0:
        raise HydroDatabaseError(f"body {body.name!r}: the mesh has no panel below the waterline z = 0")
    lid = None
    if body.geometry.shape == "axisymmetric":  # the waterplane inside the profile, dry stretches included
        if body.geometry.lid:
            lid = _axisymmetric_lid(body.geometry)
            if lid is not None and symmetry == "xOz":
                lid = reflection_symmetric(lid, body.name)
    elif body.geometry.lid and np.max(immersed.vertices[:, 2]) > -1e-6:  # surface-piercing: lid on the waterplane
        lid = immersed.generate_lid(z=0.0, faces_max_radius=_lid_panel(body.geometry))
    return cpt.FloatingBody(
        mesh=immersed,
        lid_mesh=lid,
        dofs=cpt.rigid_body_dofs(rotation_center=body.cg),
        center_of_mass=body.cg,
        name=body.name,
    )


def _axisymmetric_lid(g: BodyGeometry):
    """Lid (normals down) on the waterplane of an axisymmetric hull: the annuli between the radii where
    the whole profile crosses z = 0 (from the axis when it crosses an odd number of times); None if it
    does not cross."""
    import capytaine as cpt

    pts = np.asarray(g.profile, dtype=float)
    radii = sorted({float(a[0] + (b[0] - a[0]) * a[1] / (a[1] - b[1]))
                    for a, b in zip(pts[:-1], pts[1:], strict=True) if (a[1] > 0) != (b[1] > 0)})
    if not radii:
        return None
    if len(radii) % 2:
        radii.insert(0, 0.0)
    parts = [mesh_of_revolution([(inner, 0.0), (outer, 0.0)], g.panel_size, orient=False)
             for inner, outer in zip(radii[::2], radii[1::2], strict=True)]
    lid = parts[0] if len(parts) == 1 else cpt.Mesh.join_meshes(*parts)
    return _placed(lid, g)


def _placed(mesh, g: BodyGeometry):
    """A primitive's Capytaine mesh rotated about its origin and moved to its world position."""
    if any(g.rotation_deg):
        mesh = mesh.rotated_with_matrix(euler_xyz(g.rotation_deg))
    return mesh.translated(tuple(g.position))


def _rotation_symmetric(bodies: list[BemBody], symmetry: str):
    """The whole scene as one Capytaine body on a rotation-symmetric mesh (``C<n>``, ``D<n>``), the hull panels
    of each body in it, and plain per-body ``FloatingBody`` objects for the hydrostatics."""
    import capytaine as cpt

    order, mirror = symmetry_group(symmetry)
    hulls, lids, plain = [], [], []
    for b in bodies:
        immersed = _mesh(b.geometry).immersed_part()
        if immersed.nb_faces == 0:
            raise HydroDatabaseError(f"body {b.name!r}: the mesh has no panel below the waterline z = 0")
        surface_piercing = b.geometry.lid and np.max(immersed.vertices[:, 2]) > -1e-6
        hulls.append(immersed)
        lids.append(immersed.generate_lid(z=0.0, faces_max_radius=_lid_panel(b.geometry)) if surface_piercing else None)
        plain.append(cpt.FloatingBody(mesh=immersed, dofs=cpt.rigid_body_dofs(rotation_center=b.cg),
                                      center_of_mass=b.cg, name=b.name))
    system, panels = rotation_symmetric_system([b.name for b in bodies], np.array([b.cg for b in bodies], float),
                                               hulls, lids, order, mirror)
    return system, panels, plain


def reflection_symmetric(mesh, name: str, tolerance: float = 1e-6):
    """The half y >= 0 of a Capytaine mesh as a ``ReflectionSymmetricMesh`` about the plane y = 0.

    Panels that cross y = 0 are cut in two. Raises :class:`HydroDatabaseError` (naming the body)
    if the mesh is not its own mirror image: some panel centre has no mirror partner within
    ``tolerance`` times the mesh's size.
    """
    import capytaine as cpt

    centres = np.asarray(mesh.faces_centers)
    check_invariant(centres, MIRROR_XOZ, [name] * len(centres),
                    "mirror-symmetric about the plane y = 0 (hydro.bem_symmetry = 'xOz'; else set it to 'none')",
                    tolerance)
    half = mesh.clipped(origin=(0.0, 0.0, 0.0), normal=(0.0, -1.0, 0.0))
    return cpt.ReflectionSymmetricMesh(half=half, plane="xOz", name=mesh.name)


def _lid_panel(geometry: BodyGeometry) -> float:
    return geometry.panel_size if geometry.shape != "mesh" else 1.0


def _mesh(geometry: BodyGeometry):
    """Capytaine mesh of a body in world coordinates (primitives keep Capytaine's quadrilaterals, also when
    rotated: a rotated copy of a primitive has the rotated panels of the original, which ``hydro.bem_symmetry``
    needs)."""
    if geometry.shape == "axisymmetric":  # wetted part only (dry segments left out)
        return _placed(mesh_of_revolution(geometry.profile, geometry.panel_size, skip=geometry.dry_segments), geometry)
    if geometry.shape == "mesh":
        return to_capytaine(body_mesh(geometry))
    return _placed(_primitive_mesh(geometry), geometry)


def _primitive_mesh(geometry: BodyGeometry):
    """Capytaine mesh of a primitive in its local coordinates."""
    import capytaine as cpt

    g, ps = geometry, geometry.panel_size
    if g.shape == "vertical_cylinder":
        if g.radius <= 0 or g.draft <= 0:
            raise HydroDatabaseError("vertical_cylinder needs a positive radius and draft")
        n_theta = max(12, math.ceil(2 * math.pi * g.radius / ps))
        n_z = max(2, math.ceil(g.draft / ps))
        n_r = max(2, math.ceil(g.radius / ps))
        mesh = cpt.mesh_vertical_cylinder(
            length=2 * g.draft, radius=g.radius, center=(0.0, 0.0, 0.0), resolution=(n_r, n_theta, 2 * n_z)
        )
    elif g.shape == "sphere":
        if g.radius <= 0:
            raise HydroDatabaseError("sphere needs a positive radius")
        n = max(8, math.ceil(math.pi * g.radius / ps))
        mesh = cpt.mesh_sphere(radius=g.radius, center=(0.0, 0.0, 0.0), resolution=(n, 2 * n))
    elif g.shape == "axisymmetric":
        mesh = mesh_of_revolution(g.profile, ps)
    elif g.shape == "regular_prism":
        if g.sides < 3 or g.radius <= 0 or g.draft <= 0:
            raise HydroDatabaseError("regular_prism needs at least 3 sides and a positive radius and draft")
        mesh = regular_prism_mesh(g.sides, g.radius, g.draft, ps)
    elif g.shape == "box":
        if min(g.size) <= 0:
            raise HydroDatabaseError("box needs three positive sizes (length, width, height)")
        res = tuple(max(2, math.ceil(s / ps)) for s in g.size)
        mesh = cpt.mesh_parallelepiped(size=tuple(g.size), center=(0.0, 0.0, 0.0), resolution=res)
    else:
        raise HydroDatabaseError(f"unknown primitive shape {g.shape!r}")
    return mesh


def mesh_of_revolution(profile, panel_size: float, skip: tuple[int, ...] = (), orient: bool = True):
    """Capytaine mesh of the surface swept by revolving ``profile`` about the z axis.

    ``profile``: ``(r, z)`` points (m, r >= 0) along the hull's cross-section in a meridian
    half-plane, e.g. for a floating annulus: the outer wall from above the waterline down, the
    bottom inwards, the inner wall up. Each segment is split into pieces no longer than
    ``panel_size`` and revolved in its own number of sectors, the smallest that keeps arcs at its
    largest radius no longer than ``panel_size`` (even, at least 12): a slender column under a wide plate
    keeps panels of about the same size on both (segments meet without sharing vertices, which
    a constant-panel BEM does not need). Points on the axis close the surface with triangles. The
    vertices lie at ``r sqrt(phi / sin phi)`` (``phi`` the sector angle), so each horizontal section
    of the faceted surface has the area of the true circle: volumes and waterplane areas, hence
    the hydrostatics of vertical walls and flat bottoms, are exact for any number of sectors.
    Normals point out of the body whichever way the profile is traversed (the orientation that
    gives the immersed part a positive volume is kept) if ``orient``, else along ``t x e_theta``
    (``t`` the profile's direction). Segments whose index is in ``skip`` are left out.
    """
    import capytaine as cpt

    pts = np.asarray(profile, dtype=float).reshape(-1, 2)
    if len(pts) < 2 or np.any(pts[:, 0] < 0) or not np.all(np.isfinite(pts)):
        raise HydroDatabaseError("axisymmetric profile needs at least two (r, z) points with r >= 0")
    vertices, faces = [], []
    for index, (a, b) in enumerate(zip(pts[:-1], pts[1:], strict=True)):
        if index in skip:
            continue
        n_s = max(1, math.ceil(float(np.hypot(*(b - a))) / panel_size))
        n_t = 2 * max(6, math.ceil(math.pi * max(a[0], b[0]) / panel_size))  # even: vertices on y = 0
        phi = 2 * math.pi / n_t
        meridian = a + (b - a) * (np.arange(n_s + 1)[:, None] / n_s)
        theta = phi * np.arange(n_t)
        r = meridian[:, 0] * math.sqrt(phi / math.sin(phi))
        v = np.stack([np.outer(r, np.cos(theta)), np.outer(r, np.sin(theta)),
                      np.repeat(meridian[:, 1:], n_t, axis=1)], axis=-1).reshape(-1, 3)
        base = sum(len(x) for x in vertices)
        for i in range(n_s):
            for j in range(n_t):
                p, q = base + i * n_t + j, base + i * n_t + (j + 1) % n_t
                s, t = q + n_t, p + n_t
                if meridian[i, 0] == 0.0:
                    faces.append([p, s, t, t])
                elif meridian[i + 1, 0] == 0.0:
                    faces.append([p, q, s, s])
                else:
                    faces.append([p, q, s, t])
        vertices.append(v)
    vertices, faces = np.concatenate(vertices), np.array(faces, dtype=int)
    mesh = cpt.Mesh(vertices=vertices, faces=faces)
    if orient and _divergence_volume(mesh.immersed_part()) < 0:
        mesh = cpt.Mesh(vertices=vertices, faces=faces[:, [0, 3, 2, 1]])
    return mesh


def _divergence_volume(mesh) -> float:
    """Volume by the divergence theorem with z n_z (valid for a surface open above the waterline or closed
    by a neighbour's dry stretch, where the x and y forms are not)."""
    return float(np.sum(np.asarray(mesh.faces_centers)[:, 2] * np.asarray(mesh.faces_normals)[:, 2]
                        * np.asarray(mesh.faces_areas)))


def _file_digest(path: Path) -> str:
    if not path.is_file():
        raise HydroDatabaseError(f"mesh file {path} does not exist")
    return hashlib.sha256(path.read_bytes()).hexdigest()
