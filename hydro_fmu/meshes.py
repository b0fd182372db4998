"""Surface meshes of rigid bodies: reading, placing in the world, and checking for defects.

A :class:`SurfaceMesh` is a triangle mesh (vertices, faces) with outward normals (right-hand
rule on the vertex order). It is read from ``.obj`` or ``.stl`` (ASCII or binary) by the readers
here, or from any other format Capytaine reads (``.gdf``, ``.dat``, ``.msh``...) through
Capytaine; quadrilaterals are split into two triangles.

:func:`check_mesh` looks for the defects that make a BEM solve fail or mislead (see
``docs/hydrodynamics.md``): degenerate panels, overlapping coplanar panels (Capytaine's Green
function returns NaN on them, as on the F3OF base mesh), inward normals, holes in the wetted
surface, and a centre of buoyancy horizontally offset from the centre of gravity (the body is then
not in equilibrium at the pose given, unless a joint holds it: F3OF flaps).
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from .hdb import HydroDatabaseError
from .mesh_clip import clip_below

NATIVE_FORMATS = (".obj", ".stl")
MAX_MESH_FACES = 200_000  # triangles of a mesh file (counted before it is read; the wetted part is less)
MAX_COORDINATE = 1e5  # m: a hull larger than 100 km is a file in other units (or broken)
MAX_WETTED_PANELS = 60_000  # panels below the waterline that a BEM solve may be given


@dataclass(frozen=True)
class SurfaceMesh:
    """Triangle surface mesh.

    Attributes:
        vertices: (V, 3) coordinates, m.
        faces: (F, 3) vertex indices; the normal (v1 - v0) x (v2 - v0) points out of the body.
        name: where it came from (file name), for messages.
    """

    vertices: np.ndarray
    faces: np.ndarray
    name: str = ""

    def __post_init__(self) -> None:
        v = np.asarray(self.vertices, dtype=float).reshape(-1, 3)
        f = np.asarray(self.faces, dtype=np.int64).reshape(-1, 3)
        if len(f) and (f.min() < 0 or f.max() >= len(v)):
            raise HydroDatabaseError(f"mesh {self.name or '(unnamed)'}: a face refers to a vertex that does not exist")
        if not np.all(np.isfinite(v)):
            raise HydroDatabaseError(f"mesh {self.name or '(unnamed)'}: non-finite vertex coordinates")
        object.__setattr__(self, "vertices", v)
        object.__setattr__(self, "faces", f)

    # ------------------------------------------------------------------ geometry
    @cached_property
    def corners(self) -> np.ndarray:
        """(F, 3, 3): the three corners of each triangle."""
        return self.vertices[self.faces]

    @cached_property
    def area_vectors(self) -> np.ndarray:
        """(F, 3): area times unit outward normal of each triangle."""
        c = self.corners
        return 0.5 * np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])

    @property
    def areas(self) -> np.ndarray:
        return np.linalg.norm(self.area_vectors, axis=1)

    @property
    def centres(self) -> np.ndarray:
        return self.corners.mean(axis=1)

    @property
    def n_faces(self) -> int:
        return len(self.faces)

    def translated(self, offset: np.ndarray | tuple[float, float, float]) -> SurfaceMesh:
        return SurfaceMesh(self.vertices + np.asarray(offset, dtype=float), self.faces, self.name)

    def transformed(self, rotation: np.ndarray, offset: np.ndarray | tuple[float, float, float]) -> SurfaceMesh:
        """Vertices mapped by ``p -> rotation @ p + offset``."""
        return SurfaceMesh(self.vertices @ np.asarray(rotation).T + np.asarray(offset, dtype=float), self.faces,
                           self.name)

    def immersed_part(self) -> SurfaceMesh:
        """Triangles below z = 0, cut at the waterline (for checks; the BEM cut is Capytaine's)."""
        corners, _ = clip_below(self.corners, np.zeros(self.corners.shape[:2]))
        wet = from_corners(corners, self.name)
        # A corner exactly on the waterline leaves a zero-area sliver: not part of the hull.
        areas = wet.areas
        keep = areas > 1e-12 * max(float(areas.max(initial=0.0)), 1e-300)
        return from_corners(corners[keep], self.name)

    def volume_and_centroid(self) -> tuple[float, np.ndarray]:
        """Volume (m^3) and centroid (m) enclosed by the surface and the plane z = 0.

        Divergence theorem with fields that vanish on z = 0, so the waterplane of a cut
        (immersed) hull needs no lid: V = int z n_z dS, V x_c = int x z n_z dS,
        V z_c = int z^2/2 n_z dS (exact for flat triangles). For a closed surface the plane
        plays no role.
        """
        c = self.corners
        nz = self.area_vectors[:, 2]
        zc = c[:, :, 2].mean(axis=1)
        volume = float(np.sum(zc * nz))
        if abs(volume) < 1e-300:
            return 0.0, np.zeros(3)
        # int x z n_z dS = int x dV (for the x moment), likewise y; int z^2/2 n_z dS = int z dV.
        x, y, z = c[:, :, 0], c[:, :, 1], c[:, :, 2]
        xz = _triangle_mean_product(x, z)
        yz = _triangle_mean_product(y, z)
        zz = _triangle_mean_product(z, z)
        centroid = np.array([np.sum(xz * nz), np.sum(yz * nz), 0.5 * np.sum(zz * nz)]) / volume
        return volume, centroid


def _triangle_mean_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Mean over a triangle of the product of two linear functions given at its corners (F, 3)."""
    return (a.sum(axis=1) * b.sum(axis=1) + np.sum(a * b, axis=1)) / 12.0


def from_corners(corners: np.ndarray, name: str = "") -> SurfaceMesh:
    """A mesh from (F, 3, 3) triangle corners (vertices not shared)."""
    corners = np.asarray(corners, dtype=float).reshape(-1, 3, 3)
    return SurfaceMesh(corners.reshape(-1, 3), np.arange(3 * len(corners)).reshape(-1, 3), name)


def triangulate(faces: list[list[int]] | np.ndarray) -> np.ndarray:
    """Split polygons (fan from the first vertex) into triangles; repeated vertices are dropped."""
    out = []
    for face in faces:
        poly = [int(i) for k, i in enumerate(face) if k == 0 or int(i) != int(face[k - 1])]
        if len(poly) > 1 and poly[-1] == poly[0]:
            poly = poly[:-1]
        for k in range(1, len(poly) - 1):
            out.append((poly[0], poly[k], poly[k + 1]))
    return np.array(out, dtype=np.int64).reshape(-1, 3)


# ---------------------------------------------------------------------- readers
def mesh_face_count(path: str | Path) -> int | None:
    """The number of faces of an ``.stl`` or ``.obj`` file, counted without reading the mesh (binary STL: its
    header; ASCII STL: ``facet`` keywords; OBJ: ``f`` lines); None for other formats."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".stl":
        with open(path, "rb") as f:
            head = f.read(84)
        if len(head) == 84 and path.stat().st_size == 84 + 50 * struct.unpack("<I", head[80:84])[0]:
            return struct.unpack("<I", head[80:84])[0]
        return _count_lines(path, (b"facet",))
    if suffix == ".obj":
        return _count_lines(path, (b"f ", b"f\t"))
    return None


def _count_lines(path: Path, starts: tuple[bytes, ...]) -> int:
    count = 0
    with open(path, "rb") as f:
        for line in f:
            if line.lstrip().lower().startswith(starts):
                count += 1
    return count


def check_face_count(path: str | Path) -> None:
    """Refuse a mesh file with more than :data:`MAX_MESH_FACES` faces before any work is done on it."""
    n = mesh_face_count(path)
    if n is not None and n > MAX_MESH_FACES:
        raise HydroDatabaseError(
            f"mesh file {path} has {n} faces, more than the {MAX_MESH_FACES} a hull mesh may have here (a BEM solve's "
            "matrices are dense: N wetted panels need 32 N^2 bytes, 115 GB for 60000); coarsen the mesh")


def read_mesh(path: str | Path) -> SurfaceMesh:
    """Read a mesh file; ``.obj`` and ``.stl`` natively, other formats through Capytaine. Files of more than
    :data:`MAX_MESH_FACES` faces or with coordinates beyond :data:`MAX_COORDINATE` m are refused."""
    path = Path(path)
    if not path.is_file():
        raise HydroDatabaseError(f"mesh file {path} does not exist")
    check_face_count(path)
    suffix = path.suffix.lower()
    try:
        if suffix == ".obj":
            mesh = _read_obj(path)
        elif suffix == ".stl":
            mesh = _read_stl(path)
        else:
            mesh = _read_with_capytaine(path)
    except HydroDatabaseError:
        raise
    except Exception as exc:  # parsers raise many types for unreadable files
        raise HydroDatabaseError(f"cannot read mesh file {path}: {exc}") from None
    if mesh.n_faces == 0:
        raise HydroDatabaseError(f"mesh file {path} has no faces")
    if mesh.n_faces > MAX_MESH_FACES:
        raise HydroDatabaseError(f"mesh file {path} has {mesh.n_faces} faces, more than the {MAX_MESH_FACES} a hull "
                                 "mesh may have here; coarsen the mesh")
    largest = float(np.max(np.abs(mesh.vertices)))
    if largest > MAX_COORDINATE:
        raise HydroDatabaseError(f"mesh file {path} has coordinates up to {largest:.3g} m, beyond the "
                                 f"{MAX_COORDINATE:g} m of any hull: check the file's units (metres) and contents")
    return mesh


def _read_obj(path: Path) -> SurfaceMesh:
    vertices: list[list[float]] = []
    polygons: list[list[int]] = []
    for number, line in enumerate(path.read_text(errors="replace").splitlines(), start=1):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            if len(parts) < 4:
                raise HydroDatabaseError(f"{path}:{number}: a vertex needs three coordinates")
            vertices.append([float(p) for p in parts[1:4]])
        elif parts[0] == "f":
            idx = []
            for p in parts[1:]:
                i = int(p.split("/")[0])
                idx.append(i - 1 if i > 0 else len(vertices) + i)  # OBJ is 1-based; negative = relative
            if len(idx) < 3:
                raise HydroDatabaseError(f"{path}:{number}: a face needs at least three vertices")
            polygons.append(idx)
    return SurfaceMesh(np.array(vertices).reshape(-1, 3), triangulate(polygons), str(path))


def _read_stl(path: Path) -> SurfaceMesh:
    data = path.read_bytes()
    corners = None
    if len(data) >= 84:
        count = struct.unpack("<I", data[80:84])[0]
        if len(data) == 84 + 50 * count:  # binary STL: fixed record length
            records = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                    count=count, offset=84)
            corners = records["v"].astype(float)
    if corners is None:
        text = data.decode(errors="replace")
        if not text.lstrip().lower().startswith("solid"):
            raise HydroDatabaseError(f"{path}: neither ASCII STL (starts with 'solid') nor binary STL")
        values = [line.split()[1:4] for line in text.splitlines() if line.strip().lower().startswith("vertex")]
        if len(values) % 3:
            raise HydroDatabaseError(f"{path}: {len(values)} vertices, not a multiple of three")
        corners = np.array(values, dtype=float).reshape(-1, 3, 3)
    return _merge_vertices(corners, str(path))


def _merge_vertices(corners: np.ndarray, name: str) -> SurfaceMesh:
    """Shared vertices from triangle soup (STL), merged to 1e-9 of the mesh size."""
    points = corners.reshape(-1, 3)
    if not np.all(np.isfinite(points)):
        raise HydroDatabaseError(f"mesh {name or '(unnamed)'}: non-finite vertex coordinates (NaN or infinity)")
    scale = max(float(np.ptp(points, axis=0).max()), 1e-12)
    keys = np.round(points / (1e-9 * scale)).astype(np.int64)
    unique, inverse = np.unique(keys, axis=0, return_inverse=True)
    vertices = np.zeros((len(unique), 3))
    vertices[inverse.ravel()] = points
    return SurfaceMesh(vertices, inverse.reshape(-1, 3), name)


def _read_with_capytaine(path: Path) -> SurfaceMesh:
    import capytaine as cpt

    mesh = cpt.load_mesh(str(path))
    return from_capytaine(mesh, str(path))


def from_capytaine(mesh: object, name: str = "") -> SurfaceMesh:
    """A :class:`SurfaceMesh` from a Capytaine mesh: quadrilaterals split, coincident vertices
    merged, and the zero-area triangles that collapsed quadrilaterals (at the axis of Capytaine's
    primitives) leave behind dropped."""
    raw = SurfaceMesh(np.asarray(mesh.vertices), triangulate(np.asarray(mesh.faces)), name)
    merged = _merge_vertices(raw.corners, name)
    areas = merged.areas
    keep = areas > 1e-12 * max(float(areas.max(initial=0.0)), 1e-300)
    return SurfaceMesh(merged.vertices, merged.faces[keep], name)


def to_capytaine(mesh: SurfaceMesh, name: str = "") -> object:
    """A Capytaine mesh of the same triangles (Capytaine stores a triangle as a quad with a repeated vertex)."""
    import capytaine as cpt

    faces = np.concatenate([mesh.faces, mesh.faces[:, 2:3]], axis=1)
    return cpt.Mesh(vertices=mesh.vertices, faces=faces, name=name or None)


def write_meshes(meshes: dict[str, SurfaceMesh], path: str | Path) -> Path:
    """Several named meshes as one JSON file (deterministic bytes, so build caches stay valid)."""
    import json

    data = {name: {"vertices": m.vertices.tolist(), "faces": m.faces.tolist()} for name, m in meshes.items()}
    Path(path).write_text(json.dumps(data, sort_keys=True))
    return Path(path)


def read_meshes(path: str | Path) -> dict[str, SurfaceMesh]:
    """The meshes written by :func:`write_meshes`."""
    import json

    data = json.loads(Path(path).read_text())
    return {name: SurfaceMesh(np.array(m["vertices"]), np.array(m["faces"]), name) for name, m in data.items()}


# ---------------------------------------------------------------------- pose
def rotation_matrix(rotation_vector: np.ndarray | tuple[float, float, float]) -> np.ndarray:
    """Rotation matrix exp([theta]x) of a rotation vector theta (rad; axis times angle, Rodrigues)."""
    theta = np.asarray(rotation_vector, dtype=float)
    angle = float(np.linalg.norm(theta))
    if angle < 1e-12:
        k = np.array([[0, -theta[2], theta[1]], [theta[2], 0, -theta[0]], [-theta[1], theta[0], 0]])
        return np.eye(3) + k
    axis = theta / angle
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)


def euler_xyz(angles_deg: np.ndarray | tuple[float, float, float]) -> np.ndarray:
    """Rotation about the fixed x, then y, then z axes by the given angles (deg): Rz Ry Rx."""
    rx, ry, rz = np.radians(np.asarray(angles_deg, dtype=float))
    return rotation_matrix((0, 0, rz)) @ rotation_matrix((0, ry, 0)) @ rotation_matrix((rx, 0, 0))


# ---------------------------------------------------------------------- checks
@dataclass
class MeshReport:
    """Findings of :func:`check_mesh`: ``errors`` stop a BEM run, ``warnings`` are reported."""

    body: str
    source: str
    n_faces: int
    volume: float
    centre_of_buoyancy: np.ndarray
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    overlapping_pairs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=int))

    def raise_errors(self) -> None:
        if self.errors:
            raise HydroDatabaseError(
                f"body {self.body!r} (mesh {self.source}): " + "; ".join(self.errors))


def check_mesh(mesh: SurfaceMesh, body: str, cg: np.ndarray | tuple[float, float, float],
               *, cb_tolerance: float = 0.01) -> MeshReport:
    """Check a body's mesh, placed in the world, for defects that spoil a BEM solve or equilibrium.

    Args:
        mesh: the whole body surface in world coordinates.
        body: body name for the messages.
        cg: centre of gravity (world, m).
        cb_tolerance: horizontal distance (m) between centre of buoyancy and cg above which a
            warning is given.
    """
    wet = mesh.immersed_part()
    volume, cb = wet.volume_and_centroid()
    report = MeshReport(body, mesh.name, wet.n_faces, volume, cb)
    if wet.n_faces == 0:
        report.errors.append("no panel lies below the waterline z = 0")
        return report
    if wet.n_faces > MAX_WETTED_PANELS:
        report.errors.append(f"{wet.n_faces} panels lie below the waterline, more than the {MAX_WETTED_PANELS} a BEM "
                             "solve can take here; coarsen the mesh")
        return report
    size = float(np.sqrt(np.median(wet.areas)))
    wetted = np.flatnonzero(mesh.corners[:, :, 2].min(axis=1) < 0)
    degenerate = wetted[mesh.areas[wetted] < 1e-10 * max(size**2, 1e-30)]
    if len(degenerate):
        report.warnings.append(f"{len(degenerate)} degenerate (zero-area) panels below the waterline, first at "
                               f"{_fmt(mesh.centres[degenerate[0]])}")
    pairs = overlapping_coplanar_pairs(wet)
    report.overlapping_pairs = pairs
    if len(pairs):
        where = wet.centres[pairs[:, 0]]
        report.errors.append(
            f"{len(pairs)} pairs of overlapping coplanar panels near {_places(where)}: the surface is "
            "covered twice there; remove the duplicated panels")
    touching = centres_on_other_panels(wet)
    if len(touching):
        where = wet.centres[touching[:, 0]]
        report.errors.append(
            f"the centres of {len(touching)} panels lie on other panels (non-conforming or intersecting panels), "
            f"near {_places(where)}: Capytaine's Green function is singular there and returns NaN; make the "
            "panels meet edge to edge")
    volumes = _divergence_volumes(wet)
    if volume > 0 and np.ptp(volumes) > 0.01 * np.max(np.abs(volumes)):
        report.warnings.append(
            "the wetted surface is not closed (with the waterplane): the volume from the x, y and z forms of the "
            f"divergence theorem differs ({', '.join(f'{v:.4g}' for v in volumes)} m^3), so hydrostatics and the "
            "centre of buoyancy depend on the formula used (Capytaine averages them; the database and this check use "
            "the z form, which neither the missing waterplane nor openings in vertical faces affect: right where "
            "the body touches another one, wrong for a real hole)")
    holes = _open_edges_below_waterline(wet, tolerance=1e-6 * max(size, 1e-9))
    if volume <= 0 and holes:
        report.errors.append(
            f"the mesh is open: {holes[0]} edges below the waterline belong to one panel only (holes), e.g. at "
            f"{_fmt(holes[1])}, and the surface encloses no volume ({volume:.4g} m^3); give a closed hull surface")
    elif volume <= 0:
        report.errors.append(
            f"the enclosed volume is {volume:.4g} m^3: the panel normals point into the body; reverse the "
            "vertex order of the faces")
    elif holes:
        report.warnings.append(f"the wetted surface has {holes[0]} open edges below the waterline (holes), "
                               f"e.g. at {_fmt(holes[1])}")
    offset = np.hypot(cb[0] - cg[0], cb[1] - cg[1])
    if volume > 0 and offset > cb_tolerance:
        report.warnings.append(
            f"the centre of buoyancy {_fmt(cb)} is {offset:.3g} m horizontally from the centre of gravity "
            f"{_fmt(np.asarray(cg, dtype=float))}: buoyancy and weight make a moment at this pose, so the body is "
            "not in free-floating equilibrium (fine if a joint holds it; otherwise check where the mesh "
            "origin is relative to the cg)")
    return report


def _divergence_volumes(mesh: SurfaceMesh) -> np.ndarray:
    """Enclosed volume from int x n_x, int y n_y and int z n_z dS (equal for a closed surface)."""
    centres = mesh.centres
    return np.sum(centres * mesh.area_vectors, axis=0)


def near_pairs(centres: np.ndarray, radius: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pairs (i < j) of panels whose bounding spheres (centre, circumradius) intersect: |c_i - c_j| < r_i + r_j.

    Panels are grouped by size (radius classes a factor 2 apart) and each pair of groups is searched with a k-d
    tree at the largest radius of those two groups only: one large panel among many small ones makes a few
    candidates, not all pairs (a single search at twice the largest radius would be quadratic)."""
    from scipy.spatial import cKDTree

    n = len(centres)
    if n < 2:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    tiny = max(float(radius.max()), 1e-300) * 1e-12
    size_class = np.floor(np.log2(np.maximum(radius, tiny))).astype(np.int64)
    groups = [np.flatnonzero(size_class == k) for k in np.unique(size_class)]
    trees = [cKDTree(centres[g]) for g in groups]
    largest = [float(radius[g].max()) for g in groups]
    out_i, out_j = [], []
    for a, (ga, ta) in enumerate(zip(groups, trees, strict=True)):
        pairs = ta.query_pairs(2 * largest[a], output_type="ndarray")
        out_i.append(ga[pairs[:, 0]])
        out_j.append(ga[pairs[:, 1]])
        for b in range(a + 1, len(groups)):
            found = ta.query_ball_tree(trees[b], largest[a] + largest[b])
            counts = np.fromiter((len(x) for x in found), dtype=np.int64, count=len(found))
            if counts.sum():
                out_i.append(np.repeat(ga, counts))
                out_j.append(groups[b][np.concatenate([np.asarray(x, dtype=np.int64) for x in found if x])])
    i, j = np.concatenate(out_i), np.concatenate(out_j)
    close = np.linalg.norm(centres[i] - centres[j], axis=1) < radius[i] + radius[j]
    i, j = i[close], j[close]
    return np.minimum(i, j), np.maximum(i, j)


def centres_on_other_panels(mesh: SurfaceMesh, tolerance: float = 1e-6) -> np.ndarray:
    """Pairs (i, j): the centre of triangle i lies on triangle j (i != j), within ``tolerance``
    times j's size. A BEM collocation point on another panel makes the Green function singular."""
    c = mesh.corners
    if len(c) < 2:
        return np.zeros((0, 2), dtype=int)
    centres = c.mean(axis=1)
    radius = np.max(np.linalg.norm(c - centres[:, None, :], axis=2), axis=1)
    a_, b_ = near_pairs(centres, radius * (1 + 1e-9))
    i, j = np.concatenate([a_, b_]), np.concatenate([b_, a_])
    p = centres[i]
    a, b, d = c[j, 0], c[j, 1], c[j, 2]
    normal = np.cross(b - a, d - a)
    size = np.linalg.norm(normal, axis=1)
    ok = size > 0
    tol = tolerance * radius[j]
    plane = np.abs(np.einsum("ij,ij->i", p - a, normal)) / np.where(ok, size, 1.0)
    # Barycentric coordinates of the projection.
    v0, v1, v2 = b - a, d - a, p - a
    d00, d01, d11 = (np.einsum("ij,ij->i", x, y) for x, y in ((v0, v0), (v0, v1), (v1, v1)))
    d20, d21 = np.einsum("ij,ij->i", v2, v0), np.einsum("ij,ij->i", v2, v1)
    denom = np.where(ok, d00 * d11 - d01 * d01, 1.0)
    beta = (d11 * d20 - d01 * d21) / denom
    gamma = (d00 * d21 - d01 * d20) / denom
    slack = tol / np.where(ok, np.sqrt(size), 1.0)
    inside = (beta >= -slack) & (gamma >= -slack) & (beta + gamma <= 1 + slack)
    hit = ok & (plane < tol) & inside
    return np.stack([i[hit], j[hit]], axis=1)


def overlapping_coplanar_pairs(mesh: SurfaceMesh, *, angle_tol: float = 1e-6,
                               distance_tol: float = 1e-6, area_fraction: float = 1e-6) -> np.ndarray:
    """Pairs (i, j) of triangles that lie in one plane and overlap with positive area.

    Candidates are the pairs whose bounding spheres intersect (:func:`near_pairs`); a pair is kept when the
    normals are parallel or antiparallel to ``angle_tol`` and the planes coincide to ``distance_tol`` times the
    panel size. In the common plane a separating-axis test over the six edge normals (vectorised) drops the
    pairs that only touch (neighbours sharing an edge or a corner: every panel of a flat plate); the few left
    are clipped exactly (Sutherland-Hodgman) and kept when the intersection exceeds ``area_fraction`` of the
    smaller triangle. Cost: a k-d tree search and array operations, O(F log F) for F panels of similar sizes.
    """
    c = mesh.corners
    if len(c) < 2:
        return np.zeros((0, 2), dtype=int)
    centres = c.mean(axis=1)
    radius = np.max(np.linalg.norm(c - centres[:, None, :], axis=2), axis=1)
    area_vec = mesh.area_vectors
    areas = np.linalg.norm(area_vec, axis=1)
    ok = areas > 0
    normals = np.zeros_like(area_vec)
    normals[ok] = area_vec[ok] / areas[ok, None]
    i, j = near_pairs(centres, radius)
    if len(i) == 0:
        return np.zeros((0, 2), dtype=int)
    keep = ok[i] & ok[j]
    keep &= np.abs(np.abs(np.einsum("ij,ij->i", normals[i], normals[j])) - 1.0) < angle_tol
    scale = np.maximum(radius[i], radius[j])
    keep &= np.abs(np.einsum("ij,ij->i", normals[i], centres[j] - centres[i])) < distance_tol * scale + 1e-12
    i, j = i[keep], j[keep]
    apart = _separated_in_plane(c[i], c[j], normals[i], 1e-9 * scale[keep])
    i, j = i[~apart], j[~apart]
    out = []
    for a, b in zip(i, j, strict=True):
        overlap = _coplanar_overlap_area(c[a], c[b], normals[a])
        if overlap > area_fraction * min(areas[a], areas[b]):
            out.append((a, b))
    return np.array(out, dtype=int).reshape(-1, 2)


def _separated_in_plane(t1: np.ndarray, t2: np.ndarray, normal: np.ndarray, tol: np.ndarray) -> np.ndarray:
    """For pairs of coplanar triangles (P, 3, 3) with the plane's unit normal (P, 3): whether an edge normal of
    either triangle separates them (their projections on it overlap by at most ``tol``: apart or touching)."""
    u = t1[:, 1] - t1[:, 0]
    u /= np.maximum(np.sqrt((u * u).sum(axis=1)), 1e-300)[:, None]
    w = np.cross(normal, u)
    d1, d2 = t1 - t1[:, :1], t2 - t1[:, :1]
    px, py = (d1 * u[:, None]).sum(axis=2), (d1 * w[:, None]).sum(axis=2)  # (P, 3) plane coordinates
    qx, qy = (d2 * u[:, None]).sum(axis=2), (d2 * w[:, None]).sum(axis=2)
    apart = np.zeros(len(t1), dtype=bool)
    for x, y in ((px, py), (qx, qy)):
        for k in range(3):
            ax, ay = y[:, k] - y[:, (k + 1) % 3], x[:, (k + 1) % 3] - x[:, k]
            length = np.maximum(np.hypot(ax, ay), 1e-300)
            a = (px * ax[:, None] + py * ay[:, None]) / length[:, None]
            b = (qx * ax[:, None] + qy * ay[:, None]) / length[:, None]
            depth = np.minimum(a.max(axis=1), b.max(axis=1)) - np.maximum(a.min(axis=1), b.min(axis=1))
            apart |= depth <= tol
    return apart


def _coplanar_overlap_area(t1: np.ndarray, t2: np.ndarray, normal: np.ndarray) -> float:
    """Area of the intersection of two coplanar triangles (Sutherland-Hodgman in the plane)."""
    u = t1[1] - t1[0]
    u /= np.linalg.norm(u)
    w = np.cross(normal, u)
    p = [np.array([(q - t1[0]) @ u, (q - t1[0]) @ w]) for q in t1]
    r = [np.array([(q - t1[0]) @ u, (q - t1[0]) @ w]) for q in t2]
    if _signed_area(p) < 0:
        p = p[::-1]
    if _signed_area(r) < 0:
        r = r[::-1]
    poly = r
    for k in range(3):
        a, b = p[k], p[(k + 1) % 3]
        poly = _clip_half_plane(poly, a, b)
        if not poly:
            return 0.0
    return abs(_signed_area(poly))


def _signed_area(poly: list[np.ndarray]) -> float:
    """Shoelace formula: positive for counter-clockwise polygons."""
    n = len(poly)
    return 0.5 * sum(poly[k][0] * poly[(k + 1) % n][1] - poly[(k + 1) % n][0] * poly[k][1] for k in range(n))


def _clip_half_plane(poly: list[np.ndarray], a: np.ndarray, b: np.ndarray) -> list[np.ndarray]:
    """Part of ``poly`` on the left of the directed line a -> b."""
    def side(q: np.ndarray) -> float:
        return (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0])

    out = []
    for k in range(len(poly)):
        cur, prev = poly[k], poly[k - 1]
        sc, sp = side(cur), side(prev)
        if sc >= 0:
            if sp < 0:
                out.append(prev + (cur - prev) * (sp / (sp - sc)))
            out.append(cur)
        elif sp >= 0:
            out.append(prev + (cur - prev) * (sp / (sp - sc)))
    return out


def _open_edges_below_waterline(mesh: SurfaceMesh, tolerance: float) -> tuple[int, np.ndarray] | None:
    """Count of edges used by one triangle only and lying below z = 0 (holes); None if closed."""
    merged = _merge_vertices(mesh.corners, mesh.name)
    f = merged.faces
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    single = unique[counts == 1]
    if len(single) == 0:
        return None
    z = merged.vertices[single][:, :, 2]
    below = single[np.max(z, axis=1) < -tolerance]
    if len(below) == 0:
        return None
    return len(below), merged.vertices[below[0]].mean(axis=0)


def _fmt(p: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:.3g}" for v in p) + ")"


def _places(points: np.ndarray, limit: int = 4) -> str:
    """A few distinct locations (rounded to 0.1 m) of a set of points."""
    rounded = np.unique(np.round(points, 1), axis=0)
    text = ", ".join(_fmt(p) for p in rounded[:limit])
    return text + (f" and {len(rounded) - limit} more places" if len(rounded) > limit else "")
