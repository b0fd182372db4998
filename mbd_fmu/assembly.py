"""Mobility analysis (DOF count, redundant constraints) and consistent initial assembly.

* :func:`analyse` - rank-revealing QR (column pivoting) of the transposed constraint Jacobian:
  its rank ``r`` gives the degrees of freedom ``n - r``; the ``m - r`` rows not chosen as pivots
  are redundant (linear combinations of the others at this configuration, e.g. Bricard's
  overconstrained loop, a planar loop of revolute joints, a revolute joint between bodies that
  already move in one plane). The solvers use the independent rows only; the redundant
  equations stay satisfied because they depend on the kept ones.
* :func:`assemble` - from approximate poses and velocities, the nearest consistent state in the
  mass metric: Newton iterations ``dq = -W^-1 C^T (C W^-1 C^T)^-1 Phi`` on positions, then the
  velocity projection ``v -= W^-1 C^T (C W^-1 C^T)^-1 (C v + Phi_t)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import qr

from .kinematics import Pose
from .model import MultibodyModel
from .rotations import log_so3
from .spec_checks import ModelError, assembly_note, assembly_problem


@dataclass
class MobilityReport:
    """Result of :func:`analyse`."""

    coordinates: int
    constraints: int
    rank: int
    kept: np.ndarray
    redundant: list[str] = field(default_factory=list)
    note: str = ""  # the assembly's correction of the start pose, when more than round-off

    @property
    def dof(self) -> int:
        return self.coordinates - self.rank

    def summary(self) -> str:
        red = f"; redundant: {', '.join(self.redundant)}" if self.redundant else ""
        return (f"{self.coordinates} coordinates, {self.constraints} constraint equations of rank {self.rank}: "
                f"{self.dof} degrees of freedom, {len(self.redundant)} redundant constraints{red}")


def row_labels(model: MultibodyModel) -> list[str]:
    """Human name of every constraint row (joint and equation number, lock, driver)."""
    labels = [""] * model.m
    for cj in model.joints:
        for k, r in enumerate(cj.rows):
            labels[r] = f"{cj.joint.name}[{k + 1}]"
    for r in range(model.m_primitive):
        if not labels[r]:
            labels[r] = "dof lock"
    for k, d in enumerate(model.drivers):
        labels[model.m_primitive + k] = d.name
    return labels


def independent_rows(c: np.ndarray, rank: int | None = None, tol: float = 1e-9) -> tuple[np.ndarray, np.ndarray, int]:
    """Best-conditioned independent rows of ``c`` (QR with column pivoting of the row-normalised
    transpose): ``(kept, redundant, rank)``; ``rank`` may be imposed (the mechanism's generic rank)."""
    scale = np.maximum(np.linalg.norm(c, axis=1), 1e-300)
    _, rr, piv = qr((c / scale[:, None]).T, pivoting=True, mode="economic")
    diag = np.abs(np.diag(rr))
    if rank is None:
        rank = int(np.sum(diag > tol * max(diag[0], 1e-300))) if len(diag) else 0
    return np.sort(piv[:rank]), np.sort(piv[rank:]), rank


def analyse(model: MultibodyModel, pose: Pose, t: float = 0.0, tol: float = 1e-9) -> MobilityReport:
    """Rank and redundancy of the constraints at ``pose``; sets ``model.kept`` to the independent rows."""
    k = model.kin(pose, np.zeros(model.n), t)
    _, jf, _, _ = model.constraint_full(k, gamma=False)
    c = jf[:, model.sel]
    if model.m == 0:
        model.kept = np.arange(0)
        return MobilityReport(model.n, 0, 0, model.kept)
    kept, redundant_rows, rank = independent_rows(c, tol=tol)
    piv = np.concatenate([kept, redundant_rows])
    labels = row_labels(model)
    redundant = [labels[r] for r in redundant_rows]
    del piv
    model.kept = kept
    return MobilityReport(model.n, model.m, rank, kept, redundant)


def assemble(
    model: MultibodyModel,
    pose: Pose,
    v: np.ndarray,
    t: float = 0.0,
    tol: float = 1e-12,
    max_iter: int = 50,
) -> tuple[Pose, np.ndarray, float]:
    """Consistent pose and velocity nearest to the given ones; returns them and the largest position change."""
    w_inv = np.linalg.inv(model.mass_matrix(pose))
    start = pose.copy()
    scale = max(1.0, float(np.max(np.abs(model.cg))) if model.N else 1.0)
    for _ in range(max_iter):
        ev = model.constraint(model.kin(pose, v, t), gamma=False)
        if ev.phi.size == 0 or np.max(np.abs(ev.phi)) <= tol * scale:
            break
        c = ev.jac
        if not (np.all(np.isfinite(ev.phi)) and np.all(np.isfinite(c))):  # before LAPACK sees them
            raise ModelError("assembly failed: the constraint equations are not finite at the start pose; check the "
                             "bodies' positions, the joint positions and axes")
        delta = -w_inv @ c.T @ np.linalg.lstsq(c @ w_inv @ c.T, ev.phi, rcond=None)[0]
        pose = pose.retract(model.full(delta))
    else:
        raise ModelError(
            f"assembly did not converge: constraint violation {np.max(np.abs(ev.phi)):.3g} after {max_iter} "
            "iterations; the initial poses are too far from a configuration the joints allow")
    ev = model.constraint(model.kin(pose, v, t), gamma=False)
    if ev.jac.size:
        c = ev.jac
        v = v - w_inv @ c.T @ np.linalg.lstsq(c @ w_inv @ c.T, c @ v - ev.rhs_v, rcond=None)[0]
    moved = float(np.max(np.abs(model.displacement(pose) - model.displacement(start)))) if model.N else 0.0
    return pose, v, moved


def body_moves(model: MultibodyModel, before: Pose, after: Pose) -> dict[str, tuple[float, float]]:
    """How far a change of pose moved each body: name -> (translation of the cg in m, rotation angle in rad)."""
    out = {}
    for i, b in enumerate(model.bodies):
        turn = log_so3((after.R[i] @ before.R[i].T)[None])[0]
        out[b.name] = (float(np.linalg.norm(after.r[i] - before.r[i])), float(np.linalg.norm(turn)))
    return out


def check_start(model: MultibodyModel, given: Pose, assembled: Pose, t: float = 0.0) -> str:
    """Refuse (:class:`ModelError`) a start pose that the assembly had to move beyond the tolerance of
    :func:`mbd_fmu.spec_checks.assembly_problem`, and drivers that prescribe a coordinate the joints already fix
    (a driver must add one to the rank of the constraint Jacobian at the assembled pose). Returns the line that
    reports a correction within the tolerance ("" for round-off)."""
    if not model.N:
        return ""
    moves = body_moves(model, given, assembled)
    scale = max(1.0, float(np.max(np.abs(model.cg))))
    problem = assembly_problem(moves, scale)
    if problem:
        raise ModelError(problem)
    if model.drivers:
        k = model.kin(assembled, np.zeros(model.n), t)
        _, jf, _, _ = model.constraint_full(k, gamma=False)
        c = jf[:, model.sel]
        rank = independent_rows(c[: model.m_primitive])[2] if model.m_primitive else 0
        for j, d in enumerate(model.drivers):
            rows = np.concatenate([np.arange(model.m_primitive), [model.m_primitive + j]])
            if independent_rows(c[rows])[2] <= rank:
                raise ModelError(
                    f"driver {d.name!r} prescribes a coordinate that the joints already fix (its constraint adds "
                    "nothing to the joints' rank at the start pose): no motion can follow it; remove the driver, or "
                    "the joint or lock that holds the coordinate")
    return assembly_note(moves, scale) or ""
