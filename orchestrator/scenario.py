"""Scenario files (TOML): schema, loading and validation.

One scenario file describes a scene (bodies, PTOs, waves, environment, hydrodynamics) and how
to run it. The same file drives ``wec-cosim run`` (time domain), ``wec-cosim rao`` (frequency
domain), ``wec-cosim hydro`` (database) and ``wec-cosim build-fmus``. Every key, unit and
default is in ``docs/scenario.md``, generated from this module (``python -m orchestrator.scenario``).
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from hydro_fmu.bem_symmetry import symmetry_error
from mbd_fmu.moordyn_lines import SCHEMES as MOORDYN_SCHEMES

from . import input_checks, schema
from .errors import ScenarioError
from .schema import identifier, non_negative, option, positive

DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")
SHAPES = ("vertical_cylinder", "sphere", "box", "regular_prism", "axisymmetric", "mesh")
FORMULATIONS = ("auto", "linear", "index3", "index1", "nullspace")
INTEGRATORS = ("", "generalized_alpha", "rk4", "heun", "euler")
JOINT_KINDS = ("fixed", "revolute", "prismatic", "cylindrical", "universal", "spherical", "planar", "distance")
FORCE_KINDS = ("spring_damper", "rotary_spring_damper", "bushing", "rope", "mooring", "catenary", "friction")


def _at_least_one(value: float) -> str | None:
    return None if value >= 1 else "must be at least 1"


def _fraction(value: float) -> str | None:
    return None if 0 < value < 1 else "must be between 0 and 1"


def _six(value: list[float] | None) -> str | None:
    return None if value is None or len(value) == 6 else "needs 6 values (surge, sway, heave, roll, pitch, yaw)"


def _order(value: int) -> str | None:
    return None if value in (0, 1, 2) else "must be 0, 1 or 2"


MASTERS = ("jacobi", "gauss_seidel", "aitken", "iqn_ils", "monolithic")
ADDED_MASS = ("mass_matrix", "explicit_force", "interface")


@dataclass
class AdaptiveSection:
    """Energy-based adaptive macro step (ECCO idea); `simulation.step` is then the smallest step."""

    enabled: bool = option(False, doc="adapt the macro step to the power mismatch on the force/velocity bonds")
    max_step: float = option(1.0, unit="s", check=positive,
                             doc="largest macro step; steps are whole multiples of `simulation.step` "
                                 "(the hydro FMU's radiation grid)")
    tolerance: float = option(
        0.01, check=positive,
        doc="largest energy mismatch over a step on any bond, relative to the energy flowing through the bond "
            "in that step")
    safety: float = option(0.8, check=positive, doc="safety factor of the step-size controller (< 1)")
    max_growth: float = option(2.0, check=positive, doc="largest ratio of two consecutive steps (> 1)")


@dataclass
class SimulationSection:
    """Time-domain co-simulation settings."""

    duration: float = option(unit="s", doc="simulated time (a whole number of steps)", check=positive)
    step: float = option(unit="s", doc="macro (communication) step of the master; with `[simulation.adaptive]` the "
                                       "smallest step and the radiation grid", check=positive)
    master: str = option(
        "jacobi", choices=MASTERS,
        doc="`jacobi`, `gauss_seidel`, `aitken` (iterative, fixed point with Aitken relaxation), `iqn_ils` "
            "(iterative, interface quasi-Newton) or `monolithic` (same physics in one process, no FMI)")
    extrapolation: int = option(
        2, check=_order,
        doc="degree of the polynomial that gives the multibody FMU's force input over a step, averaged over the "
            "step: extrapolated from past values (jacobi) or interpolated through the end value (gauss_seidel, "
            "iterative); 0 = hold")
    resolve_feedthrough: bool = option(
        True,
        doc="jacobi: set the motion at each communication point into the hydro FMU before reading its force; "
            "`false` reads every output right after the step, as generic FMI hosts do (fmpy's SSP simulator, "
            "libcosim fixedStep; first order, needs extrapolation = 0)")
    interface: str = option(
        "force", choices=("force", "linearised"),
        doc="what the hydro FMU hands the multibody FMU: `force`, the force (held or extrapolated by the master); "
            "`linearised`, the affine model F0 + F0_rate (t - t_n) + dF_dx x + dF_dv v that the multibody FMU "
            "integrates implicitly (second order and stable under any fixed-step host, the coupling `export-ssp` "
            "writes; jacobi with extrapolation = 0 only: the model carries its own time rate)")
    added_mass: str = option(
        "mass_matrix", choices=ADDED_MASS,
        doc="`mass_matrix`: A_inf in the multibody mass matrix (stable, default); `explicit_force`: A_inf applied "
            "as a force from the previous step's acceleration (unstable when A_inf > mass; a demonstration); "
            "`interface`: a third-party-style multibody FMU without A_inf, the added-mass force solved within "
            "each step (needs an iterative master)")
    tolerance: float = option(1e-10, check=positive,
                              doc="iterative masters: largest interface residual relative to each variable's "
                                  "running maximum")
    max_iterations: int = option(50, check=positive, doc="iterative masters: iteration cap per step")
    relaxation: float = option(0.5, check=positive,
                               doc="iterative masters: first relaxation factor (Aitken's start, IQN-ILS's first "
                                   "update)")
    iqn_reuse: int = option(4, check=non_negative, doc="IQN-ILS: previous steps whose secant data are reused")
    divergence_limit: float = option(
        1.0e8, check=positive,
        doc="an exchanged or recorded value larger than this times its scale in the scene stops the run as "
            "diverged; the scale is the larger of 1 and the value at the start (SI units), for energies also the "
            "bodies' weight and static loads times 1 m")
    adaptive: AdaptiveSection = field(default_factory=AdaptiveSection,
                                      metadata={"doc": "energy-based adaptive step"})
    output: str = option("", doc="results file (HDF5); default `results/<name>.h5` in the working directory")
    output_every: int = option(1, check=positive, doc="record every n-th macro step")
    flush_seconds: float = option(2.0, unit="s", check=positive,
                                  doc="longest wall time between two writes of the results file to disk")
    checkpoint_every: float = option(
        0.0, unit="s", check=non_negative,
        doc="simulated time between checkpoints of all FMU states (`<output>.checkpoint.h5`, for "
            "`wec-cosim resume`); 0 = none")
    steady_periods: float = option(
        10.0, check=positive,
        doc="number of wave periods at the end of the run used for the steady-state amplitude, phase and power")

    @property
    def iterative(self) -> bool:
        return self.master in ("aitken", "iqn_ils")


@dataclass
class EnvironmentSection:
    """Water and gravity."""

    rho: float = option(1025.0, unit="kg/m^3", check=positive, doc="water density")
    g: float = option(9.81, unit="m/s^2", check=positive, doc="gravitational acceleration")
    water_depth: float = option(math.inf, unit="m", check=positive, allow_inf=True,
                                doc="water depth; `inf` for deep water")


@dataclass
class WavesSection:
    """Incident waves."""

    kind: str = option("regular", choices=("regular", "still", "irregular", "elevation"),
                       doc="`regular` wave, `still` water, `irregular` sea from a spectrum, or an imported "
                           "`elevation` record")
    height: float = option(0.0, unit="m", check=non_negative, doc="regular wave height, crest to trough")
    period: float = option(0.0, unit="s", check=non_negative, doc="regular wave period")
    phase_deg: float = option(0.0, unit="deg", doc="phase of the elevation at the world origin")
    heading_deg: float = option(0.0, unit="deg", doc="direction of propagation, 0 = towards +x (main direction "
                                                     "of a spread sea)")
    ramp_time: float | None = option(
        None, unit="s", check=non_negative,
        doc="duration of the half-cosine start-up ramp; default three wave periods (regular), three peak "
            "periods (irregular), none (elevation record)")
    spectrum: str = option("jonswap", choices=("jonswap", "pierson_moskowitz", "bretschneider", "file"),
                           doc="irregular sea spectrum; `pierson_moskowitz` without `tp` is the fully developed "
                               "sea of height `hs`; `file` reads `spectrum_file`")
    hs: float = option(0.0, unit="m", check=non_negative, doc="significant wave height (irregular)")
    tp: float = option(0.0, unit="s", check=non_negative, doc="peak period (irregular)")
    gamma: float = option(3.3, check=_at_least_one, doc="JONSWAP peak enhancement factor")
    spectrum_file: str = option("", doc="CSV spectrum with a header `omega,S` (rad/s, m^2 s/rad) or `f,S` "
                                        "(Hz, m^2/Hz), relative to the scenario file")
    discretisation: str = option("equal_frequency", choices=("equal_frequency", "equal_energy"),
                                 doc="how the spectrum is split into components")
    repeat_period: float = option(
        0.0, unit="s", check=non_negative,
        doc="equal frequency: the sea repeats after this time (frequency step 2 pi / repeat_period); "
            "default the simulated duration")
    n_components: int = option(200, check=positive, doc="equal energy: number of components")
    omega_min: float = option(0.0, unit="rad/s", check=non_negative,
                              doc="lowest component frequency; default 0.5 omega_p (file: the table's)")
    omega_max: float = option(
        0.0, unit="rad/s", check=non_negative,
        doc="highest component frequency; default 6 omega_p (file: the table's; elevation record: no cut)")
    seed: int = option(1, check=non_negative, doc="seed of the random phases (same seed, same sea)")
    spreading_s: float = option(0.0, check=non_negative,
                                doc="cos-2s directional spreading exponent; 0 = unidirectional")
    n_directions: int = option(1, check=positive, doc="number of directions of a spread sea")
    elevation_file: str = option("", doc="elevation record at the world origin: CSV with a header `t,eta` or "
                                         "HDF5 with datasets `t`, `eta`, relative to the scenario file")
    time_dataset: str = option("t", doc="HDF5 elevation file: dataset of the times")
    elevation_dataset: str = option("eta", doc="HDF5 elevation file: dataset of the elevation")


@dataclass
class FrequencyGrid:
    """Uniform frequency grid."""

    start: float = option(unit="rad/s", check=positive, doc="first frequency")
    stop: float = option(unit="rad/s", check=positive, doc="last frequency")
    step: float = option(unit="rad/s", check=positive, doc="spacing")


@dataclass
class HydroSection:
    """Hydrodynamic database and force model."""

    database: str = option("", doc="BEMIO HDF5 file (path relative to the scenario file); "
                                   "if empty the database is computed with Capytaine from the bodies' geometry")
    cache_dir: str = option("hydro_cache", doc="folder of computed databases, relative to the scenario file")
    omega: FrequencyGrid = field(
        default_factory=lambda: FrequencyGrid(0.04, 4.0, 0.04),
        metadata={"doc": "BEM frequency grid (also the resolution of the radiation impulse response)"})
    omega_refine: list[FrequencyGrid] = field(
        default_factory=list,
        metadata={"doc": "extra BEM frequency grids merged into `omega`, e.g. a fine step across a narrow resonance "
                         "(a gap or moonpool) that the main grid would under-sample; see docs/hydrodynamics.md"})
    headings_deg: list[float] = option(factory=lambda: [0.0], unit="deg", doc="BEM wave headings")
    bem_method: str = option("indirect", choices=("indirect", "direct"), doc="Capytaine formulation")
    bem_symmetry: str = option(
        "none", check=symmetry_error,
        doc="`none`, `xOz`, `C<n>` or `D<n>`. `xOz`: every hydrodynamic body is mirror-symmetric about y = 0 and "
            "Capytaine solves on half meshes (panels crossing y = 0 are split; checked, an asymmetric body is an "
            "error); 2.3 times faster per frequency at 5400 panels. `C<n>`: the set of bodies is unchanged by a "
            "rotation of 360/n deg about the z axis (the bodies themselves need not be), `D<n>`: and by the mirror "
            "about y = 0; one solve on a wedge (half-wedge) of the scene, the results symmetric to round-off "
            "(docs/nenuphar.md)")
    irf_duration: float = option(60.0, unit="s", check=positive, doc="length of the radiation impulse response")
    irf_d_omega: float = option(
        0.0, unit="rad/s", check=non_negative,
        doc="frequency step of the impulse-response transform (B resampled by shape-preserving cubic "
            "interpolation); 0 = the database's grid")
    damping_tail: float = option(
        0.0, check=non_negative,
        doc="exponent n of the radiation damping's continuation above the database's last frequency Omega in the "
            "impulse response, B(omega) = B(Omega) (Omega/omega)^n (3: wall-sided bodies in surge); 0 = B cut at "
            "Omega; see docs/hydrodynamics.md")
    radiation_method: str = option("convolution", choices=("convolution", "state_space"),
                                   doc="radiation memory: direct convolution or fitted state space")
    state_space_tolerance: float = option(
        0.002, check=_fraction,
        doc="state space: largest scaled error of the fitted impulse response; the lowest order that meets "
            "it is used")
    state_space_max_order: int = option(60, check=positive, doc="state space: highest order tried")
    excitation_method: str = option(
        "superposition", choices=("superposition", "convolution"),
        doc="wave excitation: frequency-domain superposition of the components, or convolution of the "
            "excitation impulse response with the elevation (non-causal, unidirectional seas)")
    excitation_irf_duration: float = option(30.0, unit="s", check=positive,
                                            doc="half-length of the excitation impulse response")
    excitation: bool = option(True, doc="compute the wave excitation force")
    radiation: bool = option(True, doc="compute the radiation memory force")
    hydrostatics: bool = option(True, doc="compute the hydrostatic force")
    viscous: bool = option(True, doc="compute the bodies' linear damping and quadratic drag")
    nonlinear_hydrostatics: bool = option(
        False, doc="hydrostatic force by pressure integration over the instantaneous wetted hull (large motions)")
    nonlinear_froude_krylov: bool = option(
        False, doc="Froude-Krylov force over the instantaneous wetted hull under the incident wave (the "
                   "database's diffraction part stays linear)")
    added_mass_inf: str = option(
        "bem", choices=("bem", "ogilvie", "kramers_kronig"),
        doc="infinite-frequency added mass: `bem` as the database gives it, or `ogilvie`: the least-squares value "
            "consistent with the database's A(omega) and the impulse response of its B(omega) (Ogilvie's relation), "
            "so that the time-domain radiation model reproduces A(omega); or `kramers_kronig`: A_inf and a "
            "correction of B's continuation above the database's last frequency fitted together to A(omega), for "
            "databases whose A inside the band feels damping above it (resonances just above the last frequency); "
            "see docs/hydrodynamics.md")
    check_tolerance: float = option(
        0.05, check=positive,
        doc="database checks: largest relative asymmetry of A and B, and negative eigenvalue of the scaled B")


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
    """How the scene's `catenary` lines are computed (see docs/scenarios.md, RM3)."""

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


@dataclass
class RaoSection:
    """Frequency-domain (RAO) settings for `wec-cosim rao`."""

    omega: FrequencyGrid | None = field(default=None, metadata={"doc": "frequencies; default the database grid"})
    form: str = option("dae", choices=("dae", "ode"),
                       doc="constrained scenes: `dae` (motion and Lagrange multipliers solved together) or `ode` "
                           "(null-space reduced system, multipliers recovered); the same answer")
    headings_deg: list[float] = option(factory=list, unit="deg",
                                       doc="heading sweep (database headings); default the waves' heading")


@dataclass
class SteadySection:
    """Pseudo-spectral periodic steady state for `wec-cosim steady` (regular waves, nonlinear forces)."""

    harmonics: int = option(7, check=positive, doc="harmonics N of the wave frequency (2N + 1 collocation points)")
    form: str = option("dae", choices=("dae", "ode"),
                       doc="`dae`: motion and Lagrange multipliers expanded; `ode`: null-space reduced coordinates")
    periods: list[float] = option(factory=list, unit="s", check=positive,
                                  doc="wave periods to solve; default the waves' period")
    tolerance: float = option(1e-12, check=positive, doc="relative step tolerance of the nonlinear solver")


def _limits(value: list[float]) -> str | None:
    ok = len(value) == 2 and value[0] <= value[1]
    return None if ok else "needs two values [minimum, maximum] with minimum <= maximum"


@dataclass
class ControlSection:
    """External controller over zenoh (see docs/control.md)."""

    mode: str = option("off", choices=("off", "lockstep", "realtime"),
                       doc="`lockstep` (deterministic, waits for each command), `realtime` (paced to the "
                           "wall clock, never waits) or `off`")
    run_id: str = option("", doc="key-expression namespace `wec/<run_id>/...`; default the scenario name")
    period: float | None = option(None, unit="s", check=positive,
                                  doc="control period, a whole number of macro steps; default the macro step")
    ptos: list[str] = option(factory=list, doc="PTOs driven by the controller; default all")
    fallback: str = option("hold", choices=("hold", "passive", "stop"),
                           doc="on a controller fault: `hold` the last valid command, `passive` damping, or "
                               "`stop` the run (results kept)")
    passive_damping: float = option(0.0, unit="N s/m or N m s/rad", check=non_negative,
                                    doc="damping of the `passive` fallback")
    timeout: float = option(1.0, unit="s", check=positive,
                            doc="lock-step: wall time to wait for a command before it counts as late")
    connect_timeout: float = option(10.0, unit="s", check=non_negative,
                                    doc="wall time to wait for the controller at the start")
    max_age: int = option(5, check=positive,
                          doc="real time: a command older than this many control periods counts as late")
    realtime_factor: float = option(1.0, check=positive,
                                    doc="real time: simulated seconds per wall-clock second (1 = real time)")
    endpoints: list[str] = option(factory=lambda: ["tcp/127.0.0.1:7447"],
                                  doc="zenoh endpoints the master listens on (loopback by default)")
    zenoh_config: str = option("", doc="zenoh configuration file (endpoints, TLS, access control); "
                                       "replaces `endpoints`; relative to the scenario file")
    damping_limits: list[float] = option(factory=lambda: [0.0, math.inf], unit="N s/m or N m s/rad",
                                         allow_inf=True, check=_limits, doc="accepted damping commands")
    stiffness_limits: list[float] = option(factory=lambda: [-math.inf, math.inf], unit="N/m or N m/rad",
                                           allow_inf=True, check=_limits, doc="accepted stiffness commands")
    force_limits: list[float] = option(factory=lambda: [-math.inf, math.inf], unit="N or N m",
                                       allow_inf=True, check=_limits, doc="accepted force commands")


@dataclass
class SweepSection:
    """Sweep for `wec-cosim sweep`: one full run per combination of the grid's values (see docs/sweeps.md)."""

    grid: dict[str, Any] = option(
        factory=dict,
        doc="swept keys and their values: a table whose keys are key paths of this file and whose values are "
            "arrays, e.g. `waves.hs = [1.0, 2.0]`, `waves.tp = [6.0, 8.0]`, `ptos.pto.damping = [1e5, 2e5]`, "
            "`bodies.float.mass = [...]`, `waves.heading_deg = [...]`; one case per combination (the first key "
            "varies slowest); `--grid KEY=V1,V2` on the command line adds or replaces a key")
    seeds: int = option(
        1, check=positive,
        doc="time-domain runs in irregular seas: realisations per grid cell; the seed of each is derived from the "
            "case's sea state, the seed index and `waves.seed` (never from the order of execution)")
    method: str = option("frequency_domain", choices=("frequency_domain", "time_domain"),
                         doc="exact linear frequency-domain solution (regular or irregular seas), or one "
                             "time-domain co-simulation per case")
    transient: float | None = option(
        None, unit="s", check=non_negative,
        doc="time domain: start-up discarded before the statistics; default: regular waves the last "
            "`simulation.steady_periods` periods are analysed (the duration is extended to the ramp, 15 "
            "periods of settling and that window), other seas the ramp time plus `hydro.irf_duration`")
    time_series: bool = option(False, doc="also store each case's time series in the sweep file")
    workers: int = option(0, check=non_negative,
                          doc="worker processes of the local Dask cluster; 0 = one per core (`--workers`; "
                              "`--scheduler ADDRESS` uses a running cluster instead)")


@dataclass
class Scenario:
    """A scene and how to run it."""

    simulation: SimulationSection = field(metadata={"doc": "time-domain settings"})
    bodies: list[BodySection] = field(metadata={"doc": "rigid bodies"})
    name: str = option("", doc="scenario name; default the file name without extension")
    description: str = option("", doc="free text")
    environment: EnvironmentSection = field(default_factory=EnvironmentSection)
    waves: WavesSection = field(default_factory=WavesSection)
    hydro: HydroSection = field(default_factory=HydroSection)
    ptos: list[PtoSection] = field(default_factory=list, metadata={"doc": "power take-offs"})
    multibody: MultibodySection = field(default_factory=MultibodySection)
    joints: list[JointSection] = field(default_factory=list, metadata={"doc": "joints"})
    forces: list[ForceSection] = field(default_factory=list, metadata={"doc": "force elements"})
    drivers: list[DriverSection] = field(default_factory=list, metadata={"doc": "prescribed motion"})
    mooring_lines: MooringLinesSection = field(default_factory=MooringLinesSection,
                                               metadata={"doc": "mooring-line model of the `catenary` forces"})
    rao: RaoSection = field(default_factory=RaoSection)
    steady: SteadySection = field(default_factory=SteadySection, metadata={"doc": "pseudo-spectral steady state"})
    control: ControlSection = field(default_factory=ControlSection)
    sweep: SweepSection = field(default_factory=SweepSection, metadata={"doc": "sweeps and power matrices"})
    _file: Path = field(default=Path("scenario.toml"), init=False, repr=False)
    _text: str = field(default="", init=False, repr=False)
    _overrides: list[str] = field(default_factory=list, init=False, repr=False)  # `wec-cosim run --set` items

    @property
    def file(self) -> Path:
        return self._file

    @property
    def text(self) -> str:
        return self._text

    @property
    def folder(self) -> Path:
        return self._file.parent

    def resolve(self, relative: str) -> Path:
        """A path from the scenario file, relative to the scenario's folder."""
        p = Path(relative).expanduser()
        return p if p.is_absolute() else self.folder / p

    def body(self, name: str) -> BodySection:
        return next(b for b in self.bodies if b.name == name)

    @property
    def hydro_bodies(self) -> list[BodySection]:
        return [b for b in self.bodies if b.hydro]

    @property
    def formulation(self) -> str:
        """The multibody formulation, ``auto`` resolved."""
        f = self.multibody.formulation
        if f != "auto":
            return f
        simple = (not self.joints and not self.forces and not self.drivers
                  and not any(b.point_mass for b in self.bodies)
                  and all(not (p.joint or p.body2 or p.point or p.nonlinear) for p in self.ptos))
        return "linear" if simple else "index3"

    @property
    def ramp_time(self) -> float:
        w = self.waves
        if w.ramp_time is not None:
            return w.ramp_time
        if w.kind == "regular":
            return 3.0 * w.period
        if w.kind == "irregular" and w.spectrum != "file":
            return 3.0 * (w.tp if w.tp > 0 else 2 * math.pi / (0.4 * math.sqrt(self.environment.g / max(w.hs, 1e-9))))
        return 0.0


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario file; raises :class:`ScenarioError` on any problem."""
    path = Path(path)
    return parse_scenario(input_checks.read_scenario_text(path), path)


def parse_scenario(text: str, path: Path) -> Scenario:
    input_checks.check_nesting(text, path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML: {exc}") from None
    except RecursionError:
        raise ScenarioError(f"{path}: arrays or tables nested too deeply") from None
    _refuse_old_sweep_keys(data, path)
    scenario = schema.load(Scenario, data, str(path))
    scenario._file = path
    scenario._text = text
    if not scenario.name:
        scenario.name = re.sub(r"[^A-Za-z0-9_.+-]", "_", path.stem).lstrip(".-")[:100] or "scenario"
    _check(scenario)
    return scenario


def _refuse_old_sweep_keys(data: dict, path: Path) -> None:
    """The one-key sweep table of earlier versions (parameter, values, periods) with its replacement."""
    sw = data.get("sweep")
    if not isinstance(sw, dict) or not {"parameter", "values", "periods"} & set(sw):
        return
    def array(values: object) -> str:
        text = str(values)
        return text if len(text) <= 80 else text[:60] + " ...]"

    lines = []
    if sw.get("parameter"):
        lines.append(f"{sw['parameter']} = {array(sw.get('values', []))}")
    if sw.get("periods"):
        lines.append(f"waves.period = {array(sw['periods'])}")
    raise ScenarioError(
        f"{path}: [sweep] keys parameter, values and periods were replaced by the [sweep.grid] table of key paths "
        "and values; write instead: [sweep.grid] " + "; ".join(lines) + " (see docs/sweeps.md)")


def _check(s: Scenario) -> None:
    """Checks that involve several keys."""
    f = str(s.file)
    if not s.bodies:
        raise ScenarioError(f"{f}: [[bodies]] is empty; a scene needs at least one body")
    _unique(f, "bodies", [b.name for b in s.bodies])
    _unique(f, "ptos", [p.name for p in s.ptos])
    _unique(f, "bodies/ptos", [b.name for b in s.bodies] + [p.name for p in s.ptos])
    for i, b in enumerate(s.bodies):
        where = f"{f}: bodies[{i}] ({b.name})"
        if not b.dofs:
            raise ScenarioError(f"{where}: dofs is empty; give at least one degree of freedom")
        _unique(f, f"bodies[{i}].dofs", b.dofs)
        for key in ("initial_displacement", "initial_velocity"):
            if len(getattr(b, key)) != 6:
                raise ScenarioError(f"{where}: {key} needs 6 values (surge..yaw), got {len(getattr(b, key))}")
        if b.inertia is not None and len(b.inertia) not in (3, 6):
            raise ScenarioError(f"{where}: inertia needs 3 or 6 values, got {len(b.inertia)}")
        if b.inertia is not None and any(v <= 0 for v in b.inertia[:3]):
            raise ScenarioError(f"{where}: the principal moments of inertia must be positive")
        if any(d in b.dofs for d in ("roll", "pitch", "yaw")) and b.inertia is None:
            raise ScenarioError(f"{where}: rotational dofs are active but no inertia is given")
        if b.hydro and not s.hydro.database and b.geometry is None:
            raise ScenarioError(
                f"{where}: a hydrodynamic body needs a [bodies.geometry] table, or set [hydro].database, "
                "or hydro = false")
        if b.geometry is not None:
            _check_geometry(s, b, where)
        if not b.hydro and b.mass is None:
            raise ScenarioError(f"{where}: a body without hydrodynamics needs an explicit mass")
    names = {b.name: b for b in s.bodies}
    for i, p in enumerate(s.ptos):
        where = f"{f}: ptos[{i}] ({p.name})"
        if p.body not in names:
            raise ScenarioError(f"{where}: body {p.body!r} is not defined (bodies: {', '.join(names)})")
        if not (p.joint or p.point) and not p.dof:
            raise ScenarioError(f"{where}: give the dof the PTO acts on (or a joint, or point and point2)")
        if not (p.joint or p.body2 or p.point) and p.dof not in names[p.body].dofs:
            raise ScenarioError(f"{where}: dof {p.dof!r} is not active on body {p.body!r}")
        if p.nonlinear and s.formulation == "linear":
            raise ScenarioError(f"{where}: friction_force, quadratic_damping and force_limit make the PTO law "
                                "nonlinear; the 'linear' multibody formulation cannot take it: set "
                                "multibody.formulation = 'index3' (or remove the key)")
    _check_multibody(s, f, names)
    _check_waves(s)
    _check_hydro(s)
    if s.hydro.database and not s.resolve(s.hydro.database).is_file():
        raise ScenarioError(f"{f}: hydro.database: file {s.resolve(s.hydro.database)} does not exist")
    for key, g in [("hydro.omega", s.hydro.omega)] + [
            (f"hydro.omega_refine[{i}]", r) for i, r in enumerate(s.hydro.omega_refine)]:
        if g.stop <= g.start:
            raise ScenarioError(f"{f}: {key}: stop must be larger than start")
    if s.rao.omega is not None and s.rao.omega.stop < s.rao.omega.start:
        raise ScenarioError(f"{f}: rao.omega: stop must not be smaller than start")
    _check_simulation(s)
    input_checks.check_limits(s)
    input_checks.check_files(s)


def _check_simulation(s: Scenario) -> None:
    f = str(s.file)
    sim = s.simulation
    if sim.step > sim.duration:
        raise ScenarioError(f"{f}: simulation.step ({sim.step} s) is longer than the duration ({sim.duration} s)")
    n = sim.duration / sim.step
    if abs(n - round(n)) > 1e-6 * max(1.0, n):
        raise ScenarioError(
            f"{f}: simulation.duration ({sim.duration} s) is not a whole number of steps of {sim.step} s; "
            "change the duration or the step")
    if sim.added_mass == "interface" and not sim.iterative:
        raise ScenarioError(
            f"{f}: simulation.added_mass = 'interface' solves the added-mass force within each step and needs an "
            f"iterative master; set simulation.master = 'iqn_ils' or 'aitken' (got {sim.master!r})")
    if sim.master == "monolithic" and (sim.added_mass != "mass_matrix" or sim.adaptive.enabled):
        raise ScenarioError(
            f"{f}: simulation.master = 'monolithic' steps the physics directly with A_inf in the mass matrix and a "
            "fixed step; remove simulation.added_mass and [simulation.adaptive] or choose a co-simulation master")
    if sim.master == "monolithic" and s.formulation != "linear":
        raise ScenarioError(
            f"{f}: simulation.master = 'monolithic' steps only the linear multibody model (scenes without joints, "
            f"force elements, drivers, point masses or PTOs between bodies); this scene uses the {s.formulation!r} "
            "formulation: choose a co-simulation master (e.g. 'jacobi')")
    if not sim.resolve_feedthrough and (sim.master != "jacobi" or sim.extrapolation != 0):
        raise ScenarioError(
            f"{f}: simulation.resolve_feedthrough = false is the plain zero-order-hold Jacobi of generic FMI hosts; "
            f"it needs master = 'jacobi' and extrapolation = 0 (got {sim.master!r}, {sim.extrapolation})")
    if sim.interface == "linearised" and (sim.master != "jacobi" or sim.extrapolation != 0
                                          or sim.added_mass != "mass_matrix" or sim.adaptive.enabled):
        raise ScenarioError(
            f"{f}: simulation.interface = 'linearised' hands the multibody FMU an affine force model with its own "
            f"time rate, held over the step: it needs master = 'jacobi', extrapolation = 0, the default added_mass "
            f"and a fixed step (no [simulation.adaptive]) (got {sim.master!r}, {sim.extrapolation}, "
            f"{sim.added_mass!r})")
    a = sim.adaptive
    if a.enabled and a.max_step < sim.step:
        raise ScenarioError(f"{f}: simulation.adaptive.max_step ({a.max_step} s) is smaller than simulation.step "
                            f"({sim.step} s), the smallest step")
    if a.safety >= 1 or a.max_growth <= 1:
        raise ScenarioError(f"{f}: simulation.adaptive needs safety < 1 and max_growth > 1 "
                            f"(got {a.safety}, {a.max_growth})")
    _check_control(s)


def _check_control(s: Scenario) -> None:
    c, f = s.control, str(s.file)
    if c.mode == "off":
        return
    from .control.protocol import valid_run_id

    if not valid_run_id(c.run_id or s.name):
        raise ScenarioError(f"{f}: control.run_id {c.run_id or s.name!r} may hold only letters, digits, _ and -")
    period = c.period or s.simulation.step
    ratio = period / s.simulation.step
    if abs(ratio - round(ratio)) > 1e-9 * ratio or round(ratio) < 1:
        raise ScenarioError(f"{f}: control.period ({period} s) must be a whole number of macro steps "
                            f"(simulation.step = {s.simulation.step} s)")
    names = [p.name for p in s.ptos]
    for p in c.ptos:
        if p not in names:
            raise ScenarioError(f"{f}: control.ptos: PTO {p!r} is not defined (ptos: {', '.join(names) or 'none'})")
    if not names:
        raise ScenarioError(f"{f}: control is on but the scene has no PTO to drive")
    sim = s.simulation
    if sim.master == "monolithic" or sim.adaptive.enabled or sim.added_mass != "mass_matrix":
        raise ScenarioError(
            f"{f}: [control] drives the PTO inputs of the multibody FMU at a fixed period: it needs a co-simulation "
            "master (not 'monolithic'), fixed steps (no [simulation.adaptive]) and added_mass = 'mass_matrix'")
    input_checks.check_control(s)


def _check_waves(s: Scenario) -> None:
    f, w = str(s.file), s.waves
    if w.kind == "regular" and not (w.period > 0 and w.height > 0):
        raise ScenarioError(f"{f}: [waves] kind = 'regular' needs a positive height and period")
    if w.kind == "irregular":
        if w.spectrum == "file":
            if not w.spectrum_file:
                raise ScenarioError(f"{f}: [waves] spectrum = 'file' needs spectrum_file")
            if not s.resolve(w.spectrum_file).is_file():
                raise ScenarioError(f"{f}: waves.spectrum_file: file {s.resolve(w.spectrum_file)} does not exist")
        else:
            if not w.hs > 0:
                raise ScenarioError(f"{f}: [waves] kind = 'irregular' needs a positive hs")
            if not w.tp > 0 and w.spectrum != "pierson_moskowitz":
                raise ScenarioError(f"{f}: [waves] spectrum = {w.spectrum!r} needs a positive tp")
        if w.omega_max and w.omega_max <= w.omega_min:
            raise ScenarioError(f"{f}: waves.omega_max must be larger than waves.omega_min")
    if w.kind == "elevation":
        if not w.elevation_file:
            raise ScenarioError(f"{f}: [waves] kind = 'elevation' needs elevation_file")
        path = s.resolve(w.elevation_file)
        if not path.is_file():
            raise ScenarioError(f"{f}: waves.elevation_file: file {path} does not exist")
        if path.suffix.lower() not in (".csv", ".txt", ".h5", ".hdf5"):
            raise ScenarioError(f"{f}: waves.elevation_file: {path.name} is neither CSV (.csv, .txt) nor HDF5 "
                                "(.h5, .hdf5)")
    if w.spreading_s > 0 and w.kind != "irregular":
        raise ScenarioError(f"{f}: waves.spreading_s applies to irregular seas only")
    if w.spreading_s > 0 and s.hydro.excitation_method == "convolution":
        raise ScenarioError(f"{f}: hydro.excitation_method = 'convolution' needs a unidirectional sea "
                            "(waves.spreading_s = 0): the elevation at one point does not determine a spread sea")


def _check_hydro(s: Scenario) -> None:
    f, h = str(s.file), s.hydro
    if (h.nonlinear_hydrostatics or h.nonlinear_froude_krylov):
        for b in s.hydro_bodies:
            if b.geometry is None:
                raise ScenarioError(
                    f"{f}: bodies[{s.bodies.index(b)}] ({b.name}): the nonlinear hydrostatic/Froude-Krylov force "
                    "integrates pressure over the hull: give a [bodies.geometry] table")
    if h.nonlinear_froude_krylov and h.excitation_method == "convolution":
        raise ScenarioError(f"{f}: hydro.nonlinear_froude_krylov needs hydro.excitation_method = 'superposition'")
    for i, b in enumerate(s.bodies):
        drag = (b.drag_coefficient, b.drag_area)
        if (drag[0] is None) != (drag[1] is None):
            raise ScenarioError(f"{f}: bodies[{i}] ({b.name}): drag_coefficient and drag_area go together")
        if any(v is not None for v in (b.linear_damping, *drag)) and not b.hydro:
            raise ScenarioError(f"{f}: bodies[{i}] ({b.name}): viscous forces belong to the hydro FMU; the body has "
                                "hydro = false")
        for key in ("linear_damping", "drag_coefficient", "drag_area"):
            values = getattr(b, key)
            if values is not None and any(v < 0 for v in values):
                raise ScenarioError(f"{f}: bodies[{i}] ({b.name}): {key} must not be negative")


def _check_multibody(s: Scenario, f: str, names: dict) -> None:
    """Joints, force elements, drivers and multibody PTOs: names, references, required keys."""
    bodies_or_ground = set(names) | {"ground"}
    _unique(f, "joints/forces/drivers/ptos/bodies",
            [b.name for b in s.bodies] + [x.name for x in s.joints + s.forces + s.drivers + s.ptos])
    joints = {j.name: j for j in s.joints}

    def body(where: str, key: str, value: str, ground: bool = True) -> None:
        allowed = bodies_or_ground if ground else set(names)
        if value not in allowed:
            raise ScenarioError(f"{where}: {key} {value!r} is not a defined body"
                                f"{' or ground' if ground else ''} (bodies: {', '.join(names)})")

    def vec(where: str, key: str, value: list, n: int = 3) -> None:
        if len(value) != n:
            raise ScenarioError(f"{where}: {key} needs {n} values (x, y, z), got {len(value)}")

    for i, j in enumerate(s.joints):
        where = f"{f}: joints[{i}] ({j.name})"
        body(where, "body1", j.body1)
        body(where, "body2", j.body2, ground=False)
        if j.body1 == j.body2:
            raise ScenarioError(f"{where}: body1 and body2 are the same body {j.body2!r}")
        if not any(j.axis):
            raise ScenarioError(f"{where}: axis must not be zero")
        if j.axis2:
            vec(where, "axis2", j.axis2)
        if j.kind == "distance":
            vec(where, "position2", j.position2)
        if j.kind == "universal" and not j.axis2:
            raise ScenarioError(f"{where}: a universal joint needs axis2 (the cross axis on body2)")
    for i, e in enumerate(s.forces):
        where = f"{f}: forces[{i}] ({e.name})"
        if e.kind in ("spring_damper", "rope", "bushing"):
            body(where, "body1", e.body1)
            body(where, "body2", e.body2, ground=False)
        if e.kind in ("spring_damper", "rope"):
            vec(where, "point1", e.point1)
            vec(where, "point2", e.point2)
        if e.kind in ("rotary_spring_damper", "friction") and e.joint not in joints:
            raise ScenarioError(f"{where}: joint {e.joint!r} is not defined (joints: {', '.join(joints) or 'none'})")
        if e.kind in ("bushing", "mooring"):
            if e.kind == "bushing":
                vec(where, "position", e.position)
            sizes = (6,) if e.kind == "bushing" else (6, 36)
            for key in ("stiffness_matrix", "damping_matrix"):
                value = getattr(e, key)
                if value and len(value) not in sizes:
                    raise ScenarioError(f"{where}: {key} needs {' or '.join(map(str, sizes))} values, got {len(value)}")
        if e.kind in ("mooring", "catenary"):
            body(where, "body", e.body, ground=False)
        if e.kind == "catenary":
            vec(where, "fairlead", e.fairlead)
            vec(where, "anchor", e.anchor)
            for key in ("length", "weight", "ea"):
                if getattr(e, key) <= 0:
                    raise ScenarioError(f"{where}: a catenary line needs a positive {key}")
    _check_mooring_lines(s, f)
    for i, d in enumerate(s.drivers):
        where = f"{f}: drivers[{i}] ({d.name})"
        if bool(d.joint) == bool(d.body):
            raise ScenarioError(f"{where}: give either joint or body (with dof)")
        if d.joint and d.joint not in joints:
            raise ScenarioError(f"{where}: joint {d.joint!r} is not defined")
        if d.body:
            body(where, "body", d.body, ground=False)
            if d.dof not in names[d.body].dofs:
                raise ScenarioError(f"{where}: dof {d.dof!r} is not active on body {d.body!r}")
        if d.function == "table" and (len(d.times) < 2 or len(d.times) != len(d.values)):
            raise ScenarioError(f"{where}: a table needs times and values of the same length (at least 2)")
    for i, p in enumerate(s.ptos):
        where = f"{f}: ptos[{i}] ({p.name})"
        if p.joint and p.joint not in joints:
            raise ScenarioError(f"{where}: joint {p.joint!r} is not defined (joints: {', '.join(joints) or 'none'})")
        if p.joint:
            from mbd_fmu.joints import JOINT_COORDINATE_UNITS

            kind = joints[p.joint].kind
            count = len(JOINT_COORDINATE_UNITS[kind])
            if not count:
                raise ScenarioError(f"{where}: a PTO needs a joint with a coordinate, not a {kind} joint")
            if p.joint_coordinate > count:
                raise ScenarioError(f"{where}: joint_coordinate = {p.joint_coordinate} but a {kind} joint has "
                                    f"{count} coordinate{'s' if count > 1 else ''} (1..{count})")
        if p.body2:
            body(where, "body2", p.body2)
        if p.point or p.point2:
            vec(where, "point", p.point)
            vec(where, "point2", p.point2)
        elif p.body2:
            vec(where, "position", p.position)
    if s.formulation == "linear" and s.multibody.static_equilibrium:
        raise ScenarioError(f"{f}: multibody.static_equilibrium needs a nonlinear formulation (index3, index1 or "
                            "nullspace); the linear model assumes the reference pose is the equilibrium")
    if s.formulation == "linear" and (s.joints or s.forces or s.drivers or any(b.point_mass for b in s.bodies)
                                      or any(p.joint or p.body2 or p.point for p in s.ptos)):
        raise ScenarioError(f"{f}: multibody.formulation = 'linear' supports bodies on selected DOFs with PTOs to the "
                            "ground only; use index3, index1 or nullspace for joints, forces, drivers and point masses")
    for i, b in enumerate(s.bodies):
        if b.point_mass and any(d in b.dofs for d in ("roll", "pitch", "yaw")):
            raise ScenarioError(f"{f}: bodies[{i}] ({b.name}): a point mass has no rotational dofs; "
                                "set dofs to translations only")


def _check_mooring_lines(s: Scenario, f: str) -> None:
    """MoorDyn lines: diameters, one sea bed, the axial Courant limit of MoorDyn's step."""
    m = s.mooring_lines
    if m.model != "moordyn":
        return
    lines = [(i, e) for i, e in enumerate(s.forces) if e.kind == "catenary"]
    if not lines:
        raise ScenarioError(f"{f}: mooring_lines.model = 'moordyn' but the scene has no force of kind 'catenary'")
    depths = {round(e.anchor[2], 6) for _, e in lines}
    if len(depths) > 1:
        raise ScenarioError(f"{f}: mooring_lines.model = 'moordyn' needs every catenary anchor on one sea bed "
                            f"(anchor z: {sorted(depths)} m)")
    rho, g = s.environment.rho, s.environment.g
    for i, e in lines:
        where = f"{f}: forces[{i}] ({e.name})"
        if e.diameter <= 0:
            raise ScenarioError(f"{where}: mooring_lines.model = 'moordyn' needs the line's diameter (m)")
        if e.anchor[2] >= e.fairlead[2]:
            raise ScenarioError(f"{where}: the anchor must lie below the fairlead")
        mass = e.weight / g + rho * math.pi * e.diameter ** 2 / 4
        limit = e.length / e.segments / math.sqrt(e.ea / mass)
        if m.time_step > limit:
            raise ScenarioError(
                f"{f}: mooring_lines.time_step ({m.time_step:g} s) exceeds the axial Courant limit of line {e.name!r}, "
                f"{limit:.3g} s (segment {e.length / e.segments:.3g} m, axial wave speed {math.sqrt(e.ea / mass):.4g} "
                "m/s): MoorDyn's explicit scheme would blow up; reduce the step or the number of segments")


def _check_geometry(s: Scenario, b: BodySection, where: str) -> None:
    g = b.geometry
    needs = {"vertical_cylinder": ("radius", "draft"), "sphere": ("radius",),
             "regular_prism": ("radius", "draft")}.get(g.shape, ())
    for key in needs:
        if getattr(g, key) <= 0:
            raise ScenarioError(f"{where}: geometry shape {g.shape!r} needs a positive {key}")
    if g.shape == "axisymmetric" and (len(g.profile) < 2 or any(r < 0 for r, _ in g.profile)):
        raise ScenarioError(f"{where}: geometry shape 'axisymmetric' needs profile = [[r, z], ...] with at least two "
                            "points and r >= 0")
    if any(not 0 <= i < len(g.profile) - 1 for i in g.dry_segments):
        raise ScenarioError(f"{where}: geometry dry_segments {g.dry_segments} must be indices of profile segments "
                            f"(0 to {len(g.profile) - 2})")
    if g.shape == "regular_prism" and g.sides < 3:
        raise ScenarioError(f"{where}: geometry shape 'regular_prism' needs sides >= 3")
    if g.shape == "box" and min(g.size) <= 0:
        raise ScenarioError(f"{where}: geometry shape 'box' needs size = [length, width, height], all positive")
    if g.shape == "mesh":
        if not g.mesh_file:
            raise ScenarioError(f"{where}: geometry shape 'mesh' needs mesh_file")
        if not s.resolve(g.mesh_file).is_file():
            raise ScenarioError(f"{where}: mesh_file {s.resolve(g.mesh_file)} does not exist")


def _unique(file: str, what: str, names: list[str]) -> None:
    seen = set()
    for n in names:
        if n in seen:
            raise ScenarioError(f"{file}: {what}: name {n!r} is used twice")
        seen.add(n)


def reference_markdown() -> str:
    """The scenario reference page (``docs/scenario.md``), generated from the schema."""
    head = [
        "# Scenario file reference",
        "",
        "Generated from `orchestrator/scenario.py` by `python -m orchestrator.scenario > docs/scenario.md`;",
        "a test checks that this page matches the code. Units are SI except where a key says `_deg`.",
        "Paths are relative to the scenario file. Unknown keys, wrong types, non-finite numbers and",
        "out-of-range values are errors that name the file and the key.",
        "",
    ]
    return "\n".join(head + schema.document(Scenario, "scenario")) + "\n"


if __name__ == "__main__":
    print(reference_markdown(), end="")
