"""The plain multibody FMU (PythonFMU): inputs ``<b>.F[i]``, outputs ``<b>.x[i]``, ``<b>.v[i]``
(no feedthrough), ``<p>.force``, ``<p>.power``; parameters ``<b>.mass``, ``<b>.inertia[j]``
(diagonal), ``solver.substeps``. No added-mass parameters. The scene (bodies, active DOFs, PTOs)
comes from ``scene_spec.json`` in the FMU resources."""

from __future__ import annotations

from typing import Any

import numpy as np

from fmu_base.slave import VectorSlave, load_spec

from .model import PlainMultibody, PlainPto

POS = ("m", "m", "m", "rad", "rad", "rad")
VEL = ("m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s")
FORCE = ("N", "N", "N", "N.m", "N.m", "N.m")


class PlainMultibodySlave(VectorSlave):
    """Rigid bodies with structural mass only, RK4 sub-steps (see :mod:`plain_mbd_fmu.model`)."""

    author = "wec-cosim (third-party-style test model)"
    description = "Plain rigid bodies and PTO dampers, structural mass only, RK4"
    state_attributes = ("model",)

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.spec = load_spec(self.resources)
        self.model: PlainMultibody | None = None
        self.coords = [(b["name"], d) for b in self.spec["bodies"] for d in b["dofs"]]
        for b in self.spec["bodies"]:
            n = b["name"]
            self.add_reals(f"{n}.mass", [f"{n}.mass"], "parameter", [b["mass"]], unit="kg", description="mass")
            self.add_reals(f"{n}.inertia", [f"{n}.inertia[{j}]" for j in (1, 2, 3)], "parameter",
                           np.diag(np.asarray(b["inertia"])), unit="kg.m2", description="principal inertia")
        for key, table, causality, desc in (("F", FORCE, "input", "external force"),
                                            ("x", POS, "output", "displacement"),
                                            ("v", VEL, "output", "velocity")):
            self.add_reals(key, [f"{b}.{key}[{d + 1}]" for b, d in self.coords], causality,
                           np.zeros(len(self.coords)), unit=[table[d] for _, d in self.coords], description=desc)
        names = [p["name"] for p in self.spec["ptos"]]
        self.add_reals("pto.force", [f"{n}.force" for n in names], "output", np.zeros(len(names)), unit="N",
                       description="PTO force")
        self.add_reals("pto.power", [f"{n}.power" for n in names], "output", np.zeros(len(names)), unit="W",
                       description="absorbed power")
        self.add_reals("solver.substeps", ["solver.substeps"], "parameter", [self.spec.get("substeps", 10)],
                       description="RK4 sub-steps per communication step")

    def exit_initialization_mode(self) -> None:
        diag = []
        for b in self.spec["bodies"]:
            m = float(self.array(f"{b['name']}.mass")[0])
            inertia = self.array(f"{b['name']}.inertia")
            diag += [m if d < 3 else float(inertia[d - 3]) for d in b["dofs"]]
        ptos = [PlainPto(p["name"], self.coords.index((p["body"], p["dof"])), p["stiffness"], p["damping"])
                for p in self.spec["ptos"]]
        self.model = PlainMultibody(np.diag(diag), ptos, int(self.array("solver.substeps")[0]))
        x0 = [b["x0"][d] for b in self.spec["bodies"] for d in b["dofs"]]
        v0 = [b["v0"][d] for b in self.spec["bodies"] for d in b["dofs"]]
        self.model.q, self.model.qd = np.array(x0, float), np.array(v0, float)
        self._ready = True
        self.mark_outputs_stale()

    def update_outputs(self) -> None:
        self.array("x")[:] = self.model.q
        self.array("v")[:] = self.model.qd
        if self.model.ptos:
            self.array("pto.force")[:] = self.model.pto_forces()
            self.array("pto.power")[:] = self.model.pto_powers()

    def do_step(self, current_time: float, step_size: float) -> bool:
        self.model.step(step_size, self.array("F").copy())
        self.mark_outputs_stale()
        return True
