"""Viscous forces per degree of freedom: linear damping and quadratic (Morison-type) drag.

    F_visc,i = -b_i v_i - (1/2) rho Cd_i A_i |v_i| v_i,

for each selected degree of freedom i, with v the body velocity (world frame, about the centre
of gravity; the incident-wave orbital velocity is not subtracted, as in WEC-Sim's per-DOF
quadratic drag). Units: b in N s/m (N m s/rad for rotations); for rotations the "area" A is the
characteristic area times the cube of the lever arm, m^5, so that rho Cd A omega^2 is a moment.
The force is an explicit function of the current velocity (direct feedthrough): no time
discretisation of its own; with a co-simulation step h the master's coupling error applies.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ViscousCoefficients:
    """Per selected DOF: linear damping b (n,) and quadratic coefficient q = rho Cd A / 2 (n,)."""

    linear: np.ndarray
    quadratic: np.ndarray

    @classmethod
    def from_drag(cls, rho: float, linear: np.ndarray, drag_coefficient: np.ndarray,
                  area: np.ndarray) -> ViscousCoefficients:
        return cls(np.asarray(linear, dtype=float),
                   0.5 * rho * np.asarray(drag_coefficient, dtype=float) * np.asarray(area, dtype=float))

    @property
    def active(self) -> bool:
        return bool(np.any(self.linear) or np.any(self.quadratic))


class ViscousForce:
    """F = -b v - q |v| v on the selected degrees of freedom."""

    def __init__(self, coefficients: ViscousCoefficients) -> None:
        self.linear = np.asarray(coefficients.linear, dtype=float)
        self.quadratic = np.asarray(coefficients.quadratic, dtype=float)

    def __call__(self, v: np.ndarray) -> np.ndarray:
        """Force (N, N m) for velocity ``v`` (m/s, rad/s)."""
        return -self.linear * v - self.quadratic * np.abs(v) * v

    def tangent(self, v: np.ndarray) -> np.ndarray:
        """dF/dv (n,), the diagonal of the Jacobian: -(b + 2 q |v|)."""
        return -self.linear - 2.0 * self.quadratic * np.abs(v)
