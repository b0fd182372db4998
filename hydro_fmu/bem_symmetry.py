"""Symmetries of a set of bodies that Capytaine can exploit: mirror and n-fold rotation about z.

``hydro.bem_symmetry`` names the group (Schoenflies-like): ``none``; ``xOz`` (every body is its own
mirror image about the plane y = 0; :func:`hydro_fmu.bem.reflection_symmetric`); ``C<n>`` (the set
of bodies is unchanged by a rotation of 360/n deg about the z axis, the bodies themselves need not
be: a ring of floats round a hub); ``D<n>`` (``C<n>`` plus the mirror about y = 0: the Nenuphar's
hexagonal hub with six rafts is ``D6``).

For ``C<n>`` and ``D<n>`` the whole scene becomes one Capytaine ``FloatingBody`` on a
``RotationSymmetricMesh`` (its wedge, for ``D<n>``, a ``ReflectionSymmetricMesh``), carrying the 6N
rigid-body DOFs of the N bodies as DOFs restricted to each body's panels, so one solve gives the
6N x 6N added mass and damping and the 6N excitation with all the interactions, the influence
matrices built for one wedge (one half-wedge) only and solved block-circulantly: 1/n (1/2n) of the
Green-function evaluations, 1/n^2 of the factorisation. The results then obey the symmetry to
round-off (e.g. mirror-image bodies respond equally to 1e-15), where a plain solve of the same mesh
obeys it only to the Green function's own precision (about 1e-6 here).

How the wedge is made: the hull (and lid) of every body is checked to be carried into the set of
all panels by the rotation (and mirror), within ``tolerance`` times the scene's size, and the body
permutation is read from the centres of gravity; then each body is cut by the planes through the z
axis at -180/n and +180/n deg (and y = 0 for ``D<n>``) and the pieces joined. The other wedges are
the rotated (and mirrored) copies, so panels cut by those planes are replaced by their images: the
mesh is the symmetric version of the input. A check that every body's wetted area is reproduced
(1e-6) guards the bookkeeping.
"""

from __future__ import annotations

import math
import re

import numpy as np

from .hdb import HydroDatabaseError

DOF_NAMES = ("Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw")
_GROUP = re.compile(r"^([CD])([1-9][0-9]*)$")


def symmetry_group(name: str) -> tuple[int, bool]:
    """``(rotation order n, mirror about y = 0)`` of a ``hydro.bem_symmetry`` value."""
    if name == "none":
        return 1, False
    if name == "xOz":
        return 1, True
    match = _GROUP.match(name)
    if match is None or int(match.group(2)) < 2:
        raise HydroDatabaseError(f"unknown BEM symmetry {name!r}; expected 'none', 'xOz', 'C<n>' or 'D<n>' (n >= 2)")
    return int(match.group(2)), match.group(1) == "D"


def symmetry_error(name: str) -> str | None:
    """Schema check: None if ``name`` is a valid symmetry, else the reason."""
    try:
        symmetry_group(name)
    except HydroDatabaseError as exc:
        return str(exc)
    return None


def rotation_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


MIRROR_XOZ = np.diag([1.0, -1.0, 1.0])


def check_invariant(centres: np.ndarray, transform: np.ndarray, owner: list[str], what: str,
                    tolerance: float) -> None:
    """Raise naming the first panel whose image under ``transform`` (3x3) is no panel centre."""
    from scipy.spatial import cKDTree

    size = float(np.ptp(centres, axis=0).max())
    gap, _ = cKDTree(centres).query(centres @ transform.T)
    if gap.max() > tolerance * size:
        k = int(np.argmax(gap))
        raise HydroDatabaseError(
            f"{owner[k]!r} is not {what}: the image of its panel at {np.round(centres[k], 4).tolist()} m is no "
            f"panel (nearest {gap.max():.3g} m away)")


def body_permutation(cgs: np.ndarray, transform: np.ndarray, names: list[str], what: str,
                     tolerance: float) -> np.ndarray:
    """``perm[i]``: the body whose centre of gravity is the image of body i's under ``transform``."""
    size = max(float(np.ptp(cgs, axis=0).max()), 1.0)
    images = cgs @ transform.T
    perm = np.empty(len(cgs), dtype=int)
    for i, image in enumerate(images):
        dist = np.linalg.norm(cgs - image, axis=1)
        j = int(np.argmin(dist))
        if dist[j] > tolerance * size:
            raise HydroDatabaseError(f"{names[i]!r} is not {what}: the image of its centre of gravity "
                                     f"{np.round(image, 4).tolist()} m is no body's centre of gravity")
        perm[i] = j
    return perm


def _wedge_cut(mesh, order: int, mirror: bool):
    """The part of ``mesh`` in the wedge -pi/n <= angle <= pi/n (and y >= 0 when ``mirror``)."""
    a = math.pi / order
    part = mesh.clipped(origin=(0.0, 0.0, 0.0), normal=(-math.sin(a), -math.cos(a), 0.0))
    if part.nb_faces:
        part = part.clipped(origin=(0.0, 0.0, 0.0), normal=(-math.sin(a), math.cos(a), 0.0))
    if mirror and part.nb_faces:
        part = part.clipped(origin=(0.0, 0.0, 0.0), normal=(0.0, -1.0, 0.0))
    return part


def _symmetric(pieces: list, tags: list[int], order: int, mirror: bool, rot: np.ndarray, mir: np.ndarray):
    """Capytaine symmetric mesh from the wedge ``pieces`` (body ``tags``) and the owner of each face of its
    merged form (face order: wedge k = 0..n-1 rotated by 2 pi k / n; within a wedge, half then mirror)."""
    import capytaine as cpt

    wedge = pieces[0].join_meshes(*pieces[1:]) if len(pieces) > 1 else pieces[0]
    owner = np.concatenate([np.full(p.nb_faces, t) for p, t in zip(pieces, tags, strict=True)])
    if mirror:
        wedge = cpt.ReflectionSymmetricMesh(half=wedge, plane="xOz")
        owner = np.concatenate([owner, mir[owner]])
    copies, current = [], owner
    for _ in range(order):
        copies.append(current)
        current = rot[current]
    return cpt.RotationSymmetricMesh(wedge=wedge, n=order), np.concatenate(copies)


def rotation_symmetric_system(names: list[str], cgs: np.ndarray, hulls: list, lids: list, order: int,
                              mirror: bool, tolerance: float = 1e-6):
    """One Capytaine ``FloatingBody`` for all bodies on a rotation-symmetric mesh (module docstring).

    ``hulls``: each body's immersed Capytaine mesh in world coordinates; ``lids``: its lid mesh or None.
    Returns ``(body, panels)``: the FloatingBody (DOFs ``<name>__Surge`` ... in body order) and the
    number of hull panels of each body in the symmetric mesh.
    """
    import capytaine as cpt
    from capytaine.bodies.dofs import DofOnSubmesh, RotationDof, TranslationDof

    cgs = np.asarray(cgs, dtype=float)
    turn = rotation_z(2 * math.pi / order)
    what_rot = (f"part of a set of bodies unchanged by a rotation of {360 / order:g} deg about the z axis "
                "(hydro.bem_symmetry)")
    what_mir = "part of a set of bodies mirror-symmetric about the plane y = 0 (hydro.bem_symmetry)"
    centres = np.concatenate([np.asarray(h.faces_centers) for h in hulls])
    owners = [n for n, h in zip(names, hulls, strict=True) for _ in range(h.nb_faces)]
    check_invariant(centres, turn, owners, what_rot, tolerance)
    rot = body_permutation(cgs, turn, names, what_rot, tolerance)
    mir = np.arange(len(names))
    if mirror:
        check_invariant(centres, MIRROR_XOZ, owners, what_mir, tolerance)
        mir = body_permutation(cgs, MIRROR_XOZ, names, what_mir, tolerance)

    def assemble(meshes: list):
        pieces, tags = [], []
        for i, m in enumerate(meshes):
            if m is not None and m.nb_faces:
                part = _wedge_cut(m, order, mirror)
                if part.nb_faces:
                    pieces.append(part)
                    tags.append(i)
        return _symmetric(pieces, tags, order, mirror, rot, mir) if pieces else (None, None)

    hull, owner = assemble(hulls)
    areas = np.asarray(hull.faces_areas)
    for i, (name, h) in enumerate(zip(names, hulls, strict=True)):
        expected = float(np.sum(h.faces_areas))
        got = float(np.sum(areas[owner == i]))
        if abs(got - expected) > 1e-6 * expected:
            raise HydroDatabaseError(
                f"body {name!r}: the symmetric mesh has {got:.6g} m^2 of its wetted surface, the body "
                f"{expected:.6g} m^2 (hydro.bem_symmetry: is the body cut by another's wedge?)")
    lid, _ = assemble(lids) if any(x is not None for x in lids) else (None, None)
    dofs = {}
    for i, (name, cg) in enumerate(zip(names, cgs, strict=True)):
        mask = owner == i
        for d in range(3):
            dofs[f"{name}__{DOF_NAMES[d]}"] = DofOnSubmesh(TranslationDof(np.eye(3)[d]), mask)
        for d in range(3):
            dofs[f"{name}__{DOF_NAMES[3 + d]}"] = DofOnSubmesh(RotationDof(cg, np.eye(3)[d]), mask)
    body = cpt.FloatingBody(mesh=hull, lid_mesh=lid, dofs=dofs, name="+".join(names))
    return body, [int(np.sum(owner == i)) for i in range(len(names))]
