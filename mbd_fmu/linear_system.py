"""Linear (small-motion) multibody model: rigid bodies on selected DOFs, PTOs to ground.

Generalised coordinates q are the active degrees of freedom of all bodies, body after body.
The equations of motion are

    (M + A_inf) q'' + C_pto q' + K_pto q = F(t) + u_pto,

with M the block-diagonal rigid-body mass matrix, A_inf the infinite-frequency added mass
(full matrix between the hydrodynamic bodies' coordinates, cross-body blocks included), F the
external force input (from the hydrodynamics FMU) and u_pto the PTOs' commanded forces. PTO
stiffness, damping and force commands may change between steps (:meth:`set_pto_commands`).

The external force may be given as an affine model over the step (the linearised force interface,
``hydro_fmu.linearisation``): F(t) = F_n + F_rate (t - t_n) + dF_dx q + dF_dv q' with the
Jacobians on the hydrodynamic coordinates (:meth:`set_force_tangents`). The Jacobians join the
system matrix (K_pto - dF_dx, C_pto - dF_dv), so they are integrated exactly, like the PTO; the
ramp F_rate enters through the first-order-hold input matrix. Step matrices are cached per
(PTO law, Jacobians, step): constant Jacobians (linear hydrostatics and radiation) cost one
exponential per step size for the whole run.
Gravity acts at each centre of gravity and so has no moment there; its constant part balances
the mean buoyancy and is left out.

Integration: :class:`ZeroOrderHoldStepper` - the exact solution over a step for an input held
constant during the step, or varying linearly over it (matrix exponential of the first-order
system). No truncation error, unconditionally stable (the discrete eigenvalues are exp(lambda h)
for the continuous ones), so the only time-discretisation error of a co-simulation is the
coupling error of the master or of the force model.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import expm

from .bodies import RigidBody
from .force_elements import LinearPTO


class ZeroOrderHoldStepper:
    """Exact step of z' = A z + B u for u constant over the step, or u(s) = u_0 + (s/h) du over it:
    z(h) = Phi z + Gamma u_0 + Gamma_1 du; (Phi, Gamma) and Gamma_1 cached per h."""

    def __init__(self, a: np.ndarray, b: np.ndarray) -> None:
        self.a = a
        self.b = b
        self._cache: dict[float, tuple[np.ndarray, np.ndarray]] = {}
        self._ramp: dict[float, np.ndarray] = {}

    def ramp_matrix(self, h: float) -> np.ndarray:
        """Gamma_1: exp of [[A h, B h, 0], [0, 0, I], [0, 0, 0]], block (1, 3)."""
        if h not in self._ramp:
            n, m = self.b.shape
            aug = np.zeros((n + 2 * m, n + 2 * m))
            aug[:n, :n] = self.a * h
            aug[:n, n:n + m] = self.b * h
            aug[n:n + m, n + m:] = np.eye(m)
            if len(self._ramp) > 8:
                self._ramp.clear()
            self._ramp[h] = expm(aug)[:n, n + m:]
        return self._ramp[h]

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

    def step(self, z: np.ndarray, u: np.ndarray, h: float, du: np.ndarray | None = None) -> np.ndarray:
        phi, gamma = self.matrices(h)
        out = phi @ z + gamma @ u
        if du is not None:
            out += self.ramp_matrix(h) @ du
        return out


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
        self.ptos = list(ptos)
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
        self._pto_index = [self.coordinate_index(p.body, p.dof) for p in ptos]
        self._tangent_index = np.zeros(0, dtype=int)
        self._dfdx = self._dfdv = np.zeros((0, 0))
        self.mass = self.structural_mass + self.added_mass
        self._mass_inverse = np.linalg.inv(self.mass)
        self._steppers: dict[tuple, ZeroOrderHoldStepper] = {}
        self.q = np.zeros(n)
        self.qd = np.zeros(n)
        self._assemble_ptos()

    def _assemble_ptos(self) -> None:
        n = self.n
        self.stiffness = np.zeros((n, n))
        self.damping = np.zeros((n, n))
        self.pto_force = np.zeros(n)
        for p, i in zip(self.ptos, self._pto_index, strict=True):
            self.stiffness[i, i] += p.stiffness
            self.damping[i, i] += p.damping
            self.pto_force[i] += p.force_command
        key = (tuple((p.stiffness, p.damping) for p in self.ptos), self._dfdx.tobytes(), self._dfdv.tobytes())
        if key not in self._steppers:
            minv = self._mass_inverse
            stiffness, damping = self.stiffness.copy(), self.damping.copy()
            ix = np.ix_(self._tangent_index, self._tangent_index)
            stiffness[ix] -= self._dfdx
            damping[ix] -= self._dfdv
            a = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ stiffness, -minv @ damping]])
            b = np.vstack([np.zeros((n, n)), minv])
            if len(self._steppers) > 16:
                self._steppers.clear()
            self._steppers[key] = ZeroOrderHoldStepper(a, b)
        self.stepper = self._steppers[key]

    def set_pto_commands(self, stiffness: np.ndarray, damping: np.ndarray, force: np.ndarray) -> None:
        """New PTO stiffness, damping and commanded force (one value per PTO), held from now on."""
        changed = False
        for j, p in enumerate(self.ptos):
            new = LinearPTO(p.name, p.body, p.dof, float(stiffness[j]), float(damping[j]), float(force[j]))
            if new != p:
                self.ptos[j] = new
                changed = True
        if changed:
            self._assemble_ptos()

    def set_force_tangents(self, coordinates: list[tuple[str, int]], dfdx: np.ndarray, dfdv: np.ndarray) -> None:
        """Jacobians (m, m) of the external force on ``coordinates`` ((body, dof) each) with respect to their
        displacement and velocity, held from now on (the linearised force interface)."""
        index = np.array([self.coordinate_index(*c) for c in coordinates], dtype=int)
        dfdx, dfdv = np.asarray(dfdx, float), np.asarray(dfdv, float)
        if (np.array_equal(index, self._tangent_index) and np.array_equal(dfdx, self._dfdx)
                and np.array_equal(dfdv, self._dfdv)):
            return
        self._tangent_index, self._dfdx, self._dfdv = index, dfdx.copy(), dfdv.copy()
        self._assemble_ptos()

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

    def rollback_state(self, previous: dict | None = None) -> dict:
        """What stepping, PTO commands and force tangents change (for an FMU state set back onto this object:
        ``fmu_base.slave.RollbackState``): every attribute, the position and velocity arrays and the PTO list
        copied (the other attributes are replaced, never changed in place; the steppers are a cache keyed by
        their own inputs)."""
        out = dict(self.__dict__)
        out["q"], out["qd"], out["ptos"] = self.q.copy(), self.qd.copy(), list(self.ptos)
        return out

    def restore_rollback_state(self, data: dict) -> None:
        """Back to a :meth:`rollback_state` (which stays valid for another restore)."""
        self.__dict__.clear()
        self.__dict__.update(data)
        self.q, self.qd, self.ptos = data["q"].copy(), data["qd"].copy(), list(data["ptos"])

    def step(self, h: float, force: np.ndarray, rate: np.ndarray | None = None) -> None:
        """Advance by ``h`` (s) with the external force ``force`` (n,) held constant, or varying at ``rate``
        (n,) N/s over the step, plus the force tangents' terms (:meth:`set_force_tangents`)."""
        du = None if rate is None or not np.any(rate) else rate * h
        z = self.stepper.step(np.concatenate([self.q, self.qd]), force + self.pto_force, h, du)
        self.q, self.qd = z[: self.n], z[self.n :]

    def pto_forces(self) -> np.ndarray:
        return np.array([p.force(self.q[i], self.qd[i]) for p, i in zip(self.ptos, self._pto_index, strict=True)])

    def pto_powers(self) -> np.ndarray:
        return np.array([p.power(self.q[i], self.qd[i]) for p, i in zip(self.ptos, self._pto_index, strict=True)])
