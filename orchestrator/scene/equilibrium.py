"""The scene's static equilibrium before waves start (``[multibody] static_equilibrium = true``).

:func:`scene_equilibrium` solves :func:`mbd_fmu.equilibrium.static_equilibrium` on the scene's
nonlinear multibody model at the reference pose, with the hydrostatic stiffness of the database on
the hydrodynamic coordinates (what the hydro FMU applies as ``-C x`` in the time domain), and
:func:`equilibrium_report` says what holds the device there: each body's mass, weight and buoyancy,
each force element's force (catenary fairlead tensions, tether and spring tensions), the joint
coordinates and each body's offset from the reference pose.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import block_diag

from mbd_fmu.equilibrium import Equilibrium, static_equilibrium
from orchestrator.scenario import DOFS


@dataclass
class SceneEquilibrium:
    """The equilibrium of a scene and what holds it (forces in N, lengths in m, angles in rad)."""

    equilibrium: Equilibrium
    bodies: list[dict]
    elements: list[dict]
    joints: list[dict]

    @property
    def pose(self):
        return self.equilibrium.pose

    @property
    def displacement(self) -> np.ndarray:
        return self.equilibrium.displacement

    def as_dict(self) -> dict:
        return {"residual": self.equilibrium.residual, "iterations": self.equilibrium.iterations,
                "bodies": self.bodies, "elements": self.elements, "joints": self.joints}


def scene_equilibrium(scene) -> SceneEquilibrium:
    """Static equilibrium of ``scene`` (an :class:`orchestrator.scene.Scene`) and its report data."""
    from mbd_fmu.spec import build_model

    s = scene.scenario
    model, _ = build_model(scene._mbd_spec_at_reference())
    idx = scene.hydro_index()
    stiffness = block_diag(*scene.hdb.hydrostatic_stiffness)[np.ix_(idx, idx)] if s.hydro.hydrostatics else None
    coordinates = list(scene.hydro_coordinates) if stiffness is not None else []
    try:
        eq = static_equilibrium(model, stiffness, coordinates)
    except ValueError as exc:
        from orchestrator.errors import ScenarioError

        raise ScenarioError(f"{s.file}: multibody.static_equilibrium: {exc}") from None
    kin = model.kin(eq.pose, np.zeros(model.n))
    g = s.environment.g
    bodies = []
    for i, b in enumerate(s.bodies):
        load = scene.static_load(b) if s.multibody.gravity else [0.0] * 6
        bodies.append({"name": b.name, "mass": float(model.mass[i]), "weight": float(model.mass[i] * g),
                       "buoyancy": float(load[2]), "offset": eq.displacement[i].tolist()})
    elements = []
    for e in model.elements:
        out = e.output(kin)
        entry = {"name": e.name, "kind": type(e).__name__}
        if len(out) == 3:  # catenary: force on the body at the fairlead
            entry.update(horizontal=float(math.hypot(out[0], out[1])), vertical=float(-out[2]),
                         tension=float(np.linalg.norm(out)))
        elif len(out) == 1:
            entry.update(force=float(out[0]))
        elements.append(entry)
    joints = []
    for cj in model.joints:
        values = [float(c.evaluate(kin)[0]) for c in cj.coordinates]
        joints.append({"name": cj.joint.name, "coordinates": values})
    return SceneEquilibrium(eq, bodies, elements, joints)


def equilibrium_report(found: SceneEquilibrium) -> str:
    """Human-readable report of :func:`scene_equilibrium`'s result."""
    eq = found.equilibrium
    lines = [f"static equilibrium (unbalanced force {eq.residual:.3g} N after {eq.iterations} Newton iterations):",
             f"  {'body':<12}{'mass kg':>12}{'weight N':>13}{'buoyancy N':>13}  offset from the reference pose"]
    for b in found.bodies:
        x = b["offset"]
        shift = ", ".join(f"{DOFS[d]} {1e3 * x[d]:+.3f} mm" for d in range(3) if abs(x[d]) > 5e-7)
        turn = ", ".join(f"{DOFS[d]} {math.degrees(x[d]):+.4f} deg" for d in range(3, 6) if abs(x[d]) > 1e-8)
        lines.append(f"  {b['name']:<12}{b['mass']:>12.6g}{b['weight']:>13.6g}{b['buoyancy']:>13.6g}  "
                     f"{'; '.join(p for p in (shift, turn) if p) or 'none'}")
    for e in found.elements:
        if "tension" in e:
            lines.append(f"  {e['name']}: fairlead tension {e['tension']:.6g} N (horizontal {e['horizontal']:.6g}, "
                         f"vertical {e['vertical']:.6g})")
        elif "force" in e and abs(e["force"]) > 0:
            lines.append(f"  {e['name']}: {e['force']:.6g} N" + (" (tension)" if e["kind"] == "Rope" else ""))
    moved = [j for j in found.joints if any(abs(v) > 1e-8 for v in j["coordinates"])]
    for j in moved:
        lines.append(f"  joint {j['name']}: " + ", ".join(f"{v:.6g}" for v in j["coordinates"]))
    return "\n".join(lines)
