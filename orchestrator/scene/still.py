"""Coordinates of a scene that cannot move: a body fixed to the ground, a joint locked, a DOF its joints take away.

Such a coordinate's velocity is always zero, so the radiation memory of its own motion is never excited: the
state-space fit gives its kernel columns no states (:func:`hydro_fmu.state_space.fit_state_space`, ``still``).

Test: the null space of the joints' constraint Jacobian (driver rows left out: a prescribed motion moves its
coordinate) at the assembled start pose and at two poses moved from it along the mechanism's own degrees of
freedom (random directions, 0.05 rad or 0.05 of the scene's length scale, assembled again). A coordinate whose row
of the null-space basis is zero at all three is still. One pose would not do: a coordinate that moves only to
second order there (the heave of a flap hanging straight from its hinge) has a zero row at that pose alone.
"""

from __future__ import annotations

import numpy as np


def still_coordinates(scene, *, seed: int = 0) -> list[tuple[str, int]]:  # noqa: ANN001 - Scene
    """(body, DOF index 0-5) of every hydrodynamic coordinate of ``scene`` that cannot move (module docstring);
    empty for the linear multibody model (no joints)."""
    s = scene.scenario
    if s.formulation == "linear" or not s.joints:
        return []
    from mbd_fmu.assembly import analyse, assemble
    from mbd_fmu.spec import build_model, initial_pose

    spec = scene.mbd_spec(dynamic_lines=False)
    model, _ = build_model(spec)
    pose, _ = initial_pose(spec)
    v = np.zeros(model.n)
    pose, _, _ = assemble(model, pose, v, 0.0)
    analyse(model, pose, 0.0)
    length = max(1.0, float(np.max(np.abs(model.cg))) if model.N else 1.0)
    rng = np.random.default_rng(seed)
    still = np.ones(model.n, dtype=bool)
    for _ in range(3):
        basis = _null_space(model, pose)
        still &= np.all(np.abs(basis) <= 1e-9, axis=1)
        if not still.any() or basis.shape[1] == 0:
            break
        direction = basis @ rng.normal(size=basis.shape[1])
        scale = np.where(model.sel % 6 >= 3, 0.05, 0.05 * length)
        step = direction / max(float(np.max(np.abs(direction) / scale)), 1e-300)
        try:
            pose, _, _ = assemble(model, pose.retract(model.full(step)), v, 0.0)
        except ValueError:  # a pose the joints cannot reach from there: the poses tried so far decide
            break
    coords = [(model.bodies[int(model.sel[i]) // 6].name, int(model.sel[i]) % 6) for i in range(model.n)]
    hydro = set(scene.hydro_coordinates)
    return [(b, d) for (b, d), s_ in zip(coords, still, strict=True) if s_ and (b, d) in hydro]


def _null_space(model, pose) -> np.ndarray:  # noqa: ANN001 - MultibodyModel, Pose
    """Orthonormal basis (n, dof) of the null space of the joints' constraint rows at ``pose`` (no drivers)."""
    _, jf, _, _ = model.constraint_full(model.kin(pose, np.zeros(model.n), 0.0), gamma=False)
    c = jf[: model.m_primitive][:, model.sel]
    if c.shape[0] == 0:
        return np.eye(model.n)
    _, sv, vt = np.linalg.svd(c)
    rank = int(np.sum(sv > 1e-9 * max(float(sv[0]), 1e-300))) if sv.size else 0
    return vt[rank:].T
