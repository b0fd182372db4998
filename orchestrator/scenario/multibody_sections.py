"""Scenario sections of the multibody model: formulation and integrator, joints, force elements, mooring
lines and drivers."""

from __future__ import annotations

from dataclasses import dataclass

from mbd_fmu.moordyn_lines import SCHEMES as MOORDYN_SCHEMES

from .body_sections import DOFS
from .schema import identifier, non_negative, option, positive

FORMULATIONS = ("auto", "linear", "index3", "index1", "nullspace")
INTEGRATORS = ("", "generalized_alpha", "rk4", "heun", "euler")
JOINT_KINDS = ("fixed", "revolute", "prismatic", "cylindrical", "universal", "spherical", "planar", "distance")
FORCE_KINDS = ("spring_damper", "rotary_spring_damper", "bushing", "rope", "mooring", "catenary", "friction")


@dataclass
class MultibodySection:
    """Multibody formulation and integrator."""

    formulation: str = option(
        "auto", choices=FORMULATIONS,
        doc="`linear` (small motions, exact step), `index3` (Lagrange multipliers, generalised-alpha), `index1` "
            "(acceleration level with projection, Runge-Kutta), `nullspace` (reduced ODE, Runge-Kutta); `auto`: "
            "`linear` without joints, forces, drivers, point masses or non-DOF PTOs, else `index3`")
    integrator: str = option("", choices=INTEGRATORS,
                             doc="default `generalized_alpha` for index3, `rk4` for index1 and nullspace")
    spectral_radius: float = option(0.8, check=lambda v: None if 0 <= v <= 1 else "must be in [0, 1]",
                                    doc="generalised-alpha spectral radius at infinite frequency (1: no numerical "
                                        "dissipation)")
    max_step: float = option(0.0, unit="s", check=non_negative,
                             doc="largest integrator step; 0 = one step per macro step")
    newton_tolerance: float = option(1e-10, check=positive, doc="Newton tolerance on positions (relative to "
                                                                 "max(1 m, largest cg coordinate))")
    restart: str = option(
        "consistent", choices=("consistent", "increment"),
        doc="generalised-alpha restart when the held inputs change at a macro step: `consistent` resets the "
            "algorithmic acceleration from the consistent acceleration and its derivative (one factorisation, "
            "two solves), `increment` adds the jump of the consistent acceleration (one solve); both second order "
            "(docs/multibody.md)")
    gravity: bool = option(True, doc="apply gravity at the centres of gravity and the bodies' buoyancy "
                                     "(nonlinear formulations)")
    static_equilibrium: bool = option(
        False, doc="find the static equilibrium (gravity, buoyancy, hydrostatic stiffness, moorings, tethers, "
                   "springs) before the run, report it, start the run from it (initial displacements are added) "
                   "and linearise the frequency domain about it (nonlinear formulations; docs/nenuphar.md)")


@dataclass
class JointSection:
    """A joint between two bodies or a body and the ground (nonlinear formulations)."""

    name: str = option(check=identifier, doc="joint name (used in FMU variable names)")
    kind: str = option(choices=JOINT_KINDS, doc="joint kind (see docs/multibody.md)")
    body2: str = option(doc="second body")
    position: tuple[float, float, float] = option(unit="m", doc="joint point (world, at equilibrium); for "
                                                                "`distance` the point on body1")
    body1: str = option("ground", doc="first body, or `ground`")
    axis: tuple[float, float, float] = option((0.0, 0.0, 1.0), doc="joint axis (revolute, prismatic, cylindrical), "
                                                                  "plane normal (planar), first axis (universal)")
    axis2: list[float] = option(factory=list, doc="universal: the cross axis on body2; others: x axis of the joint "
                                                 "frame (optional)")
    position2: list[float] = option(factory=list, unit="m", doc="distance joint: the point on body2")
    locked: bool = option(False, doc="hold the joint fixed at the bodies' initial relative pose")


@dataclass
class ForceSection:
    """A force element (nonlinear formulations)."""

    name: str = option(check=identifier, doc="element name (used in FMU variable names)")
    kind: str = option(choices=FORCE_KINDS, doc="element kind (see docs/multibody.md)")
    body: str = option("", doc="body of a mooring or catenary line")
    body1: str = option("ground", doc="first body (spring_damper, rope, bushing), or `ground`")
    body2: str = option("", doc="second body (spring_damper, rope, bushing)")
    point1: list[float] = option(factory=list, unit="m", doc="attachment on body1 (world, at equilibrium)")
    point2: list[float] = option(factory=list, unit="m", doc="attachment on body2 (world, at equilibrium)")
    joint: str = option("", doc="joint of a rotary_spring_damper or friction element")
    stiffness: float = option(0.0, unit="N/m or N m/rad", check=non_negative, doc="scalar stiffness")
    damping: float = option(0.0, unit="N s/m or N m s/rad", check=non_negative, doc="scalar damping")
    free_length: float | None = option(None, unit="m", check=non_negative,
                                       doc="spring/rope free length; default the length at equilibrium")
    stiffness_matrix: list[float] = option(factory=list, doc="bushing: 6 stiffnesses on relative surge..yaw; "
                                                           "mooring: 6 (diagonal) or 36 values (row-major)")
    damping_matrix: list[float] = option(factory=list, doc="as stiffness_matrix, for damping")
    position: list[float] = option(factory=list, unit="m", doc="bushing frame origin (world)")
    fairlead: list[float] = option(factory=list, unit="m", doc="catenary: fairlead on the body (world, equilibrium)")
    anchor: list[float] = option(factory=list, unit="m", doc="catenary: anchor on the sea bed (world)")
    length: float = option(0.0, unit="m", check=non_negative, doc="catenary: unstretched length")
    weight: float = option(0.0, unit="N/m", check=non_negative, doc="catenary: submerged weight per length")
    ea: float = option(0.0, unit="N", check=non_negative, doc="catenary: axial stiffness")
    diameter: float = option(0.0, unit="m", check=non_negative,
                             doc="catenary with MoorDyn: volume-equivalent line diameter (buoyancy, drag, added mass; "
                                 "the mass per length is weight / g + rho pi diameter^2 / 4)")
    segments: int = option(20, check=positive, doc="catenary with MoorDyn: number of lumped-mass segments")
    drag_normal: float = option(1.2, check=non_negative, doc="catenary with MoorDyn: normal drag coefficient")
    drag_axial: float = option(0.4, check=non_negative, doc="catenary with MoorDyn: axial drag coefficient")
    added_mass_normal: float = option(1.0, check=non_negative,
                                      doc="catenary with MoorDyn: normal added-mass coefficient")
    added_mass_axial: float = option(0.0, check=non_negative, doc="catenary with MoorDyn: axial added-mass coefficient")
    internal_damping: float = option(0.8, check=non_negative,
                                     doc="catenary with MoorDyn: axial damping of each segment, fraction of critical")
    force: float = option(0.0, unit="N or N m", check=non_negative, doc="friction: Coulomb force or torque")
    velocity: float = option(1e-3, unit="m/s or rad/s", check=positive, doc="friction: regularisation velocity")


MOORING_MODELS = ("quasi_static", "moordyn")


@dataclass
class MooringLinesSection:
    """How the scene's mooring lines are computed: its `catenary` forces, or a MoorDyn input file (docs/scenarios.md,
    RM3)."""

    model: str = option(
        "quasi_static", choices=MOORING_MODELS,
        doc="`quasi_static`: the elastic catenary with sea-bed contact solved at every evaluation (cheap, no line "
            "dynamics); `moordyn`: MoorDyn's lumped-mass line dynamics (drag, added mass and inertia of the lines) "
            "stepped inside the multibody FMU, its state saved with the FMU state. The frequency-domain and "
            "steady-state solvers always use the quasi-static lines")
    time_step: float = option(0.001, unit="s", check=positive,
                              doc="MoorDyn's own step dtM (sub-cycled within each multibody step); must stay below "
                                  "each line's axial Courant limit, segment length / sqrt(EA / mass per length)")
    scheme: str = option("RK2", choices=MOORDYN_SCHEMES,
                         doc="MoorDyn's time scheme (explicit; RK2 is MoorDyn's default)")
    seabed_stiffness: float = option(3.0e6, unit="Pa/m", check=positive,
                                     doc="MoorDyn's sea-bed contact stiffness per unit area (the sea bed is at the "
                                         "anchors' depth)")
    seabed_damping: float = option(3.0e5, unit="Pa s/m", check=non_negative,
                                   doc="MoorDyn's sea-bed contact damping per unit area")
    ic_time: float = option(60.0, unit="s", check=positive,
                            doc="longest dynamic relaxation of MoorDyn's initial line shapes")
    ic_tolerance: float = option(1e-3, unit="m/s^2", check=positive,
                                 doc="the relaxation stops when the largest node acceleration is below this")
    moordyn_file: str = option(
        "", doc="a MoorDyn v2 input file used as it is (relative to the scenario file): its lines, points (anchors, "
                "buoys, clump weights, line-to-line joints), rods, sea bed and solver options (dtM, kBot, cBot, the "
                "initial-condition settings) all from the file, rho and g from [environment]; its Coupled points "
                "move with the bodies named in `coupled_bodies`. MoorDyn's own output files are off: the results "
                "file records each coupled point's force (`/mooring/point<ID>/force`) and the tension at both ends "
                "of every line (`/mooring/line<ID>/tension`). With model = `quasi_static` (and in the frequency "
                "domain) the lines are their linearised stiffness from MoorDyn's static solves of the file. The "
                "keys above (time_step ... ic_tolerance) apply to `catenary` forces only")
    coupled_bodies: list[str] = option(
        factory=list, doc="with `moordyn_file`: the body each Coupled point of the file is attached to, in the "
                          "order of the points' IDs (their positions in the file are world coordinates at "
                          "equilibrium)")


@dataclass
class DriverSection:
    """Prescribed motion of a joint coordinate or a body DOF (nonlinear formulations)."""

    name: str = option(check=identifier, doc="driver name")
    joint: str = option("", doc="joint whose (first) coordinate is prescribed")
    body: str = option("", doc="or: body whose DOF `dof` is prescribed (displacement from equilibrium)")
    dof: str = option("", choices=("",) + DOFS, doc="body DOF")
    level: str = option("position", choices=("position", "velocity"), doc="prescribe the position or the velocity")
    function: str = option("harmonic", choices=("harmonic", "table"), doc="`harmonic`: offset + amplitude "
                                                                        "sin(2 pi t / period + phase); `table`")
    amplitude: float = option(0.0, doc="harmonic amplitude (m, rad, m/s or rad/s)")
    period: float = option(0.0, unit="s", check=non_negative, doc="harmonic period (0: constant)")
    phase_deg: float = option(0.0, unit="deg", doc="harmonic phase")
    offset: float = option(0.0, doc="harmonic offset")
    times: list[float] = option(factory=list, unit="s", doc="table times (cubic spline)")
    values: list[float] = option(factory=list, doc="table values")
