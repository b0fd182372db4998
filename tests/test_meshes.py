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


def test_repaired_f3of_meshes_pass_the_checks_and_keep_the_geometry() -> None:
    """scenarios/data/f3of/repair_meshes.py: no error left, mirror-symmetric about y = 0 (the half-mesh
    BEM accepts them), the same volume and centre of buoyancy as the originals at every resolution
    (the refinements split flat panels), and the base's x and z divergence volumes now agree (the
    misplaced end faces of the fore bearing blocks reached 0.5 m into the corner blocks)."""
    from scipy.spatial import cKDTree

    from hydro_fmu.meshes import _divergence_volumes

    for body, pos, n in (("base", (0, 0, -9), 1616), ("flap", (12.5, 0, -5.5), 496)):
        v0, c0 = read_mesh(F3OF / f"{body}.obj").translated(pos).immersed_part().volume_and_centroid()
        for suffix, factor in (("", 1), ("_x2", 2), ("_x4", 4)):
            mesh = read_mesh(F3OF / f"{body}_repaired{suffix}.obj")
            assert mesh.n_faces == factor * n
            if not suffix:  # (the refined meshes are checked by every BEM run that uses them: 20 s more here)
                assert check_mesh(mesh.translated(pos), body, pos).errors == []
            volume, centre = mesh.translated(pos).immersed_part().volume_and_centroid()
            assert volume == pytest.approx(v0, rel=1e-12)
            np.testing.assert_allclose(centre, c0, atol=1e-9)
            gap, _ = cKDTree(mesh.centres).query(mesh.centres * [1, -1, 1])
            assert gap.max() < 1e-9
            vx, _, vz = _divergence_volumes(mesh.translated(pos).immersed_part())
            assert vx == pytest.approx(vz, rel=1e-12)


def test_hull_hydrostatics_of_a_box_and_of_a_box_open_where_it_touches_another() -> None:
    """Volume, centre of buoyancy and restoring matrix by the z form, against the closed-form box:
    A_wp = L B, C55 = rho g (B L^3 / 12 + L B x_c^2 ... about the cg) and C44 likewise. The box is cut
    in two at x = 0 and each half loses its face there (like the F3OF flap and base at their hinge
    tubes): each half still gets its own exact volume, centre of buoyancy and matrix, and the two
    halves' matrices sum to the whole box's about the same point."""
    from hydro_fmu.hydrostatics import hull_hydrostatics
    from hydro_fmu.meshes import from_corners

    rho, g = 1025.0, 9.81
    L, B, D = 4.0, 2.0, 3.0
    cg = np.array([0.3, 0.2, -1.2])

    def box(x0: float, x1: float, open_face: str | None):
        v = np.array([[x, y, z] for z in (-D, 0.5) for y in (-B / 2, B / 2) for x in (x0, x1)])
        quads = {"bottom": [0, 2, 3, 1], "top": [4, 5, 7, 6], "y-": [0, 1, 5, 4], "y+": [2, 6, 7, 3],
                 "x-": [0, 4, 6, 2], "x+": [1, 3, 7, 5]}
        tris = [[v[q[0]], v[q[1]], v[q[2]]] for k, q in quads.items() if k != open_face] + \
               [[v[q[0]], v[q[2]], v[q[3]]] for k, q in quads.items() if k != open_face]
        return from_corners(np.array(tris)).immersed_part()

    def exact(x0: float, x1: float) -> tuple[float, np.ndarray, np.ndarray]:
        length, xm = x1 - x0, (x0 + x1) / 2
        vol = length * B * D
        zb = -D / 2
        k = np.zeros((6, 6))
        k[2, 2] = rho * g * length * B
        k[2, 3] = k[3, 2] = rho * g * length * B * (0 - cg[1])
        k[2, 4] = k[4, 2] = -rho * g * length * B * (xm - cg[0])
        k[3, 3] = rho * g * (length * B**3 / 12 + length * B * cg[1] ** 2 + vol * (zb - cg[2]))
        k[3, 4] = k[4, 3] = -rho * g * length * B * (xm - cg[0]) * (0 - cg[1])
        k[4, 4] = rho * g * (B * length**3 / 12 + length * B * (xm - cg[0]) ** 2 + vol * (zb - cg[2]))
        k[3, 5] = -rho * g * vol * (xm - cg[0])
        k[4, 5] = -rho * g * vol * (0 - cg[1])
        return vol, np.array([xm, 0.0, zb]), k

    total = np.zeros((6, 6))
    for x0, x1, face in ((-L / 2, L / 2, None), (-L / 2, 0.0, "x+"), (0.0, L / 2, "x-")):
        vol, cb, k = hull_hydrostatics(box(x0, x1, face), cg, rho, g)
        v_ref, cb_ref, k_ref = exact(x0, x1)
        assert vol == pytest.approx(v_ref, rel=1e-12)
        np.testing.assert_allclose(cb, cb_ref, atol=1e-12)
        np.testing.assert_allclose(k, k_ref, rtol=1e-12, atol=1e-9 * np.abs(k_ref).max())
        if face is None:
            whole = k
        else:
            total += k
    np.testing.assert_allclose(total[2:5, 2:5], whole[2:5, 2:5], rtol=1e-12)
