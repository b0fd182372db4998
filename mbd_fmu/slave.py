"""Multibody FMU (thin PythonFMU wrapper around :class:`mbd_fmu.linear_system.LinearMultibodySystem`
for the ``linear`` formulation, :class:`mbd_fmu.simulator.MultibodySimulator` for the others).

Variables (see ``docs/fmu_variables.md``), for each body ``b`` and active degree of freedom
``i`` (1 surge ... 6 yaw), and each PTO ``p``:

* inputs ``b.F[i]`` external force (N, N m) held over the step, e.g. the hydrodynamic force;
* inputs of the linearised force interface (:mod:`fmu_base.coupling`, start 0): ``b.F0[i]``,
  ``b.F0_rate[i]`` on the hydrodynamic coordinates, ``dF_dx[k,l]``, ``dF_dv[k,l]``: the force
  F0 + F0_rate (t - t_n) + dF_dx x + dF_dv v is added over the step and integrated implicitly;
* outputs ``b.x[i]`` displacement from equilibrium (m, rad), ``b.v[i]`` velocity; ``p.force``
  (force on the body, N or N m) and ``p.power`` (absorbed power, W). No output depends directly
  on an input (no direct feedthrough);
* inputs ``p.stiffness``, ``p.damping``, ``p.force_command`` (PTO law F = -k x - c v + u; start
  values from the scenario; a controller may change them between steps);
* parameters ``b.mass``, ``b.inertia[j,k]``, ``b.x0[i]``, ``b.v0[i]``, and ``A_inf[k,l]``
  (infinite-frequency added mass in the scene's hydrodynamic DOF numbering; start values the
  scene's, equal to the hydrodynamics FMU's calculated parameters of the same name).

Nonlinear formulations add outputs (none with direct feedthrough): ``b.pose[1..6]`` (cg world
position, rotation vector from equilibrium), ``p.position``, ``p.velocity`` (the PTO's
coordinate from its neutral value and its rate), for each joint ``j``: ``j.coordinate[k]``,
``j.rate[k]``, ``j.force[1..3]``, ``j.moment[1..3]`` (reaction on body 2 from body 1 about the
joint point, world frame); for each force element ``e``: ``e.force[k]``; ``energy.kinetic``,
``energy.potential``, ``energy.dissipated``, ``energy.external_work``, ``energy.pto`` (the part of
the dissipated energy the PTOs convert), ``energy.balance``;
``mbd.constraint_violation``, ``mbd.dof``, ``mbd.redundant_constraints``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pythonfmu.enums import Fmi2Status

from fmu_base.coupling import coupling_variables
from fmu_base.slave import VectorSlave, indexed_names, load_spec, matrix_names

from .bodies import RigidBody
from .force_elements import LinearisedInputForce, LinearPTO
from .joints import JOINT_COORDINATE_UNITS
from .linear_system import LinearMultibodySystem
from .simulator import MultibodySimulator
from .spec import build_simulator

POS_UNITS = ("m", "m", "m", "rad", "rad", "rad")
VEL_UNITS = ("m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s")
FORCE_UNITS = ("N", "N", "N", "N.m", "N.m", "N.m")


class MultibodySlave(VectorSlave):
    """Rigid bodies with A_inf in the mass matrix and linear PTOs, integrated exactly per step."""

    author = "wec-cosim"
    description = "Multibody dynamics: rigid bodies on selected DOFs, A_inf in the mass matrix, linear PTOs"
    state_attributes = ("system",)

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.spec = load_spec(self.resources)
        self.system: LinearMultibodySystem | MultibodySimulator | None = None
        self.nonlinear = self.spec.get("multibody", {}).get("formulation", "linear") != "linear"
        self._pending = set(self._WATCHED.values())  # watched inputs that may have changed (set_real)
        self._touches: dict[tuple[int, ...], frozenset[str]] = {}
        self._pending_for: MultibodySimulator | None = None  # the simulator _pending is about
        self.set_default_experiment(self.spec)
        self._register_bodies()
        self._register_coupling()
        self._register_ptos()
        self._register_added_mass()
        if self.nonlinear:
            self._register_nonlinear_outputs()

    def _register_bodies(self) -> None:
        dofs = [(b["name"], d) for b in self.spec["bodies"] for d in b["dofs"]]
        for b in self.spec["bodies"]:
            n = b["name"]
            self.add_reals(f"{n}.mass", [f"{n}.mass"], "parameter", [b["mass"]], unit="kg",
                           description="mass")
            self.add_reals(f"{n}.inertia", matrix_names(f"{n}.inertia", (1, 2, 3), (1, 2, 3)), "parameter",
                           np.ravel(b["inertia"]), unit="kg.m2", description="inertia tensor about the cg")
            ids = [d + 1 for d in b["dofs"]]
            self.add_reals(f"{n}.x0", indexed_names(f"{n}.x0", ids), "parameter",
                           [b["x0"][d] for d in b["dofs"]], unit=[POS_UNITS[d] for d in b["dofs"]],
                           description="initial displacement")
            self.add_reals(f"{n}.v0", indexed_names(f"{n}.v0", ids), "parameter",
                           [b["v0"][d] for d in b["dofs"]], unit=[VEL_UNITS[d] for d in b["dofs"]],
                           description="initial velocity")
        for key, table, causality, desc in (
            ("F", FORCE_UNITS, "input", "external force (hydrodynamic force from the hydro FMU)"),
            ("x", POS_UNITS, "output", "displacement from equilibrium"),
            ("v", VEL_UNITS, "output", "velocity"),
        ):
            self.add_reals(key, [f"{b}.{key}[{d + 1}]" for b, d in dofs], causality, np.zeros(len(dofs)),
                           unit=[table[d] for _, d in dofs], description=desc)

    def _register_coupling(self) -> None:
        """Inputs of the linearised force interface (fmu_base.coupling; all start at 0: without them the
        force input F alone acts, held over each step)."""
        pattern = self.spec.get("coupling")
        self._coupling = pattern is not None
        if not self._coupling:
            return
        coords = [tuple(c) for c in self.spec["hydro_coordinates"]]
        labels = [k + 1 for k in self._hydro_index()]
        for group in coupling_variables(coords, labels, pattern["stiffness"], pattern["damping"]):
            self.add_reals(group.key, group.names, "input", np.zeros(len(group.names)), unit=group.units,
                           description=group.description)
        m = len(coords)
        self._tangent_slots = {key: tuple(np.array(pattern[key], dtype=int).reshape(-1, 2).T)
                               for key in ("stiffness", "damping")}
        self._tangent_shape = (m, m)

    def _tangents(self) -> tuple[np.ndarray, np.ndarray]:
        """dF_dx and dF_dv (m, m) on the hydrodynamic coordinates from the inputs."""
        dfdx, dfdv = np.zeros(self._tangent_shape), np.zeros(self._tangent_shape)
        dfdx[self._tangent_slots["stiffness"]] = self.array("dF_dx")
        dfdv[self._tangent_slots["damping"]] = self.array("dF_dv")
        return dfdx, dfdv

    def _register_ptos(self) -> None:
        ptos = self.spec["ptos"]
        names = [p["name"] for p in ptos]
        rot = [_pto_rotational(p) for p in ptos]
        # Stiffness, damping and force command are inputs (start values from the scenario): a
        # controller may change them between steps; left unconnected they keep their start values.
        for key, start, units, desc in (
            ("stiffness", [p["stiffness"] for p in ptos], ["N.m/rad" if r else "N/m" for r in rot], "PTO stiffness"),
            ("damping", [p["damping"] for p in ptos], ["N.m.s/rad" if r else "N.s/m" for r in rot], "PTO damping"),
            ("force_command", [0.0] * len(ptos), ["N.m" if r else "N" for r in rot], "PTO commanded force"),
        ):
            self.add_reals(f"pto.{key}", [f"{n}.{key}" for n in names], "input", start, unit=units, description=desc)
        self.add_reals("pto.force", [f"{n}.force" for n in names], "output", np.zeros(len(names)),
                       unit=["N.m" if r else "N" for r in rot], description="PTO force on the body")
        self.add_reals("pto.power", [f"{n}.power" for n in names], "output", np.zeros(len(names)),
                       unit="W", description="power absorbed by the PTO")

    def _register_added_mass(self) -> None:
        labels = [k + 1 for k in self._hydro_index()]
        coords = self.spec["hydro_coordinates"]
        units = [("kg", "kg.m", "kg.m2")[(a[1] >= 3) + (b[1] >= 3)] for a in coords for b in coords]
        # Start values: the scene's A_inf (the hydro FMU's calculated parameters), so that the FMU is right
        # without a parameter set; a host may still copy them from the hydro FMU (same values).
        start = self.spec.get("added_mass_inf", np.zeros(len(labels) ** 2))
        self.add_reals("A_inf", matrix_names("A_inf", labels, labels), "parameter", np.ravel(start), unit=units,
                       description="infinite-frequency added mass (start: the scene's; the hydro FMU's A_inf)")

    def _register_nonlinear_outputs(self) -> None:
        for b in self.spec["bodies"]:
            n = b["name"]
            self.add_reals(f"{n}.pose", indexed_names(f"{n}.pose", range(1, 7)), "output", np.zeros(6),
                           unit=list(POS_UNITS), description="cg world position and rotation vector from equilibrium")
        ptos = self.spec["ptos"]
        rot = [_pto_rotational(p) for p in ptos]
        self.add_reals("pto.position", [f"{p['name']}.position" for p in ptos], "output", np.zeros(len(ptos)),
                       unit=["rad" if r else "m" for r in rot], description="PTO coordinate from its neutral value")
        self.add_reals("pto.velocity", [f"{p['name']}.velocity" for p in ptos], "output", np.zeros(len(ptos)),
                       unit=["rad/s" if r else "m/s" for r in rot], description="PTO coordinate rate")
        for j in self.spec.get("joints", []):
            n, units = j["name"], JOINT_COORDINATE_UNITS[j["kind"]]
            k = range(1, len(units) + 1)
            if units:
                self.add_reals(f"{n}.coordinate", indexed_names(f"{n}.coordinate", k), "output", np.zeros(len(units)),
                               unit=[u for u, _ in units], description="joint coordinate")
                self.add_reals(f"{n}.rate", indexed_names(f"{n}.rate", k), "output", np.zeros(len(units)),
                               unit=[u for _, u in units], description="joint coordinate rate")
            self.add_reals(f"{n}.force", indexed_names(f"{n}.force", (1, 2, 3)), "output", np.zeros(3), unit="N",
                           description="reaction force on body 2 from body 1 (world frame)")
            self.add_reals(f"{n}.moment", indexed_names(f"{n}.moment", (1, 2, 3)), "output", np.zeros(3),
                           unit="N.m", description="reaction moment on body 2 about the joint point (world frame)")
        for f in self.spec.get("forces", []):
            n, size = f["name"], _force_outputs(f)
            self.add_reals(f"{n}.force", indexed_names(f"{n}.force", range(1, size + 1)), "output", np.zeros(size),
                           unit=_force_units(f), description="force element output (see docs/fmu_variables.md)")
        for key in ("kinetic", "potential", "dissipated", "external_work", "pto", "balance"):
            self.add_reals(f"energy.{key}", [f"energy.{key}"], "output", [0.0], unit="J", description=f"energy: {key}")
        for key, desc in (("constraint_violation", "largest constraint residual (m or rad)"),
                          ("dof", "degrees of freedom"), ("redundant_constraints", "redundant constraint equations")):
            self.add_reals(f"mbd.{key}", [f"mbd.{key}"], "output", [0.0], description=desc)

    def _hydro_index(self) -> list[int]:
        """Scene hydrodynamic DOF number (0-based, 6 * hydro body index + dof) of each coordinate."""
        order = {name: i for i, name in enumerate(self.spec["hydro_bodies"])}
        return [6 * order[b] + d for b, d in self.spec["hydro_coordinates"]]

    # ------------------------------------------------------------------ FMI life cycle
    def exit_initialization_mode(self) -> None:
        if self.nonlinear:
            self._build_nonlinear()
            self._ready = True
            self.mark_outputs_stale()
            return
        bodies = [
            RigidBody(
                name=b["name"],
                mass=float(self.array(f"{b['name']}.mass")[0]),
                inertia=self.array(f"{b['name']}.inertia").reshape(3, 3),
                cg=b["cg"],
                dofs=tuple(b["dofs"]),
            )
            for b in self.spec["bodies"]
        ]
        ptos = [
            LinearPTO(p["name"], p["body"], p["dof"], float(k), float(c), float(u))
            for p, k, c, u in zip(self.spec["ptos"], self.array("pto.stiffness"), self.array("pto.damping"),
                                  self.array("pto.force_command"), strict=True)
        ]
        m = len(self.spec["hydro_coordinates"])
        self.system = LinearMultibodySystem(
            bodies, ptos, self.array("A_inf").reshape(m, m),
            [tuple(c) for c in self.spec["hydro_coordinates"]],
        )
        q0 = np.concatenate([self.array(f"{b['name']}.x0") for b in self.spec["bodies"]])
        v0 = np.concatenate([self.array(f"{b['name']}.v0") for b in self.spec["bodies"]])
        self.system.set_state(q0, v0)
        if self._coupling:
            self._coupling_index = np.array([self.system.coordinate_index(*c) for c in
                                             (tuple(c) for c in self.spec["hydro_coordinates"])], dtype=int)
        self._ready = True
        self.mark_outputs_stale()

    def _build_nonlinear(self) -> None:
        spec = dict(self.spec)
        bodies = []
        for b in spec["bodies"]:
            b = dict(b)
            n = b["name"]
            b["mass"] = float(self.array(f"{n}.mass")[0])
            b["inertia"] = self.array(f"{n}.inertia").reshape(3, 3).tolist()
            x0, v0 = list(b["x0"]), list(b["v0"])
            for k, d in enumerate(b["dofs"]):
                x0[d], v0[d] = float(self.array(f"{n}.x0")[k]), float(self.array(f"{n}.v0")[k])
            b["x0"], b["v0"] = x0, v0
            bodies.append(b)
        spec["bodies"] = bodies
        spec["ptos"] = [dict(p, stiffness=float(k), damping=float(c), force_command=float(u))
                        for p, k, c, u in zip(spec["ptos"], self.array("pto.stiffness"), self.array("pto.damping"),
                                              self.array("pto.force_command"), strict=True)]
        m = len(spec["hydro_coordinates"])
        self.system = build_simulator(spec, self.array("A_inf").reshape(m, m))
        self.system.eager_outputs = True  # a host reads the outputs at every communication point
        model = self.system.model
        self._input_slots = np.array([model.slot_of(b["name"], d) for b in spec["bodies"] for d in b["dofs"]],
                                     dtype=int)
        # the generalised input vector of each step (None: the input array F is that vector, slot for slot)
        same = np.array_equal(self._input_slots, np.arange(model.n))
        self._input_buffer = None if same else np.zeros(model.n)
        if self._coupling:
            coords = [tuple(c) for c in spec["hydro_coordinates"]]
            model.elements.append(LinearisedInputForce(np.array([model.index(b) for b, _ in coords]),
                                                       np.array([d for _, d in coords]), model.cg))
        self.array("mbd.dof")[0] = self.system.report.dof
        self.array("mbd.redundant_constraints")[0] = len(self.system.report.redundant)

    # Nonlinear outputs are computed by groups, only those a host reads (reactions and energy cost a
    # constraint evaluation each; a master that reads the motion only should not pay for them).
    def _output_group(self, key: str) -> str | None:
        if key in ("x", "v") or key.endswith(".pose"):
            return "motion"
        if key.startswith("pto."):
            return "pto"
        if key.startswith("energy."):
            return "energy"
        if key == "mbd.constraint_violation":
            return "violation"
        names = {j["name"] for j in self.spec.get("joints", [])}
        if key.split(".")[0] in names:
            return "joints"
        if key.split(".")[0] in {f["name"] for f in self.spec.get("forces", [])}:
            return "forces"
        return None

    def get_real(self, vrs: list[int]) -> list[float]:
        if not (self.nonlinear and self._ready):
            return super().get_real(vrs)
        values = self.system.output_values()
        if values is None:  # the Python path: by groups
            return self._get_real_grouped(vrs)
        gathers = self.__dict__.setdefault("_gathers", {})
        key = tuple(vrs)
        gather = gathers.get(key)
        if gather is None:
            gather = gathers[key] = self._gather(vrs)
        index, others = gather
        out = values[index].tolist()
        if others:  # outputs the flat array does not hold (Python-side element outputs, constants)
            for k, value in zip(others, self._get_real_grouped([vrs[k] for k in others]), strict=True):
                out[k] = value
        return out

    def _gather(self, vrs: list[int]) -> tuple[np.ndarray, list[int]]:
        """Positions of ``vrs`` in the simulator's flat output array (:meth:`MultibodySimulator.output_values`) and
        the positions among ``vrs`` of those it does not hold (their place in the index: 0)."""
        where = self.__dict__.get("_flat_index")
        if where is None:
            where = self._flat_index = self._flat_positions()
        index = np.array([where.get(vr, 0) for vr in vrs], dtype=np.int64)
        return index, [k for k, vr in enumerate(vrs) if vr not in where]

    def _flat_positions(self) -> dict[int, int]:
        """Value reference -> position in the flat output array, for every output it holds."""
        sim = self.system
        model, cm, at = sim.model, sim.formulation.compiled, sim.output_layout()
        bodies = [b["name"] for b in self.spec["bodies"]]
        joints = [j["name"] for j in self.spec.get("joints", [])]
        slots = self._input_slots
        coords = [model.coordinates[k] for k in slots]
        position: dict[str, list[int]] = {
            "x": [at["displacement"] + 6 * model.index(b) + d for b, d in coords],
            "v": [at["v"] + int(k) for k in slots],
            "energy.kinetic": [at["kinetic"]], "energy.potential": [at["potential"]],
            "energy.dissipated": [at["energy"]], "energy.external_work": [at["energy"] + 1],
            "energy.pto": [at["energy"] + 2], "energy.balance": [at["balance"]],
            "mbd.constraint_violation": [at["violation"]]}
        for i, b in enumerate(bodies):
            position[f"{b}.pose"] = [at["r"] + 3 * i + k for k in range(3)] + [at["displacement"] + 6 * i + k
                                                                             for k in range(3, 6)]
        for k, key in enumerate(("position", "velocity", "force", "power")):
            position[f"pto.{key}"] = [at["pto"] + 4 * p + k for p in range(len(sim.ptos))]
        for j, name in enumerate(joints):
            position[f"{name}.force"] = [at["reactions"] + 6 * j + k for k in range(3)]
            position[f"{name}.moment"] = [at["reactions"] + 6 * j + k for k in range(3, 6)]
            if cm.joint_coordinates is not None:
                position[f"{name}.coordinate"] = [at["coordinates"] + 2 * int(c) for c in cm.joint_coordinates[j]]
                position[f"{name}.rate"] = [at["coordinates"] + 2 * int(c) + 1 for c in cm.joint_coordinates[j]]
        key_of = {id(a): k for k, a in self._arrays.items()}
        out = {}
        for vr, (array, i) in self._slot.items():
            places = position.get(key_of[id(array)])
            if places is not None and self._output_group(key_of[id(array)]) is not None:
                out[vr] = places[i]
        return out

    def _get_real_grouped(self, vrs: list[int]) -> list[float]:
        """The outputs by groups, each computed once per state, only those a host reads."""
        if self._outputs_stale:
            self._fresh: set[str] = set()
            self._outputs_stale = False
        if not hasattr(self, "_group_of"):
            key_of = {id(a): k for k, a in self._arrays.items()}
            self._group_of = {vr: self._output_group(key_of[id(a)]) for vr, (a, _) in self._slot.items()}
        for group in {self._group_of[vr] for vr in vrs} - {None} - self._fresh:
            getattr(self, f"_update_{group}")()
            self._fresh.add(group)
        slot = self._slot
        return [slot[vr][0].item(slot[vr][1]) for vr in vrs]

    def _update_motion(self) -> None:
        sim = self.system
        compiled = sim.compiled_outputs()
        disp = compiled["displacement"] if compiled is not None else sim.model.displacement(sim.formulation.pose)
        if not hasattr(self, "_motion_index"):  # (body, dof) of each input slot; each body's pose array
            model = sim.model
            coords = [model.coordinates[k] for k in self._input_slots]
            self._motion_index = (np.array([model.index(b) for b, _ in coords], dtype=int),
                                  np.array([d for _, d in coords], dtype=int),
                                  [self.array(f"{b['name']}.pose") for b in self.spec["bodies"]])
        bodies, dofs, poses = self._motion_index
        self.array("x")[:] = disp[bodies, dofs]
        self.array("v")[:] = sim.formulation.v[self._input_slots]
        r = sim.formulation.pose.r
        for i, pose in enumerate(poses):
            pose[:3] = r[i]
            pose[3:] = disp[i, 3:]

    def _update_pto(self) -> None:
        if self.system.ptos:
            out = self.system.pto_outputs()
            for k, key in enumerate(("pto.position", "pto.velocity", "pto.force", "pto.power")):
                self._arrays[key][:] = out[:, k]

    def _update_joints(self) -> None:
        sim = self.system
        if not hasattr(self, "_joint_arrays"):
            self._joint_arrays = [tuple(self._arrays.get(f"{j['name']}.{key}")
                                        for key in ("coordinate", "rate", "force", "moment"))
                                  for j in self.spec.get("joints", [])]
        for (coordinate, rate, force, moment), (q, qd), (f, m) in zip(self._joint_arrays, sim.joint_coordinates(),
                                                                      sim.reactions(), strict=True):
            if len(q):
                coordinate[:] = q
                rate[:] = qd
            force[:] = f
            moment[:] = m

    def _update_forces(self) -> None:
        sim = self.system
        for f in self.spec.get("forces", []):
            parts = sim.element_outputs([e for e in sim.model.elements
                                         if e.name == f["name"] or e.name.startswith(f["name"] + ".")])
            self.array(f"{f['name']}.force")[:] = np.concatenate(parts) if parts else 0.0

    def _update_energy(self) -> None:
        for key, value in self.system.energy().items():
            self.array(f"energy.{key}")[0] = value

    def _update_violation(self) -> None:
        self.array("mbd.constraint_violation")[0] = self.system.constraint_violation()

    def _update_nonlinear(self) -> None:
        for group in ("motion", "pto", "joints", "forces", "energy", "violation"):
            getattr(self, f"_update_{group}")()

    def update_outputs(self) -> None:
        assert self.system is not None
        if self.nonlinear:
            self._update_nonlinear()
            return
        self.array("x")[:] = self.system.q
        self.array("v")[:] = self.system.qd
        if self.system.ptos:
            self.array("pto.force")[:] = self.system.pto_forces()
            self.array("pto.power")[:] = self.system.pto_powers()

    def do_step(self, current_time: float, step_size: float) -> bool:
        if self.nonlinear:
            return self._step_nonlinear(step_size)
        if self.system.ptos:
            self.system.set_pto_commands(self.array("pto.stiffness"), self.array("pto.damping"),
                                         self.array("pto.force_command"))
        force, rate = self.array("F"), None
        if self._coupling:
            self.system.set_force_tangents(self._coordinates(), *self._tangents())
            force = force.copy()
            force[self._coupling_index] += self.array("F0")
            rate = np.zeros_like(force)
            rate[self._coupling_index] = self.array("F0_rate")
        self.system.step(step_size, force, rate)
        self.mark_outputs_stale()
        return True

    def _input_force_index(self) -> int:
        """Position of the linearised input-force element among the model's elements (kept: the same in copies of
        the state)."""
        index = self.__dict__.get("_input_force")
        if index is None:
            index = self._input_force = next(i for i, e in enumerate(self.system.model.elements)
                                             if isinstance(e, LinearisedInputForce))
        return index

    def _coordinates(self) -> list[tuple[str, int]]:
        return [tuple(c) for c in self.spec["hydro_coordinates"]]

    # Inputs a host seldom changes, looked at by do_step only when they may have changed: after a set_real that wrote
    # one of them, after a state restore (the restored simulator is a new object; it holds the restored values, looked
    # at again all the same) and at the first step. "commands": the PTO law (pto.stiffness, pto.damping,
    # pto.force_command); "coupling": the linearised force interface (F0, F0_rate, dF_dx, dF_dv).
    _WATCHED = {"pto.stiffness": "commands", "pto.damping": "commands", "pto.force_command": "commands",
                "F0": "coupling", "F0_rate": "coupling", "dF_dx": "coupling", "dF_dv": "coupling"}

    def set_real(self, vrs: list[int], values: list[float]) -> None:
        super().set_real(vrs, values)
        key = tuple(vrs)
        touched = self._touches.get(key)
        if touched is None:
            if len(self._touches) >= 256:  # (a host uses a handful of lists; bounded all the same)
                self._touches.clear()
            touched = self._touches[key] = self._watched_groups(vrs)
        if touched:
            self._pending |= touched

    def _watched_groups(self, vrs: list[int]) -> frozenset[str]:
        """The groups of :attr:`_WATCHED` that a set_real of ``vrs`` writes."""
        group_of = {id(array): self._WATCHED[key] for key, array in self._arrays.items() if key in self._WATCHED}
        return frozenset(group_of[id(self._slot[vr][0])] for vr in vrs
                         if vr in self._slot and id(self._slot[vr][0]) in group_of)

    def _pto_commands(self) -> list[list[float]]:
        """(stiffness, damping, force command) of every PTO from the inputs, as Python floats (compared with the
        PTOs' commands without numpy scalars): one read of the three input arrays, adjacent in the value store."""
        keys = ("pto.stiffness", "pto.damping", "pto.force_command")
        stacked = self.__dict__.get("_commands_view")
        if stacked is None:
            stacked = self._commands_view = self.stacked(keys)
            if stacked is None:  # (not adjacent: read one by one)
                stacked = self._commands_view = False
        return stacked.tolist() if stacked is not False else [self._arrays[key].tolist() for key in keys]

    def _set_fmu_state(self, state: Any) -> None:
        """The state set back (in place on the same simulator, or a new one): every watched input is read again at
        the next step, since the commands the state holds may differ from those the simulator last saw."""
        super()._set_fmu_state(state)
        self._pending_for = None

    def _step_nonlinear(self, step_size: float) -> bool:
        sim = self.system
        arrays = self._arrays
        pending = self._pending
        if sim is not self._pending_for:  # a restored state (_set_fmu_state) or a new simulator: every watched input
            pending.update(self._WATCHED.values())
            self._pending_for = sim
        if sim.ptos and "commands" in pending:
            sim.set_pto_commands(*self._pto_commands(), defer=not self._coupling)
        buffer = self._input_buffer
        if buffer is None:  # every slot is an input, in order: the input array itself (advance copies what it keeps)
            inputs = arrays["F"]
        else:
            inputs = buffer
            inputs[self._input_slots] = arrays["F"]
        restart = False
        if self._coupling:
            element = sim.model.elements[self._input_force_index()]  # (the element of this state: state copies)
            if element.active or ("coupling" in pending and any(
                    np.count_nonzero(arrays[key]) for key in ("F0", "F0_rate", "dF_dx", "dF_dv"))):
                restart = element.set(sim.time, arrays["F0"], arrays["F0_rate"], *self._tangents())
            else:  # inputs at zero, as the element's (a master that uses the force F only): what set() would do
                element.t0 = float(sim.time)
        pending.clear()
        try:
            sim.advance(step_size, inputs, restart=restart)
        except (RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
            self.log(f"multibody step failed at t = {sim.time:g} s: {exc}", Fmi2Status.error)
            return False
        self.mark_outputs_stale()
        return True


def _force_outputs(f: dict) -> int:
    """Number of outputs of a force element: tension or force (1), mooring wrench (6), catenary
    fairlead force (3), bushing: one per stiff or damped relative DOF."""
    if f["kind"] == "mooring":
        return 6
    if f["kind"] in ("catenary", "moordyn_point"):
        return 3
    if f["kind"] == "moordyn_tensions":
        return 2 * int(f["lines"])
    if f["kind"] == "bushing":
        return sum(1 for k, c in zip(f["stiffness"], f["damping"], strict=True) if k or c)
    return 1


def _force_units(f: dict) -> list[str]:
    rot = f["kind"] in ("rotary_spring_damper", "friction") and f.get("rotational", True)
    if f["kind"] == "mooring":
        return ["N"] * 3 + ["N.m"] * 3
    if f["kind"] in ("catenary", "moordyn_point"):
        return ["N"] * 3
    if f["kind"] == "moordyn_tensions":
        return ["N"] * (2 * int(f["lines"]))
    if f["kind"] == "bushing":
        return [("N.m" if d >= 3 else "N") for d, (k, c) in enumerate(zip(f["stiffness"], f["damping"], strict=True))
                if k or c]
    return ["N.m" if rot else "N"]


def _pto_rotational(p: dict) -> bool:
    """True if a PTO acts on an angle (rotational units)."""
    c = p.get("coordinate", {})
    if c.get("kind") == "joint":
        return c.get("rotational", False)
    if c.get("kind") in ("body", "relative"):
        return int(c["dof"]) >= 3
    if c.get("kind") == "points":
        return False
    return p["dof"] >= 3
