"""Linear (small-motion) multibody model: rigid bodies on selected DOFs, PTOs to ground.

Generalised coordinates q are the active degrees of freedom of all bodies, body after body.
The equations of motion are

    (M + A_inf) q'' + C_pto q' + K_pto q = F(t),

with M the block-diagonal rigid-body mass matrix, A_inf the infinite-frequency added mass
(full matrix between the hydrodynamic bodies' coordinates, cross-body blocks included) and F the
external force input (from the hydrodynamics FMU). Gravity acts at each centre of gravity and so
has no moment there; its constant part balances the mean buoyancy and is left out.

Integration: :class:`ZeroOrderHoldStepper` - the exact solution over a step for an input held
constant during the step (matrix exponential of the first-order system). No truncation error,
unconditionally stable (the discrete eigenvalues are exp(lambda h) for the continuous ones),
so the only time-discretisation error of a co-simulation is the coupling error of the master.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import expm

from .bodies import RigidBody
from .force_elements import LinearPTO


class ZeroOrderHoldStepper:
    """Exact step of z' = A z + B u for u constant over the step; (Phi, Gamma) cached per h."""

    def __init__(self, a: np.ndarray, b: np.ndarray) -> None:
        self.a = a
        self.b = b
        self._cache: dict[float, tuple[np.ndarray, np.ndarray]] = {}

    def matrices(self, h: float) -> tuple[np.ndarray, np.ndarray]:
        if h not in self._cache:
            n, m = self.b.shape
            aug = np.zeros((n + m, n + m))
            aug[:n, :n] = self.a
            aug[:n, n:] = self.b
            e = expm(aug * h)
            if len(self._cache) > 8:
                self._cache.clear()
            self._cache[h] = (e[:n, :n], e[:n, n:])
        return self._cache[h]

    def step(self, z: np.ndarray, u: np.ndarray, h: float) -> np.ndarray:
        phi, gamma = self.matrices(h)
        return phi @ z + gamma @ u


class LinearMultibodySystem:
    """Bodies restricted to their active DOFs, with A_inf in the mass matrix and linear PTOs.

    Args:
        bodies: the rigid bodies.
        ptos: linear PTOs to ground.
        added_mass_inf: (m, m) infinite-frequency added mass.
        added_mass_coordinates: the (body name, dof) of each row of ``added_mass_inf``.
    """

    def __init__(
        self,
        bodies: list[RigidBody],
        ptos: list[LinearPTO],
        added_mass_inf: np.ndarray | None = None,
        added_mass_coordinates: list[tuple[str, int]] | None = None,
    ) -> None:
        self.bodies = bodies
        self.ptos = ptos
        self.coordinates = [(b.name, d) for b in bodies for d in b.dofs]
        self._position = {c: i for i, c in enumerate(self.coordinates)}
        n = len(self.coordinates)
        self.structural_mass = np.zeros((n, n))
        for b in bodies:
            idx = [self._position[(b.name, d)] for d in b.dofs]
            self.structural_mass[np.ix_(idx, idx)] = b.mass_matrix()[np.ix_(b.dofs, b.dofs)]
        self.added_mass = np.zeros((n, n))
        if added_mass_inf is not None:
            idx = [self.coordinate_index(*c) for c in added_mass_coordinates or []]
            self.added_mass[np.ix_(idx, idx)] = added_mass_inf
        self.stiffness = np.zeros((n, n))
        self.damping = np.zeros((n, n))
        self._pto_index = []
        for p in ptos:
            i = self.coordinate_index(p.body, p.dof)
            self.stiffness[i, i] += p.stiffness
            self.damping[i, i] += p.damping
            self._pto_index.append(i)
        self.mass = self.structural_mass + self.added_mass
        minv = np.linalg.inv(self.mass)
        a = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ self.stiffness, -minv @ self.damping]])
        b = np.vstack([np.zeros((n, n)), minv])
        self.stepper = ZeroOrderHoldStepper(a, b)
        self.q = np.zeros(n)
        self.qd = np.zeros(n)

    @property
    def n(self) -> int:
        return len(self.coordinates)

    def coordinate_index(self, body: str, dof: int) -> int:
        try:
            return self._position[(body, dof)]
        except KeyError:
            raise ValueError(f"body {body!r} has no active degree of freedom {dof}") from None

    def set_state(self, q: np.ndarray, qd: np.ndarray) -> None:
        self.q = np.array(q, dtype=float)
        self.qd = np.array(qd, dtype=float)

    def step(self, h: float, force: np.ndarray) -> None:
        """Advance by ``h`` (s) with the external force ``force`` (n,) held constant."""
        z = self.stepper.step(np.concatenate([self.q, self.qd]), force, h)
        self.q, self.qd = z[: self.n], z[self.n :]

    def pto_forces(self) -> np.ndarray:
        return np.array([p.force(self.q[i], self.qd[i]) for p, i in zip(self.ptos, self._pto_index, strict=True)])

    def pto_powers(self) -> np.ndarray:
        return np.array([p.power(self.q[i], self.qd[i]) for p, i in zip(self.ptos, self._pto_index, strict=True)])
