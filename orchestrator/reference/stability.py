"""Static stability of a scene about its equilibrium: the restoring matrix must not push a body away.

The static stiffness ``K`` of the linear model (hydrostatics ``C_hs`` from the database, PTO and mooring
stiffness, springs and, for constrained scenes, the geometric stiffness of the static loads, all on the
constraint null space) decides: a negative eigenvalue of its symmetric part is a direction in which a
displacement is pushed further away, and every time-domain run grows exponentially along it, whatever the
step or the master. A frequency-domain answer (RAOs, PTO power) of such a scene is finite but no motion
converges to it, so ``wec-cosim rao`` and ``steady`` refuse it; a run that diverges is told the cause.

The sign test is made on ``D K_s D`` with ``D = diag(1/sqrt|K_ii|)`` (Sylvester's law of inertia: the signs
of the eigenvalues do not change under this congruence, and the mixed units of translations and rotations
drop out); an eigenvalue below ``-NEGATIVE`` is unstable. Zero eigenvalues (free surge, sway, yaw) are
neutral, not unstable.
"""

from __future__ import annotations

import numpy as np

from orchestrator.scenario import DOFS
from orchestrator.scene import Scene

NEGATIVE = 1e-8  # eigenvalue of the scaled symmetric stiffness below which a direction is unstable


def static_stiffness(scene: Scene) -> tuple[np.ndarray, np.ndarray | None, list]:
    """The static stiffness on the multibody coordinates (multibody K plus the hydrostatics the scene switches
    on), the null space of the linearised constraints (None without joints) and the coordinates (body, dof)."""
    from scipy.linalg import block_diag

    from .frequency_domain import mechanical_matrices

    mech = mechanical_matrices(scene)
    k = np.array(mech.stiffness, dtype=float)
    if scene.scenario.hydro.hydrostatics:
        idx = scene.hydro_index()
        k[np.ix_(mech.rows, mech.rows)] += block_diag(*scene.hdb.hydrostatic_stiffness)[np.ix_(idx, idx)]
    return k, mech.basis, list(mech.system.coordinates)


def static_instability(scene: Scene) -> str | None:
    """What makes the scene statically unstable (the coordinate and its restoring terms), or None."""
    k, basis, coordinates = static_stiffness(scene)
    reduced = basis.T @ k @ basis if basis is not None else k
    reduced = 0.5 * (reduced + reduced.T)
    if not reduced.size:
        return None
    diag = np.abs(np.diag(reduced))
    scale = np.sqrt(np.maximum(diag, 1e-12 * max(float(diag.max()), 1e-300)))
    values, vectors = np.linalg.eigh(reduced / np.outer(scale, scale))
    if values[0] >= -NEGATIVE:
        return None
    # the coordinate to name: one whose own restoring term is negative, else the mode's largest component
    mode = vectors[:, 0] / scale
    mode = basis @ mode if basis is not None else mode
    weight = np.abs(mode) * np.sqrt(np.maximum(np.abs(np.diag(k)), 1e-300))
    negative = np.diag(k) < 0
    j = int(np.argmax(np.where(negative, weight + weight.max(), weight)))
    body, dof = coordinates[j]
    return _describe(scene, body, dof)


def _describe(scene: Scene, body: str, dof: int) -> str:
    unit = "N/m" if dof < 3 else "N m/rad"
    text = f"body {body!r} {DOFS[dof]} is statically unstable: its restoring stiffness about equilibrium is negative"
    if (body, dof) in scene.hydro_coordinates:
        b = scene.hdb.body_index(body)
        c = float(scene.hdb.hydrostatic_stiffness[b][dof, dof])
        if c < 0:
            why = {2: "rho g times the waterplane area, positive for any floating body: the database is wrong",
                   3: "negative metacentric height: the centre of gravity lies too high, or the database is wrong",
                   4: "negative metacentric height: the centre of gravity lies too high, or the database is "
                      "wrong"}.get(dof, "zero for a floating body: the database is wrong")
            text += (f" (the hydrostatic stiffness C{dof + 1}{dof + 1} = {c:.4g} {unit} of the database "
                     f"{scene.hdb_file}; it is {why})")
    return (text + ", so any displacement grows and no motion settles to a steady answer; check the database "
            "and the centre of gravity, or add restoring stiffness (PTO stiffness, mooring)")
