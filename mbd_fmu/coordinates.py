"""Scalar coordinates of a mechanism: the quantities force elements, PTOs, drivers and outputs act on.

A coordinate ``q_c`` is a smooth scalar function of the poses of two bodies i and j (either may
be the ground). :meth:`Coordinate.evaluate` returns its value, its Jacobian over the twelve
world-frame slots of the two bodies (so ``dq_c/dt = jac . [v_i, w_i, v_j, w_j]`` and a scalar
force ``F`` on the coordinate is the generalised force ``jac^T F``) and the velocity-quadratic
part ``quad`` of its second derivative (``q_c'' = jac . a + quad``), which drivers need.

* :class:`Slide` - ``n_i . (p_j - p_i)``: a body's translation (i = ground), a prismatic joint's
  displacement, a relative translation in a frame of body i;
* :class:`Angle` - rotation of marker j's x axis about marker i's z axis (revolute, cylindrical
  joints), unwrapped continuously across turns;
* :class:`Distance` - ``|p_j - p_i|`` (point-to-point spring-dampers, ropes);
* :class:`RotationComponent` - component k of the rotation vector of the relative rotation
  ``F_i^T F_j`` of two frames (a body's rotation from equilibrium when i is the ground).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .kinematics import Kin
from .rotations import cross, left_jacobian_inverse, log_so3


class Coordinate:
    """Base class: ``bi``, ``bj`` are body indices (N = ground)."""

    bi: int
    bj: int

    def cols(self) -> np.ndarray:
        return np.concatenate([6 * self.bi + np.arange(6), 6 * self.bj + np.arange(6)])

    def evaluate(self, k: Kin) -> tuple[float, np.ndarray, float]:  # pragma: no cover - abstract
        raise NotImplementedError

    def rate(self, k: Kin) -> tuple[float, float, np.ndarray]:
        """Value, time derivative and Jacobian."""
        value, jac, _ = self.evaluate(k)
        w = np.concatenate([k.W[self.bi], k.W[self.bj]])
        return value, float(jac @ w), jac

    def commit(self, k: Kin) -> None:
        """Called after every accepted step (angle unwrapping)."""


def _numeric_quad(coord: Coordinate, k: Kin, eps: float = 1e-6) -> float:
    """d/dt(jac) . w by a central difference along the motion (O(eps^2) error)."""
    w = np.concatenate([k.W[coord.bi], k.W[coord.bj]])
    scale = max(1.0, float(np.max(np.abs(w))))
    h = eps / scale
    _, jp, _ = coord.evaluate_jacobian_only(k.shifted(h))
    _, jm, _ = coord.evaluate_jacobian_only(k.shifted(-h))
    return float((jp - jm) @ w / (2 * h))


@dataclass
class Slide(Coordinate):
    """``n . (p_j - p_i) - offset`` with ``n`` a body-fixed unit vector of body i, points ``s_i``, ``s_j``."""

    bi: int
    bj: int
    n: np.ndarray
    si: np.ndarray
    sj: np.ndarray
    offset: float = 0.0

    def evaluate(self, k: Kin) -> tuple[float, np.ndarray, float]:
        Ri, Rj = k.RR[self.bi], k.RR[self.bj]
        n, ai, aj = Ri @ self.n, Ri @ self.si, Rj @ self.sj
        d = k.rr[self.bj] + aj - k.rr[self.bi] - ai
        jac = np.concatenate([-n, cross(n, d + ai), n, cross(aj, n)])
        vi, wi, vj, wj = k.W[self.bi, :3], k.W[self.bi, 3:], k.W[self.bj, :3], k.W[self.bj, 3:]
        dd = vj + cross(wj, aj) - vi - cross(wi, ai)
        quad = (cross(wi, cross(wi, n)) @ d + 2 * cross(wi, n) @ dd
                + n @ (cross(wj, cross(wj, aj)) - cross(wi, cross(wi, ai))))
        return float(n @ d - self.offset), jac, float(quad)


@dataclass
class Distance(Coordinate):
    """``|p_j - p_i|``."""

    bi: int
    bj: int
    si: np.ndarray
    sj: np.ndarray

    def evaluate(self, k: Kin) -> tuple[float, np.ndarray, float]:
        ai, aj = k.RR[self.bi] @ self.si, k.RR[self.bj] @ self.sj
        d = k.rr[self.bj] + aj - k.rr[self.bi] - ai
        length = float(np.linalg.norm(d))
        e = d / length
        jac = np.concatenate([-e, -cross(ai, e), e, cross(aj, e)])
        vi, wi, vj, wj = k.W[self.bi, :3], k.W[self.bi, 3:], k.W[self.bj, :3], k.W[self.bj, 3:]
        dd = vj + cross(wj, aj) - vi - cross(wi, ai)
        quad = e @ (cross(wj, cross(wj, aj)) - cross(wi, cross(wi, ai))) + (dd @ dd - (e @ dd) ** 2) / length
        return length, jac, float(quad)


@dataclass
class Angle(Coordinate):
    """Angle of marker j's x axis about marker i's z axis, from marker i's x axis (rad), unwrapped.

    ``theta = atan2(x_j . y_i, x_j . x_i)``; exact Jacobian, so a spring on it is conservative.
    ``quad`` assumes the axes are aligned (the joint's constraints hold), where
    ``theta' = z_i . (w_j - w_i)``.
    """

    bi: int
    bj: int
    axes_i: np.ndarray  # (3, 3) columns x, y, z of marker i (body-fixed)
    x_j: np.ndarray  # marker j's x axis (body-fixed)
    reference: float = 0.0  # last committed value (for unwrapping)

    def _raw(self, k: Kin) -> tuple[float, np.ndarray, np.ndarray]:
        fi = k.RR[self.bi] @ self.axes_i
        xj = k.RR[self.bj] @ self.x_j
        c, s = xj @ fi[:, 0], xj @ fi[:, 1]
        raw = math.atan2(s, c)
        value = raw + 2 * math.pi * round((self.reference - raw) / (2 * math.pi))
        g = (c * cross(xj, fi[:, 1]) - s * cross(xj, fi[:, 0])) / (c * c + s * s)
        return value, g, fi[:, 2]

    def evaluate(self, k: Kin) -> tuple[float, np.ndarray, float]:
        value, g, z = self._raw(k)
        jac = np.concatenate([np.zeros(3), -g, np.zeros(3), g])
        wi, wj = k.W[self.bi, 3:], k.W[self.bj, 3:]
        quad = float(cross(wi, z) @ (wj - wi))
        return value, jac, quad

    def commit(self, k: Kin) -> None:
        fi = k.RR[self.bi] @ self.axes_i[:, :2]
        xj = k.RR[self.bj] @ self.x_j
        raw = math.atan2(float(xj @ fi[:, 1]), float(xj @ fi[:, 0]))
        self.reference = raw + 2 * math.pi * round((self.reference - raw) / (2 * math.pi))


@dataclass
class RotationComponent(Coordinate):
    """Component ``k`` of ``log(F_i^T F_j)`` (F = R A, marker axes A); body rotation when i is the ground."""

    bi: int
    bj: int
    axes_i: np.ndarray
    axes_j: np.ndarray
    k: int
    _cache: dict = field(default_factory=dict, repr=False)

    def _phi(self, kin: Kin) -> tuple[np.ndarray, np.ndarray]:
        fi = kin.RR[self.bi] @ self.axes_i
        fj = kin.RR[self.bj] @ self.axes_j
        return log_so3(fi.T @ fj), fi

    def evaluate_jacobian_only(self, kin: Kin) -> tuple[float, np.ndarray, float]:
        phi, fi = self._phi(kin)
        row = left_jacobian_inverse(phi)[self.k] @ fi.T
        return float(phi[self.k]), np.concatenate([np.zeros(3), -row, np.zeros(3), row]), 0.0

    def evaluate(self, kin: Kin) -> tuple[float, np.ndarray, float]:
        value, jac, _ = self.evaluate_jacobian_only(kin)
        return value, jac, _numeric_quad(self, kin)
