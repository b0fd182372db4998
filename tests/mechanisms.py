"""Test mechanisms built directly from the multibody library (no scenario file)."""

from __future__ import annotations

import numpy as np

from mbd_fmu.bodies import RigidBody
from mbd_fmu.force_elements import CoordinateSpringDamper
from mbd_fmu.joints import Joint
from mbd_fmu.kinematics import Pose
from mbd_fmu.model import MultibodyModel
from mbd_fmu.moorings import LinearMooring
from mbd_fmu.spec import coordinate

G = 9.81


def rod(name: str, cg, along, mass: float = 1.0, length: float = 1.0, dofs=(0, 1, 2, 3, 4, 5),
        spin: float = 1e-6) -> RigidBody:
    """Thin uniform rod: m L^2 / 12 about axes across it, ``spin m L^2`` along it (keeps M regular)."""
    u = np.asarray(along, float) / np.linalg.norm(along)
    inertia = mass * length**2 / 12 * (np.eye(3) - np.outer(u, u)) + spin * mass * length**2 * np.outer(u, u)
    return RigidBody(name, mass, inertia, np.asarray(cg, float), tuple(dofs))


def point_pendulum() -> tuple[MultibodyModel, Pose]:
    """Point mass m = 1 kg on a massless rod L = 1 m (distance joint), x-z plane, released horizontal."""
    b = RigidBody("m", 1.0, np.eye(3), [0.0, 0.0, -1.0], dofs=(0, 2), point_mass=True)
    j = Joint("rod", "distance", None, "m", position=(0, 0, 0), position2=(0, 0, -1))
    model = MultibodyModel([b], [j], gravity=(0, 0, -G))
    return model, Pose(np.array([[1.0, 0, 0]]), np.eye(3)[None])


def rod_pendulum() -> tuple[MultibodyModel, Pose]:
    """Uniform rod L = 1 m, m = 1 kg, revolute joint at its end about y, released horizontal."""
    b = rod("rod", [0, 0, -0.5], [0, 0, 1])
    j = Joint("pivot", "revolute", None, "rod", position=(0, 0, 0), axis=(0, 1, 0))
    model = MultibodyModel([b], [j], gravity=(0, 0, -G))
    from mbd_fmu.rotations import exp_so3

    rot = exp_so3(np.array([0, -np.pi / 2, 0]))  # hanging -z -> horizontal +x
    return model, Pose((rot @ np.array([0, 0, -0.5]))[None], rot[None])


def double_four_bar() -> tuple[MultibodyModel, Pose, np.ndarray]:
    """IFToMM double four-bar: five 1 m, 1 kg bars in the x-y plane, gravity -y, cranks vertical at t = 0,
    couplers moving at 1 m/s along +x. Returns the model, pose and slot velocities."""
    up, across = [0, 1.0, 0], [1.0, 0, 0]
    bodies = [rod(f"crank{i}", [i, 0.5, 0], up, dofs=(0, 1, 5)) for i in range(3)]
    bodies += [rod(f"coupler{i}", [i + 0.5, 1, 0], across, dofs=(0, 1, 5)) for i in range(2)]
    ax = (0, 0, 1)
    joints = [Joint(f"ground{i}", "revolute", None, f"crank{i}", (i, 0, 0), ax) for i in range(3)]
    for i in range(2):
        joints += [Joint(f"left{i}", "revolute", f"crank{i}", f"coupler{i}", (i, 1, 0), ax),
                   Joint(f"right{i}", "revolute", f"crank{i + 1}", f"coupler{i}", (i + 1, 1, 0), ax)]
    model = MultibodyModel(bodies, joints, gravity=(0, -G, 0))
    v6 = np.zeros((5, 6))
    v6[:3] = [0.5, 0, 0, 0, 0, -1.0]
    v6[3:] = [1.0, 0, 0, 0, 0, 0]
    v = np.array([v6[model.index(b), d] for b, d in model.coordinates])
    return model, model.reference.copy(), v


def crank_angles(model: MultibodyModel, pose: Pose) -> np.ndarray:
    """Angle of each crank (tip about its ground pivot) from +x."""
    out = []
    for i in range(3):
        b = model.index(f"crank{i}")
        tip = pose.r[b] + pose.R[b] @ np.array([0, 0.5, 0])
        out.append(np.arctan2(tip[1], tip[0] - i))
    return np.array(out)


def hexagon_loop(gravity: bool = False) -> tuple[MultibodyModel, Pose]:
    """Seed 000's hexagonal loop: three floating nodes and three link arms alternating, spherical
    joints at the arm ends; nodes held by linear 6x6 moorings (hydrostatic-like springs)."""
    radius, node_r = 1.6, 0.35
    centres = [radius * np.array([np.cos(a), np.sin(a), 0.0]) for a in np.radians([90, 210, 330])]
    bodies = [RigidBody(f"node{i}", 200.0, np.diag([30.0, 30.0, 20.0]), c - [0, 0, 0.3]) for i, c in enumerate(centres)]
    joints = []
    for i in range(3):
        j = (i + 1) % 3
        d = centres[j] - centres[i]
        u = d / np.linalg.norm(d)
        pi, pj = centres[i] + node_r * u - [0, 0, 0.3], centres[j] - node_r * u - [0, 0, 0.3]
        length = np.linalg.norm(pj - pi)
        bodies.append(rod(f"arm{i}", (pi + pj) / 2, u, mass=40.0, length=length, spin=0.01 / length**2))
        joints += [Joint(f"node{i}_arm{i}", "spherical", f"node{i}", f"arm{i}", tuple(pi)),
                   Joint(f"arm{i}_node{j}", "spherical", f"arm{i}", f"node{j}", tuple(pj))]
    model = MultibodyModel(bodies, joints, gravity=(0, 0, -G) if gravity else (0, 0, 0))
    k = np.diag([50.0, 50.0, 400.0, 40.0, 40.0, 20.0])  # natural periods 4-20 s, like a moored WEC
    model.elements = [LinearMooring(f"mooring{i}", i, k, None, model.cg[i].copy()) for i in range(3)]
    return model, model.reference.copy()


def bricard(length: float = 1.0, mass: float = 1.0) -> tuple[MultibodyModel, Pose]:
    """Orthogonal Bricard 6R linkage on the edges of a cube (five moving bars and the ground),
    consecutive joint axes perpendicular; Grubler count 0, true mobility 1."""
    L = length
    pts = L * np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1], [0, 0, 1]], float)
    axes = [(0, 1, 0), (0, 0, 1), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 0, 0)]
    # ground bar from pts[5] to pts[0]; moving bars k = 0..4 from pts[k] to pts[k+1]
    bodies = [rod(f"bar{k}", (pts[k] + pts[k + 1]) / 2, pts[k + 1] - pts[k], mass, L) for k in range(5)]
    joints = [Joint("j0", "revolute", None, "bar0", tuple(pts[0]), axes[0])]
    joints += [Joint(f"j{k + 1}", "revolute", f"bar{k}", f"bar{k + 1}", tuple(pts[k + 1]), axes[k + 1])
               for k in range(4)]
    joints += [Joint("j5", "revolute", None, "bar4", tuple(pts[5]), axes[5])]
    model = MultibodyModel(bodies, joints, gravity=(0, 0, -G))
    return model, model.reference.copy()


def two_hinge_beam(length: float = 4.0, cg_x: float = 1.5, mass: float = 300.0) -> MultibodyModel:
    """A beam on two spherical hinges (x = 0 and x = length) to the ground, cg on the hinge line."""
    beam = rod("beam", [cg_x, 0, 0], [1, 0, 0], mass, length)
    joints = [Joint("hinge_a", "spherical", None, "beam", (0, 0, 0)),
              Joint("hinge_b", "spherical", None, "beam", (length, 0, 0))]
    return MultibodyModel([beam], joints, gravity=(0, 0, -G))


def sliding_oscillator(k: float = 400.0, m: float = 4.0) -> tuple[MultibodyModel, CoordinateSpringDamper]:
    """A block on a vertical prismatic joint with a linear spring to the ground (conservative, linear)."""
    block = RigidBody("block", m, np.diag([1.0, 2.0, 3.0]), [0, 0, 0])
    j = Joint("slider", "prismatic", None, "block", (0, 0, 0), (0, 0, 1))
    model = MultibodyModel([block], [j], gravity=(0, 0, -G))
    spring = CoordinateSpringDamper("spring", coordinate(model, {"kind": "joint", "joint": "slider"}), k, 0.0)
    model.elements = [spring]
    return model, spring
