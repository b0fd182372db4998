"""The hydrodynamic force model of a scene: what the hydro FMU computes, usable without FMI.

For the selected degrees of freedom of the hydrodynamic bodies,

    F(t) = F_exc(t) - mu(t) + F_hs(x) + F_visc(v),

excitation (:mod:`hydro_fmu.excitation`: superposition or impulse-response convolution; with a
nonlinear Froude-Krylov force the database's diffraction part plus
:mod:`hydro_fmu.nonlinear_hydrostatics`), radiation memory (:mod:`hydro_fmu.radiation`
convolution or :mod:`hydro_fmu.state_space`), hydrostatics (linear -C x or nonlinear over the
instantaneous wetted mesh) and viscous forces (:mod:`hydro_fmu.drag`). The infinite-frequency
added mass is not in F: :attr:`HydroModel.added_mass_inf` is published for the multibody mass
matrix. Only the selected bodies, degrees of freedom and force components are computed.

Time stepping: inputs (x, v) are samples at communication points; the force at a point uses the
inputs at that point (direct feedthrough). :meth:`HydroModel.advance` commits the velocity of the
current point to the radiation memory and moves on by the step: a whole number of convolution
steps ``dt`` for the convolution, any step for the state space.

One implementation: the constructor does the offline preparation (database selection, excitation
coefficients, impulse responses, state-space fit, meshes, checks) and hands it to the compiled runtime
(:mod:`hydro_fmu.runtime`, ``native/src/hydro``), which does every step-time computation: forces,
elevation, powers and work, the linearised interface, the memories and their state. The Python
component objects kept here (:attr:`HydroModel.excitation`, :meth:`HydroModel.reference_memory`, the
pressure models...) are the preparation and the independent references the runtime is tested against.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .drag import ViscousCoefficients, ViscousForce
from .excitation import ExcitationConvolution, ExcitationForce
from .hdb import DOF_NAMES, HydroDatabase
from .hydrostatics import LinearHydrostatics
from .linearisation import AffineForce, CouplingPattern
from .meshes import SurfaceMesh
from .nonlinear_hydrostatics import BodyPressureModel
from .radiation import RadiationMemory, damping_tail, impulse_response, irf_diagnostics, resample_damping
from .runtime import HydroRuntime
from .runtime_input import runtime_input
from .state_space import DEFAULT_MAX_ORDER, DEFAULT_TOLERANCE, StateSpaceMemory, fit_state_space, frequency_error
from .waves import Ramp, WaveComponents

RADIATION_METHODS = ("convolution", "state_space")
FORCE_ROWS = ("total", "excitation", "radiation", "hydrostatic", "viscous")  # rows of HydroModel.block
EXCITATION_METHODS = ("superposition", "convolution")


@dataclass(frozen=True)
class ForceSwitches:
    """Which force components the model computes (all on by default)."""

    excitation: bool = True
    radiation: bool = True
    hydrostatics: bool = True
    viscous: bool = True


@dataclass(frozen=True)
class HydroOptions:
    """How each force component is computed (beyond the radiation step and kernel length).

    Attributes:
        radiation_method: ``convolution`` (trapezoidal, step ``dt``) or ``state_space``.
        irf_d_omega: frequency step (rad/s) of the impulse-response transform; 0 = the database's.
        damping_tail: exponent n of B's continuation above the database (0 = cut there), see
            :func:`hydro_fmu.radiation.damping_tail`.
        tail_correction: (nodes (k,), values (k, 6 N, 6 N) on all DOFs of the model's bodies) added to that
            continuation (:func:`hydro_fmu.radiation.kramers_kronig_tail`); None: none.
        state_space_tolerance, state_space_max_order: order selection of the state-space fit.
        excitation_method: ``superposition`` or ``convolution`` (non-causal impulse response).
        excitation_irf_duration: half-length of the excitation kernel (s).
        nonlinear_hydrostatics, nonlinear_froude_krylov: pressure integration over the wetted mesh.
        meshes: body name -> hull mesh relative to its centre of gravity (nonlinear options).
        viscous: per selected DOF viscous coefficients (None: no viscous force).
    """

    radiation_method: str = "convolution"
    irf_d_omega: float = 0.0
    damping_tail: float = 0.0
    tail_correction: tuple[np.ndarray, np.ndarray] | None = None
    state_space_tolerance: float = DEFAULT_TOLERANCE
    state_space_max_order: int = DEFAULT_MAX_ORDER
    excitation_method: str = "superposition"
    excitation_irf_duration: float = 30.0
    nonlinear_hydrostatics: bool = False
    nonlinear_froude_krylov: bool = False
    meshes: dict[str, SurfaceMesh] = field(default_factory=dict)
    viscous: ViscousCoefficients | None = None

    def __post_init__(self) -> None:
        if self.radiation_method not in RADIATION_METHODS:
            raise ValueError(f"radiation method must be one of {RADIATION_METHODS}, not {self.radiation_method!r}")
        if self.excitation_method not in EXCITATION_METHODS:
            raise ValueError(f"excitation method must be one of {EXCITATION_METHODS}, not {self.excitation_method!r}")


@dataclass
class HydroForces:
    """Force components (N, N m) on the selected degrees of freedom at one instant."""

    total: np.ndarray
    excitation: np.ndarray
    radiation: np.ndarray
    hydrostatic: np.ndarray
    viscous: np.ndarray


@dataclass
class RadiationReport:
    """What the radiation model is and how accurate it is (reported, not hidden).

    Attributes:
        method: ``convolution`` or ``state_space``.
        kernel_samples: number of kernel samples (convolution).
        order: state-space order (0 for the convolution).
        kernel_error: state-space fit error against the impulse response (scaled, see
            :func:`hydro_fmu.state_space.scaled_error`); 0 for the convolution.
        frequency_error: error of the model's A(omega), B(omega) against the database (scaled);
            for the convolution, that of the truncated impulse response itself.
        warnings: impulse-response accuracy warnings.
    """

    method: str
    kernel_samples: int = 0
    order: int = 0
    kernel_error: float = 0.0
    frequency_error: float = float("nan")
    warnings: list[str] = field(default_factory=list)


class HydroModel:
    """Hydrodynamic forces on selected degrees of freedom of selected bodies.

    Args:
        hdb: database holding at least ``bodies``.
        bodies: names of the hydrodynamic bodies, in the order of the scene.
        dofs: per body, the active degrees of freedom (0 = surge ... 5 = yaw).
        waves: incident wave components.
        ramp: start-up ramp of the excitation.
        dt: time step of the radiation convolution (s); communication steps must be multiples of it.
        irf_duration: length of the impulse response kernel (s).
        switches: force components to compute.
        options: methods and their settings.
        record: an imported elevation record eta(t) at the origin (unramped, vectorised), if the sea
            comes from one: the elevation output and the excitation convolution use it instead of
            the component sum.
    """

    def __init__(
        self,
        hdb: HydroDatabase,
        bodies: list[str],
        dofs: list[list[int]],
        waves: WaveComponents,
        ramp: Ramp,
        dt: float,
        irf_duration: float,
        switches: ForceSwitches = ForceSwitches(),
        options: HydroOptions = HydroOptions(),
        record=None,
    ) -> None:
        if not dt > 0:
            raise ValueError(f"radiation time step must be positive (got {dt})")
        sub = hdb.select_bodies(bodies)
        self.hdb = sub
        self.bodies = list(bodies)
        self.dofs = [list(d) for d in dofs]
        self.index = np.array([6 * b + d for b, ds in enumerate(dofs) for d in ds], dtype=int)
        self.labels = [f"{bodies[k // 6]} {DOF_NAMES[k % 6]}" for k in self.index]
        self.switches = switches
        self.options = options
        self.waves = waves
        self.ramp = ramp
        self.dt = float(dt)
        self.irf_duration = float(irf_duration)
        self.added_mass_inf = sub.added_mass_inf[np.ix_(self.index, self.index)]
        self.record = record
        self.excitation = self._excitation(record) if switches.excitation else None
        self.hydrostatics = LinearHydrostatics(sub, self.index)
        self.pressure_models = self._pressure_models()
        self.viscous = (ViscousForce(options.viscous) if switches.viscous and options.viscous is not None
                        and options.viscous.active else None)
        self.report = RadiationReport(options.radiation_method)
        self.state_space = None
        if switches.radiation:
            self._radiation()
        self.runtime = HydroRuntime(runtime_input(self))  # every step-time computation from here on
        self._masks: tuple[CouplingPattern, np.ndarray, np.ndarray] | None = None

    # ------------------------------------------------------------------ construction
    @property
    def nonlinear(self) -> bool:
        o = self.options
        return (o.nonlinear_hydrostatics and self.switches.hydrostatics) or (
            o.nonlinear_froude_krylov and self.switches.excitation)

    def _excitation(self, record):
        o = self.options
        part = "diffraction" if o.nonlinear_froude_krylov else "total"
        if o.excitation_method == "superposition":
            return ExcitationForce(self.hdb, self.waves, self.index, self.ramp, part)
        if o.nonlinear_froude_krylov:
            raise ValueError("the excitation convolution cannot be combined with a nonlinear Froude-Krylov force")
        if not self.waves.unidirectional:
            raise ValueError("the excitation convolution needs a unidirectional sea (no directional spreading)")
        eta = record if record is not None else self.waves.elevation
        return ExcitationConvolution(self.hdb, self.index, self.waves.main_heading, eta,
                                     o.excitation_irf_duration, self.dt, self.ramp)

    def _pressure_models(self) -> dict[int, BodyPressureModel]:
        if not self.nonlinear:
            return {}
        models = {}
        for b, name in enumerate(self.bodies):
            if name not in self.options.meshes:
                raise ValueError(f"body {name!r}: the nonlinear hydrostatic/Froude-Krylov force needs its hull mesh")
            models[b] = BodyPressureModel(self.options.meshes[name], self.hdb.cg[b], self.hdb.rho, self.hdb.g,
                                          self.hdb.water_depth)
        return models

    def _radiation(self) -> None:
        """The impulse response (:attr:`kernel` at :attr:`kernel_time`), its report and, for the state space, the
        fit (:attr:`state_space`)."""
        o = self.options
        omega, damping = self.hdb.omega, self.hdb.radiation_damping[:, self.index][:, :, self.index]
        if o.irf_d_omega > 0:
            omega, damping = resample_damping(omega, damping, o.irf_d_omega)
        correction = None
        if o.tail_correction is not None:
            nodes, values = o.tail_correction
            correction = (np.asarray(nodes, dtype=float), np.asarray(values)[:, self.index][:, :, self.index])
        table = damping_tail(omega, damping, o.damping_tail, correction=correction)
        n_kernel = max(2, int(math.ceil(self.irf_duration / self.dt)) + 1)
        self.kernel_time = np.arange(n_kernel) * self.dt
        self.kernel = impulse_response(*table, self.kernel_time)
        self.report.warnings = irf_diagnostics(omega, damping, self.kernel_time, self.kernel, self.labels,
                                               continued=o.damping_tail > 0 or correction is not None)
        self.report.kernel_samples = n_kernel
        added_mass = self.hdb.added_mass[:, self.index][:, :, self.index]
        if o.radiation_method == "convolution":
            table = self.hdb.radiation_damping[:, self.index][:, :, self.index]
            self.report.frequency_error = _kernel_frequency_error(
                self.kernel_time, self.kernel, self.hdb.omega, added_mass, table, self.added_mass_inf,
                self._scale_floors(table))
            return
        floors = self._scale_floors(self.kernel)
        body = self.index // 6  # one realisation per pair of bodies (order proportional to what couples)
        groups = [np.nonzero(body == b)[0] for b in np.unique(body)]
        fit = fit_state_space(self.kernel_time, self.kernel, float(omega[-1]), o.state_space_tolerance,
                              o.state_space_max_order,
                              kernel_function=lambda t: impulse_response(*table, t), floors=floors, groups=groups)
        self.state_space = fit
        self.report.order = fit.order
        self.report.kernel_error = fit.kernel_error
        self.report.frequency_error = frequency_error(
            fit, self.hdb.omega, added_mass, self.hdb.radiation_damping[:, self.index][:, :, self.index],
            self.added_mass_inf, self._scale_floors(self.hdb.radiation_damping[:, self.index][:, :, self.index]))

    @property
    def radiation(self) -> str | None:
        """The radiation memory's method (``convolution`` or ``state_space``), None when it is off."""
        return self.options.radiation_method if self.switches.radiation else None

    def reference_memory(self) -> RadiationMemory | StateSpaceMemory | None:
        """A new Python radiation memory of this model at rest (the reference implementation of what the runtime
        steps: tests, benchmarks), None when the radiation is off."""
        if self.radiation is None:
            return None
        return StateSpaceMemory(self.state_space) if self.state_space is not None else RadiationMemory(
            self.kernel, self.dt)

    def _scale_floors(self, table: np.ndarray) -> np.ndarray:
        """1e-3 of the largest diagonal norm among the DOFs of the same kind (translation, rotation)."""
        from .state_space import dof_scales

        s = dof_scales(table)
        rotation = self.index % 6 >= 3
        floors = np.zeros_like(s)
        for kind in (rotation, ~rotation):
            if kind.any():
                floors[kind] = 1e-3 * s[kind].max()
        return floors

    # ------------------------------------------------------------------ forces
    @property
    def n(self) -> int:
        """Number of selected degrees of freedom."""
        return len(self.index)

    def forces(self, t: float, x: np.ndarray, v: np.ndarray) -> HydroForces:
        """Force components at time ``t`` (s) for displacement ``x`` and velocity ``v``."""
        self.runtime.evaluate(t, x, v)
        return HydroForces(*self.runtime.block.copy())

    def evaluate(self, t: float, x: np.ndarray, v: np.ndarray) -> float:
        """The force components at time ``t`` (s) for ``x``, ``v`` written into :attr:`block` (rows in
        :data:`FORCE_ROWS` order: total, excitation, radiation, hydrostatic, viscous); returns the wave
        elevation at the origin (m). One runtime call (native/src/hydro/evaluate.c)."""
        return self.runtime.evaluate(t, x, v)

    @property
    def block(self) -> np.ndarray:
        """The force rows (5, n) of the last :meth:`evaluate` or :meth:`forces`."""
        return self.runtime.block

    def outputs(self, t: float, x: np.ndarray, v: np.ndarray, rows: np.ndarray, out: np.ndarray,
                power: np.ndarray, energy: np.ndarray) -> float:
        """Everything the FMU publishes at time ``t`` (s) for ``x``, ``v``: the force rows ``rows`` (FORCE_ROWS
        indices) into the rows of ``out``, the power of each component (W, :data:`hydro_fmu.work.COMPONENTS` order)
        into ``power`` and its work at ``t`` (J; trapezoidal rule over the committed points) into ``energy``; returns
        the wave elevation at the origin (m). One runtime call."""
        return self.runtime.outputs(t, x, v, rows, out, power, energy)

    def commit_work(self, t: float, x: np.ndarray, v: np.ndarray) -> None:
        """Accept the point ``t`` for inputs ``x``, ``v`` into the work account (evaluated there if it was not)."""
        self.runtime.commit_work(t, x, v)

    def affine(self, t: float, x: np.ndarray, v: np.ndarray, pattern: CouplingPattern,
               forces: HydroForces | None = None) -> AffineForce:
        """The affine model of the force over the next step about (t, x, v), with the tangents restricted to
        ``pattern`` (:mod:`hydro_fmu.linearisation`; native/src/hydro/linearised.c). Call it at every communication
        point: the memory rate is the difference between the last two calls at different times. ``forces`` (the
        point's forces, if known) is not needed: the runtime keeps its last point."""
        if self._masks is None or self._masks[0] is not pattern:
            self._masks = (pattern, pattern.mask(self.n, "stiffness"), pattern.mask(self.n, "damping"))
        return AffineForce(*self.runtime.linearise(t, x, v, self._masks[1], self._masks[2]))

    def advance(self, t: float, h: float, v: np.ndarray) -> None:
        """Commit the velocity at time ``t`` and step to ``t + h`` (convolution: ``h`` a whole number of radiation
        steps ``dt``, any number, so variable communication steps work; state space: any h); ``ValueError`` with
        the reason if the step cannot be taken (t not the current point, h not a multiple of dt)."""
        self.runtime.advance(t, h, v)

    def elevation(self, t: float) -> float:
        """Incident wave elevation at the world origin (m): the record if imported, else the components."""
        return self.runtime.elevation(t)

    @property
    def start_time(self) -> float:
        """Time of the first communication point (s)."""
        return getattr(self, "_start_time", 0.0)

    @start_time.setter
    def start_time(self, value: float) -> None:
        self._start_time = float(value)
        self.runtime.set_start_time(value)

    # ------------------------------------------------------------------ copies and state
    def __deepcopy__(self, memo: dict) -> HydroModel:
        """An independent model: the preparation shared (read-only), the runtime cloned (its state copied)."""
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        new.runtime = self.runtime.clone()
        memo[id(self)] = new
        return new

    def __copy__(self) -> HydroModel:
        """The same as a deep copy: a model's copy steps on its own."""
        return self.__deepcopy__({})

    def __getstate__(self) -> dict:
        """What changes as the model runs: the runtime's state (bytes) and the start time; everything else is the
        preparation, which a state is loaded back onto (:mod:`fmu_base.state_codec` templates, FMU states)."""
        return {"runtime": self.runtime.state(), "start_time": self.start_time}

    def __setstate__(self, state: dict) -> None:
        if "runtime" not in vars(self):
            raise ValueError("a hydro model state is loaded into a model built from the same scene, not on its own")
        if not isinstance(state, dict) or not isinstance(state.get("runtime"), bytes):
            raise ValueError("not a hydro model state of the compiled runtime (a state saved by an earlier version of "
                             "the toolkit cannot be loaded: run again from the start)")
        self.runtime.load_state(state["runtime"])
        self._start_time = float(state["start_time"])


def _kernel_frequency_error(t: np.ndarray, kernel: np.ndarray, omega: np.ndarray, added_mass: np.ndarray,
                            damping: np.ndarray, added_mass_inf: np.ndarray, floors: np.ndarray) -> float:
    """Scaled error of the truncated, sampled kernel's A(omega), B(omega) against the database."""
    from .state_space import dof_scales, scaled_error

    dt = t[1] - t[0]
    w = np.full(len(t), dt)
    w[0] = w[-1] = dt / 2
    b = np.einsum("wt,tij->wij", np.cos(np.outer(omega, t)) * w, kernel)
    wa = -np.einsum("wt,tij->wij", np.sin(np.outer(omega, t)) * w, kernel)
    ref = np.concatenate([damping, omega[:, None, None] * (added_mass - added_mass_inf[None])], axis=0)
    return scaled_error(ref, np.concatenate([b, wa], axis=0), dof_scales(ref, floors))
