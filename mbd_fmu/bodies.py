"""Rigid bodies of the multibody model.

A body's motion is described at its centre of gravity: displacement (surge, sway, heave, roll,
pitch, yaw) from equilibrium in the world frame, as on every interface of the toolkit. A body
may be restricted to a subset of its six degrees of freedom (the others are held at zero).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .spec_checks import ModelError, inertia_problem

DOF_NAMES = ("surge", "sway", "heave", "roll", "pitch", "yaw")


@dataclass(frozen=True)
class RigidBody:
    """A rigid body.

    Attributes:
        name: identifier (FMI variable prefix).
        mass: kg, > 0.
        inertia: 3x3 inertia tensor about the centre of gravity, world axes at equilibrium, kg m^2.
        cg: centre of gravity at equilibrium, world frame, m.
        dofs: active degrees of freedom, 0 = surge ... 5 = yaw, increasing.
        point_mass: a 3-DOF point mass (translations only; ``inertia`` unused).
    """

    name: str
    mass: float
    inertia: np.ndarray
    cg: np.ndarray
    dofs: tuple[int, ...] = (0, 1, 2, 3, 4, 5)
    point_mass: bool = False

    def __post_init__(self) -> None:
        inertia = np.asarray(self.inertia, dtype=float).reshape(3, 3)
        object.__setattr__(self, "inertia", inertia)
        object.__setattr__(self, "cg", np.asarray(self.cg, dtype=float).reshape(3))
        if not (self.mass > 0 and np.isfinite(self.mass)):
            raise ModelError(f"body {self.name!r}: mass must be positive (got {self.mass})")
        if not np.allclose(inertia, inertia.T, rtol=1e-12, atol=0):
            raise ModelError(f"body {self.name!r}: inertia tensor is not symmetric")
        if not np.all(np.isfinite(inertia)) or not np.all(np.isfinite(self.cg)):
            raise ModelError(f"body {self.name!r}: inertia and cg must be finite numbers")
        rotational = [d for d in self.dofs if d >= 3]
        if self.point_mass and rotational:
            raise ModelError(f"body {self.name!r}: a point mass has no rotational degrees of freedom")
        problem = inertia_problem(inertia) if rotational else None
        if problem:
            raise ModelError(f"body {self.name!r}: {problem}")
        if list(self.dofs) != sorted(set(self.dofs)) or not set(self.dofs) <= set(range(6)):
            raise ModelError(f"body {self.name!r}: dofs must be increasing indices in 0..5 (got {self.dofs})")

    def mass_matrix(self) -> np.ndarray:
        """6x6 rigid-body mass matrix about the centre of gravity."""
        m = np.zeros((6, 6))
        m[:3, :3] = self.mass * np.eye(3)
        m[3:, 3:] = self.inertia
        return m
