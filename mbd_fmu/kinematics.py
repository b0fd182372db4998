"""Kinematic snapshot of a multibody system: poses and velocities with the ground appended.

Generalised velocities are world-frame (translational velocity of the centre of gravity,
angular velocity) *slots*, six per body; a body restricted to some degrees of freedom, or a
point mass, has only its active slots in the generalised velocity vector ``v`` (``sel`` maps
them into the full slot vector of length ``6 (N + 1)``, the last six slots being the ground's,
always zero). Position increments use the same slots: ``q (+) delta`` moves centres by the
translational part and rotates orientations by ``exp(S(delta_rot)) R`` (world frame).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .rotations import exp_so3

_EYE = np.eye(3)


@dataclass
class Pose:
    """Positions of the N bodies: centres of gravity ``r`` (N, 3) and orientations ``R`` (N, 3, 3)."""

    r: np.ndarray
    R: np.ndarray

    def copy(self) -> Pose:
        return Pose(self.r.copy(), self.R.copy())

    def retract(self, delta_full: np.ndarray) -> Pose:
        """``self (+) delta`` for a full slot vector ``delta_full`` (6 N or 6 (N + 1))."""
        n = len(self.r)
        d = np.asarray(delta_full)[: 6 * n].reshape(n, 6)
        return Pose(self.r + d[:, :3], exp_so3(d[:, 3:]) @ self.R)


class Kin:
    """Poses and velocities with the ground as body N: ``rr`` (N+1, 3), ``RR`` (N+1, 3, 3), ``W`` (N+1, 6)."""

    __slots__ = ("rr", "RR", "W", "t", "n_bodies", "world_inertia")

    def __init__(self, pose: Pose, w_full: np.ndarray, t: float = 0.0) -> None:
        n = len(pose.r)
        self.n_bodies = n
        self.rr = np.zeros((n + 1, 3))
        self.rr[:n] = pose.r
        self.RR = np.empty((n + 1, 3, 3))
        self.RR[:n] = pose.R
        self.RR[n] = _EYE
        self.W = np.asarray(w_full, dtype=float).reshape(n + 1, 6)
        self.t = t
        self.world_inertia = None  # (N, 3, 3), set by the model when first needed

    def shifted(self, eps: float, w_dot_full: np.ndarray | None = None) -> Kin:
        """The snapshot moved along its own velocity by time ``eps`` (first order), for directional derivatives."""
        n = self.n_bodies
        k = Kin.__new__(Kin)
        k.n_bodies = n
        k.rr = self.rr + eps * self.W[:, :3]
        k.RR = exp_so3(eps * self.W[:, 3:]) @ self.RR
        k.W = self.W if w_dot_full is None else self.W + eps * np.asarray(w_dot_full).reshape(n + 1, 6)
        k.t = self.t + eps
        k.world_inertia = None
        return k
