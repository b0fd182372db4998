"""Linear hydrostatic restoring force about the equilibrium position.

    F_hs = - C x,

with C the block-diagonal matrix of the bodies' restoring matrices (database convention: about
each body's centre of gravity, buoyancy only, see :mod:`hydro_fmu.hdb`) and x the displacement
from equilibrium. The constant parts (weight and mean buoyancy) balance at equilibrium and are
left out.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import block_diag

from .hdb import HydroDatabase
from .meshes import SurfaceMesh


class LinearHydrostatics:
    """Restoring force on the selected degrees of freedom (indices into the 6N numbering)."""

    def __init__(self, hdb: HydroDatabase, dofs: np.ndarray) -> None:
        full = block_diag(*hdb.hydrostatic_stiffness)
        self.stiffness = full[np.ix_(dofs, dofs)]

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Force (N, N m) for displacement ``x`` (m, rad)."""
        return -self.stiffness @ x


def hull_hydrostatics(wet: SurfaceMesh, cg: np.ndarray | tuple[float, float, float], rho: float,
                      g: float) -> tuple[float, np.ndarray, np.ndarray]:
    """Displaced volume (m^3), centre of buoyancy (m) and the 6 x 6 restoring matrix about ``cg``
    of a hull's wetted surface ``wet`` (cut at z = 0, world frame), by the z form of the
    divergence theorem.

    Every integral is one of the surface with fields whose flux through the waterplane and through
    vertical faces vanishes: V = int z n_z dS, the centroid by
    :meth:`~hydro_fmu.meshes.SurfaceMesh.volume_and_centroid`, and waterplane integrals
    int_wp f dA = -int f(x, y) n_z dS (exact on flat triangles for f of degree <= 2). A surface that
    is open along vertical faces (a body in contact with another one there, such as the F3OF flaps
    and base at their hinge tubes) therefore gets the volume and centre of buoyancy of the closed
    body, where Capytaine 3.0's average of the x, y and z forms does not. The matrix is Capytaine's
    rigid-body formula with the rotation centre at the cg (so the weight term vanishes):
    C33 = rho g A_wp, C34 = rho g int y', C35 = -rho g int x', C44 = rho g (int y'^2 + V (z_b - z_g)),
    C45 = -rho g int x' y', C55 = rho g (int x'^2 + V (z_b - z_g)), C46 = -rho g V (x_b - x_g),
    C56 = -rho g V (y_b - y_g), symmetric in the heave-roll-pitch block, x' = x - x_g, y' = y - y_g.
    """
    from .meshes import _triangle_mean_product

    cg = np.asarray(cg, dtype=float)
    volume, cb = wet.volume_and_centroid()
    c = wet.corners
    nz = wet.area_vectors[:, 2]
    x, y = c[:, :, 0] - cg[0], c[:, :, 1] - cg[1]

    def waterplane(mean: np.ndarray) -> float:
        return -float(np.sum(mean * nz))

    area = waterplane(np.ones(len(c)))
    sx, sy = waterplane(x.mean(axis=1)), waterplane(y.mean(axis=1))
    ixx, iyy, ixy = (waterplane(_triangle_mean_product(a, b)) for a, b in ((y, y), (x, x), (x, y)))
    rg = rho * g
    k = np.zeros((6, 6))
    k[2, 2] = rg * area
    k[2, 3] = k[3, 2] = rg * sy
    k[2, 4] = k[4, 2] = -rg * sx
    k[3, 3] = rg * (ixx + volume * (cb[2] - cg[2]))
    k[3, 4] = k[4, 3] = -rg * ixy
    k[4, 4] = rg * (iyy + volume * (cb[2] - cg[2]))
    k[3, 5] = -rg * volume * (cb[0] - cg[0])
    k[4, 5] = -rg * volume * (cb[1] - cg[1])
    return volume, cb, k
