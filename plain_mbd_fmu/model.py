"""Rigid bodies on selected degrees of freedom with linear PTOs to ground, structural mass only.

    M q'' = F(t) - C q' - K q,

M the block-diagonal mass matrix (mass on translations, inertia on rotations) restricted to the
active degrees of freedom, C and K the PTO dampers and springs, F the external force input.

Integration: classical fourth-order Runge-Kutta with ``substeps`` equal sub-steps per
communication step and the input held constant over the step (what a general-purpose tool does
with a zero-order-hold input). Local error O(dt^5), global O(dt^4) in the sub-step dt; stable for
dt * omega_max < 2.78 (the fastest PTO/mass mode); no knowledge of the fluid.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class PlainPto:
    """Linear spring-damper between one coordinate and the ground: F = -k x - c v."""

    name: str
    index: int
    stiffness: float
    damping: float


class PlainMultibody:
    """State q, qd of n coordinates; :meth:`step` advances by h with a constant external force."""

    def __init__(self, mass: np.ndarray, ptos: list[PlainPto], substeps: int = 10) -> None:
        self.mass = np.asarray(mass, dtype=float)
        n = len(self.mass)
        self.inverse_mass = np.linalg.inv(self.mass)
        self.ptos = ptos
        self.stiffness = np.zeros((n, n))
        self.damping = np.zeros((n, n))
        for p in ptos:
            self.stiffness[p.index, p.index] += p.stiffness
            self.damping[p.index, p.index] += p.damping
        self.substeps = max(1, int(substeps))
        self.q = np.zeros(n)
        self.qd = np.zeros(n)

    def _rates(self, q: np.ndarray, qd: np.ndarray, force: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return qd, self.inverse_mass @ (force - self.damping @ qd - self.stiffness @ q)

    def step(self, h: float, force: np.ndarray) -> None:
        dt = h / self.substeps
        q, qd = self.q, self.qd
        for _ in range(self.substeps):
            k1q, k1v = self._rates(q, qd, force)
            k2q, k2v = self._rates(q + 0.5 * dt * k1q, qd + 0.5 * dt * k1v, force)
            k3q, k3v = self._rates(q + 0.5 * dt * k2q, qd + 0.5 * dt * k2v, force)
            k4q, k4v = self._rates(q + dt * k3q, qd + dt * k3v, force)
            q = q + dt / 6 * (k1q + 2 * k2q + 2 * k3q + k4q)
            qd = qd + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        self.q, self.qd = q, qd

    def pto_forces(self) -> np.ndarray:
        return np.array([-p.stiffness * self.q[p.index] - p.damping * self.qd[p.index] for p in self.ptos])

    def pto_powers(self) -> np.ndarray:
        return np.array([-f * self.qd[p.index] for f, p in zip(self.pto_forces(), self.ptos, strict=True)])
