"""Hydrodynamics FMU (thin PythonFMU wrapper around :class:`hydro_fmu.model.HydroModel`).

Variables (see ``docs/fmu_variables.md``), for each hydrodynamic body ``b`` and each of its
active degrees of freedom ``i`` (1 surge ... 6 yaw):

* inputs ``b.x[i]`` displacement from equilibrium (m, rad), ``b.v[i]`` velocity (m/s, rad/s);
* outputs ``b.F[i]`` total hydrodynamic force (N, N m) and its parts ``b.F_exc[i]``,
  ``b.F_rad[i]`` (radiation memory only) and ``b.F_hs[i]``; ``wave.elevation`` at the origin;
* calculated parameters ``A_inf[k,l]``: infinite-frequency added mass between scene degrees of
  freedom k and l (k = 6 (body index) + i), to be copied into the multibody FMU;
* parameters ``wave.height``, ``wave.period``, ``wave.phase``, ``wave.heading``,
  ``wave.ramp_time``, ``radiation.dt``, ``radiation.irf_duration``.

The scene (bodies, active DOFs, wave kind) is fixed at build time in ``scene_spec.json`` and
the database in the BEMIO file next to it, both in the FMU's resources.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from pythonfmu.enums import Fmi2Status

from fmu_base.slave import VectorSlave, load_spec, matrix_names

from .bemio import read_bemio
from .model import ForceSwitches, HydroModel
from .waves import Ramp, WaveComponents, regular_wave, still_water

DOF_UNITS = ("m", "m", "m", "rad", "rad", "rad")
VEL_UNITS = ("m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s")
FORCE_UNITS = ("N", "N", "N", "N.m", "N.m", "N.m")


class HydroSlave(VectorSlave):
    """Hydrodynamic forces of a scene's bodies (Cummins equation, linear potential flow)."""

    author = "wec-cosim"
    description = "Hydrodynamic forces (Cummins equation): excitation, radiation memory, hydrostatics"
    state_attributes = ("model", "time")

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.spec = load_spec(self.resources)
        self.hdb = read_bemio(Path(self.resources) / self.spec["database"])
        bodies = self.spec["bodies"]
        self.body_names = [b["name"] for b in bodies]
        self.dofs = [list(b["dofs"]) for b in bodies]
        self.model: HydroModel | None = None
        self.time = 0.0
        self._register_parameters()
        self._register_body_variables()
        self._register_added_mass()

    # ------------------------------------------------------------------ variables
    def _register_parameters(self) -> None:
        w = self.spec["waves"]
        self.add_reals("wave.height", ["wave.height"], "parameter", [w.get("height", 0.0)], unit="m",
                       description="regular wave height, crest to trough")
        self.add_reals("wave.period", ["wave.period"], "parameter", [w.get("period", 1.0)], unit="s",
                       description="regular wave period")
        self.add_reals("wave.phase", ["wave.phase"], "parameter", [w.get("phase", 0.0)], unit="rad",
                       description="regular wave phase at the origin")
        self.add_reals("wave.heading", ["wave.heading"], "parameter", [w.get("heading", 0.0)], unit="rad",
                       description="wave direction, 0 = towards +x")
        self.add_reals("wave.ramp_time", ["wave.ramp_time"], "parameter", [w.get("ramp_time", 0.0)],
                       unit="s", description="duration of the half-cosine start-up ramp")
        r = self.spec["radiation"]
        self.add_reals("radiation.dt", ["radiation.dt"], "parameter", [r["dt"]], unit="s",
                       description="radiation convolution step; must equal the master's macro step")
        self.add_reals("radiation.irf_duration", ["radiation.irf_duration"], "parameter",
                       [r["irf_duration"]], unit="s", description="length of the radiation impulse response")
        self.add_reals("wave.elevation", ["wave.elevation"], "output", [0.0], unit="m",
                       description="incident wave elevation at the world origin")

    def _register_body_variables(self) -> None:
        def names(var: str) -> list[str]:
            return [f"{b}.{var}[{d + 1}]" for b, ds in zip(self.body_names, self.dofs, strict=True) for d in ds]

        n = sum(len(d) for d in self.dofs)
        zeros = np.zeros(n)
        all_dofs = [d for ds in self.dofs for d in ds]
        for key, table, causality, desc in (
            ("x", DOF_UNITS, "input", "displacement from equilibrium"),
            ("v", VEL_UNITS, "input", "velocity"),
            ("F", FORCE_UNITS, "output", "total hydrodynamic force (radiation memory, excitation, hydrostatics)"),
            ("F_exc", FORCE_UNITS, "output", "wave excitation force"),
            ("F_rad", FORCE_UNITS, "output", "radiation memory force (A_inf part excluded)"),
            ("F_hs", FORCE_UNITS, "output", "linear hydrostatic restoring force"),
        ):
            # Direct feedthrough: hydrostatics from x, radiation memory from the current v (all bodies).
            deps = {"F": ("x", "v"), "F_rad": ("v",), "F_hs": ("x",)}.get(key, ())
            self.add_reals(key, names(key), causality, zeros, unit=[table[d] for d in all_dofs],
                           description=desc, depends_on=deps)

    def _register_added_mass(self) -> None:
        index = [6 * b + d for b, ds in enumerate(self.dofs) for d in ds]
        sub = self.hdb.select_bodies(self.body_names)
        values = sub.added_mass_inf[np.ix_(index, index)]
        labels = [k + 1 for k in index]
        units = [("kg", "kg.m", "kg.m2")[(k % 6 >= 3) + (l % 6 >= 3)] for k in index for l in index]
        self.add_reals("A_inf", matrix_names("A_inf", labels, labels), "calculatedParameter", values.ravel(),
                       unit=units, description="infinite-frequency added mass (scene DOF numbering)")

    # ------------------------------------------------------------------ FMI life cycle
    def setup_experiment(self, start_time: float, stop_time: float | None, tolerance: float | None) -> None:
        self.time = float(start_time)

    def exit_initialization_mode(self) -> None:
        self.model = self._build_model()
        self.model.start_time = self.time
        self._ready = True
        self.mark_outputs_stale()

    def _build_model(self) -> HydroModel:
        p = {k: float(self.array(k)[0]) for k in (
            "wave.height", "wave.period", "wave.phase", "wave.heading", "wave.ramp_time",
            "radiation.dt", "radiation.irf_duration")}
        return HydroModel(
            self.hdb,
            self.body_names,
            self.dofs,
            self._waves(p),
            Ramp(p["wave.ramp_time"]),
            dt=p["radiation.dt"],
            irf_duration=p["radiation.irf_duration"],
            switches=ForceSwitches(**self.spec.get("switches", {})),
        )

    def _waves(self, p: dict[str, float]) -> WaveComponents:
        kind = self.spec["waves"]["kind"]
        if kind == "regular":
            return regular_wave(p["wave.height"], p["wave.period"], p["wave.phase"], p["wave.heading"])
        if kind == "still":
            return still_water()
        raise ValueError(f"unknown wave kind {kind!r} in the FMU's scene specification")

    def update_outputs(self) -> None:
        assert self.model is not None
        f = self.model.forces(self.time, self.array("x"), self.array("v"))
        self.array("F")[:] = f.total
        self.array("F_exc")[:] = f.excitation
        self.array("F_rad")[:] = f.radiation
        self.array("F_hs")[:] = f.hydrostatic
        self.array("wave.elevation")[0] = self.model.elevation(self.time)

    def do_step(self, current_time: float, step_size: float) -> bool:
        try:
            self.model.advance(current_time, step_size, self.array("v").copy())
        except ValueError as exc:
            self.log(str(exc), Fmi2Status.error)
            return False
        self.time = current_time + step_size
        self.mark_outputs_stale()
        return True
