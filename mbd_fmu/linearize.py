"""Linearisation of a multibody model about a static equilibrium, for frequency-domain solvers.

About the pose ``q0`` at rest, with position perturbations ``delta`` in world-frame slots
(``q = q0 (+) delta``) the constrained equations linearise to

    M delta'' + D delta' + K delta + C^T dlambda = dF,   C delta = 0,

with ``M = M(q0) + A_inf``, ``D = -df/dv``, ``K = -df/dq + d(C^T lambda0)/dq`` (the last term
is the geometric stiffness of the static constraint forces, e.g. a pendulum's ``m g L``) and
``lambda0`` the static multipliers (least squares of ``C^T lambda0 = f(q0)``; the residual says
whether ``q0`` is an equilibrium). With ``P`` an orthonormal basis of the null space of ``C``
the unconstrained reduced system is ``P^T M P x'' + P^T D P x' + P^T K P x = P^T dF``,
``delta = P x``. ``K`` and ``D`` are central differences of the model's own force and
constraint functions (step 1e-6, truncation error ~1e-12 relative).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import null_space

from .kinematics import Pose
from .model import MultibodyModel


@dataclass
class Linearization:
    """Matrices in the model's generalised slots (``coordinates``) and the constraint null space."""

    coordinates: list[tuple[str, int]]
    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    constraint_jacobian: np.ndarray
    null_space: np.ndarray
    static_multipliers: np.ndarray
    equilibrium_residual: float

    def reduced(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``P^T M P``, ``P^T D P``, ``P^T K P``."""
        p = self.null_space
        return p.T @ self.mass @ p, p.T @ self.damping @ p, p.T @ self.stiffness @ p

    def natural_frequencies(self) -> np.ndarray:
        """Undamped natural frequencies of the reduced system (rad/s), ascending."""
        m, _, k = self.reduced()
        ev = np.linalg.eigvals(np.linalg.solve(m, k))
        return np.sort(np.sqrt(np.abs(ev.real)))


def linearize(model: MultibodyModel, pose: Pose | None = None, t: float = 0.0, eps: float = 1e-6) -> Linearization:
    """Linearise ``model`` about ``pose`` (default: the equilibrium reference pose) at rest."""
    pose = pose or model.reference
    n = model.n
    zero = np.zeros(n)

    def force(delta: np.ndarray, v: np.ndarray) -> np.ndarray:
        return model.forces(model.kin(pose.retract(model.full(delta)), v, t))

    ev = model.constraint(model.kin(pose, zero, t), gamma=False)
    c = ev.jac
    f0 = force(zero, zero)
    lam0 = np.linalg.lstsq(c.T, f0, rcond=None)[0] if c.size else np.zeros(0)
    residual = float(np.max(np.abs(c.T @ lam0 - f0))) if n else 0.0

    def constraint_force(delta: np.ndarray) -> np.ndarray:
        if not c.size:
            return np.zeros(n)
        jac = model.constraint(model.kin(pose.retract(model.full(delta)), zero, t), gamma=False).jac
        return jac.T @ lam0

    k = np.zeros((n, n))
    d = np.zeros((n, n))
    for i in range(n):
        e = np.zeros(n)
        e[i] = eps
        k[:, i] = (-(force(e, zero) - force(-e, zero)) + constraint_force(e) - constraint_force(-e)) / (2 * eps)
        d[:, i] = -(force(zero, e) - force(zero, -e)) / (2 * eps)
    p = null_space(c) if c.size else np.eye(n)
    return Linearization(list(model.coordinates), model.mass_matrix(pose), d, k, c, p, lam0, residual)
