"""The nonlinear multibody model: bodies, joints, drivers and force elements, assembled into
the quantities every formulation needs.

Equations of motion in world-frame slots (see :mod:`mbd_fmu.kinematics`):

    (M(q) + A_inf) v' + C(q)^T lambda = f(q, v, t) + F_in,      Phi(q, t) = 0,

with ``M`` block diagonal (``m I`` and the world inertia ``R I_0 R^T``), ``A_inf`` the
infinite-frequency added mass (constant in the world frame, the small-rotation assumption of
linear hydrodynamics), ``f`` the gyroscopic moments ``-w x (I w)``, gravity at the centres of
gravity, constant static loads (mean buoyancy of hydrodynamic bodies) and the force elements,
``F_in`` the external input (the hydrodynamic force of the coupling contract). The constraint
force on the bodies is ``-C^T lambda``. Velocity and acceleration constraints:
``C v = -Phi_t``, ``C v' = gamma``.

Bodies restricted to some degrees of freedom keep only those slots when they have 0, 1 or 3
active rotations (exact: rotations stay about the one world axis); with 2 active rotations all
three rotation slots stay and the locked one is held at zero as a ZYX Cardan angle by a
``perp`` constraint with the ground.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .bodies import RigidBody
from .constraints import ConstraintSet
from .force_elements import ForceElement
from .joints import CompiledJoint, Driver, Joint, Marker, compile_joint, joint_frame
from .kinematics import Kin, Pose
from .rotations import cross, exp_so3, log_so3, skew

# ZYX Cardan angle held at zero by "u . w = 0" between body vector u and world vector w
_CARDAN_LOCK = {3: ((1, 2)), 4: ((0, 2)), 5: ((0, 1))}


@dataclass
class Evaluation:
    """Constraint quantities at one state: values, Jacobian (kept rows, generalised slots), gamma, -Phi_t."""

    phi: np.ndarray
    jac: np.ndarray
    gamma: np.ndarray | None
    rhs_v: np.ndarray


class MultibodyModel:
    """Rigid bodies and point masses with joints, drivers and force elements (module docstring).

    Args:
        bodies: the bodies (``RigidBody``; ``point_mass=True`` for 3-DOF masses).
        joints: joints between bodies or to the ground (``body1 = None``).
        elements: force elements built against this model's body indices (see :meth:`index`).
        drivers: prescribed coordinates.
        gravity: gravitational acceleration vector (m/s^2), applied at every centre of gravity.
        static_loads: constant world wrench (force, moment about the cg) per body name.
        added_mass: (m, m) A_inf on ``added_mass_coordinates`` ((body, dof) pairs).
        initial_pose: start poses (locked joints are fixed at the relative pose of these).
    """

    def __init__(
        self,
        bodies: list[RigidBody],
        joints: list[Joint] = (),
        elements: list[ForceElement] = (),
        drivers: list[Driver] = (),
        gravity: np.ndarray = (0.0, 0.0, 0.0),
        static_loads: dict[str, np.ndarray] | None = None,
        added_mass: np.ndarray | None = None,
        added_mass_coordinates: list[tuple[str, int]] | None = None,
        initial_pose: Pose | None = None,
    ) -> None:
        self.bodies = list(bodies)
        self.N = len(bodies)
        self.names = [b.name for b in bodies]
        if len(set(self.names)) != self.N:
            raise ValueError("body names must be unique")
        self._index = {n: i for i, n in enumerate(self.names)}
        self.ground = self.N
        self.cg = np.array([b.cg for b in bodies], dtype=float).reshape(self.N, 3)
        self.mass = np.array([b.mass for b in bodies], dtype=float)
        self.inertia = np.array([np.zeros((3, 3)) if b.point_mass else b.inertia for b in bodies]).reshape(self.N, 3, 3)
        self.gravity = np.asarray(gravity, dtype=float)
        self.static = np.zeros((self.N + 1, 6))
        for name, w in (static_loads or {}).items():
            self.static[self.index(name)] = w
        self._build_slots()
        self.reference = Pose(self.cg.copy(), np.repeat(np.eye(3)[None], self.N, axis=0))
        self.constraints = ConstraintSet()
        self.joints: list[CompiledJoint] = []
        start = initial_pose or self.reference
        for j in joints:
            self._add_joint(j, start)
        self._add_dof_locks()
        self.constraints.freeze()
        self.m_primitive = self.constraints.m
        self.drivers = list(drivers)
        self.m = self.m_primitive + len(self.drivers)
        self.elements = list(elements)
        self.kept = np.arange(self.m)  # rows used by the solvers (redundant ones removed by assembly)
        self.added = np.zeros((self.n, self.n))
        if added_mass is not None and added_mass_coordinates:
            idx = [self.slot_of(b, d) for b, d in added_mass_coordinates]
            self.added[np.ix_(idx, idx)] = added_mass
        self._mass_full = np.zeros((6 * (self.N + 1), 6 * (self.N + 1)))

    # ------------------------------------------------------------------ structure
    def index(self, name: str | None) -> int:
        if name is None or name == "ground":
            return self.ground
        try:
            return self._index[name]
        except KeyError:
            raise ValueError(f"unknown body {name!r} (bodies: {', '.join(self.names)})") from None

    def _build_slots(self) -> None:
        sel, coords, self.extra_locks = [], [], []
        for i, b in enumerate(self.bodies):
            dofs = [d for d in b.dofs if d < 3 or not b.point_mass]
            rot = [d for d in dofs if d >= 3]
            active = list(dofs)
            if len(rot) == 2:
                active = [d for d in dofs if d < 3] + [3, 4, 5]
                locked = ({3, 4, 5} - set(rot)).pop()
                self.extra_locks.append((i, locked))
            sel += [6 * i + d for d in active]
            coords += [(b.name, d) for d in active]
        self.sel = np.array(sel, dtype=int)
        self.coordinates = coords
        self.n = len(sel)
        self._slot = {c: k for k, c in enumerate(coords)}

    def slot_of(self, body: str, dof: int) -> int:
        try:
            return self._slot[(body, dof)]
        except KeyError:
            raise ValueError(f"body {body!r} has no active degree of freedom {dof}") from None

    def marker(self, body: str | None, point, axes: np.ndarray, pose: Pose | None = None) -> Marker:
        """Marker at world ``point`` with world ``axes`` given at ``pose`` (default: equilibrium)."""
        b = self.index(body)
        if b == self.ground:
            return Marker(b, np.asarray(point, float), np.asarray(axes, float))
        pose = pose or self.reference
        R, r = pose.R[b], pose.r[b]
        return Marker(b, R.T @ (np.asarray(point, float) - r), R.T @ np.asarray(axes, float))

    def _add_joint(self, j: Joint, start: Pose) -> None:
        axes = joint_frame(j.axis, j.axis2)
        m1 = self.marker(j.body1, j.position, axes)
        if j.kind == "universal" and j.axis2 is not None:
            a2 = joint_frame(j.axis2, j.axis)
            axes2 = np.column_stack([a2[:, 2], cross(axes[:, 2], a2[:, 2]), axes[:, 2]])
            m2 = self.marker(j.body2, j.position, axes2)
        else:
            m2 = self.marker(j.body2, j.position2 if j.kind == "distance" else j.position, axes)
        if j.locked:  # marker 2 moved to where marker 1 is in the start pose
            k = self._pose_kin(start)
            world_p = k.rr[m1.body] + k.RR[m1.body] @ m1.offset
            world_a = k.RR[m1.body] @ m1.axes
            m2 = self.marker(j.body2, world_p, world_a, start)
        length = float(np.linalg.norm(np.asarray(j.position2, float) - np.asarray(j.position, float))) \
            if j.kind == "distance" else 0.0
        cj = compile_joint(j, m1, m2, length)
        for prim in cj.primitives:
            kind, vi, vj, ni = prim[:4]
            c0 = prim[4] if len(prim) > 4 else 0.0
            b1, b2 = m1.body, m2.body
            row = self.constraints.add(kind, b1, b2, vi, vj, ni, c0)
            cj.rows += list(range(row, row + (3 if kind == "point" else 1)))
        self.joints.append(cj)

    def _add_dof_locks(self) -> None:
        e = np.eye(3)
        for body, dof in self.extra_locks:
            a, b = _CARDAN_LOCK[dof]
            self.constraints.add("perp", body, self.ground, e[a], e[b])

    # ------------------------------------------------------------------ state helpers
    def full(self, v: np.ndarray) -> np.ndarray:
        out = np.zeros(6 * (self.N + 1))
        out[self.sel] = v
        return out

    def _pose_kin(self, pose: Pose) -> Kin:
        return Kin(pose, np.zeros(6 * (self.N + 1)))

    def kin(self, pose: Pose, v: np.ndarray, t: float = 0.0) -> Kin:
        return Kin(pose, self.full(v), t)

    def displacement(self, pose: Pose) -> np.ndarray:
        """(N, 6): translation of each cg from equilibrium and rotation vector from equilibrium."""
        return np.hstack([pose.r - self.cg, log_so3(pose.R)])

    def pose_from_displacement(self, x: np.ndarray) -> Pose:
        x = np.asarray(x, float).reshape(self.N, 6)
        return Pose(self.cg + x[:, :3], exp_so3(x[:, 3:]))

    # ------------------------------------------------------------------ dynamics
    def mass_matrix(self, pose: Pose, k: Kin | None = None) -> np.ndarray:
        """(n, n) structural mass plus A_inf, in generalised slots (``k``: a snapshot at ``pose`` whose world
        inertia is reused)."""
        if not hasattr(self, "_mass_index"):
            self._build_mass_index()
        m = self._mass_constant.copy()
        if self._rotating:
            rows, cols, b, lr, lc = self._mass_index
            if k is not None:
                iw = self.world_inertia(k)
            else:
                r = pose.R
                iw = r @ self.inertia @ np.transpose(r, (0, 2, 1))
            m[rows, cols] += iw[b, lr, lc]
        return m

    def _build_mass_index(self) -> None:
        """Constant part of the mass matrix (A_inf and the bodies' masses on their translation slots) and
        the scatter indices of the world inertia's entries on the rotation slots."""
        body, local = self.sel // 6, self.sel % 6
        rows, cols = np.nonzero((body[:, None] == body[None, :]) & (local[:, None] >= 3) & (local[None, :] >= 3))
        self._mass_index = (rows, cols, body[rows], local[rows] - 3, local[cols] - 3)
        self._rotating = bool(np.any(self.inertia)) and len(rows) > 0
        translation = np.nonzero(local < 3)[0]
        self._mass_constant = self.added.copy()
        self._mass_constant[translation, translation] += self.mass[body[translation]]

    def forces_full(self, k: Kin) -> np.ndarray:
        """Generalised force in full slots: gyroscopic, gravity, static loads, force elements."""
        if not hasattr(self, "_constant_force"):
            self._constant_force = self.static.copy()
            self._constant_force[: self.N, :3] = self.mass[:, None] * self.gravity + self.static[: self.N, :3]
        fb = self._constant_force.copy()
        w = k.W[: self.N, 3:]
        if w.any():
            iw = self.world_inertia(k)
            fb[: self.N, 3:] -= cross(w, (iw @ w[:, :, None])[:, :, 0])
        f = fb.reshape(-1)
        for e in self.elements:
            e.apply(k, f)
        return f

    def forces(self, k: Kin, inputs: np.ndarray | None = None) -> np.ndarray:
        f = self.forces_full(k)[self.sel]
        return f if inputs is None else f + inputs

    def tangents(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        """Approximate stiffness and damping (n, n) of the force elements, for the Newton matrix."""
        size = 6 * (self.N + 1)
        if not self.elements:
            return np.zeros((self.n, self.n)), np.zeros((self.n, self.n))
        kf, df = np.zeros((size, size)), np.zeros((size, size))
        for e in self.elements:
            t = e.tangent(k)
            if t is not None:
                cols, kk, dd = t
                kf[np.ix_(cols, cols)] += kk
                df[np.ix_(cols, cols)] += dd
        s = self.sel
        return kf[np.ix_(s, s)], df[np.ix_(s, s)]

    def world_inertia(self, k: Kin) -> np.ndarray:
        """(N, 3, 3) inertia tensors in world axes, ``R I_0 R^T`` (kept on the snapshot)."""
        if k.world_inertia is None:
            r = k.RR[: self.N]
            k.world_inertia = r @ self.inertia @ np.transpose(r, (0, 2, 1))
        return k.world_inertia

    def _rotation_blocks(self, blocks: np.ndarray | None) -> np.ndarray:
        """(n, n) matrix with per-body 3x3 ``blocks`` on the rotation slots (zero if None)."""
        size = 6 * (self.N + 1)
        out = np.zeros((size, size))
        if blocks is not None:
            for i in range(self.N):
                out[6 * i + 3:6 * i + 6, 6 * i + 3:6 * i + 6] = blocks[i]
        return out[np.ix_(self.sel, self.sel)]

    def gyroscopic_damping(self, k: Kin) -> np.ndarray:
        """d(w x I w)/dw per body, (n, n): the gyroscopic part of -df/dv."""
        if not self._has_rotation():
            return self._rotation_blocks(None)
        iw = self.world_inertia(k)
        w = k.W[: self.N, 3:]
        return self._rotation_blocks(skew(w) @ iw - skew(np.einsum("kab,kb->ka", iw, w)))

    def inertial_stiffness(self, k: Kin, acc: np.ndarray) -> np.ndarray:
        """d(I_w a)/dtheta per body: the rotation of the world inertia under a position increment."""
        if not self._has_rotation():
            return self._rotation_blocks(None)
        a = self.full(acc).reshape(self.N + 1, 6)[: self.N, 3:]
        iw = self.world_inertia(k)
        return self._rotation_blocks(-skew(np.einsum("kab,kb->ka", iw, a)) + iw @ skew(a))

    def geometric_stiffness(self, k: Kin, lam_kept: np.ndarray) -> np.ndarray:
        """d(C^T lambda)/dq of the joints' point and perp primitives, (n, n)."""
        size = 6 * (self.N + 1)
        out = np.zeros((size, size))
        if len(lam_kept) and self._has_rotation():
            lam = np.zeros(self.m)
            lam[self.kept] = lam_kept
            self.constraints.geometric_stiffness(k, lam, out)
        return out[np.ix_(self.sel, self.sel)]

    def _has_rotation(self) -> bool:
        if not hasattr(self, "_rotation_flag"):
            self._rotation_flag = bool(np.any(self.inertia)) and bool(np.any(self.sel % 6 >= 3))
        return self._rotation_flag

    # ------------------------------------------------------------------ constraints
    def constraint_full(self, k: Kin, *, gamma: bool = True, jac: bool = True, kept_only: bool = False) -> tuple:
        """All rows: Phi (m,), Jacobian (m, 6(N+1)) in full slots, gamma (m,), -Phi_t (m,). With ``kept_only``
        primitive kinds without a kept row are skipped (their rows stay zero)."""
        m, size = self.m, 6 * (self.N + 1)
        phi = np.zeros(m)
        jf = np.zeros((m, size)) if jac else None
        gm = np.zeros(m) if gamma else None
        self.constraints.evaluate(k, phi, jf, gm, self._kept_groups() if kept_only else None)
        rhs_v = np.zeros(m)
        for r, d in enumerate(self.drivers, start=self.m_primitive):
            value, row, quad = d.coordinate.evaluate(k) if (gamma or jac) else (*d.coordinate.evaluate(k)[:1], None, 0)
            phi[r] = value - d.function.value(k.t)
            rhs_v[r] = d.function.d1(k.t)
            if jac:
                jf[r, d.coordinate.cols()] += row
            if gamma:
                gm[r] = d.function.d2(k.t) - quad
        return phi, jf, gm, rhs_v

    def velocity_rhs(self, t: float) -> np.ndarray:
        """``-Phi_t`` of the kept rows at time ``t`` (non-zero only on driver rows)."""
        rhs_v = np.zeros(self.m)
        for r, d in enumerate(self.drivers, start=self.m_primitive):
            rhs_v[r] = d.function.d1(t)
        return rhs_v[self.kept]

    def constraint_gamma(self, k: Kin) -> np.ndarray:
        """gamma of the kept rows only (cheaper than :meth:`constraint` when the Jacobian is known)."""
        gm = np.zeros(self.m)
        self.constraints.evaluate(k, None, None, gm, self._kept_groups())
        for r, d in enumerate(self.drivers, start=self.m_primitive):
            gm[r] = d.function.d2(k.t) - d.coordinate.evaluate(k)[2]
        return gm[self.kept]

    def constraint(self, k: Kin, *, gamma: bool = True) -> Evaluation:
        """Kept rows, generalised slots."""
        phi, jf, gm, rhs = self.constraint_full(k, gamma=gamma, kept_only=True)
        kept = self.kept
        self._kept_groups()
        return Evaluation(phi[kept], jf[self._kept_ix], None if gm is None else gm[kept], rhs[kept])

    def _kept_groups(self) -> list:
        """Primitive groups with at least one kept row, and the kept block's index (cached per kept set)."""
        kept = self.kept
        if getattr(self, "_kept_key", None) is not kept:
            rows = set(kept.tolist())
            groups = [g for g in self.constraints.active if rows.intersection(g.ROW.ravel().tolist())]
            self._kept_key, self._kept_ix, self._kept_group_list = kept, np.ix_(kept, self.sel), groups
        return self._kept_group_list

    # ------------------------------------------------------------------ energy
    def kinetic_energy(self, pose: Pose, v: np.ndarray) -> float:
        return 0.5 * float(v @ self.mass_matrix(pose) @ v)

    def potential_energy(self, k: Kin) -> float:
        """Gravity and static loads (constant forces: -F . r) plus the elements' stored energy."""
        r = k.rr[: self.N]
        v = -float(np.sum(self.mass[:, None] * self.gravity * r))
        v -= float(np.sum(self.static[: self.N, :3] * (r - self.cg)))
        v -= float(np.sum(self.static[: self.N, 3:] * log_so3(k.RR[: self.N])))  # exact only for small rotations
        return v + sum(e.potential(k) for e in self.elements)

    def commit(self, k: Kin) -> None:
        for e in self.elements:
            e.commit(k)
        for d in self.drivers:
            d.coordinate.commit(k)
        for j in self.joints:
            for c in j.coordinates:
                c.commit(k)
