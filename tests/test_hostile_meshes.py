"""Generated broken hull meshes: a closed box hull (STL and OBJ) scaled to absurd sizes, given non-finite
coordinates, opened (each face of the box removed in turn), turned inside out, with duplicated panels, lifted out
of the water, cut short, and files declaring more faces than the limit (two million among them).

Each case runs ``wec-cosim hydro`` (the mesh is checked before any BEM work): exit status 2 and one paragraph naming
the mesh file, no traceback and no numpy warning line before it. The face limit is applied from the file's header
or lines, before the mesh is read.
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest

from hydro_fmu.meshes import MAX_MESH_FACES, SurfaceMesh

from .hostile import Case, check, cylinder
from .test_malformed_generated import _materialise, run_in_process


def box(n: int = 6, length: float = 10.0, height: float = 5.0) -> SurfaceMesh:
    """A closed box hull, 10 x 10 x 5 m centred on the waterline, each face n x n squares of two triangles,
    normals out. Faces in the order bottom, top, y-, y+, x-, x+ (2 n^2 triangles each)."""
    verts, faces = [], []

    def face(origin: np.ndarray, u: np.ndarray, v: np.ndarray) -> None:
        base = len(verts)
        ii, jj = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
        verts.extend((origin + np.multiply.outer(ii / n, u) + np.multiply.outer(jj / n, v)).reshape(-1, 3))
        a = base + ii[:-1, :-1] * (n + 1) + jj[:-1, :-1]
        b, d = a + n + 1, a + 1
        faces.extend(np.stack([a, b, b + 1], -1).reshape(-1, 3))
        faces.extend(np.stack([a, b + 1, d], -1).reshape(-1, 3))

    h, z = length / 2, height / 2
    x, y, up = np.array([length, 0, 0]), np.array([0, length, 0]), np.array([0, 0, height])
    face(np.array([-h, -h, -z]), y, x)
    face(np.array([-h, -h, z]), x, y)
    face(np.array([-h, -h, -z]), x, up)
    face(np.array([-h, h, -z]), up, x)
    face(np.array([-h, -h, -z]), up, y)
    face(np.array([h, -h, -z]), y, up)
    return SurfaceMesh(np.array(verts, float), np.array(faces))


def binary_stl(corners: np.ndarray, count: int | None = None) -> bytes:
    rec = np.zeros(len(corners), dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    rec["v"] = corners
    return b"\0" * 80 + struct.pack("<I", len(corners) if count is None else count) + rec.tobytes()


def obj(mesh: SurfaceMesh) -> str:
    return "".join(f"v {float(a)!r} {float(b)!r} {float(c)!r}\n" for a, b, c in mesh.vertices) + "".join(
        f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in mesh.faces)


def mesh_cases() -> list[tuple[str, str, object, list[str]]]:
    """(label, file name, content (bytes or str), fragments of the message)."""
    m = box()
    c = m.corners
    per_face = len(c) // 6
    out = []
    for scale in (1e5, 1e30, -6e37):  # metres read as micrometres, and up to float32's largest
        out.append((f"coordinates times {scale:g}", "hull.stl", binary_stl(c * scale), ["coordinates up to"]))
    for bad in (np.nan, np.inf):
        corners = c.copy()
        corners[7, 1, 2] = bad
        out.append((f"a {bad} coordinate", "hull.stl", binary_stl(corners), ["non-finite"]))
        text = obj(m).replace(f"v {float(m.vertices[3][0])!r}", f"v {bad}", 1)
        out.append((f"a {bad} coordinate (OBJ)", "hull.obj", text, ["non-finite"]))
    faces = {name: c[k * per_face:(k + 1) * per_face] for k, name in enumerate(("bottom", "top", "y-", "y+", "x-",
                                                                                "x+"))}
    sides = ("y-", "y+", "x-", "x+")
    # hulls opened so that no volume is enclosed below the waterline (open edges alone are only a warning: meshes
    # of bodies that touch each other, and non-conforming ones, have them)
    opened = [("bottom",), *(("bottom", side) for side in sides), *(tuple(f for f in faces if f != side)
                                                                   for side in sides)]
    for removed in opened:
        kept = np.concatenate([v for k, v in faces.items() if k not in removed])
        out.append((f"the {', '.join(removed)} face(s) removed", "hull.stl", binary_stl(kept), ["the mesh is open"]))
    out.append(("turned inside out", "hull.stl", binary_stl(c[:, ::-1]), ["normals point into the body"]))
    out.append(("turned inside out (OBJ)", "hull.obj", obj(SurfaceMesh(m.vertices, m.faces[:, ::-1])),
                ["normals point into the body"]))
    out.append(("ten panels duplicated", "hull.stl", binary_stl(np.concatenate([c, c[:10]])),
                ["overlapping coplanar panels"]))
    out.append(("lifted out of the water", "hull.stl", binary_stl(c + [0, 0, 10.0]), ["below the waterline"]))
    data = binary_stl(c)
    out.append(("cut in the middle of a record", "hull.stl", data[:84 + 50 * 37 + 20], ["hull.stl"]))
    out.append(("header only", "hull.stl", data[:84], ["hull.stl"]))
    out.append(("header declaring two million faces", "hull.stl", binary_stl(c, 2_000_000), ["hull.stl"]))
    big = np.repeat(c[:1], MAX_MESH_FACES + 1, axis=0)
    out.append((f"{MAX_MESH_FACES + 1} faces (binary STL)", "hull.stl", binary_stl(big), ["faces, more than"]))
    out.append((f"{MAX_MESH_FACES + 1} faces (OBJ)", "hull.obj",
                "v 0 0 0\nv 1 0 -1\nv 0 1 -1\n" + "f 1 2 3\n" * (MAX_MESH_FACES + 1), ["faces, more than"]))
    return out


CASES = mesh_cases()


def _scenario(tmp: str, mesh_file: str) -> dict:
    data = cylinder(hydro={"cache_dir": f"{tmp}/cache"})
    data["bodies"][0]["geometry"] = {"shape": "mesh", "mesh_file": mesh_file}
    data["bodies"][0]["mass"] = 2.5e5
    return data


@pytest.mark.parametrize("label, name, content, fragments", CASES, ids=[c[0] for c in CASES])
def test_a_broken_mesh_is_one_clean_error_before_any_bem_work(tmp_path, label, name, content, fragments) -> None:
    case = Case(label, ["hydro", "{dir}/s.toml"], {"s.toml": _scenario(str(tmp_path), name), name: content},
                ["{dir}/" + name, *fragments])
    code, stderr = run_in_process(_materialise(case, tmp_path))
    check(case, code, stderr, tmp_path)
    assert not (tmp_path / "cache").exists() or not any(Path(tmp_path / "cache").glob("*.h5")), "a BEM solve ran"


def test_the_face_limit_is_applied_before_the_mesh_is_read(tmp_path) -> None:
    """Two million faces: refused at the scenario's load from the STL header alone (the file's records are
    zeros: a reader that parsed them would find no hull at all)."""
    path = tmp_path / "hull.stl"
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", 2_000_000))
        f.truncate(84 + 50 * 2_000_000)
    case = Case("two million faces", ["hydro", "{dir}/s.toml"], {"s.toml": _scenario(str(tmp_path), "hull.stl")},
                ["bodies[0].geometry.mesh_file", "2000000 faces"])
    code, stderr = run_in_process(_materialise(case, tmp_path))
    check(case, code, stderr, tmp_path)


def test_the_overlap_search_finds_what_it_must_on_a_large_mesh() -> None:
    """The vectorised search (near pairs by size class, separating axes, exact clipping of the few left) on a
    box of 19 200 panels: none on the intact hull, exactly the duplicated ones and the panel slid half over its
    neighbour."""
    from hydro_fmu.meshes import overlapping_coplanar_pairs

    m = box(40)
    assert len(overlapping_coplanar_pairs(m)) == 0
    c = m.corners
    slid = c[5] + (c[5, 1] - c[5, 0]) * 0.5  # a copy of panel 5 moved half an edge along itself
    corners = np.concatenate([c, c[[100, 2000, 9000]], slid[None]])
    from hydro_fmu.meshes import from_corners

    doubled = from_corners(corners)
    pairs = {tuple(sorted(p)) for p in overlapping_coplanar_pairs(doubled)}
    n = len(c)
    assert {(100, n), (2000, n + 1), (9000, n + 2)} <= pairs
    assert any(n + 3 in p for p in pairs)
