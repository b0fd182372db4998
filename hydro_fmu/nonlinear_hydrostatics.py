"""Nonlinear hydrostatic and Froude-Krylov forces over the instantaneous wetted surface.

For large motions the linear restoring force -C x and the database's Froude-Krylov force (both
about the equilibrium pose) are replaced by pressure integrals over the body mesh in its
current pose, cut at the current free surface:

    F_hs(x)    = -int_{S_w} p_s n dS - F_hs(0),   p_s = -rho g z,
    F_FK(x, t) = -int_{S_w} p_d n dS,             p_d = rho g r(t) Re sum_k a_k exp(i phi_k) E_k(z)
                                                        exp(i (omega_k t - k_k (x cos beta_k + y sin beta_k))),

moments about the current centre of gravity, world frame; n is the outward normal, E_k(z) =
exp(k z) in deep water and cosh(k (z + h)) / cosh(k h) at depth h, with z clipped at 0 above the
still-water level (constant extrapolation of the linear pressure into crests). S_w is the part
of the hull below the surface: z = 0 for hydrostatics alone, z = eta(x, y, t) (the incident
wave) when the Froude-Krylov force is nonlinear too. ``F_hs(0)`` (buoyancy at the equilibrium
pose in still water, which the weight balances) is subtracted, so F_hs(0) = 0 and the small-
motion limit is -C x with C the database's matrix about the centre of gravity.

Pose parametrisation: the displacement x = (surge, sway, heave, r1, r2, r3) moves the centre of
gravity by (x1, x2, x3) and rotates the body about it by the rotation vector r (world frame, axis
times angle): R = exp([r]x) (Rodrigues). For small angles this is the small-angle world-frame
rotation that the linear model uses, so both agree to first order.

Numerics: triangles are cut at the surface along their edges (the surface is taken linear between
the corner elevations); each wetted triangle uses the three-point edge-midpoint rule (exact for
quadratic integrands: the hydrostatic force and moment are exact on a flat-panel mesh; the
Froude-Krylov pressure is approximated to second order in the panel size).
"""

from __future__ import annotations

import math

import numpy as np

from .mesh_clip import clip_below
from .meshes import SurfaceMesh, rotation_matrix
from .waves import Ramp, WaveComponents, wavenumber


def _midpoints(triangles: np.ndarray) -> np.ndarray:
    """(G, 3, 3) edge midpoints of each triangle (the quadrature points)."""
    return 0.5 * (triangles + np.roll(triangles, -1, axis=1))


class BodyPressureModel:
    """Pressure forces on one body's hull in any pose.

    Args:
        mesh: whole hull (above and below water) in coordinates relative to the centre of gravity
            at the equilibrium pose (world axes).
        cg: centre of gravity at equilibrium (world, m).
        rho, g, water_depth: kg/m^3, m/s^2, m.
    """

    def __init__(self, mesh: SurfaceMesh, cg: np.ndarray, rho: float, g: float, water_depth: float = math.inf) -> None:
        self.mesh = mesh
        self.cg = np.asarray(cg, dtype=float)
        self.rho, self.g, self.water_depth = float(rho), float(g), float(water_depth)
        self.equilibrium = self._hydrostatic(self._corners(np.zeros(6)), np.zeros(3) + self.cg, None)

    def _corners(self, x: np.ndarray) -> np.ndarray:
        rot = rotation_matrix(x[3:6])
        return self.mesh.corners @ rot.T + (self.cg + x[:3])

    def _hydrostatic(self, corners: np.ndarray, centre: np.ndarray, surface: np.ndarray | None) -> np.ndarray:
        wet, _ = clip_below(corners, np.zeros(corners.shape[:2]) if surface is None else surface)
        return self._integrate(wet, centre, lambda p: -self.rho * self.g * p[..., 2])

    def _integrate(self, wet: np.ndarray, centre: np.ndarray, pressure) -> np.ndarray:
        """-int p n dS and its moment about ``centre`` (6,) by the edge-midpoint rule."""
        if len(wet) == 0:
            return np.zeros(6)
        area_vec = 0.5 * np.cross(wet[:, 1] - wet[:, 0], wet[:, 2] - wet[:, 0])  # (G, 3)
        points = _midpoints(wet)  # (G, 3, 3)
        p = pressure(points)  # (G, 3)
        force_q = -(p / 3.0)[:, :, None] * area_vec[:, None, :]  # (G, 3 points, 3)
        force = force_q.sum(axis=(0, 1))
        moment = np.cross(points - centre, force_q).sum(axis=(0, 1))
        return np.concatenate([force, moment])

    def forces(self, x: np.ndarray, t: float = 0.0, waves: WaveComponents | None = None, ramp: Ramp | None = None,
               hydrostatics: bool = True, froude_krylov: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """(F_hs, F_FK), each (6,), for displacement ``x`` (6,) at time ``t`` (module docstring)."""
        x = np.asarray(x, dtype=float)
        corners = self._corners(x)
        centre = self.cg + x[:3]
        surface = None
        fk = np.zeros(6)
        if froude_krylov and waves is not None and len(waves.omega):
            ramp_value = ramp(float(t)) if ramp is not None else 1.0
            model = _IncidentPressure(waves, self.rho, self.g, self.water_depth, ramp_value)
            surface = model.elevation(corners[..., 0], corners[..., 1], t)
            wet, _ = clip_below(corners, surface)
            fk = self._integrate(wet, centre, lambda p: model.pressure(p, t))
        hs = self._hydrostatic(corners, centre, surface) - self.equilibrium if hydrostatics else np.zeros(6)
        return hs, fk


class _IncidentPressure:
    """Linear incident-wave elevation and dynamic pressure at arbitrary points."""

    def __init__(self, waves: WaveComponents, rho: float, g: float, water_depth: float, ramp_value: float) -> None:
        self.omega = waves.omega
        self.k = wavenumber(waves.omega, water_depth, g)
        h = waves.headings
        self.kx, self.ky = self.k * np.cos(h), self.k * np.sin(h)
        self.coefficients = waves.complex_amplitude * ramp_value
        self.rho, self.g, self.depth = rho, g, water_depth

    def _phasors(self, x: np.ndarray, y: np.ndarray, t: float) -> np.ndarray:
        return np.exp(1j * (self.omega * t - np.multiply.outer(x, self.kx) - np.multiply.outer(y, self.ky)))

    def elevation(self, x: np.ndarray, y: np.ndarray, t: float) -> np.ndarray:
        return np.real(self._phasors(x, y, t) @ self.coefficients)

    def pressure(self, points: np.ndarray, t: float) -> np.ndarray:
        z = np.minimum(points[..., 2], 0.0)
        if math.isinf(self.depth):
            depth_factor = np.exp(np.multiply.outer(z, self.k))
        else:
            depth_factor = np.cosh(np.multiply.outer(z + self.depth, self.k)) / np.cosh(self.k * self.depth)
        phasor = self._phasors(points[..., 0], points[..., 1], t) * depth_factor
        return self.rho * self.g * np.real(phasor @ self.coefficients)
