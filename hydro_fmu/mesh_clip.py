"""Triangles of a surface mesh clipped below another surface (the wetted part of a hull under the free
surface): each triangle cut along its edges where the linear interpolant of the height above the surface
vanishes, the cut parts kept as triangles with the original orientation. Used by the wetted-area check of
:mod:`hydro_fmu.meshes` and by the pressure integrals of :mod:`hydro_fmu.nonlinear_hydrostatics`."""

from __future__ import annotations

import numpy as np


def clip_below(corners: np.ndarray, surface: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parts of triangles below a surface, as triangles with the original orientation.

    Args:
        corners: (F, 3, 3) triangle corners.
        surface: (F, 3) surface height above each corner's (x, y).

    Returns ``(triangles (G, 3, 3), parent (G,))``: the wetted triangles and the index of the
    triangle each comes from. The cut along an edge is where the linear interpolant of
    z - surface vanishes.
    """
    d = corners[:, :, 2] - surface
    below = d < 0
    count = below.sum(axis=1)
    pieces = [corners[count == 3]]
    parents = [np.flatnonzero(count == 3)]
    # One corner below: roll it to the front; keep that corner and the two cut points.
    one = np.flatnonzero(count == 1)
    if len(one):
        shift = np.argmax(below[one], axis=1)
        c, dd = _roll(corners[one], d[one], shift)
        p01 = _cut(c[:, 0], c[:, 1], dd[:, 0], dd[:, 1])
        p02 = _cut(c[:, 0], c[:, 2], dd[:, 0], dd[:, 2])
        pieces.append(np.stack([c[:, 0], p01, p02], axis=1))
        parents.append(one)
    # Two corners below: roll the dry corner to the back; the wet quadrilateral makes two triangles.
    two = np.flatnonzero(count == 2)
    if len(two):
        dry = np.argmax(~below[two], axis=1)
        c, dd = _roll(corners[two], d[two], (dry + 1) % 3)
        p12 = _cut(c[:, 1], c[:, 2], dd[:, 1], dd[:, 2])
        p20 = _cut(c[:, 2], c[:, 0], dd[:, 2], dd[:, 0])
        pieces.append(np.stack([c[:, 0], c[:, 1], p12], axis=1))
        pieces.append(np.stack([c[:, 0], p12, p20], axis=1))
        parents += [two, two]
    return np.concatenate(pieces, axis=0), np.concatenate(parents)


def _roll(corners: np.ndarray, d: np.ndarray, shift: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cyclically rotate each triangle's corners so that corner ``shift`` comes first."""
    order = (shift[:, None] + np.arange(3)[None, :]) % 3
    rows = np.arange(len(corners))[:, None]
    return corners[rows, order], d[rows, order]


def _cut(p: np.ndarray, q: np.ndarray, dp: np.ndarray, dq: np.ndarray) -> np.ndarray:
    """Point on the segment p-q where the linear function with end values dp, dq vanishes."""
    return p + (q - p) * (dp / (dp - dq))[:, None]
