"""Panel mesh of a regular polygonal prism (a hexagonal pontoon, a polygonal column).

The prism has ``sides`` flat sides, circumradius ``radius`` (centre to corner), its axis along z
through the origin, the bottom at ``z = -draft`` and the deck at ``z = +freeboard``; a flat side faces
+x (its outward normal is the x axis), so the corners lie at the angles ``(2k + 1) pi / sides``.

The mesh is built from one twelfth (for a hexagon; ``1 / (2 sides)`` in general) of the hull: the
half-sector ``0 <= angle <= pi / sides``, reflected about y = 0 and rotated ``sides`` times. Every
panel therefore has its exact mirror and rotated images, and the sector boundaries (the rays to the
corners and the side's centre line) are panel edges: a BEM solve that cuts the hull along them
(``hydro.bem_symmetry``) splits no panel. The bottom and the deck of a half-sector are ``m = ceil(apothem /
panel_size)`` rings parallel to the side, each cut into quadrilaterals about ``panel_size`` wide (a
fan of triangles round the axis); neighbouring rings do not share their vertices (T-junctions, which
a constant-panel BEM does not need), the outer ring matches the side's panels. The side is a grid of
quadrilaterals with the waterline z = 0 as a grid line. Triangles are stored
as quadrilaterals with a repeated last vertex, as Capytaine does.
"""

from __future__ import annotations

import math

import numpy as np


def regular_prism_mesh(sides: int, radius: float, draft: float, panel_size: float,
                       freeboard: float | None = None, name: str | None = None):
    """Capytaine mesh of the closed prism (see the module docstring); lengths in m."""
    import capytaine as cpt

    vertices, faces = regular_prism_panels(sides, radius, draft, panel_size, freeboard)
    return cpt.Mesh(vertices=vertices, faces=faces, name=name)


def regular_prism_panels(sides: int, radius: float, draft: float, panel_size: float,
                         freeboard: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) and quadrilateral faces (F, 4) of the prism, normals outward (at least two rows of
    side panels below the waterline)."""
    if sides < 3 or radius <= 0 or draft <= 0 or panel_size <= 0:
        raise ValueError("a regular prism needs at least 3 sides and a positive radius, draft and panel size")
    freeboard = draft if freeboard is None else freeboard
    vertices, faces = _half_sector(sides, radius, draft, freeboard, panel_size)
    mirrored = vertices * np.array([1.0, -1.0, 1.0])
    piece_v = np.concatenate([vertices, mirrored])
    piece_f = np.concatenate([faces, faces[:, ::-1] + len(vertices)])  # reversed order keeps normals outward
    all_v, all_f = [], []
    for k in range(sides):
        c, s = math.cos(2 * math.pi * k / sides), math.sin(2 * math.pi * k / sides)
        rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        all_f.append(piece_f + len(piece_v) * k)
        all_v.append(piece_v @ rot.T)
    return np.concatenate(all_v), _repeat_last(np.concatenate(all_f))


def _repeat_last(faces: np.ndarray) -> np.ndarray:
    """Reversed triangles stored as (a, a, b, c) become (a, b, c, c): the repeated vertex last."""
    out = faces.copy()
    first = out[:, 0] == out[:, 1]
    out[first] = out[first][:, [0, 2, 3, 3]]
    return out


def _half_sector(sides: int, radius: float, draft: float, freeboard: float,
                 panel_size: float) -> tuple[np.ndarray, np.ndarray]:
    """Bottom, deck and side panels of the half-sector between the angles 0 and pi / sides."""
    apothem = radius * math.cos(math.pi / sides)
    half_side = radius * math.sin(math.pi / sides)
    m = max(2, math.ceil(apothem / panel_size))
    vertices: list[list[float]] = []
    faces: list[list[int]] = []

    def cap(z: float, up: bool) -> None:
        for i in range(m):  # ring i between the apothem fractions i / m and (i + 1) / m
            k = max(1, math.ceil(half_side * (i + 1) / (m * panel_size)))
            x0, x1 = apothem * i / m, apothem * (i + 1) / m
            y0, y1 = half_side * i / m, half_side * (i + 1) / m
            for j in range(k):
                corners = [[x0, y0 * j / k], [x1, y1 * j / k], [x1, y1 * (j + 1) / k], [x0, y0 * (j + 1) / k]]
                if i == 0:
                    corners = corners[:3]  # the ring round the axis is a fan of triangles
                first = len(vertices)
                vertices.extend([cx, cy, z] for cx, cy in corners)
                face = list(range(first, first + len(corners)))  # counter-clockwise seen from above
                faces.append(face if up else face[::-1])

    cap(-draft, up=False)
    cap(freeboard, up=True)
    n_y = max(1, math.ceil(half_side / panel_size))  # as the outer ring
    z = np.concatenate([np.linspace(-draft, 0.0, max(2, math.ceil(draft / panel_size)) + 1),
                        np.linspace(0.0, freeboard, max(1, math.ceil(freeboard / panel_size)) + 1)[1:]])
    y = np.linspace(0.0, half_side, n_y + 1)
    start = len(vertices)
    for zk in z:
        for yk in y:
            vertices.append([apothem, yk, zk])
    for k in range(len(z) - 1):
        for j in range(n_y):
            a = start + k * (n_y + 1) + j
            faces.append([a, a + 1, a + n_y + 2, a + n_y + 1])  # outward normal +x
    quads = [f if len(f) == 4 else [f[0], f[1], f[2], f[2]] for f in faces]
    return np.array(vertices, float), np.array(quads, dtype=np.int64)
