"""Hydrodynamics FMU (thin PythonFMU wrapper around :class:`hydro_fmu.model.HydroModel`).

Variables (see ``docs/fmu_variables.md``), for each hydrodynamic body ``b`` and each of its
active degrees of freedom ``i`` (1 surge ... 6 yaw); only what the scene selects exists:

* inputs ``b.x[i]`` displacement from equilibrium (m, rad), ``b.v[i]`` velocity (m/s, rad/s);
* outputs ``b.F[i]`` total hydrodynamic force (N, N m) and the parts that are switched on:
  ``b.F_exc[i]``, ``b.F_rad[i]`` (radiation memory only), ``b.F_hs[i]``, ``b.F_visc[i]``;
  ``wave.elevation`` at the origin; ``energy.excitation_work``, ``energy.radiation_work``,
  ``energy.hydrostatic_work``, ``energy.viscous_work``: work (J) of each part on the bodies since
  the start (:mod:`hydro_fmu.work`, trapezoidal rule over the communication points);
* outputs of the linearised force interface (:mod:`hydro_fmu.linearisation`, :mod:`fmu_base.coupling`):
  ``b.F0[i]``, ``b.F0_rate[i]``, ``dF_dx[k,l]``, ``dF_dv[k,l]`` (the pattern's entries only), for
  plain fixed-step hosts;
* calculated parameters ``A_inf[k,l]``: infinite-frequency added mass between scene degrees of
  freedom k and l (k = 6 (body index) + i), to be copied into the multibody FMU; and the
  radiation model's report ``radiation.order``, ``radiation.fit_error``,
  ``radiation.frequency_error``;
* parameters of the sea (by kind: regular ``wave.height``, ``wave.period``, ``wave.phase``;
  irregular ``wave.hs``, ``wave.tp``, ``wave.gamma``, ``wave.seed``; all ``wave.heading``,
  ``wave.ramp_time``) and of the radiation model (``radiation.dt``, ``radiation.irf_duration``,
  state space ``radiation.state_space_tolerance``).

The scene (bodies, active DOFs, sea, methods) is fixed at build time in ``scene_spec.json``, the
database in the BEMIO file next to it, and imported wave data and hull meshes beside them, all in
the FMU's resources. The model is built when the FMU is instantiated and rebuilt at the end of
initialisation if a parameter changed. ``DefaultExperiment``: the scenario's duration and step.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np
from pythonfmu import Fmi2Causality, Fmi2Variability, Integer
from pythonfmu.enums import Fmi2Initial, Fmi2Status

from fmu_base.coupling import coupling_variables
from fmu_base.slave import VectorSlave, load_spec, matrix_names

from .bemio import read_bemio
from .drag import ViscousCoefficients
from .linearisation import CouplingPattern
from .meshes import read_meshes
from .model import ForceSwitches, HydroModel, HydroOptions
from .sea import SeaSpec, build_sea
from .state_space import DEFAULT_TOLERANCE
from .work import COMPONENTS

DOF_UNITS = ("m", "m", "m", "rad", "rad", "rad")
VEL_UNITS = ("m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s")
FORCE_UNITS = ("N", "N", "N", "N.m", "N.m", "N.m")

# Sea parameters per wave kind: (variable, SeaSpec field, unit, description).
WAVE_PARAMETERS = {
    "regular": (("wave.height", "height", "m", "regular wave height, crest to trough"),
                ("wave.period", "period", "s", "regular wave period"),
                ("wave.phase", "phase", "rad", "regular wave phase at the origin")),
    "irregular": (("wave.hs", "hs", "m", "significant wave height"),
                  ("wave.tp", "tp", "s", "peak period"),
                  ("wave.gamma", "gamma", "1", "JONSWAP peak enhancement factor")),
    "elevation": (),
    "still": (),
}


class StepClock:
    """Communication points t = t_a + k h counted from the last change of step (no accumulated round-off,
    the same in every host that passes the same step sizes)."""

    def __init__(self, start: float = 0.0) -> None:
        self.anchor, self.step, self.count = float(start), 0.0, 0

    def advance(self, h: float) -> float:
        if h != self.step:
            self.anchor, self.step, self.count = self.anchor + self.count * self.step, float(h), 0
        self.count += 1
        return self.anchor + self.count * self.step


class HydroSlave(VectorSlave):
    """Hydrodynamic forces of a scene's bodies (Cummins equation, linear potential flow)."""

    author = "wec-cosim"
    description = "Hydrodynamic forces (Cummins equation): excitation, radiation memory, hydrostatics, drag"
    state_attributes = ("model", "time", "clock")  # the work account lives in the model's runtime

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.spec = load_spec(self.resources)
        self.hdb = read_bemio(Path(self.resources) / self.spec["database"])
        bodies = self.spec["bodies"]
        self.body_names = [b["name"] for b in bodies]
        self.dofs = [list(b["dofs"]) for b in bodies]
        self.sea_spec = SeaSpec.from_json(self.spec["waves"]).with_files(self.resources)
        self.switches = ForceSwitches(**self.spec.get("switches", {}))
        self.seed = int(self.sea_spec.seed)
        self.model: HydroModel | None = None
        self._built_with: tuple | None = None
        self.time = 0.0
        self._power = np.zeros(len(COMPONENTS))  # the point's powers (not state: computed with the outputs)
        self.clock = StepClock()
        self.set_default_experiment(self.spec)
        self._register_parameters()
        self._register_body_variables()
        self._force_outputs = self._force_output_map()
        self._x, self._v = self.array("x"), self.array("v")
        self._elevation, self._energy = self.array("wave.elevation"), self.array("energy")
        self._affine_fresh = False
        self._register_coupling()
        self._register_added_mass()
        self._register_report()
        try:  # built now so that the calculated parameters are right from the start
            self._build_if_changed()
        except ValueError:  # e.g. no state-space fit within the tolerance: reported at initialisation
            self.model = None

    # ------------------------------------------------------------------ variables
    def _register_parameters(self) -> None:
        sea = self.sea_spec
        wave = [*WAVE_PARAMETERS[sea.kind]]
        if sea.kind != "still":
            wave += [("wave.heading", "heading", "rad", "wave direction, 0 = towards +x"),
                     ("wave.ramp_time", "ramp_time", "s", "duration of the half-cosine start-up ramp")]
        for name, key, unit, desc in wave:
            self.add_reals(name, [name], "parameter", [getattr(sea, key)], unit=unit, description=desc)
        if sea.kind == "irregular":
            self.register_variable(Integer(
                "wave.seed", causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed,
                initial=Fmi2Initial.exact, description="seed of the random phases (same seed, same sea)",
                getter=lambda: self.seed, setter=lambda v: setattr(self, "seed", int(v))))
        r = self.spec["radiation"]
        radiation = [("radiation.dt", r["dt"], "radiation convolution step; must divide the master's macro steps"),
                     ("radiation.irf_duration", r["irf_duration"], "length of the radiation impulse response")]
        for name, value, desc in radiation:
            self.add_reals(name, [name], "parameter", [value], unit="s", description=desc)
        if r.get("method") == "state_space":
            self.add_reals("radiation.state_space_tolerance", ["radiation.state_space_tolerance"], "parameter",
                           [r["state_space_tolerance"]], description="largest scaled error of the fitted kernel")
        self.add_reals("wave.elevation", ["wave.elevation"], "output", [0.0], unit="m",
                       description="incident wave elevation at the world origin")
        self.add_reals("energy", [f"energy.{c}" for c in COMPONENTS], "output", np.zeros(len(COMPONENTS)),
                       unit="J", description="work of a hydrodynamic force component on the bodies since the start",
                       depends_on=("x", "v"))

    def _register_body_variables(self) -> None:
        def names(var: str) -> list[str]:
            return [f"{b}.{var}[{d + 1}]" for b, ds in zip(self.body_names, self.dofs, strict=True) for d in ds]

        n = sum(len(d) for d in self.dofs)
        zeros = np.zeros(n)
        all_dofs = [d for ds in self.dofs for d in ds]
        sw = self.switches
        nonlinear = self.spec.get("nonlinear", {})
        viscous = self.spec.get("viscous") is not None and sw.viscous
        # Direct feedthrough: hydrostatics from x, radiation memory and drag from the current v,
        # a nonlinear Froude-Krylov force from x (the wetted surface moves with the body).
        exc_deps = ("x",) if nonlinear.get("froude_krylov") else ()
        parts = [("x", DOF_UNITS, "input", "displacement from equilibrium", (), True),
                 ("v", VEL_UNITS, "input", "velocity", (), True),
                 ("F", FORCE_UNITS, "output", "total hydrodynamic force (the parts below)", ("x", "v"), True),
                 ("F_exc", FORCE_UNITS, "output", "wave excitation force", exc_deps, sw.excitation),
                 ("F_rad", FORCE_UNITS, "output", "radiation memory force (A_inf part excluded)", ("v",),
                  sw.radiation),
                 ("F_hs", FORCE_UNITS, "output", "hydrostatic restoring force", ("x",), sw.hydrostatics),
                 ("F_visc", FORCE_UNITS, "output", "viscous force (linear damping and quadratic drag)", ("v",),
                  viscous)]
        for key, table, causality, desc, deps, present in parts:
            if present:
                self.add_reals(key, names(key), causality, zeros, unit=[table[d] for d in all_dofs],
                               description=desc, depends_on=deps)

    def _force_output_map(self) -> tuple[np.ndarray, np.ndarray | list[np.ndarray]]:
        """(rows of HydroModel.block, where they go): the force outputs that exist, as one stacked view of
        the value store when they are adjacent there (one copy per point), else one array each."""
        keys = [k for k in ("F", "F_exc", "F_rad", "F_hs", "F_visc") if k in self._arrays]
        rows = np.array([("F", "F_exc", "F_rad", "F_hs", "F_visc").index(k) for k in keys], dtype=np.intp)
        stacked = self.stacked(keys)
        return rows, stacked if stacked is not None else [self.array(k) for k in keys]

    def _register_coupling(self) -> None:
        """Outputs of the linearised force interface (fmu_base.coupling), if the scene lists its pattern."""
        self.pattern = CouplingPattern.from_json(self.spec["coupling"]) if "coupling" in self.spec else None
        if self.pattern is None:
            return
        coords = [(b, d) for b, ds in zip(self.body_names, self.dofs, strict=True) for d in ds]
        labels = [6 * i + d + 1 for i, ds in enumerate(self.dofs) for d in ds]
        nonlinear = self.spec.get("nonlinear", {})
        position = ("x",) if nonlinear.get("hydrostatics") or nonlinear.get("froude_krylov") else ()
        viscous = self.spec.get("viscous")
        velocity = ("v",) if viscous is not None and any(viscous["quadratic"]) and self.switches.viscous else ()
        deps = {"F0": position + velocity, "F0_rate": ("x",) if nonlinear.get("froude_krylov") else (),
                "dF_dx": position, "dF_dv": velocity}
        for group in coupling_variables(coords, labels, self.pattern.stiffness, self.pattern.damping):
            self.add_reals(group.key, group.names, "output", np.zeros(len(group.names)), unit=group.units,
                           description=group.description, depends_on=deps[group.key])
        self._pattern_index = {key: tuple(np.array(getattr(self.pattern, key), dtype=int).reshape(-1, 2).T)
                               for key in ("stiffness", "damping")}
        self._affine_vrs = {vr for key in ("F0", "F0_rate", "dF_dx", "dF_dv")
                            for vr, (a, _) in self._slot.items() if a is self._arrays[key]}

    def _register_added_mass(self) -> None:
        index = [6 * b + d for b, ds in enumerate(self.dofs) for d in ds]
        sub = self.hdb.select_bodies(self.body_names)
        values = sub.added_mass_inf[np.ix_(index, index)]
        labels = [k + 1 for k in index]
        units = [("kg", "kg.m", "kg.m2")[(k % 6 >= 3) + (l % 6 >= 3)] for k in index for l in index]
        self.add_reals("A_inf", matrix_names("A_inf", labels, labels), "calculatedParameter", values.ravel(),
                       unit=units, description="infinite-frequency added mass (scene DOF numbering)")

    def _register_report(self) -> None:
        for name, desc in (("radiation.order", "state-space order of the radiation model (0: convolution)"),
                           ("radiation.fit_error", "scaled error of the fitted impulse response (0: convolution)"),
                           ("radiation.frequency_error", "scaled error of the model's A, B against the database")):
            self.add_reals(name, [name], "calculatedParameter", [0.0], description=desc)

    # ------------------------------------------------------------------ model
    def _parameters(self) -> dict[str, float]:
        return {k: float(a[0]) for k, a in self._arrays.items() if k.startswith(("wave.", "radiation."))
                and k not in ("wave.elevation", "radiation.order", "radiation.fit_error", "radiation.frequency_error")}

    def _build_if_changed(self) -> None:
        p = self._parameters()
        signature = (tuple(sorted(p.items())), self.seed)
        if self.model is not None and signature == self._built_with:
            return
        self.model = self._build_model(p)
        self._built_with = signature
        report = self.model.report
        self.array("radiation.order")[0] = report.order
        self.array("radiation.fit_error")[0] = report.kernel_error
        self.array("radiation.frequency_error")[0] = report.frequency_error

    def _build_model(self, p: dict[str, float]) -> HydroModel:
        changes = {key: p[name] for kind in WAVE_PARAMETERS.values() for name, key, _, _ in kind if name in p}
        for name, key in (("wave.heading", "heading"), ("wave.ramp_time", "ramp_time")):
            if name in p:
                changes[key] = p[name]
        sea = build_sea(dataclasses.replace(self.sea_spec, seed=self.seed, **changes))
        r, e = self.spec["radiation"], self.spec["excitation"]
        nonlinear = self.spec.get("nonlinear", {})
        viscous = self.spec.get("viscous")
        options = HydroOptions(
            radiation_method=r.get("method", "convolution"), irf_d_omega=r.get("irf_d_omega", 0.0),
            damping_tail=r.get("damping_tail", 0.0),
            tail_correction=(None if not r.get("tail_correction") else
                             (np.array(r["tail_correction"]["nodes"]), np.array(r["tail_correction"]["values"]))),
            state_space_tolerance=p.get("radiation.state_space_tolerance",
                                        r.get("state_space_tolerance", DEFAULT_TOLERANCE)),
            state_space_max_order=r.get("state_space_max_order", 60),
            excitation_method=e.get("method", "superposition"), excitation_irf_duration=e.get("irf_duration", 30.0),
            nonlinear_hydrostatics=nonlinear.get("hydrostatics", False),
            nonlinear_froude_krylov=nonlinear.get("froude_krylov", False),
            meshes=read_meshes(Path(self.resources) / nonlinear["meshes"]) if nonlinear.get("meshes") else {},
            viscous=None if viscous is None else ViscousCoefficients(np.array(viscous["linear"]),
                                                                     np.array(viscous["quadratic"])))
        model = HydroModel(self.hdb, self.body_names, self.dofs, sea.components, sea.ramp,
                           dt=p["radiation.dt"], irf_duration=p["radiation.irf_duration"], switches=self.switches,
                           options=options, record=sea.record)
        return model

    def _log_report(self, model: HydroModel) -> None:
        report = model.report
        if model.radiation is not None:
            if report.method == "state_space":
                text = (f"radiation: state space of order {report.order}, impulse-response error "
                        f"{report.kernel_error:.3g} (tolerance {model.options.state_space_tolerance:g})")
            else:
                text = f"radiation: convolution over {report.kernel_samples} kernel samples"
            text += f", error of A and B against the database {report.frequency_error:.3g}"
            self.log(text, Fmi2Status.ok)
        for message in report.warnings:
            self.log(message, Fmi2Status.warning)

    # ------------------------------------------------------------------ FMI life cycle
    def setup_experiment(self, start_time: float, stop_time: float | None, tolerance: float | None) -> None:
        self.time = float(start_time)
        self.clock = StepClock(self.time)

    def exit_initialization_mode(self) -> None:
        try:
            self._build_if_changed()
        except ValueError as exc:  # bad parameter values: explain, then let the host see the error
            self.log(str(exc), Fmi2Status.error)
            raise
        self._log_report(self.model)  # here, not at instantiation: hosts enable logging after that
        self.model.start_time = self.time
        self._ready = True
        self.mark_outputs_stale()

    def update_outputs(self) -> None:
        """Every output of the current point in one pass (:meth:`HydroModel.outputs`: forces, their copy into the
        output variables, powers and work; one runtime call)."""
        rows, outputs = self._force_outputs
        self._affine_fresh = False
        if isinstance(outputs, np.ndarray):
            self._elevation[0] = self.model.outputs(self.time, self._x, self._v, rows, outputs, self._power,
                                                    self._energy)
            return
        block = np.zeros((len(rows), len(self._v)))  # outputs not adjacent in the store: copied one by one
        self._elevation[0] = self.model.outputs(self.time, self._x, self._v, rows, block, self._power, self._energy)
        for row, out in zip(block, outputs, strict=True):
            out[:] = row

    def get_real(self, vrs: list[int]) -> list[float]:
        """Outputs of the current point; the linearised force interface's (F0, F0_rate, dF_dx, dF_dv) only when a
        host reads them (a master using the plain force ``F`` does not pay for them). Its memory rate is the
        backward difference between the last two points where it was read (every point for a host that reads
        it at every step, as the interface expects)."""
        if self._outputs_stale and self._ready:  # refresh_outputs(), inlined: this runs at every step
            self.update_outputs()
            self._outputs_stale = False
        if self.pattern is not None and self._ready and not self._affine_fresh and not self._affine_vrs.isdisjoint(vrs):
            self._update_affine()
        return self._values.gather(vrs)

    def _update_affine(self) -> None:
        a = self.model.affine(self.time, self._x, self._v, self.pattern)  # at this point (its outputs ran first)
        self.array("F0")[:] = a.constant
        self.array("F0_rate")[:] = a.rate
        self.array("dF_dx")[:] = a.dfdx[self._pattern_index["stiffness"]]
        self.array("dF_dv")[:] = a.dfdv[self._pattern_index["damping"]]
        self._affine_fresh = True

    def do_step(self, current_time: float, step_size: float) -> bool:
        if self._outputs_stale:  # the power at this point (its inputs set, outputs maybe not read)
            self.update_outputs()
            self._outputs_stale = False
        self.model.commit_work(self.time, self._x, self._v)  # the FMU's own clock (below); work at this point
        try:
            self.model.advance(current_time, step_size, self._v)  # the memories copy what they keep
        except ValueError as exc:
            self.log(str(exc), Fmi2Status.error)
            return False
        # The FMU's own clock, not the host's current_time + step_size: hosts compute the communication point
        # differently (fmpy adds the step, libcosim counts nanoseconds, a C loop multiplies), and a last-bit
        # difference in the excitation's time must not make the answer depend on the host (advance() has
        # checked that current_time agrees with this clock).
        self.time = self.clock.advance(step_size)
        self.mark_outputs_stale()
        return True
