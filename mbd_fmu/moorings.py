"""Moorings: linear 6x6 stiffness to the ground and quasi-static elastic catenary lines.

* :class:`LinearMooring` - ``F = -K x`` with ``x`` the body's displacement from equilibrium
  (translation of the cg, rotation vector), world frame. The moment is the exact gradient of the
  potential ``x^T K_s x / 2`` (``K_s`` the symmetric part), ``-J_l(phi)^-T (K x)_rot``, so a
  symmetric ``K`` is conservative at any amplitude.
* :class:`CatenaryLine` - a quasi-static elastic catenary from an anchor on the sea bed to a
  fairlead on the body (Jonkman 2007, NREL/TP-500-41958, eqs. 2-2..2-5, sea-bed contact
  without friction): horizontal and vertical fairlead tensions ``H``, ``V`` solve the two
  catenary equations for the fairlead's horizontal distance and height above the anchor by
  Newton's method (analytic 2x2 Jacobian). The line's force on the body is ``-(H e_h + V e_z)``
  at the fairlead. Its work is booked as external work (no stored energy is computed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .force_elements import ForceElement
from .kinematics import Kin
from .rotations import cross, left_jacobian_inverse, log_so3, skew


@dataclass
class LinearMooring(ForceElement):
    """Linear 6x6 mooring stiffness (and optional damping) of body ``body`` to the ground."""

    name: str
    body: int
    stiffness: np.ndarray
    damping: np.ndarray | None = None

    def _x(self, k: Kin, r0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        phi = log_so3(k.RR[self.body])
        return np.concatenate([k.rr[self.body] - r0, phi]), left_jacobian_inverse(phi)

    r0: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def wrench(self, k: Kin) -> np.ndarray:
        x, jinv = self._x(k, self.r0)
        g = -self.stiffness @ x
        if self.damping is not None:
            g = g - self.damping @ k.W[self.body]
        g[3:] = jinv.T @ g[3:]  # moment: the exact gradient of the potential in the rotation vector
        return g

    def apply(self, k: Kin, f: np.ndarray) -> None:
        f[6 * self.body:6 * self.body + 6] += self.wrench(k)

    def tangent(self, k: Kin):
        d = self.damping if self.damping is not None else np.zeros((6, 6))
        return 6 * self.body + np.arange(6), self.stiffness, d

    def potential(self, k: Kin) -> float:
        x, _ = self._x(k, self.r0)
        return 0.5 * x @ (0.5 * (self.stiffness + self.stiffness.T)) @ x

    def dissipation(self, k: Kin) -> float:
        if self.damping is None:
            return 0.0
        w = k.W[self.body]
        return float(w @ self.damping @ w)

    def supply(self, k: Kin) -> float:
        """Work rate of the non-symmetric part of K (zero for a symmetric stiffness)."""
        skew_part = 0.5 * (self.stiffness - self.stiffness.T)
        if not skew_part.any():
            return 0.0
        x, jinv = self._x(k, self.r0)
        g = -skew_part @ x
        return float(np.concatenate([g[:3], jinv.T @ g[3:]]) @ k.W[self.body])

    def output(self, k: Kin) -> np.ndarray:
        return self.wrench(k)


def catenary_tensions(x: float, z: float, length: float, w: float, ea: float,
                      guess: tuple[float, float] | None = None) -> tuple[float, float]:
    """Fairlead tensions (H, V) of an elastic catenary with sea-bed contact (Jonkman 2007).

    ``x`` horizontal distance and ``z`` height of the fairlead above the anchor (m), unstretched
    ``length`` (m), submerged weight ``w`` (N/m), axial stiffness ``ea`` (N).
    """
    if guess is None:
        if x <= 0:
            lam = 1e6
        elif length**2 <= x**2 + z**2:
            lam = 0.2
        else:
            lam = math.sqrt(3 * ((length**2 - z**2) / x**2 - 1))
        h = max(abs(w * x / (2 * lam)), 1e-3 * w * length)
        v = w / 2 * (z / math.tanh(lam) + length)
    else:
        h, v = guess
    for _ in range(100):
        r, jac = _catenary_residual(h, v, x, z, length, w, ea)
        step = np.linalg.solve(jac, -r)
        # keep H positive
        scale = 1.0
        while h + scale * step[0] <= 0:
            scale *= 0.5
        h, v = h + scale * step[0], v + scale * step[1]
        if abs(step[0]) <= 1e-12 * max(h, 1.0) and abs(step[1]) <= 1e-12 * max(abs(v), 1.0):
            return h, v
    raise ValueError(f"catenary line did not converge (horizontal span {x:g} m, height {z:g} m, length {length:g} m)")


def _catenary_residual(h, v, x, z, length, w, ea):
    vb = v - w * length
    if vb >= 0:  # fully suspended
        s1, s2 = math.sqrt(1 + (v / h) ** 2), math.sqrt(1 + (vb / h) ** 2)
        fx = h / w * (math.asinh(v / h) - math.asinh(vb / h)) + h * length / ea - x
        fz = h / w * (s1 - s2) + (v * length - w * length**2 / 2) / ea - z
        dfx_dh = (math.asinh(v / h) - math.asinh(vb / h)) / w - (v / h / s1 - vb / h / s2) / w + length / ea
        dfx_dv = (1 / s1 - 1 / s2) / w
        dfz_dh = (s1 - s2) / w - ((v / h) ** 2 / s1 - (vb / h) ** 2 / s2) / w
        dfz_dv = (v / h / s1 - vb / h / s2) / w + length / ea
    else:  # part of the line rests on the sea bed
        lb = length - v / w
        s1 = math.sqrt(1 + (v / h) ** 2)
        fx = lb + h / w * math.asinh(v / h) + h * length / ea - x
        fz = h / w * (s1 - 1) + v * v / (2 * ea * w) - z
        dfx_dh = math.asinh(v / h) / w - (v / h) / s1 / w + length / ea
        dfx_dv = -1 / w + 1 / (w * s1)
        dfz_dh = (s1 - 1) / w - (v / h) ** 2 / s1 / w
        dfz_dv = (v / h) / s1 / w + v / (ea * w)
    return np.array([fx, fz]), np.array([[dfx_dh, dfx_dv], [dfz_dh, dfz_dv]])


@dataclass
class CatenaryLine(ForceElement):
    """Quasi-static catenary from ``anchor`` (world) to a fairlead ``offset`` (body-fixed) on ``body``."""

    nonlinear = True

    name: str
    body: int
    offset: np.ndarray
    anchor: np.ndarray
    length: float
    weight: float
    ea: float
    _guess: tuple[float, float] | None = None

    def fairlead_force(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        a = k.RR[self.body] @ self.offset
        p = k.rr[self.body] + a
        d = p - self.anchor
        xh = math.hypot(d[0], d[1])
        e_h = np.array([d[0], d[1], 0.0]) / xh if xh > 0 else np.zeros(3)
        h, v = catenary_tensions(xh, d[2], self.length, self.weight, self.ea, self._guess)
        self._guess = (h, v)
        return -(h * e_h + v * np.array([0.0, 0.0, 1.0])), a

    def apply(self, k: Kin, f: np.ndarray) -> None:
        force, a = self.fairlead_force(k)
        f[6 * self.body:6 * self.body + 3] += force
        f[6 * self.body + 3:6 * self.body + 6] += cross(a, force)

    def supply(self, k: Kin) -> float:
        force, a = self.fairlead_force(k)
        vel = k.W[self.body, :3] + cross(k.W[self.body, 3:], a)
        return float(force @ vel)

    def output(self, k: Kin) -> np.ndarray:
        return self.fairlead_force(k)[0]


def point_jacobian(a: np.ndarray) -> np.ndarray:
    """3x6 map from a body's slots (v, w) to the velocity of the point at world offset ``a``."""
    return np.hstack([np.eye(3), -skew(a)])
