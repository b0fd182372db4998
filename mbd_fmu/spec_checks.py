"""Checks of a multibody model's data that the equations cannot survive, each with one message that names the
body or joint, what is wrong and what to do (:class:`ModelError`).

* inertia tensors: symmetric, finite, positive definite (its smallest principal moment above
  :data:`SINGULAR` times the largest; a singular tensor gives an infinite angular acceleration), and its
  principal moments within the triangle inequality ``I1 + I2 >= I3`` that every rigid body's moments obey
  (``I1 + I2 - I3 = 2 * integral of z'^2 dm >= 0`` in the principal frame), to :data:`TRIANGLE` relative;
* axes: any finite vector that is not zero, scaled by its largest component before it is normalised
  (``[0, 1e200, 1e200]`` is the direction (0, 1, 1)/sqrt(2), not an overflow; ``[1e-200, 0, 0]`` is x);
* universal joints: two axes at a right angle (within :data:`PERPENDICULAR` of the cosine), which rules out
  parallel axes; distance joints: two points that do not coincide;
* assembly (:func:`check_assembly`): the start pose a scene gives must satisfy its joints; the assembly that
  makes it consistent may move a body by at most :data:`ASSEMBLY_TOLERANCE` times the scene's length scale
  (max(1 m, the largest cg coordinate)) in translation, and by as many radians in rotation; beyond that the
  scene is refused with the largest move named (a body placed off its hinge, a loop that does not close);
* drivers (:func:`check_drivers`): each driver must prescribe a coordinate the joints leave free (it adds one
  to the rank of the constraint Jacobian); a driver on a coordinate that other constraints already fix cannot
  be met.
"""

from __future__ import annotations

import numpy as np

SINGULAR = 1e-12  # smallest principal moment of inertia, relative to the largest
TRIANGLE = 1e-6  # principal moments: I1 + I2 >= I3 (1 - TRIANGLE)
PERPENDICULAR = 1e-6  # |cos| of the angle between a universal joint's two axes
ASSEMBLY_TOLERANCE = 1e-3  # largest move of the start pose by the assembly, relative to the scene's length scale
ASSEMBLY_REPORT = 1e-6  # moves above this (relative) are reported, below it they are round-off


class ModelError(ValueError):
    """A multibody model that cannot be built or started; the message names the body or joint and the fix."""


def direction(vector: object, what: str) -> np.ndarray:
    """The unit vector along ``vector`` (any finite, non-zero 3-vector); ModelError naming ``what`` otherwise."""
    v = np.asarray(vector, dtype=float).reshape(-1)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ModelError(f"{what} must be three finite numbers (got {list(map(float, v))})")
    scale = float(np.max(np.abs(v)))
    if scale == 0.0:
        raise ModelError(f"{what} is the zero vector; give the direction, e.g. [0, 1, 0]")
    v = v / scale
    return v / np.linalg.norm(v)


def inertia_problem(inertia: np.ndarray) -> str | None:
    """Why a 3x3 inertia tensor (kg m^2, about the cg) cannot belong to a rigid body, or None."""
    inertia = np.asarray(inertia, dtype=float).reshape(3, 3)
    if not np.all(np.isfinite(inertia)):
        return "the inertia holds a value that is not a finite number"
    if not np.allclose(inertia, inertia.T, rtol=1e-12, atol=0):
        return "the inertia tensor is not symmetric"
    moments = np.linalg.eigvalsh(inertia)
    if moments[-1] <= 0 or moments[0] <= SINGULAR * moments[-1]:
        return (f"the inertia tensor is not positive definite (principal moments {_moments(moments)} kg m^2): a "
                "body needs a positive moment about every axis; check the products of inertia (Ixy, Ixz, Iyz) "
                "against the moments")
    if moments[0] + moments[1] < moments[2] * (1 - TRIANGLE):
        return (f"no rigid body has the principal moments {_moments(moments)} kg m^2: the two smaller must add up to "
                "at least the largest (I1 + I2 >= I3); check the values and their order [Ixx, Iyy, Izz]")
    return None


def _moments(moments: np.ndarray) -> str:
    return ", ".join(f"{m:.4g}" for m in moments)


def universal_axes_problem(axis: object, axis2: object) -> str | None:
    """Why two axes cannot be a universal joint's (parallel, or not at a right angle), or None."""
    a, b = direction(axis, "axis"), direction(axis2, "axis2")
    cos = float(abs(a @ b))
    if cos > 1 - 1e-9:
        return ("axis and axis2 are parallel: a universal joint is two hinges about perpendicular axes; give axis2 "
                "at a right angle to axis (or use a revolute joint)")
    if cos > PERPENDICULAR:
        angle = float(np.degrees(np.arccos(cos)))
        return (f"axis and axis2 are at {angle:.4g} deg; a universal joint needs them at a right angle (90 deg, "
                f"within a cosine of {PERPENDICULAR:g})")
    return None


def distance_problem(position: object, position2: object) -> str | None:
    """Why a distance joint between two points cannot be formed, or None."""
    p1, p2 = np.asarray(position, dtype=float), np.asarray(position2, dtype=float)
    length = float(np.linalg.norm(p2 - p1))
    scale = max(1.0, float(np.max(np.abs(np.concatenate([p1, p2])))))
    if not length > 1e-9 * scale:
        return ("position and position2 coincide (length 0): a distance joint holds two distinct points at their "
                "distance; to hold two points together use a spherical joint")
    return None


def assembly_problem(moves: dict[str, tuple[float, float]], scale: float) -> str | None:
    """Why a start pose that the assembly moved by ``moves`` (body -> (translation m, rotation rad)) is refused,
    or None (the moves within :data:`ASSEMBLY_TOLERANCE` of ``scale`` m and rad)."""
    limit = ASSEMBLY_TOLERANCE * scale
    name, (dx, dr) = max(moves.items(), key=lambda item: max(item[1][0] / scale, item[1][1]))
    if dx <= limit and dr <= ASSEMBLY_TOLERANCE:
        return None
    return (f"the start pose does not satisfy the joints: assembling it would move body {name!r} by {dx:.4g} m and "
            f"{np.degrees(dr):.4g} deg (more than the {limit:.3g} m and {np.degrees(ASSEMBLY_TOLERANCE):.3g} deg "
            "the assembly may correct); place the bodies where their joints hold (initial displacements that "
            "agree with the joints, joint positions at the bodies' attachment points) or check the joint positions")


def assembly_note(moves: dict[str, tuple[float, float]], scale: float) -> str | None:
    """A line reporting the assembly's correction of the start pose, when it is more than round-off."""
    shown = {n: m for n, m in moves.items() if m[0] > ASSEMBLY_REPORT * scale or m[1] > ASSEMBLY_REPORT}
    if not shown:
        return None
    return "assembly moved the start pose to satisfy the joints: " + ", ".join(
        f"{n} by {dx:.3g} m and {np.degrees(dr):.3g} deg" for n, (dx, dr) in shown.items())
