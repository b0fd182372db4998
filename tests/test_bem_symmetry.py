"""Rotation and dihedral symmetry of a set of bodies in the BEM (``hydro.bem_symmetry = "C<n>"``, ``"D<n>"``)
and the regular-prism primitive.

The scene is a small Nenuphar: a triangular hub with three boxes on its sides (D3). Expected values come
from the geometry (volumes, centroids) and from the group itself: a solve on the full mesh obeys the
symmetry only to the precision of Capytaine's panel integrals, the symmetric solve to round-off, and both
solve the same discretised problem, so they agree to that precision."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydro_fmu.bem import BemBody, BemSettings, BodyGeometry, compute_database
from hydro_fmu.bem_symmetry import MIRROR_XOZ, rotation_z, symmetry_group
from hydro_fmu.hdb import HydroDatabaseError
from hydro_fmu.prism_mesh import regular_prism_mesh

RHO, G = 1000.0, 9.81
R_HUB, DRAFT, R_BOX = 1.2, 0.3, 2.3


def scene(shift: float = 0.0, lid: bool = False) -> list[BemBody]:
    """Hub and three boxes; without lids by default (a plain solve generates each rotated body's lid on a grid of
    world axes, so its lids would not be rotated copies of each other)."""
    bodies = [BemBody("hub", BodyGeometry("regular_prism", sides=3, radius=R_HUB, draft=DRAFT, panel_size=0.3,
                                          lid=lid), (0.0, 0.0, 0.0))]
    for k in range(3):
        a = math.radians(120 * k)
        cg = (R_BOX * math.cos(a) + (shift if k == 2 else 0.0), R_BOX * math.sin(a), 0.0)
        bodies.append(BemBody(f"raft{k + 1}", BodyGeometry("box", size=(2.0, 1.0, 2 * DRAFT), position=cg,
                                                            rotation_deg=(0.0, 0.0, 120.0 * k), panel_size=0.3,
                                                            lid=lid),
                              cg))
    return bodies


SETTINGS = BemSettings(omega=(1.5, 3.0), headings_deg=(0.0, 30.0, 120.0), rho=RHO, g=G)


@pytest.fixture(scope="module")
def solves():
    import dataclasses

    bodies = scene()
    out = {s: compute_database(bodies, dataclasses.replace(SETTINGS, symmetry=s)) for s in ("none", "D3", "C3")}
    out["D3 with lids"] = compute_database(scene(lid=True), dataclasses.replace(SETTINGS, symmetry="D3"))
    return out


def group_matrix(transform: np.ndarray, perm: list[int], axial_sign: float) -> np.ndarray:
    """Action on the 6N rigid-body coordinates: body i's (force, moment) goes to body perm[i], rotated; a
    reflection also flips the moment (an axial vector)."""
    n = len(perm)
    q = np.zeros((6 * n, 6 * n))
    for i, j in enumerate(perm):
        q[6 * j:6 * j + 3, 6 * i:6 * i + 3] = transform
        q[6 * j + 3:6 * j + 6, 6 * i + 3:6 * i + 6] = axial_sign * transform
    return q


ROTATION = group_matrix(rotation_z(2 * math.pi / 3), [0, 2, 3, 1], 1.0)
MIRROR = group_matrix(MIRROR_XOZ, [0, 1, 3, 2], -1.0)


def asymmetry(hdb, q: np.ndarray, heading_map: dict[int, int]) -> float:
    """Largest violation of A = Q A Q^T, B = Q B Q^T and X(heading') = Q X(heading), relative to each array."""
    out = 0.0
    for a in (hdb.added_mass, hdb.radiation_damping):
        out = max(out, float(np.max(np.abs(q @ a @ q.T - a)) / np.max(np.abs(a))))
    x = hdb.excitation
    for h, image in heading_map.items():
        out = max(out, float(np.max(np.abs(x[image] - x[h] @ q.T)) / np.max(np.abs(x))))
    return out


def test_symmetry_names() -> None:
    assert symmetry_group("none") == (1, False) and symmetry_group("xOz") == (1, True)
    assert symmetry_group("D6") == (6, True) and symmetry_group("C4") == (4, False)
    for bad in ("D1", "E6", "D", "C0"):
        with pytest.raises(HydroDatabaseError, match="unknown BEM symmetry"):
            symmetry_group(bad)


def test_regular_prism_mesh_is_the_prism() -> None:
    """Volume 3 sqrt(3)/4 R^2 (draft + freeboard) of a triangular prism, centroid on the axis (the closed hull:
    Capytaine's centroid of an open immersed part mixes its three volume estimates), normals out; the immersed
    part has the volume below the waterline."""
    from hydro_fmu.meshes import from_capytaine

    mesh = regular_prism_mesh(3, R_HUB, DRAFT, 0.3)
    area = 3 * math.sqrt(3) / 4 * R_HUB**2
    volume, centroid = from_capytaine(mesh).volume_and_centroid()
    assert volume == pytest.approx(area * 2 * DRAFT, rel=1e-12)
    np.testing.assert_allclose(centroid, [0.0, 0.0, 0.0], atol=1e-12)
    assert mesh.immersed_part().volume == pytest.approx(area * DRAFT, rel=1e-12)
    hexagon = regular_prism_mesh(6, 7.5, 0.7, 0.7).immersed_part()
    assert hexagon.volume == pytest.approx(3 * math.sqrt(3) / 2 * 7.5**2 * 0.7, rel=1e-12)
    bottom = np.asarray(hexagon.faces_centers)[:, 2] < -0.69
    assert np.all(np.asarray(hexagon.faces_normals)[bottom, 2] < -0.999)


def test_dihedral_solve_is_symmetric_to_round_off_and_equals_the_full_solve(solves) -> None:
    """D3: the 120 deg rotation and the mirror y -> -y hold to 1e-12 in A, B and the excitation (heading 0 maps to
    120 deg under the rotation, to itself under the mirror), with and without lids. The plain solve of the same
    panels obeys the rotation to 1e-5 but the mirror only to 5e-4 here (measured: a mirrored panel's vertices run
    the other way round, which Capytaine's panel integrals feel at that level), so the two databases can agree
    only to about that: 3e-3 of each array's largest entry."""
    full, d3 = solves["none"], solves["D3"]
    assert asymmetry(d3, ROTATION, {0: 2}) < 1e-12
    assert asymmetry(d3, MIRROR, {0: 0}) < 1e-12
    assert asymmetry(full, ROTATION, {0: 2}) < 1e-4 and asymmetry(full, MIRROR, {0: 0}) < 1e-3
    lids = solves["D3 with lids"]
    assert asymmetry(lids, ROTATION, {0: 2}) < 1e-12 and asymmetry(lids, MIRROR, {0: 0}) < 1e-12
    for name in ("added_mass", "radiation_damping", "added_mass_inf", "excitation", "hydrostatic_stiffness",
                 "displaced_volume"):
        a, b = getattr(full, name), getattr(d3, name)
        np.testing.assert_allclose(b, a, rtol=0, atol=3e-3 * np.abs(a).max(), err_msg=name)
    assert "symmetry D3" in d3.source


def test_rotation_only_solve(solves) -> None:
    """C3 (no mirror): the rotation holds to round-off, the mirror only to the panel integrals' precision, and the
    result is the dihedral one to that precision."""
    c3, d3 = solves["C3"], solves["D3"]
    assert asymmetry(c3, ROTATION, {0: 2}) < 1e-12
    np.testing.assert_allclose(c3.added_mass, d3.added_mass, rtol=0, atol=3e-3 * np.abs(d3.added_mass).max())


def test_a_scene_without_the_symmetry_is_an_error() -> None:
    import dataclasses

    # raft3 moved 5 cm: raft2's image under the rotation is where raft3 should be, and is no panel
    with pytest.raises(HydroDatabaseError, match="'raft2' is not part of a set of bodies unchanged by a rotation "
                                                 "of 120 deg about the z axis.*0.05 m away"):
        compute_database(scene(shift=0.05), dataclasses.replace(SETTINGS, symmetry="C3"))
