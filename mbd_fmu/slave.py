"""Multibody FMU (thin PythonFMU wrapper around :class:`mbd_fmu.linear_system.LinearMultibodySystem`).

Variables (see ``docs/fmu_variables.md``), for each body ``b`` and active degree of freedom
``i`` (1 surge ... 6 yaw), and each PTO ``p``:

* inputs ``b.F[i]`` external force (N, N m), e.g. the hydrodynamic force;
* outputs ``b.x[i]`` displacement from equilibrium (m, rad), ``b.v[i]`` velocity; ``p.force``
  (force on the body, N or N m) and ``p.power`` (absorbed power, W). No output depends directly
  on an input (no direct feedthrough);
* inputs ``p.stiffness``, ``p.damping``, ``p.force_command`` (PTO law F = -k x - c v + u; start
  values from the scenario; a controller may change them between steps);
* parameters ``b.mass``, ``b.inertia[j,k]``, ``b.x0[i]``, ``b.v0[i]``, and ``A_inf[k,l]``
  (infinite-frequency added mass in the scene's hydrodynamic DOF numbering, copied from the
  hydrodynamics FMU's calculated parameters of the same name).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from fmu_base.slave import VectorSlave, indexed_names, load_spec, matrix_names

from .bodies import RigidBody
from .force_elements import LinearPTO
from .linear_system import LinearMultibodySystem

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
        self.system: LinearMultibodySystem | None = None
        self._register_bodies()
        self._register_ptos()
        self._register_added_mass()

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

    def _register_ptos(self) -> None:
        ptos = self.spec["ptos"]
        names = [p["name"] for p in ptos]
        rot = [p["dof"] >= 3 for p in ptos]
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
        self.add_reals("A_inf", matrix_names("A_inf", labels, labels), "parameter",
                       np.zeros(len(labels) ** 2), unit=units,
                       description="infinite-frequency added mass, set from the hydro FMU's A_inf")

    def _hydro_index(self) -> list[int]:
        """Scene hydrodynamic DOF number (0-based, 6 * hydro body index + dof) of each coordinate."""
        order = {name: i for i, name in enumerate(self.spec["hydro_bodies"])}
        return [6 * order[b] + d for b, d in self.spec["hydro_coordinates"]]

    # ------------------------------------------------------------------ FMI life cycle
    def exit_initialization_mode(self) -> None:
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
        self._ready = True
        self.mark_outputs_stale()

    def update_outputs(self) -> None:
        assert self.system is not None
        self.array("x")[:] = self.system.q
        self.array("v")[:] = self.system.qd
        if self.system.ptos:
            self.array("pto.force")[:] = self.system.pto_forces()
            self.array("pto.power")[:] = self.system.pto_powers()

    def do_step(self, current_time: float, step_size: float) -> bool:
        if self.system.ptos:
            self.system.set_pto_commands(self.array("pto.stiffness"), self.array("pto.damping"),
                                         self.array("pto.force_command"))
        self.system.step(step_size, self.array("F"))
        self.mark_outputs_stale()
        return True
