"""Moving a hydrodynamic database's coefficients from one reference point to another.

A BEM code gives the rotational coefficients about a reference point P (WAMIT's body origin,
Nemoh's and Capytaine's rotation centre); BEMIO files store it as each body's ``cg``. Our
coupling contract wants them about the body's centre of gravity G (:mod:`hydro_fmu.hdb`). For a
rigid body and small motions the motion of P follows from the motion of G and the rotation,

    x_P = x_G + theta x (P - G) = x_G + S(d) theta,   d = G - P,  S(d) theta = d x theta,

so q_P = T q_G with T = [[I, S(d)], [0, I]] per body, and a force (f, m_P) about P is the force
(f, m_P + (P - G) x f) about G: F_G = T^T F_P (virtual work). Hence, with T block-diagonal over
the bodies,

    A_G = T^T A_P T,   B_G = T^T B_P T,   A_inf,G = T^T A_inf,P T,   X_G = T^T X_P

for the added mass, damping and every excitation table (total, Froude-Krylov, diffraction): the
BEM's radiation boundary conditions for rotations about G are these same combinations of those
about P, so the transformation is exact for the discretised problem too (a database computed about
G equals the transformed one to round-off).

The hydrostatic matrix is the Hessian of a potential whose gradient, the buoyancy force
rho g V e_z, is not zero, so it is not a congruence alone. With the database convention
(buoyancy restoring only, Capytaine's rigid-body formula, x' = x - x_ref), writing both matrices
from the waterplane moments about each point gives exactly

    C_G = T^T C_P T + rho g V [ -d_z (e44 + e55) + d_x e46 + d_y e56 ],

(the waterplane terms are the congruence; the V (z_b - z_ref) terms of roll and pitch and the
-rho g V (x_b - x_ref), -rho g V (y_b - y_ref) terms of roll-yaw and pitch-yaw shift with the point).
The identity is checked against the formula at both points in ``tests/test_bemio_files.py``.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .hdb import HydroDatabase


def skew(d: np.ndarray) -> np.ndarray:
    """S(d) with S(d) v = d x v."""
    return np.array([[0.0, -d[2], d[1]], [d[2], 0.0, -d[0]], [-d[1], d[0], 0.0]])


def motion_transfer(shift: np.ndarray) -> np.ndarray:
    """T (6N, 6N) with q_P = T q_G for bodies whose centre of gravity is ``shift`` (N, 3) m away from the
    database's reference point (``shift = G - P``)."""
    shift = np.asarray(shift, dtype=float).reshape(-1, 3)
    t = np.eye(6 * len(shift))
    for b, d in enumerate(shift):
        t[6 * b:6 * b + 3, 6 * b + 3:6 * b + 6] = skew(d)
    return t


def buoyancy_stiffness_about(stiffness: np.ndarray, volume: float, rho: float, g: float,
                             shift: np.ndarray) -> np.ndarray:
    """The 6 x 6 buoyancy restoring matrix about G from the one about P (module docstring); ``shift = G - P`` (m),
    ``volume`` the displaced volume (m^3)."""
    d = np.asarray(shift, dtype=float)
    t = motion_transfer(d[None])
    out = t.T @ np.asarray(stiffness, dtype=float) @ t
    weight = rho * g * volume
    out[3, 3] -= weight * d[2]
    out[4, 4] -= weight * d[2]
    out[3, 5] += weight * d[0]
    out[4, 5] += weight * d[1]
    return out


def moved_to(hdb: HydroDatabase, points: np.ndarray) -> HydroDatabase:
    """The database with every coefficient about ``points`` (N, 3) m, one per body (usually the bodies'
    centres of gravity), instead of about ``hdb.cg``; ``cg`` becomes ``points``."""
    points = np.asarray(points, dtype=float).reshape(hdb.n_bodies, 3)
    shift = points - hdb.cg
    if not np.any(shift):
        return hdb
    t = motion_transfer(shift)

    def radiation(a: np.ndarray) -> np.ndarray:
        return t.T @ a @ t

    def forces(x: np.ndarray | None) -> np.ndarray | None:
        return None if x is None else x @ t  # rows are forces: (T^T x)^T = x^T T

    stiffness = np.stack([buoyancy_stiffness_about(hdb.hydrostatic_stiffness[b], hdb.displaced_volume[b], hdb.rho,
                                                   hdb.g, shift[b]) for b in range(hdb.n_bodies)])
    extra = dict(hdb.extra)
    extra["reference_points"] = hdb.cg.copy()
    return dataclasses.replace(
        hdb, added_mass=radiation(hdb.added_mass), radiation_damping=radiation(hdb.radiation_damping),
        added_mass_inf=radiation(hdb.added_mass_inf), excitation=forces(hdb.excitation),
        froude_krylov=forces(hdb.froude_krylov), diffraction=forces(hdb.diffraction),
        hydrostatic_stiffness=stiffness, cg=points, extra=extra,
        source=f"{hdb.source} (moved from its reference point to the centres of gravity)")
