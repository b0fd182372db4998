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
        """The twelve full slot indices of bodies i and j (built once)."""
        try:
            return self._cols
        except AttributeError:
            self._cols = np.concatenate([6 * self.bi + np.arange(6), 6 * self.bj + np.arange(6)])
            return self._cols

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
        n = (k.RR[self.bi] @ self.n).tolist()
        ai, aj, d, wi, wj, dd = _two_points(k, self.bi, self.bj, self.si, self.sj)
        win = _cross3(wi, n)
        jac = np.array((*_neg3(n), *_cross3(n, _add3(d, ai)), *n, *_cross3(aj, n)))
        centripetal = _sub3(_cross3(wj, _cross3(wj, aj)), _cross3(wi, _cross3(wi, ai)))
        quad = _dot3(_cross3(wi, win), d) + 2 * _dot3(win, dd) + _dot3(n, centripetal)
        return _dot3(n, d) - self.offset, jac, quad


@dataclass
class Distance(Coordinate):
    """``|p_j - p_i|``."""

    bi: int
    bj: int
    si: np.ndarray
    sj: np.ndarray

    def evaluate(self, k: Kin) -> tuple[float, np.ndarray, float]:
        length, e, ai, aj, wi, wj, dd = self._state(k)
        jac = np.array((*_neg3(e), *_neg3(_cross3(ai, e)), *e, *_cross3(aj, e)))
        centripetal = _sub3(_cross3(wj, _cross3(wj, aj)), _cross3(wi, _cross3(wi, ai)))
        ed = _dot3(e, dd)
        quad = _dot3(e, centripetal) + (_dot3(dd, dd) - ed * ed) / length
        return length, jac, quad

    def rate(self, k: Kin) -> tuple[float, float, np.ndarray]:
        """Value, time derivative ``e . (relative velocity of the points)`` and Jacobian."""
        length, e, ai, aj, _, _, dd = self._state(k)
        jac = np.array((*_neg3(e), *_neg3(_cross3(ai, e)), *e, *_cross3(aj, e)))
        return length, _dot3(e, dd), jac

    def _state(self, k: Kin) -> tuple:
        """Length, unit vector from point i to j, offsets, angular velocities and relative velocity (floats)."""
        ai, aj, d, wi, wj, dd = _two_points(k, self.bi, self.bj, self.si, self.sj)
        length = math.sqrt(_dot3(d, d))
        e = (d[0] / length, d[1] / length, d[2] / length)
        return length, e, ai, aj, wi, wj, dd


def _two_points(k: Kin, bi: int, bj: int, si: np.ndarray, sj: np.ndarray) -> tuple:
    """Plain-float kinematics (3-tuples, cheaper than numpy for single vectors) of body-fixed points ``s_i``,
    ``s_j``: world offsets ``a = R s`` from the cgs, ``d = p_j - p_i``, angular velocities and ``d'``."""
    ai, aj = (k.RR[bi] @ si).tolist(), (k.RR[bj] @ sj).tolist()
    ri, rj = k.rr[bi].tolist(), k.rr[bj].tolist()
    vi, vj = k.W[bi].tolist(), k.W[bj].tolist()
    wi, wj = vi[3:], vj[3:]
    d = _sub3(_add3(rj, aj), _add3(ri, ai))
    dd = _sub3(_add3(vj, _cross3(wj, aj)), _add3(vi, _cross3(wi, ai)))
    return ai, aj, d, wi, wj, dd


def _cross3(a, b) -> tuple[float, float, float]:
    return a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]


def _dot3(a, b) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _add3(a, b) -> tuple[float, float, float]:
    return a[0] + b[0], a[1] + b[1], a[2] + b[2]


def _sub3(a, b) -> tuple[float, float, float]:
    return a[0] - b[0], a[1] - b[1], a[2] - b[2]


def _neg3(a) -> tuple[float, float, float]:
    return -a[0], -a[1], -a[2]


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

    def rate(self, kin: Kin) -> tuple[float, float, np.ndarray]:
        """Value, rate and Jacobian without ``quad`` (its numerical derivative costs two more evaluations
        and a shifted kinematics; force elements and outputs need only these)."""
        value, jac, _ = self.evaluate_jacobian_only(kin)
        w = np.concatenate([kin.W[self.bi], kin.W[self.bj]])
        return value, float(jac @ w), jac
