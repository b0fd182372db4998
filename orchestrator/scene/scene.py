"""A scenario resolved against its hydrodynamic database: what the FMUs, the master and the
frequency-domain solver need, derived in one place.

Coordinate conventions: the *hydro coordinates* are the active degrees of freedom of the
hydrodynamic bodies, body after body in scenario order; scene hydro DOF number k (1-based in FMI
names ``A_inf[k,l]``) is ``6 * (index among hydrodynamic bodies) + dof + 1``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hydro_fmu.bem import body_mesh
from hydro_fmu.drag import ViscousCoefficients
from hydro_fmu.hdb import HydroDatabase, HydroDatabaseError
from hydro_fmu.linearisation import CouplingPattern, coupling_pattern
from hydro_fmu.meshes import SurfaceMesh, write_meshes
from hydro_fmu.model import ForceSwitches, HydroOptions
from hydro_fmu.sea import Sea, SeaSpec, build_sea, discretisation, sea_spectrum
from hydro_fmu.spectra import held_variance
from hydro_fmu.waves import Ramp, WaveComponents
from mbd_fmu.bodies import RigidBody
from mbd_fmu.force_elements import LinearPTO
from mbd_fmu.linear_system import LinearMultibodySystem
from orchestrator.errors import ScenarioError
from orchestrator.scenario import DOFS, Scenario
from orchestrator.scenario.body_sections import BodySection
from orchestrator.scenario.checks import inertia_tensor

from .database import TAIL_CORRECTION, bem_inputs, check_wave_range, load_database, sorted_dofs

HYDRO = "hydro"
MBD = "mbd"
# Names of the data files in the hydro FMU's resources (besides the database).
ELEVATION_RESOURCE = "wave_elevation"
SPECTRUM_RESOURCE = "wave_spectrum.csv"
MESH_RESOURCE = "hull_meshes.json"


@dataclass(frozen=True)
class Connection:
    """Output ``source.source_variable`` feeds input ``target.target_variable``."""

    source: str
    source_variable: str
    target: str
    target_variable: str


class Scene:
    """A validated scenario with its database: FMU specifications, connections, physics objects."""

    def __init__(self, scenario: Scenario, hdb: HydroDatabase, hdb_file: Path) -> None:
        self.scenario = scenario
        self.hdb = hdb
        self.hdb_file = hdb_file
        self._mobility = None  # mobility(), computed once
        self.hydro_bodies = [b.name for b in scenario.hydro_bodies]
        self.hydro_coordinates = [(b.name, DOFS.index(d)) for b in scenario.hydro_bodies
                                  for d in sorted_dofs(b)]
        if scenario.waves.kind == "irregular" and scenario.waves.discretisation == "equal_frequency":
            check_held_energy(scenario, self.sea_spec())
        if scenario.waves.kind != "still":
            try:
                headings = np.unique(self.waves().headings) if scenario.waves.spreading_s > 0 else [
                    math.radians(scenario.waves.heading_deg)]
                for heading in headings:  # every component's heading must be within the database's
                    hdb.excitation_at(hdb.omega[:1], float(heading))
            except HydroDatabaseError as exc:
                raise ScenarioError(f"{scenario.file}: waves: {exc}") from None

    # ------------------------------------------------------------------ physics objects
    def body_mass(self, b: BodySection) -> float:
        if b.mass is not None:
            return b.mass
        i = self.hydro_bodies.index(b.name)
        return self.hdb.rho * float(self.hdb.displaced_volume[i])

    @staticmethod
    def inertia_matrix(b: BodySection) -> np.ndarray:
        if b.inertia is None:
            return np.eye(3)  # unused: no rotational DOF is active
        return np.array(inertia_tensor(b.inertia))

    def rigid_bodies(self) -> list[RigidBody]:
        return [
            RigidBody(b.name, self.body_mass(b), self.inertia_matrix(b), np.asarray(b.cg),
                      tuple(DOFS.index(d) for d in sorted_dofs(b)))
            for b in self.scenario.bodies
        ]

    def ptos(self) -> list[LinearPTO]:
        return [LinearPTO(p.name, p.body, DOFS.index(p.dof), p.stiffness, p.damping) for p in self.scenario.ptos
                if not (p.joint or p.body2 or p.point)]

    def sea_spec(self, files: dict[str, str] | None = None) -> SeaSpec:
        """The sea as :class:`SeaSpec`; data files by absolute path, or renamed by ``files``."""
        s = self.scenario
        w = s.waves
        spectrum_file = str(s.resolve(w.spectrum_file)) if w.spectrum_file else ""
        elevation_file = str(s.resolve(w.elevation_file)) if w.elevation_file else ""
        if files is not None:
            spectrum_file = files.get("spectrum", spectrum_file)
            elevation_file = files.get("elevation", elevation_file)
        return SeaSpec(
            kind=w.kind, height=w.height, period=w.period, phase=math.radians(w.phase_deg),
            heading=math.radians(w.heading_deg), ramp_time=s.ramp_time, spectrum=w.spectrum, hs=w.hs, tp=w.tp,
            gamma=w.gamma, spectrum_file=spectrum_file if w.spectrum == "file" else "",
            discretisation=w.discretisation,
            repeat_period=w.repeat_period if w.repeat_period > 0 else s.simulation.duration,
            n_components=w.n_components, omega_min=w.omega_min, omega_max=w.omega_max, seed=w.seed,
            spreading_s=w.spreading_s, n_directions=w.n_directions if w.spreading_s > 0 else 1,
            elevation_file=elevation_file if w.kind == "elevation" else "", time_dataset=w.time_dataset,
            elevation_dataset=w.elevation_dataset, g=s.environment.g)

    def sea(self) -> Sea:
        if not hasattr(self, "_sea"):
            self._sea = build_sea(self.sea_spec())
        return self._sea

    def waves(self) -> WaveComponents:
        return self.sea().components

    def ramp(self) -> Ramp:
        return Ramp(self.scenario.ramp_time)

    def switches(self) -> ForceSwitches:
        h = self.scenario.hydro
        return ForceSwitches(excitation=h.excitation, radiation=h.radiation, hydrostatics=h.hydrostatics,
                             viscous=h.viscous)

    def viscous(self) -> ViscousCoefficients | None:
        """Linear damping and rho Cd A / 2 on the hydro coordinates (None if no body has any)."""
        linear, quadratic = [], []
        for b in self.scenario.hydro_bodies:
            for d in sorted_dofs(b):
                j = DOFS.index(d)
                linear.append(b.linear_damping[j] if b.linear_damping else 0.0)
                cd = b.drag_coefficient[j] if b.drag_coefficient else 0.0
                area = b.drag_area[j] if b.drag_area else 0.0
                quadratic.append(0.5 * self.scenario.environment.rho * cd * area)
        coefficients = ViscousCoefficients(np.array(linear), np.array(quadratic))
        return coefficients if coefficients.active else None

    def hull_meshes(self) -> dict[str, SurfaceMesh]:
        """Whole hull of each hydrodynamic body relative to its centre of gravity (nonlinear options)."""
        h = self.scenario.hydro
        if not (h.nonlinear_hydrostatics or h.nonlinear_froude_krylov):
            return {}
        bodies, _ = bem_inputs(self.scenario)
        return {b.name: body_mesh(b.geometry).translated(-np.asarray(b.cg)) for b in bodies}

    def tail_correction(self) -> tuple[np.ndarray, np.ndarray] | None:
        """(nodes, values (k, n, n) on the database's 6 N DOFs) of B's fitted continuation, if the scenario asks
        for one (``hydro.added_mass_inf = "kramers_kronig"``)."""
        return self.hdb.extra.get(TAIL_CORRECTION)

    def hydro_options(self) -> HydroOptions:
        h = self.scenario.hydro
        return HydroOptions(
            radiation_method=h.radiation_method, irf_d_omega=h.irf_d_omega, damping_tail=h.damping_tail,
            tail_correction=self.tail_correction(),
            state_space_tolerance=h.state_space_tolerance, state_space_max_order=h.state_space_max_order,
            still=tuple(self.still_coordinates()), excitation_method=h.excitation_method,
            excitation_irf_duration=h.excitation_irf_duration,
            nonlinear_hydrostatics=h.nonlinear_hydrostatics, nonlinear_froude_krylov=h.nonlinear_froude_krylov,
            meshes=self.hull_meshes(), viscous=self.viscous())

    def still_coordinates(self) -> list[tuple[str, int]]:
        """(body, DOF) of the hydrodynamic coordinates that cannot move (:mod:`orchestrator.scene.still`), for the
        state-space fit (computed once; empty unless the radiation is a state space)."""
        if self.scenario.hydro.radiation_method != "state_space":
            return []
        if not hasattr(self, "_still"):
            from .still import still_coordinates

            self._still = still_coordinates(self)
        return self._still

    def hydro_model(self, dt: float | None = None):
        """The scene's :class:`hydro_fmu.model.HydroModel` in-process (what the hydro FMU computes)."""
        from hydro_fmu.model import HydroModel

        s = self.scenario
        sea = self.sea()
        dofs = [[DOFS.index(d) for d in sorted_dofs(b)] for b in s.hydro_bodies]
        return HydroModel(self.hdb, self.hydro_bodies, dofs, sea.components, sea.ramp, dt or s.simulation.step,
                          s.hydro.irf_duration, self.switches(), self.hydro_options(),
                          record=sea.record)

    def radiation_check(self, dt: float | None = None):
        """How well the convolution kernel of the hydro model reproduces the database, per degree of freedom
        (:func:`hydro_fmu.radiation_check.impedance_check`), with each DOF's structural inertia."""
        from hydro_fmu.hdb import DOF_NAMES
        from hydro_fmu.radiation_check import impedance_check

        s, index = self.scenario, self.hydro_index()
        block = np.ix_(index, index)
        inertia = self._apparent_inertia() - np.diag(self.hdb.added_mass_inf[block])
        correction = self.tail_correction()
        if correction is not None:
            correction = (correction[0], np.asarray(correction[1])[(slice(None),) + block])
        h = s.hydro
        return impedance_check(self.hdb.omega, self.hdb.added_mass[(slice(None),) + block],
                               self.hdb.radiation_damping[(slice(None),) + block], self.hdb.added_mass_inf[block],
                               np.array(inertia), [f"{name} {DOF_NAMES[d]}" for name, d in self.hydro_coordinates],
                               dt or s.simulation.step, h.irf_duration, d_omega=h.irf_d_omega,
                               tail_exponent=h.damping_tail, tail_correction=correction, band=self._sea_band())

    def _apparent_inertia(self) -> np.ndarray:
        """The inertia a force on each hydrodynamic coordinate meets (kg, kg m^2), A_inf included:
        1 / [P (P^T M P)^-1 P^T]_ii with M the mass matrix and P the null space of the joints' constraints (P = I
        without joints); a body tied to others by joints moves them too."""
        idx = self.hydro_index()
        a_inf = self.hdb.added_mass_inf[np.ix_(idx, idx)]
        if self.scenario.formulation == "linear":
            bodies = {b.name: b for b in self.scenario.bodies}
            mass = np.diag([self.body_mass(bodies[n]) if d < 3 else self.inertia_matrix(bodies[n])[d - 3, d - 3]
                            for n, d in self.hydro_coordinates]) + a_inf
            return 1.0 / np.diag(np.linalg.inv(mass))
        from mbd_fmu.linearize import linearize
        from mbd_fmu.spec import build_model

        model, _ = build_model(self._mbd_spec_at_reference(), a_inf)
        lin = linearize(model)
        p = lin.null_space
        compliance = p @ np.linalg.solve(p.T @ lin.mass @ p, p.T)
        rows = [lin.coordinates.index(c) for c in self.hydro_coordinates]
        with np.errstate(divide="ignore"):  # a coordinate the joints hold still to first order: infinite inertia
            return 1.0 / np.abs(np.diag(compliance)[rows])

    def _sea_band(self) -> tuple[float, float] | None:
        """The frequencies of the sea's components that carry 99 % of its variance (rad/s); None in still water."""
        waves = self.waves()
        if not len(waves.omega):
            return None
        energy = np.asarray(waves.amplitude, dtype=float) ** 2
        order = np.argsort(waves.omega)
        share = np.cumsum(energy[order]) / energy.sum()
        lo = waves.omega[order][np.searchsorted(share, 0.005)]
        hi = waves.omega[order][min(len(order) - 1, np.searchsorted(share, 0.995))]
        return float(lo), float(hi)

    def hydro_index(self) -> np.ndarray:
        """Index of each hydro coordinate in the database's 6N numbering."""
        return np.array([6 * self.hydro_bodies.index(b) + d for b, d in self.hydro_coordinates], dtype=int)

    def multibody_system(self, *, added_mass: bool = True) -> LinearMultibodySystem:
        """The multibody model; ``added_mass`` puts the database's A_inf in its mass matrix."""
        idx = self.hydro_index()
        a_inf = self.hdb.added_mass_inf[np.ix_(idx, idx)] if added_mass else None
        system = LinearMultibodySystem(self.rigid_bodies(), self.ptos(), a_inf, self.hydro_coordinates)
        q0 = [b.initial_displacement[DOFS.index(d)] for b in self.scenario.bodies for d in sorted_dofs(b)]
        v0 = [b.initial_velocity[DOFS.index(d)] for b in self.scenario.bodies for d in sorted_dofs(b)]
        system.set_state(np.array(q0), np.array(v0))
        return system

    # ------------------------------------------------------------------ FMU specifications
    def coupling_pattern(self) -> CouplingPattern:
        """Entries of the linearised force interface's dF_dx and dF_dv (hydro_fmu.linearisation)."""
        h = self.scenario.hydro
        idx = self.hydro_index()
        viscous = self.viscous() if h.viscous else None
        mask = None if viscous is None else (viscous.linear != 0) | (viscous.quadratic != 0)
        return coupling_pattern(
            self.hdb, idx, idx // 6, hydrostatics=h.hydrostatics and not h.nonlinear_hydrostatics,
            nonlinear_position=(h.nonlinear_hydrostatics and h.hydrostatics) or (h.nonlinear_froude_krylov
                                                                                 and h.excitation),
            radiation=h.radiation, viscous=mask)

    def experiment(self) -> dict:
        """The FMUs' DefaultExperiment: the scenario's duration and macro step."""
        sim = self.scenario.simulation
        return {"start": 0.0, "stop": sim.duration, "step": sim.step}

    def hydro_data_files(self, folder: Path) -> dict[str, Path]:
        """Data files the hydro FMU needs besides its database, written to or found from ``folder``:
        resource name -> file (imported wave data, hull meshes for the nonlinear options)."""
        s = self.scenario
        w = s.waves
        files: dict[str, Path] = {}
        if w.kind == "elevation":
            path = s.resolve(w.elevation_file)
            files[ELEVATION_RESOURCE + path.suffix.lower()] = path
        if w.kind == "irregular" and w.spectrum == "file":
            files[SPECTRUM_RESOURCE] = s.resolve(w.spectrum_file)
        meshes = self.hull_meshes()
        if meshes:
            target = Path(folder) / MESH_RESOURCE
            write_meshes(meshes, target)
            files[MESH_RESOURCE] = target
        return files

    def hydro_spec(self, database_name: str, data_files: dict[str, Path] | None = None) -> dict:
        s = self.scenario
        h = s.hydro
        names = list(data_files or {})
        renamed = {"elevation": next((n for n in names if n.startswith(ELEVATION_RESOURCE)), ""),
                   "spectrum": SPECTRUM_RESOURCE if SPECTRUM_RESOURCE in names else ""}
        viscous = self.viscous()
        return {
            "kind": HYDRO,
            "database": database_name,
            "bodies": [{"name": b.name, "dofs": [DOFS.index(d) for d in sorted_dofs(b)]} for b in s.hydro_bodies],
            "waves": self.sea_spec({k: v for k, v in renamed.items() if v}).to_json(),
            "radiation": {"dt": s.simulation.step, "irf_duration": h.irf_duration, "method": h.radiation_method,
                          "irf_d_omega": h.irf_d_omega, "damping_tail": h.damping_tail,
                          "tail_correction": _correction_json(self.tail_correction()),
                          "state_space_tolerance": h.state_space_tolerance,
                          "state_space_max_order": h.state_space_max_order,
                          "still": [list(c) for c in self.still_coordinates()]},
            "excitation": {"method": h.excitation_method, "irf_duration": h.excitation_irf_duration},
            "nonlinear": {"hydrostatics": h.nonlinear_hydrostatics, "froude_krylov": h.nonlinear_froude_krylov,
                          "meshes": MESH_RESOURCE if MESH_RESOURCE in names else ""},
            "viscous": None if viscous is None else {"linear": viscous.linear.tolist(),
                                                     "quadratic": viscous.quadratic.tolist()},
            "switches": {"excitation": h.excitation, "radiation": h.radiation, "hydrostatics": h.hydrostatics,
                         "viscous": h.viscous},
            "coupling": self.coupling_pattern().to_json(),
            "experiment": self.experiment(),
        }

    def static_load(self, b: BodySection) -> list[float]:
        """Constant world wrench at the cg of the nonlinear models: buoyancy (and its moment about the cg)."""
        if b.buoyancy is not None or not b.hydro:
            return [0.0, 0.0, b.buoyancy or 0.0, 0.0, 0.0, 0.0]
        i = self.hydro_bodies.index(b.name)
        hdb = self.hdb
        force = np.array([0.0, 0.0, hdb.rho * hdb.g * float(hdb.displaced_volume[i])])
        moment = np.cross(np.asarray(hdb.cb[i]) - np.asarray(b.cg), force)
        return force.tolist() + moment.tolist()

    def mbd_spec(self, *, dynamic_lines: bool = True) -> dict:
        """The multibody FMU's specification; ``dynamic_lines=False`` gives MoorDyn lines as quasi-static
        catenaries (the frequency-domain solvers' model). With ``multibody.static_equilibrium`` the bodies start
        from the static equilibrium (their initial displacements added to it)."""
        spec = self._mbd_spec_at_reference(dynamic_lines)
        if self.scenario.multibody.static_equilibrium:
            offsets = self.equilibrium().displacement
            for b, offset in zip(spec["bodies"], offsets, strict=True):
                b["x0"] = (np.asarray(b["x0"], float) + offset).tolist()
        return spec

    def equilibrium(self):
        """The static equilibrium of the scene (:func:`orchestrator.scene.equilibrium.scene_equilibrium`), computed
        once."""
        if not hasattr(self, "_equilibrium"):
            from .equilibrium import scene_equilibrium

            self._equilibrium = scene_equilibrium(self)
        return self._equilibrium

    def linearisation_pose(self, model):
        """Pose the frequency domain linearises about: the static equilibrium if the scene asks for it, else the
        reference pose."""
        return self.equilibrium().pose if self.scenario.multibody.static_equilibrium else model.reference

    def _mbd_spec_at_reference(self, dynamic_lines: bool = False) -> dict:
        """The specification at the reference pose (MoorDyn lines as quasi-static catenaries unless
        ``dynamic_lines``)."""
        spec = self._linear_mbd_spec()
        s = self.scenario
        if s.formulation == "linear":
            return spec
        mb = s.multibody
        spec["multibody"] = {"formulation": s.formulation, "integrator": mb.integrator,
                             "spectral_radius": mb.spectral_radius, "max_step": mb.max_step,
                             "newton_tolerance": mb.newton_tolerance, "restart": mb.restart}
        spec["gravity"] = [0.0, 0.0, -s.environment.g] if mb.gravity else [0.0, 0.0, 0.0]
        for b, out in zip(s.bodies, spec["bodies"], strict=True):
            out["point_mass"] = b.point_mass
            out["static_load"] = self.static_load(b) if mb.gravity else [0.0] * 6
        spec["joints"] = [
            {"name": j.name, "kind": j.kind, "body1": None if j.body1 == "ground" else j.body1, "body2": j.body2,
             "position": list(j.position), "axis": list(j.axis), "axis2": list(j.axis2) or None,
             "position2": list(j.position2) or None, "locked": j.locked} for j in s.joints]
        kinds = {j.name: j.kind for j in s.joints}
        from mbd_fmu.joints import JOINT_COORDINATE_UNITS

        first_unit = {name: (JOINT_COORDINATE_UNITS[kind] or [("", "")])[0][0] for name, kind in kinds.items()}
        spec["forces"] = [dict(self._force_spec(e), rotational=first_unit.get(e.joint) == "rad") for e in s.forces]
        if s.mooring_lines.moordyn_file:
            from .moordyn_file import dynamic_spec, linearised_spec

            if dynamic_lines and s.mooring_lines.model == "moordyn":
                dynamic_spec(s, spec)
            else:
                linearised_spec(spec, self.moordyn_linearised())
        elif dynamic_lines and s.mooring_lines.model == "moordyn":
            self._moordyn_spec(spec)
        spec["drivers"] = [self._driver_spec(d) for d in s.drivers]
        joints = {j.name: j for j in s.joints}
        for p, out in zip(s.ptos, spec["ptos"], strict=True):
            out["coordinate"] = self._pto_coordinate(p, joints)
        return spec

    @staticmethod
    def _ground(name: str) -> str | None:
        return None if name in ("", "ground") else name

    def _force_spec(self, e) -> dict:
        def matrix(values: list[float]) -> list[float] | None:
            if not values:
                return None
            return np.diag(values).ravel().tolist() if len(values) == 6 else list(values)

        d = {"name": e.name, "kind": e.kind, "body1": self._ground(e.body1), "body2": self._ground(e.body2),
             "point1": list(e.point1), "point2": list(e.point2), "joint": e.joint, "stiffness": e.stiffness,
             "damping": e.damping, "free_length": e.free_length, "body": e.body, "position": list(e.position),
             "fairlead": list(e.fairlead), "anchor": list(e.anchor), "length": e.length, "weight": e.weight,
             "ea": e.ea, "force": e.force, "velocity": e.velocity}
        if e.kind == "bushing":
            d["stiffness"] = list(e.stiffness_matrix) or [0.0] * 6
            d["damping"] = list(e.damping_matrix) or [0.0] * 6
        if e.kind == "mooring":
            d["stiffness"] = matrix(e.stiffness_matrix) or [0.0] * 36
            d["damping"] = matrix(e.damping_matrix)
        return d

    def moordyn_linearised(self) -> dict:
        """The MoorDyn input file's lines as a quasi-static stiffness and mean wrench per coupled body (computed once;
        :func:`orchestrator.scene.moordyn_file.linearised`)."""
        if not hasattr(self, "_moordyn_linearised"):
            from .moordyn_file import linearised

            self._moordyn_linearised = linearised(self.scenario)
        return self._moordyn_linearised

    def _moordyn_spec(self, spec: dict) -> None:
        """Mark the catenary lines for MoorDyn and add its solver options."""
        s = self.scenario
        m = s.mooring_lines
        for e, d in zip(s.forces, spec["forces"], strict=True):
            if e.kind == "catenary":
                d.update(model="moordyn", diameter=e.diameter, segments=e.segments, drag_normal=e.drag_normal,
                         drag_axial=e.drag_axial, added_mass_normal=e.added_mass_normal,
                         added_mass_axial=e.added_mass_axial, internal_damping=e.internal_damping)
        spec["moordyn"] = {"time_step": m.time_step, "scheme": m.scheme, "seabed_stiffness": m.seabed_stiffness,
                           "seabed_damping": m.seabed_damping, "ic_time": m.ic_time, "ic_tolerance": m.ic_tolerance,
                           "rho": s.environment.rho, "g": s.environment.g}

    @staticmethod
    def _driver_spec(d) -> dict:
        coordinate = ({"kind": "joint", "joint": d.joint, "index": 0} if d.joint
                      else {"kind": "body", "body": d.body, "dof": DOFS.index(d.dof)})
        function = {"kind": d.function, "amplitude": d.amplitude, "period": d.period,
                    "phase": math.radians(d.phase_deg), "offset": d.offset, "times": list(d.times),
                    "values": list(d.values)}
        return {"name": d.name, "coordinate": coordinate, "function": function, "level": d.level}

    def _pto_coordinate(self, p, joints: dict) -> dict:
        if p.joint:
            from mbd_fmu.joints import JOINT_COORDINATE_UNITS

            index = p.joint_coordinate - 1
            return {"kind": "joint", "joint": p.joint, "index": index,
                    "rotational": JOINT_COORDINATE_UNITS[joints[p.joint].kind][index][0] == "rad"}
        if p.point:
            return {"kind": "points", "body1": p.body, "point1": list(p.point),
                    "body2": self._ground(p.body2), "point2": list(p.point2)}
        if p.body2:
            return {"kind": "relative", "body1": self._ground(p.body2), "body2": p.body,
                    "position": list(p.position), "dof": DOFS.index(p.dof)}
        return {"kind": "body", "body": p.body, "dof": DOFS.index(p.dof)}

    def mobility(self):  # noqa: ANN201 - mbd_fmu.assembly.MobilityReport | None
        """DOF count, redundant constraint rows and the assembly's correction of the start pose of a constrained
        scene (``mbd_fmu.spec.mobility_report``, computed once), or None for the linear model. A model that
        cannot be built or assembled (``mbd_fmu.spec_checks.ModelError``) is a :class:`ScenarioError` naming the
        scenario file."""
        if self.scenario.formulation == "linear":
            return None
        if self._mobility is None:
            from mbd_fmu.spec import mobility_report
            from mbd_fmu.spec_checks import ModelError

            try:
                self._mobility = mobility_report(self.mbd_spec(dynamic_lines=False))
            except ModelError as exc:
                raise ScenarioError(f"{self.scenario.file}: {exc}") from None
        return self._mobility

    def multibody_simulator(self, *, added_mass: bool = True):
        """The nonlinear multibody model of the scene, assembled (for linearisation and tests); MoorDyn lines
        are the quasi-static catenaries of the same properties here (the frequency-domain model)."""
        from mbd_fmu.spec import build_simulator

        idx = self.hydro_index()
        a_inf = self.hdb.added_mass_inf[np.ix_(idx, idx)] if added_mass else np.zeros((len(idx), len(idx)))
        return build_simulator(self.mbd_spec(dynamic_lines=False), a_inf)

    def _linear_mbd_spec(self) -> dict:
        s = self.scenario
        return {
            "kind": MBD,
            "bodies": [
                {"name": b.name, "mass": self.body_mass(b), "inertia": self.inertia_matrix(b).tolist(),
                 "cg": list(b.cg), "dofs": [DOFS.index(d) for d in sorted_dofs(b)],
                 "x0": list(b.initial_displacement), "v0": list(b.initial_velocity)}
                for b in s.bodies
            ],
            "ptos": [{"name": p.name, "body": p.body, "dof": DOFS.index(p.dof) if p.dof else 0,
                      "stiffness": p.stiffness, "damping": p.damping, "friction_force": p.friction_force,
                      "quadratic_damping": p.quadratic_damping, "force_limit": p.force_limit,
                      "velocity_scale": p.velocity_scale} for p in s.ptos],
            "hydro_bodies": self.hydro_bodies,
            "hydro_coordinates": [list(c) for c in self.hydro_coordinates],
            "added_mass_inf": self.hdb.added_mass_inf[np.ix_(self.hydro_index(), self.hydro_index())].ravel().tolist(),
            "coupling": self.coupling_pattern().to_json(),
            "experiment": self.experiment(),
        }

    def connections(self) -> list[Connection]:
        """Force/velocity bonds: MBD displacement and velocity -> hydro, hydro force -> MBD."""
        links = []
        for b, d in self.hydro_coordinates:
            i = d + 1
            links.append(Connection(MBD, f"{b}.x[{i}]", HYDRO, f"{b}.x[{i}]"))
            links.append(Connection(MBD, f"{b}.v[{i}]", HYDRO, f"{b}.v[{i}]"))
            links.append(Connection(HYDRO, f"{b}.F[{i}]", MBD, f"{b}.F[{i}]"))
        return links

    def linearised_connections(self) -> list[Connection]:
        """The linearised force interface: MBD displacement and velocity -> hydro; hydro F0, F0_rate, dF_dx,
        dF_dv -> the MBD inputs of the same names (what plain fixed-step hosts need, see docs/masters.md)."""
        links = [link for link in self.connections() if link.source == MBD]
        for b, d in self.hydro_coordinates:
            for var in ("F0", "F0_rate"):
                name = f"{b}.{var}[{d + 1}]"
                links.append(Connection(HYDRO, name, MBD, name))
        labels = [k + 1 for k in self.hydro_index()]
        pattern = self.coupling_pattern()
        for var, pairs in (("dF_dx", pattern.stiffness), ("dF_dv", pattern.damping)):
            for i, j in pairs:
                name = f"{var}[{labels[i]},{labels[j]}]"
                links.append(Connection(HYDRO, name, MBD, name))
        return links

    def parameter_links(self) -> list[Connection]:
        """Calculated parameters copied at initialisation: A_inf from the hydro FMU to the MBD FMU."""
        labels = [k + 1 for k in self.hydro_index()]
        return [Connection(HYDRO, f"A_inf[{k},{l}]", MBD, f"A_inf[{k},{l}]") for k in labels for l in labels]


HS_TOLERANCE = 0.25  # largest relative difference of the discretised sea's Hs from the spectrum's


def check_held_energy(scenario: Scenario, spec: SeaSpec) -> None:
    """Refuse an equal-frequency sea whose components hold an Hs more than :data:`HS_TOLERANCE` off the spectrum's
    (a repeat period too short for the spectrum: 2 pi / repeat_period wider than its peak leaves few components
    or none, and an Hs 2 m sea becomes still water)."""
    ratio = math.sqrt(held_variance(sea_spectrum(spec), discretisation(spec)))
    if abs(ratio - 1) > HS_TOLERANCE:
        w = scenario.waves
        key = "waves.repeat_period" if w.repeat_period > 0 else "waves.repeat_period (default: simulation.duration)"
        raise ScenarioError(
            f"{scenario.file}: {key} = {spec.repeat_period:g} s spaces the wave components by "
            f"{2 * math.pi / spec.repeat_period:.4g} rad/s: they hold an Hs {100 * ratio:.3g} % of the spectrum's "
            f"(more than {100 * HS_TOLERANCE:g} % off), the sea would not be the one asked for; give a repeat period "
            f"of many peak periods (e.g. 100 Tp or more) or discretisation = 'equal_energy'")


def _correction_json(correction: tuple[np.ndarray, np.ndarray] | None) -> dict | None:
    if correction is None:
        return None
    nodes, values = correction
    return {"nodes": np.asarray(nodes).tolist(), "values": np.asarray(values).tolist()}


def load_scene(scenario: Scenario, *, refresh: bool = False, log=print, progress: bool = False) -> Scene:
    """The scenario resolved against its database (computed if needed, see :func:`load_database`); a constrained
    scene's multibody model built and assembled once (:meth:`Scene.mobility`), so that a model the equations
    cannot take is refused here, naming the scenario file."""
    hdb, path = load_database(scenario, refresh=refresh, log=log, progress=progress)
    check_wave_range(scenario, hdb, path)
    scene = Scene(scenario, hdb, path)
    scene.mobility()
    return scene
