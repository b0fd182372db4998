"""Build a multibody model from the scene specification (the JSON the FMU carries).

The same function serves the FMU slave and the orchestrator (frequency-domain linearisation),
so both see one model. Keys (all SI, world frame at equilibrium; written by
``orchestrator.scene.Scene.mbd_spec``): ``bodies`` (name, mass, inertia, cg, dofs, x0, v0,
point_mass, static_load), ``joints``, ``forces``, ``drivers``, ``ptos``, ``gravity``,
``multibody`` (formulation, integrator, spectral_radius, max_step, newton_tolerance, restart),
``moordyn`` (MoorDyn's solver options, for ``catenary`` forces with ``model = "moordyn"``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .assembly import MobilityReport, analyse, assemble, check_start
from .bodies import RigidBody
from .coordinates import Coordinate, Distance, RotationComponent, Slide
from .force_elements import CoordinateSpringDamper, CoulombFriction, ForceElement, PtoLaw, Rope
from .formulations import Settings
from .joints import Driver, Harmonic, Joint, Table, TimeFunction
from .kinematics import Pose
from .model import MultibodyModel
from .moordyn_lines import LineSpec, MoorDynLine, MoorDynSettings, MoorDynSystem, MoorDynTensions
from .moorings import CatenaryLine, LinearMooring
from .simulator import MultibodySimulator

DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")


def bodies_from_spec(spec: dict[str, Any]) -> list[RigidBody]:
    return [RigidBody(b["name"], float(b["mass"]), np.asarray(b["inertia"], float), np.asarray(b["cg"], float),
                      tuple(b["dofs"]), bool(b.get("point_mass", False))) for b in spec["bodies"]]


def initial_pose(spec: dict[str, Any]) -> tuple[Pose, np.ndarray]:
    """Start pose (x0: translation, rotation vector) and full 6-per-body velocity."""
    from .rotations import exp_so3

    x0 = np.array([b["x0"] for b in spec["bodies"]], float).reshape(-1, 6)
    v0 = np.array([b["v0"] for b in spec["bodies"]], float).reshape(-1, 6)
    cg = np.array([b["cg"] for b in spec["bodies"]], float).reshape(-1, 3)
    return Pose(cg + x0[:, :3], exp_so3(x0[:, 3:])), v0


def coordinate(model: MultibodyModel, d: dict[str, Any]) -> Coordinate:
    """A scalar coordinate from its description (``kind``: body, joint, points, relative)."""
    kind = d["kind"]
    if kind == "body":
        b, dof = model.index(d["body"]), int(d["dof"])
        if dof < 3:
            return Slide(model.ground, b, np.eye(3)[dof], model.cg[b].copy(), np.zeros(3))
        return RotationComponent(model.ground, b, np.eye(3), np.eye(3), dof - 3)
    if kind == "joint":
        cj = next(j for j in model.joints if j.joint.name == d["joint"])
        return cj.coordinates[int(d.get("index", 0))]
    if kind == "points":
        m1 = model.marker(d.get("body1"), d["point1"], np.eye(3))
        m2 = model.marker(d.get("body2"), d["point2"], np.eye(3))
        return Distance(m1.body, m2.body, m1.offset, m2.offset)
    if kind == "relative":
        m1 = model.marker(d.get("body1"), d["position"], np.eye(3))
        m2 = model.marker(d.get("body2"), d["position"], np.eye(3))
        dof = int(d["dof"])
        if dof < 3:
            return Slide(m1.body, m2.body, np.eye(3)[dof], m1.offset, m2.offset)
        return RotationComponent(m1.body, m2.body, np.eye(3), np.eye(3), dof - 3)
    raise ValueError(f"unknown coordinate kind {kind!r}")


def time_function(d: dict[str, Any]) -> TimeFunction:
    if d["kind"] == "harmonic":
        omega = 2 * math.pi / d["period"] if d.get("period", 0) > 0 else 0.0
        return Harmonic(d.get("amplitude", 0.0), omega, d.get("phase", 0.0), d.get("offset", 0.0))
    if d["kind"] == "table":
        return Table(d["times"], d["values"])
    raise ValueError(f"unknown function kind {d['kind']!r}")


def _neutral(model: MultibodyModel, coord: Coordinate, pose: Pose) -> float:
    return coord.evaluate(model.kin(pose, np.zeros(model.n)))[0]


def moordyn_lines(model: MultibodyModel, spec: dict[str, Any]) -> dict[str, ForceElement]:
    """The ``catenary`` forces with ``model = "moordyn"`` as lines of one :class:`MoorDynSystem`, by name; or, with a
    MoorDyn input file (``spec["moordyn_file"]``), its coupled points (``moordyn_point`` forces) and its lines' end
    tensions (the ``moordyn_tensions`` output)."""
    if spec.get("moordyn_file"):
        return moordyn_file_elements(model, spec)
    entries = [d for d in spec.get("forces", []) if d["kind"] == "catenary" and d.get("model") == "moordyn"]
    if not entries:
        return {}
    lines = []
    for d in entries:
        b = model.index(d["body"])
        lines.append(LineSpec(d["name"], b, np.asarray(d["fairlead"], float) - model.cg[b],
                              np.asarray(d["anchor"], float), d["length"], d["weight"], d["ea"], d["diameter"],
                              d["drag_normal"], d["drag_axial"], d["added_mass_normal"], d["added_mass_axial"],
                              int(d["segments"]), d["internal_damping"]))
    system = MoorDynSystem(lines, MoorDynSettings(**spec["moordyn"]))
    return {d["name"]: MoorDynLine(d["name"], system, i) for i, d in enumerate(entries)}


def moordyn_file_elements(model: MultibodyModel, spec: dict[str, Any]) -> dict[str, ForceElement]:
    """A MoorDyn input file's coupled points as force elements on their bodies and the lines' end tensions."""
    m = spec["moordyn_file"]
    points = [d for d in spec.get("forces", []) if d["kind"] == "moordyn_point"]
    bodies = np.array([model.index(d["body"]) for d in points], dtype=int)
    offsets = np.array([np.asarray(d["position"], float) - model.cg[b] for d, b in zip(points, bodies, strict=True)])
    system = MoorDynSystem([], MoorDynSettings(**spec["moordyn"]), file_text=m["text"], bodies=bodies,
                           offsets=offsets)
    out: dict[str, ForceElement] = {d["name"]: MoorDynLine(d["name"], system, i) for i, d in enumerate(points)}
    for d in spec.get("forces", []):
        if d["kind"] == "moordyn_tensions":
            out[d["name"]] = MoorDynTensions(d["name"], system, int(d["lines"]))
    return out


def force_element(model: MultibodyModel, d: dict[str, Any],
                  dynamic_lines: dict[str, MoorDynLine] | None = None) -> list[ForceElement]:
    kind, name = d["kind"], d["name"]
    ref = model.reference
    if kind in ("spring_damper", "rotary_spring_damper", "rope"):
        desc = ({"kind": "points", "body1": d.get("body1"), "point1": d["point1"], "body2": d.get("body2"),
                 "point2": d["point2"]} if kind != "rotary_spring_damper"
                else {"kind": "joint", "joint": d["joint"], "index": d.get("index", 0)})
        c = coordinate(model, desc)
        neutral = d.get("free_length") if kind != "rotary_spring_damper" else d.get("neutral_angle")
        if neutral is None:
            neutral = _neutral(model, c, ref)
        if kind == "rope":
            return [Rope(name, c, d["stiffness"], d.get("damping", 0.0), neutral)]
        return [CoordinateSpringDamper(name, c, d.get("stiffness", 0.0), d.get("damping", 0.0), 0.0, neutral)]
    if kind == "bushing":
        out = []
        for dof in range(6):
            k, c = d["stiffness"][dof], d["damping"][dof]
            if k or c:
                coord = coordinate(model, {"kind": "relative", "body1": d.get("body1"), "body2": d["body2"],
                                           "position": d["position"], "dof": dof})
                out.append(CoordinateSpringDamper(f"{name}.{DOFS[dof]}", coord, k, c, 0.0, 0.0))
        return out
    if kind == "mooring":
        b = model.index(d["body"])
        damping = np.asarray(d["damping"], float).reshape(6, 6) if d.get("damping") is not None else None
        return [LinearMooring(name, b, np.asarray(d["stiffness"], float).reshape(6, 6), damping, model.cg[b].copy())]
    if kind == "catenary" and d.get("model", "quasi_static") == "moordyn" or kind in ("moordyn_point",
                                                                                          "moordyn_tensions"):
        return [dynamic_lines[name]]
    if kind == "catenary":
        b = model.index(d["body"])
        return [CatenaryLine(name, b, np.asarray(d["fairlead"], float) - model.cg[b], np.asarray(d["anchor"], float),
                             d["length"], d["weight"], d["ea"])]
    if kind == "friction":
        c = coordinate(model, {"kind": "joint", "joint": d["joint"], "index": d.get("index", 0)})
        return [CoulombFriction(name, c, d["force"], d.get("velocity", 1e-3))]
    raise ValueError(f"unknown force element kind {kind!r}")


def pto_element(model: MultibodyModel, p: dict[str, Any]) -> CoordinateSpringDamper:
    c = coordinate(model, p["coordinate"])
    neutral = _neutral(model, c, model.reference)
    law = PtoLaw(p.get("friction_force", 0.0), p.get("quadratic_damping", 0.0), p.get("force_limit", 0.0),
                 p.get("velocity_scale", 0.01))
    return CoordinateSpringDamper(p["name"], c, p.get("stiffness", 0.0), p.get("damping", 0.0),
                                  p.get("force_command", 0.0), neutral, law)


def build_model(spec: dict[str, Any], added_mass: np.ndarray | None = None) -> tuple[MultibodyModel, list]:
    """The nonlinear model of ``spec`` and its PTO elements (which are also in ``model.elements``)."""
    bodies = bodies_from_spec(spec)
    pose, _ = initial_pose(spec)
    joints = [Joint(j["name"], j["kind"], j.get("body1"), j["body2"], tuple(j["position"]), tuple(j["axis"]),
                    tuple(j["axis2"]) if j.get("axis2") else None,
                    tuple(j["position2"]) if j.get("position2") else None, bool(j.get("locked", False)))
              for j in spec.get("joints", [])]
    static = {b["name"]: np.asarray(b.get("static_load", [0.0] * 6), float) for b in spec["bodies"]}
    coords = [tuple(c) for c in spec.get("hydro_coordinates", [])]
    model = MultibodyModel(bodies, joints, gravity=spec.get("gravity", (0.0, 0.0, 0.0)), static_loads=static,
                           added_mass=added_mass, added_mass_coordinates=coords if added_mass is not None else None,
                           initial_pose=pose)
    elements: list[ForceElement] = []
    dynamic = moordyn_lines(model, spec)
    for d in spec.get("forces", []):
        elements += force_element(model, d, dynamic)
    ptos = [pto_element(model, p) for p in spec.get("ptos", [])]
    model.elements = elements + ptos
    for d in spec.get("drivers", []):
        c = coordinate(model, d["coordinate"])
        f = time_function(d["function"])
        if d.get("level", "position") == "velocity":
            f = f.integral(0.0, _neutral(model, c, pose))
        model.drivers.append(Driver(d["name"], c, f))
    model.m = model.m_primitive + len(model.drivers)
    model.kept = np.arange(model.m)
    return model, ptos


def mobility_report(spec: dict[str, Any]) -> MobilityReport:
    """DOF count and redundant constraint rows at the assembled start pose: what
    :meth:`MultibodySimulator.start` reports, without initialising the integrator (no consistent acceleration, no
    compiled kernel)."""
    model, _ = build_model(spec)
    pose, v6 = initial_pose(spec)
    v = np.array([v6[model.index(b), d] for b, d in model.coordinates])
    given = pose
    pose, _, _ = assemble(model, pose, v, 0.0)
    note = check_start(model, given, pose, 0.0)
    report = analyse(model, pose, 0.0)
    report.note = note
    return report


def build_simulator(spec: dict[str, Any], added_mass: np.ndarray | None = None) -> MultibodySimulator:
    mb = spec.get("multibody", {})
    model, ptos = build_model(spec, added_mass)
    settings = Settings(mb.get("formulation", "index3"), mb.get("integrator", ""), mb.get("spectral_radius", 0.8),
                        mb.get("newton_tolerance", 1e-10), restart=mb.get("restart", "consistent"))
    sim = MultibodySimulator(model, settings, mb.get("max_step", 0.0), ptos)
    pose, v6 = initial_pose(spec)
    v = np.array([v6[model.index(b), d] for b, d in model.coordinates])
    sim.start(pose, v, 0.0)
    return sim
