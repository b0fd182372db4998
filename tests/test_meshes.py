"""Mesh files: readers, placement, and the defect checks (F3OF meshes as the real-world case)."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from hydro_fmu.bem import BemBody, BemSettings, BodyGeometry, body_mesh, cached_database
from hydro_fmu.hdb import HydroDatabaseError
from hydro_fmu.meshes import check_mesh, read_mesh

from .conftest import SCENARIOS

F3OF = SCENARIOS / "data" / "f3of"


def box_faces() -> tuple[np.ndarray, list[list[int]]]:
    """Unit cube [0, 1]^3 with outward quads (OBJ numbering, 1-based)."""
    v = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=float)
    quads = [[1, 3, 4, 2], [5, 6, 8, 7], [1, 2, 6, 5], [3, 7, 8, 4], [1, 5, 7, 3], [2, 4, 8, 6]]
    return v, quads


def write_obj(path, vertices, faces) -> None:
    lines = [f"v {x} {y} {z}" for x, y, z in vertices] + ["f " + " ".join(str(i) for i in f) for f in faces]
    path.write_text("# cube\n" + "\n".join(lines) + "\n")


def write_stl(path, triangles, binary: bool) -> None:
    if binary:
        data = bytearray(b"\0" * 80) + struct.pack("<I", len(triangles))
        for tri in triangles:
            data += struct.pack("<12fH", 0, 0, 0, *tri.ravel(), 0)
        path.write_bytes(bytes(data))
    else:
        body = "".join("facet normal 0 0 0\n outer loop\n" + "".join(f"  vertex {a} {b} {c}\n" for a, b, c in tri)
                       + " endloop\nendfacet\n" for tri in triangles)
        path.write_text("solid cube\n" + body + "endsolid cube\n")


def test_obj_and_stl_readers_agree_on_a_cube(tmp_path) -> None:
    v, quads = box_faces()
    write_obj(tmp_path / "cube.obj", v, quads)
    obj = read_mesh(tmp_path / "cube.obj")
    for binary in (False, True):
        name = tmp_path / f"cube_{binary}.stl"
        write_stl(name, obj.corners, binary)
        stl = read_mesh(name)
        assert stl.n_faces == 12 and len(stl.vertices) == 8  # STL vertices merged
        np.testing.assert_allclose(np.sort(stl.areas), np.sort(obj.areas))
    # Placed half under water: volume 1/2, centre of buoyancy at the middle of the wet half.
    placed = obj.translated((-0.5, -0.5, -0.5))
    volume, centroid = placed.immersed_part().volume_and_centroid()
    assert volume == pytest.approx(0.5)
    np.testing.assert_allclose(centroid, [0, 0, -0.25], atol=1e-12)


def test_rotated_placement_keeps_volume_and_turns_the_centroid(tmp_path) -> None:
    v, quads = box_faces()
    write_obj(tmp_path / "cube.obj", v * [2.0, 1.0, 1.0], quads)  # 2 x 1 x 1 box, origin at a corner
    straight = body_mesh(BodyGeometry("mesh", mesh_file=str(tmp_path / "cube.obj"), position=(0, 0, -3)))
    turned = body_mesh(BodyGeometry("mesh", mesh_file=str(tmp_path / "cube.obj"), position=(0, 0, -3),
                                    rotation_deg=(0, 0, 90)))
    (v1, c1), (v2, c2) = straight.volume_and_centroid(), turned.volume_and_centroid()
    assert v1 == pytest.approx(2.0) and v2 == pytest.approx(2.0)
    np.testing.assert_allclose(c2, [-c1[1], c1[0], c1[2]], atol=1e-12)  # +90 deg about z: (x, y) -> (-y, x)


def test_unreadable_and_inside_out_meshes_are_named(tmp_path) -> None:
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nf 1 2 9\n")
    with pytest.raises(HydroDatabaseError, match="bad.obj.*vertex that does not exist"):
        read_mesh(bad)
    with pytest.raises(HydroDatabaseError, match="does not exist"):
        read_mesh(tmp_path / "missing.stl")
    v, quads = box_faces()
    write_obj(tmp_path / "inside_out.obj", v - 0.5, [q[::-1] for q in quads])
    report = check_mesh(read_mesh(tmp_path / "inside_out.obj"), "cube", (0, 0, 0))
    assert any("normals point into the body" in e for e in report.errors)


def test_f3of_base_defect_is_found_and_located() -> None:
    """The base mesh's recess panels: two panel centres lie on perpendicular panels near
    (-11.5, +-11, -8.7) once placed at the base cg (0, 0, -9): Capytaine returns NaN there."""
    mesh = read_mesh(F3OF / "base.obj").translated((0, 0, -9))
    report = check_mesh(mesh, "base", (0, 0, -9))
    assert len(report.errors) == 1
    message = report.errors[0]
    assert "centres of 2 panels lie on other panels" in message and "NaN" in message
    assert "(-11.5, -11, -8.7)" in message and "(-11.5, 11, -8.7)" in message
    assert any("not closed" in w for w in report.warnings)


def test_f3of_flap_is_not_closed_and_its_buoyancy_centre_is_on_the_cg_vertical() -> None:
    """The flap's volume differs between the divergence forms (369 vs 304 m^3: the hub has no end
    faces). By the z form, which the open waterplane does not affect, the centre of buoyancy is on the
    vertical of the cg (the flap is symmetric in x); an averaged volume (Capytaine 3.0) moves it to
    x = 12.5 * 369 / 347 = 13.28 m, the 0.78 m offset reported for this mesh."""
    mesh = read_mesh(F3OF / "flap.obj").translated((12.5, 0, -5.5))
    report = check_mesh(mesh, "flap", (12.5, 0, -5.5))
    assert report.errors == []
    closure = next(w for w in report.warnings if "not closed" in w)
    assert "368.9, 304, 368.9" in closure
    assert report.centre_of_buoyancy[0] == pytest.approx(12.5, abs=1e-9)
    assert not any("horizontally from the centre of gravity" in w for w in report.warnings)


def test_cb_offset_warning_names_the_distance(tmp_path) -> None:
    v, quads = box_faces()
    write_obj(tmp_path / "cube.obj", v, quads)
    mesh = read_mesh(tmp_path / "cube.obj").translated((0.0, -0.5, -0.5))  # cb at x = 0.5
    report = check_mesh(mesh, "cube", (0.0, 0.0, -0.5))
    assert any("0.5 m horizontally from the centre of gravity" in w for w in report.warnings)


def test_bem_run_on_the_f3of_base_stops_with_the_defect(tmp_path) -> None:
    body = BemBody("base", BodyGeometry("mesh", mesh_file=str(F3OF / "base.obj"), position=(0, 0, -9)), (0, 0, -9))
    with pytest.raises(HydroDatabaseError, match=r"body 'base' \(mesh .*base.obj\): the centres of 2 panels"):
        cached_database([body], BemSettings(omega=(0.5, 1.0)), tmp_path)


def test_capytaine_averaged_volume_moves_the_flap_buoyancy_centre() -> None:
    """Dependency pitfall (docs/design.md): Capytaine 3.0 divides the x-moment by the mean of the three
    divergence volumes, so on the non-closed flap mesh its centre of buoyancy moves with the placement."""
    import capytaine as cpt

    placed = cpt.load_mesh(str(F3OF / "flap.obj")).translated((12.5, 0, -5.5))
    assert placed.center_of_buoyancy[0] == pytest.approx(12.5 * 368.87 / ((2 * 368.87 + 304.0) / 3), rel=1e-4)
