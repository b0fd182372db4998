"""Static equilibrium of a constrained multibody model: where the device rests before waves start.

The static loads are those of the model at rest (gravity at the centres of gravity, the constant
buoyancy of the hydrodynamic bodies with the moment of their centre of buoyancy, the force
elements: catenary lines, tethers, springs, PTO springs) plus a linear restoring force ``-K x`` on
chosen coordinates, ``x`` the displacement from the reference pose (translation of the cg,
rotation vector): the hydrostatic stiffness that the hydro FMU applies in the time domain. The
equilibrium ``q*`` satisfies ``Phi(q*) = 0`` and ``P^T (f(q*) - K x(q*)) = 0`` with ``P`` a basis
of the null space of the constraint Jacobian (the constraint forces take the rest).

Method: Newton's method on the constraint manifold. At each iterate the reduced tangent
``P^T (K_f + K) P`` (``K_f`` from :func:`mbd_fmu.linearize.linearize`: the force elements'
stiffness by central differences and the geometric stiffness of the gravity and constraint
forces) gives a step ``delta = P y``; the pose is moved by ``delta`` and projected back onto the
constraints (:func:`mbd_fmu.assembly.assemble`). Quadratic convergence near a regular equilibrium
(the central differences are exact to about 1e-12 relative); the unbalanced force is reported. A
reduced tangent that is not positive definite (an unstable or neutrally stable equilibrium: a free
surge without mooring) is handled by a least-squares step, and such directions are listed.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .assembly import assemble
from .kinematics import Pose
from .linearize import linearize
from .model import MultibodyModel


@dataclass
class Equilibrium:
    """Result of :func:`static_equilibrium`.

    Attributes:
        pose: the equilibrium pose.
        displacement: (N, 6) translation (m) and rotation vector (rad) of each body from the reference pose.
        residual: largest unbalanced generalised force along the free motions (N or N m).
        iterations: Newton iterations taken.
        neutral: indices (into ``model.coordinates``-sized reduced space) of directions without stiffness.
    """

    pose: Pose
    displacement: np.ndarray
    residual: float
    iterations: int
    neutral: list[int] = field(default_factory=list)


def unbalanced_force(model: MultibodyModel, pose: Pose, stiffness: np.ndarray, slots: np.ndarray) -> np.ndarray:
    """``f(q) - K x(q)`` in the model's slots at rest (N, N m)."""
    f = model.forces(model.kin(pose, np.zeros(model.n)))
    if len(slots):
        x = model.displacement(pose).reshape(-1)[_full_index(model, slots)]
        f = f.copy()
        f[slots] -= stiffness @ x
    return f


def _full_index(model: MultibodyModel, slots: np.ndarray) -> np.ndarray:
    """Index into the (N * 6) displacement of each slot."""
    return model.sel[slots]


def static_equilibrium(model: MultibodyModel, stiffness: np.ndarray | None = None,
                       coordinates: list[tuple[str, int]] | None = None, *, pose: Pose | None = None,
                       tolerance: float = 1e-9, max_iterations: int = 30) -> Equilibrium:
    """The static equilibrium nearest ``pose`` (default the reference pose); see the module docstring.

    ``stiffness`` (k, k) acts on ``coordinates`` ((body, dof) pairs, dof 0..5); ``tolerance`` is relative to
    the largest static load (weight or element force) of the model.
    """
    coordinates = coordinates or []
    slots = np.array([model.slot_of(b, d) for b, d in coordinates], dtype=int)
    k_ext = np.zeros((model.n, model.n))
    if len(slots):
        k_ext[np.ix_(slots, slots)] = stiffness
    stiffness = np.zeros((0, 0)) if stiffness is None else np.asarray(stiffness, float)
    pose = (pose or model.reference).copy()
    pose, _, _ = assemble(model, pose, np.zeros(model.n))
    scale = max(float(np.max(np.abs(model.forces(model.kin(pose, np.zeros(model.n)))))), 1.0)
    neutral: list[int] = []
    for iteration in range(max_iterations + 1):
        lin = linearize(model, pose)
        p = lin.null_space if lin.constraint_jacobian.size else np.eye(model.n)
        g = p.T @ unbalanced_force(model, pose, stiffness, slots)
        residual = float(np.max(np.abs(g))) if g.size else 0.0
        if residual <= tolerance * scale or iteration == max_iterations:
            break
        kr = p.T @ (lin.stiffness + k_ext) @ p
        kr = 0.5 * (kr + kr.T)
        w, v = np.linalg.eigh(kr)
        keep = w > 1e-9 * max(float(np.max(np.abs(w))), 1e-300)
        neutral = [int(i) for i in np.flatnonzero(~keep)]
        y = v[:, keep] @ ((v[:, keep].T @ g) / w[keep])
        pose = pose.retract(model.full(p @ y))
        pose, _, _ = assemble(model, pose, np.zeros(model.n))
    if residual > tolerance * scale:
        raise ValueError(f"static equilibrium not found: unbalanced force {residual:.3g} after {max_iterations} "
                         "Newton iterations (is the device held in every direction: mooring, tether, hydrostatics?)")
    return Equilibrium(pose, model.displacement(pose), residual, iteration, neutral)
