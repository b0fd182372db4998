"""Scenario sections of the bodies and their power take-offs: geometry, mass properties, active degrees of
freedom, PTO laws."""

from __future__ import annotations

from dataclasses import dataclass, field

from .schema import identifier, non_negative, option, positive

DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")
SHAPES = ("vertical_cylinder", "sphere", "box", "regular_prism", "axisymmetric", "mesh")
def _six(value: list[float] | None) -> str | None:
    return None if value is None or len(value) == 6 else "needs 6 values (surge, sway, heave, roll, pitch, yaw)"


@dataclass
class GeometrySection:
    """Wetted shape of a body for the BEM solver."""

    shape: str = option(choices=SHAPES, doc="primitive or mesh file")
    radius: float = option(0.0, unit="m", check=non_negative,
                           doc="cylinder or sphere radius; regular_prism: axis to corner")
    draft: float = option(0.0, unit="m", check=non_negative,
                          doc="cylinder or regular_prism draft (immersed length; the freeboard is the same)")
    sides: int = option(0, check=non_negative, doc="regular_prism: number of sides (a flat side faces +x)")
    size: tuple[float, float, float] = option((0.0, 0.0, 0.0), unit="m", check=non_negative,
                                              doc="box length, width, height")
    mesh_file: str = option("", doc="mesh file (.obj, .stl, .gdf, ...), relative to the scenario file")
    profile: list[tuple[float, float]] = option(
        factory=list, unit="m",
        doc="axisymmetric: [r, z] points of the hull's cross-section in a meridian half-plane, in order along the "
            "surface (e.g. an annular float: outer wall from above the waterline down, bottom inwards, inner wall "
            "up), revolved about the shape's vertical axis; faceted so that volumes and waterplane areas are exact")
    dry_segments: list[int] = option(
        factory=list,
        doc="axisymmetric: indices (0 = first) of profile segments in contact with another body, e.g. a float's "
            "bore on a spar's column: they close the body for its hydrostatics but are not wetted (left out of "
            "the BEM mesh); give the neighbour's hull there as dry too (no water gap)")
    position: tuple[float, float, float] = option(
        (0.0, 0.0, 0.0), unit="m",
        doc="world position of the shape's origin (cylinder, regular_prism: axis at the waterline; sphere, box: "
            "centre; axisymmetric: the profile's r = 0, z = 0; mesh: the file's origin)")
    rotation_deg: tuple[float, float, float] = option(
        (0.0, 0.0, 0.0), unit="deg",
        doc="rotation of the shape about its origin: about the fixed x, then y, then z axis")
    panel_size: float = option(0.5, unit="m", check=positive, doc="target panel size of primitive meshes")
    lid: bool = option(True, doc="lid on the waterplane against irregular frequencies (surface-piercing bodies)")


@dataclass
class BodySection:
    """A rigid body."""

    name: str = option(check=identifier, doc="body name (used in FMU variable names)")
    cg: tuple[float, float, float] = option(unit="m", doc="centre of gravity at equilibrium (world frame)")
    mass: float | None = option(None, unit="kg", check=positive,
                                doc="mass; default the displaced mass rho*V (freely floating)")
    inertia: list[float] | None = option(
        None, unit="kg m^2", check=None,
        doc="inertia about the cg: [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]; required for rotations")
    dofs: list[str] = option(factory=lambda: list(DOFS), choices=DOFS, doc="active degrees of freedom")
    hydro: bool = option(True, doc="the body has hydrodynamic forces")
    geometry: GeometrySection | None = field(default=None, metadata={"doc": "shape for the BEM solver"})
    linear_damping: list[float] | None = option(
        None, unit="N s/m, N m s/rad", check=_six, doc="viscous linear damping per degree of freedom (6 values)")
    drag_coefficient: list[float] | None = option(
        None, check=_six, doc="quadratic drag coefficient Cd per degree of freedom (6 values): F = -rho Cd A |v| v / 2")
    drag_area: list[float] | None = option(
        None, unit="m^2, m^5", check=_six,
        doc="drag area per degree of freedom (6 values; for rotations area times lever arm cubed)")
    initial_displacement: list[float] = option(
        factory=lambda: [0.0] * 6, unit="m, rad", doc="initial displacement from equilibrium (6 values)")
    initial_velocity: list[float] = option(
        factory=lambda: [0.0] * 6, unit="m/s, rad/s", doc="initial velocity (6 values)")
    point_mass: bool = option(False, doc="a 3-DOF point mass (translations only; nonlinear formulations)")
    buoyancy: float | None = option(
        None, unit="N", check=non_negative,
        doc="constant upward force at the cg in nonlinear formulations; default rho g V (with the moment of "
            "the centre of buoyancy) for hydrodynamic bodies, 0 for the others (e.g. m g for a neutrally "
            "buoyant link arm)")


@dataclass
class PtoSection:
    """Power take-off: a body DOF to the ground (default), a joint coordinate, two points, or a relative DOF."""

    name: str = option(check=identifier, doc="PTO name (used in FMU variable names)")
    body: str = option(doc="body the PTO acts on")
    dof: str = option("", choices=("",) + DOFS,
                      doc="degree of freedom it acts on (body DOF to the ground, or relative DOF with `body2`)")
    stiffness: float = option(0.0, unit="N/m or N m/rad", check=non_negative, doc="spring stiffness")
    damping: float = option(0.0, unit="N s/m or N m s/rad", check=non_negative, doc="damping (power absorption)")
    joint: str = option("", doc="act on this joint's coordinate (revolute angle, prismatic displacement) "
                                "instead of a body DOF (nonlinear formulations)")
    joint_coordinate: int = option(1, check=lambda v: None if v >= 1 else "must be 1 or more",
                                   doc="with `joint`: which of the joint's coordinates (1-based, as the FMU's "
                                       "`<joint>.coordinate[k]`; spherical and universal joints: 1, 2, 3 = relative "
                                       "roll, pitch, yaw about the joint frame's x, y, z)")
    body2: str = option("", doc="second body: with `point`/`point2` a point-to-point PTO, otherwise the PTO acts "
                                "on the relative `dof` of `body2` with respect to `body` at `position`")
    point: list[float] = option(factory=list, unit="m", doc="attachment point on `body` (world, at equilibrium)")
    point2: list[float] = option(factory=list, unit="m",
                                 doc="attachment point on `body2` or on the ground (world, at equilibrium)")
    position: list[float] = option(factory=list, unit="m", doc="origin of the relative-DOF frame (world)")
    friction_force: float = option(0.0, unit="N or N m", check=non_negative,
                                   doc="nonlinear law: regularised Coulomb force F_c tanh(v / velocity_scale) "
                                       "opposing the rate (with quadratic_damping: a hydraulic-like PTO)")
    quadratic_damping: float = option(0.0, unit="N s^2/m^2 or N m s^2/rad^2", check=non_negative,
                                      doc="nonlinear law: quadratic damping c_q |v| v (orifice losses)")
    force_limit: float = option(0.0, unit="N or N m", check=non_negative,
                                doc="nonlinear law: smooth saturation F_max tanh(F / F_max) of the total force; "
                                    "0 = none")
    velocity_scale: float = option(0.01, unit="m/s or rad/s", check=positive,
                                   doc="regularisation velocity of friction_force")

    @property
    def nonlinear(self) -> bool:
        """The PTO has a nonlinear law (needs a nonlinear multibody formulation)."""
        return bool(self.friction_force or self.quadratic_damping or self.force_limit)
