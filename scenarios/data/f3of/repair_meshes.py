"""Repair the F3OF meshes (seed 000) for the BEM and write two resolutions.

Run from anywhere (writes next to this file, deterministic output):

    python scenarios/data/f3of/repair_meshes.py

Inputs: ``base.obj`` and ``flap.obj`` as copied from the project's shared data (body-local
coordinates, origin at each body's centre of gravity). Outputs:

- ``base_repaired.obj``, ``flap_repaired.obj``: the original panels, repaired (below);
- ``base_repaired_x2.obj``, ``flap_repaired_x2.obj``: the same surfaces with every triangle split
  in two at the midpoint of its longest edge (twice the panels);
- ``base_repaired_x4.obj``, ``flap_repaired_x4.obj``: every triangle split into four by its edge
  midpoints (half the panel size).

The refinements keep the flat-panel geometry exactly (same volume, waterplane and centre of
buoyancy); they serve the mesh-convergence check and the scenarios' database (docs/f3of.md).

Repairs (each one printed with what it changed):

1. **Fore bearing blocks of the base.** The blocks x in [-13.5, -11.5], y in +-[10.5, 11],
   z in [-1, 1] (local) carry the fore flap's outer hinge bearings. Their end face x = -11.5 is
   split into two triangles whose corner at (-11.5, +-11.5, -1) should be at (-11.5, +-11, -1):
   the face runs 0.5 m into the corner block next to it, and the centre of one of its triangles
   lies on the edge of the corner block's face y = +-11 (Capytaine's Green function returns NaN
   there; ``hydro_fmu.meshes.check_mesh`` reports it). The aft blocks (x = +11.5) are right; the
   corner is moved to where the aft blocks have it.
2. **Mirror symmetry about y = 0.** Both surfaces are mirror-symmetric (same areas and moments on
   each side) but 64 base and 16 flap panels are triangulated differently on the two sides; no
   panel crosses y = 0. The half y > 0 is kept and mirrored, so the BEM can solve on half meshes
   (``hydro.bem_symmetry = "xOz"``), which halves the unknowns.

Not repaired, on purpose: the openings of the hinge tubes. The flap's hinge tube (y in +-[1, 10.5])
and the base's bearing tubes (|y| < 1 and 10.5 < |y| < 11) have no end faces where they meet: in
the assembled device they touch there, so those faces are not wetted, and the union of the three
surfaces is closed. Capping them would put two coincident panels of opposite normals at each seam
(again a NaN for the Green function). The caps' normals are along y, so the z form of the
divergence theorem (which the project uses for the volume and the centre of buoyancy of mesh
bodies) is not affected by them, nor by the open waterplane.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[2]))  # the repository root, for hydro_fmu

from hydro_fmu.meshes import SurfaceMesh, _merge_vertices, check_mesh, read_mesh  # noqa: E402

PLACEMENT = {"base": (0.0, 0.0, -9.0), "flap": (12.5, 0.0, -5.5)}  # seed 000, Table 1 (cg of the aft flap)


def fix_fore_bearing_end_faces(mesh: SurfaceMesh) -> tuple[SurfaceMesh, int]:
    """Move the misplaced corner (-11.5, +-11.5, -1) of the fore bearing blocks' end faces to y = +-11."""
    vertices = mesh.vertices.copy()
    corners = mesh.corners
    centres = corners.mean(axis=1)
    end_faces = np.flatnonzero((np.abs(centres[:, 0] + 11.5) < 1e-9) & (np.abs(np.abs(centres[:, 1]) - 10.9) < 0.45))
    moved = 0
    new_faces = mesh.faces.copy()
    for f in end_faces:
        for k in range(3):
            p = corners[f, k]
            if abs(p[0] + 11.5) < 1e-9 and abs(abs(p[1]) - 11.5) < 1e-9 and abs(p[2] + 1.0) < 1e-9:
                vertices = np.vstack([vertices, [p[0], np.sign(p[1]) * 11.0, p[2]]])
                new_faces[f, k] = len(vertices) - 1
                moved += 1
    return SurfaceMesh(vertices, new_faces, mesh.name), moved


def mirror_symmetric(mesh: SurfaceMesh) -> SurfaceMesh:
    """The half y > 0 and its mirror image about y = 0 (orientation kept outward)."""
    corners = mesh.corners
    centres = corners.mean(axis=1)
    if np.any((corners[:, :, 1].min(axis=1) < -1e-9) & (corners[:, :, 1].max(axis=1) > 1e-9)):
        raise ValueError(f"{mesh.name}: a panel crosses y = 0; cut it before mirroring")
    half = corners[centres[:, 1] > 0]
    mirrored = half[:, ::-1] * np.array([1.0, -1.0, 1.0])  # reflection reverses orientation: reverse the order
    return _merge_vertices(np.concatenate([half, mirrored]), mesh.name)


def bisect(mesh: SurfaceMesh) -> SurfaceMesh:
    """Every triangle split in two at the midpoint of its longest edge (twice the panels)."""
    c = mesh.corners
    longest = np.argmax(np.linalg.norm(c[:, [1, 2, 0]] - c, axis=2), axis=1)  # edge k runs from corner k to k+1
    rolled = np.stack([np.roll(t, -k, axis=0) for t, k in zip(c, longest, strict=True)])  # longest edge first
    a, b, d = rolled[:, 0], rolled[:, 1], rolled[:, 2]
    m = (a + b) / 2
    parts = np.stack([np.stack([a, m, d], 1), np.stack([m, b, d], 1)], axis=1).reshape(-1, 3, 3)
    return _merge_vertices(parts, mesh.name)


def subdivide(mesh: SurfaceMesh) -> SurfaceMesh:
    """Every triangle split into four by its edge midpoints."""
    c = mesh.corners
    a, b, d = c[:, 0], c[:, 1], c[:, 2]
    ab, bd, da = (a + b) / 2, (b + d) / 2, (d + a) / 2
    parts = np.stack([np.stack([a, ab, da], 1), np.stack([ab, b, bd], 1), np.stack([da, bd, d], 1),
                      np.stack([ab, bd, da], 1)], axis=1).reshape(-1, 3, 3)
    return _merge_vertices(parts, mesh.name)


def write_obj(mesh: SurfaceMesh, path: Path, header: list[str]) -> None:
    lines = [f"# {h}" for h in header]
    lines += [f"v {x:.10g} {y:.10g} {z:.10g}" for x, y, z in mesh.vertices]
    lines += [f"f {i + 1} {j + 1} {k + 1}" for i, j, k in mesh.faces]
    path.write_text("\n".join(lines) + "\n")


def describe(mesh: SurfaceMesh, body: str) -> str:
    """Panel count and the defects ``check_mesh`` finds with the body placed as in the scenarios."""
    pos = PLACEMENT[body]
    report = check_mesh(mesh.translated(pos), body, pos)
    volumes = np.sum(mesh.translated(pos).immersed_part().centres
                     * mesh.translated(pos).immersed_part().area_vectors, axis=0)
    text = [f"{mesh.n_faces} panels, z-form volume {report.volume:.3f} m^3, centre of buoyancy "
            f"{np.round(report.centre_of_buoyancy, 4).tolist()} m (placed), x/y/z-form volumes "
            f"{', '.join(f'{v:.1f}' for v in volumes)} m^3"]
    text += [f"  error: {e}" for e in report.errors] + [f"  warning: {w}" for w in report.warnings]
    return "\n".join(text)


def main() -> None:
    for body in ("base", "flap"):
        original = read_mesh(HERE / f"{body}.obj")
        print(f"{body}.obj: {describe(original, body)}")
        mesh = original
        if body == "base":
            mesh, moved = fix_fore_bearing_end_faces(mesh)
            print(f"  repair 1: {moved} corners of the fore bearing blocks' end faces moved from y = +-11.5 to +-11")
        mesh = mirror_symmetric(mesh)
        print(f"  repair 2: mirror-symmetric about y = 0 ({mesh.n_faces} panels)")
        for out, suffix, what in ((mesh, "", "original panels"),
                                  (bisect(mesh), "_x2", "each panel split in two across its longest edge"),
                                  (subdivide(mesh), "_x4", "each panel split into four")):
            path = HERE / f"{body}_repaired{suffix}.obj"
            write_obj(out, path, [f"F3OF {body}, repaired by repair_meshes.py from {body}.obj ({what})",
                                  "body-local coordinates, origin at the centre of gravity (seed 000, Table 1)"])
            print(f"{path.name}: {describe(out, body)}")


if __name__ == "__main__":
    main()
