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
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .drag import ViscousCoefficients, ViscousForce
from .excitation import ExcitationConvolution, ExcitationForce
from .hdb import DOF_NAMES, HydroDatabase
from .hydrostatics import LinearHydrostatics
from .kernels import COMPILED, RADIATION_CONVOLUTION, RADIATION_GIVEN, RADIATION_NONE, point_outputs
from .linearisation import AffineForce, CouplingPattern, MemoryRate
from .meshes import SurfaceMesh
from .nonlinear_hydrostatics import BodyPressureModel
from .radiation import RadiationMemory, damping_tail, impulse_response, irf_diagnostics, resample_damping
from .state_space import (
    DEFAULT_MAX_ORDER,
    DEFAULT_TOLERANCE,
    CombinedMemory,
    StateSpaceMemory,
    fit_cached,
    frequency_error,
    sampling_step,
)
from .waves import PhasorClock, Ramp, WaveComponents
from .work import WorkAccount

RADIATION_METHODS = ("convolution", "state_space")
# Arguments of the compiled pass for the parts a model does not have (never read there)
_NO_VECTOR = np.zeros(0)
_NO_MATRIX = np.zeros((2, 0))
_NO_ROWS = np.zeros(0, dtype=np.intp)
_NO_BLOCK = np.zeros(4, dtype=np.int64)
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
        still: (body, DOF) pairs whose velocity is always zero (a fixed body, a locked joint): the state-space
            fit gives their columns no memory (:func:`hydro_fmu.state_space.fit_state_space`).
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
    still: tuple[tuple[str, int], ...] = ()
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
        warnings: impulse-response accuracy warnings (and state-space blocks left to the convolution).
        convolution_blocks: (force on body, from the motion of body) of each state-space block no order up to
            the limit fitted, left to the convolution.
    """

    method: str
    kernel_samples: int = 0
    order: int = 0
    kernel_error: float = 0.0
    frequency_error: float = float("nan")
    warnings: list[str] = field(default_factory=list)
    convolution_blocks: list[tuple[str, str]] = field(default_factory=list)


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
        self.start_time = 0.0
        self._elapsed = 0.0
        self._elapsed_error = 0.0  # compensation of the running sum of steps (advance)
        self.record = record
        self._clock = PhasorClock(waves.omega)
        self.excitation = self._excitation(record) if switches.excitation else None
        self.hydrostatics = LinearHydrostatics(sub, self.index)
        self.pressure_models = self._pressure_models()
        self.viscous = (ViscousForce(options.viscous) if switches.viscous and options.viscous is not None
                        and options.viscous.active else None)
        self.report = RadiationReport(options.radiation_method)
        self.radiation = self._radiation() if switches.radiation else None
        self._memory_rate = MemoryRate()
        self._restoring = -self.hydrostatics.stiffness  # F_hs = -C x as one product (evaluate())
        self.block = np.zeros((len(FORCE_ROWS), self.n))  # evaluate(): the force components, FORCE_ROWS order
        self._phasor_table = self._combined_phasor_table()

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

    def _combined_phasor_table(self) -> np.ndarray | None:
        """(K, n + 1) complex: the excitation's complex force amplitude of each wave component (zero for the
        components above the database, which it leaves out) and, last, the component's complex elevation
        amplitude, so that one product with exp(i omega_k t) gives both (:meth:`evaluate`); None if the
        excitation or the elevation is not the superposition of the components."""
        convolution = self.excitation is not None and not isinstance(self.excitation, ExcitationForce)
        if self.record is not None or convolution:
            return None
        table = np.zeros((len(self.waves.omega), self.n + 1), complex)
        table[:, self.n] = self.waves.complex_amplitude
        if self.excitation is not None and len(self.excitation.omega):
            keep = np.asarray(self.waves.omega, dtype=float) <= self.hdb.omega[-1]  # as ExcitationForce
            table[keep, : self.n] = self.excitation.coefficients
        return table

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

    def _radiation(self):
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
            return RadiationMemory(self.kernel, self.dt)
        body = self.index // 6  # one realisation per pair of bodies (order proportional to what couples)
        groups = [np.nonzero(body == b)[0] for b in np.unique(body)]
        still_pairs = {(b, int(d)) for b, d in o.still}
        still = np.array([(self.bodies[k // 6], k % 6) in still_pairs for k in self.index], dtype=bool)
        sampling = sampling_step(*table, float(omega[-1]), o.state_space_tolerance, float(self.kernel_time[-1]))
        fit = fit_cached(table, self.kernel_time, self.kernel, omega_max=float(omega[-1]),
                         tolerance=o.state_space_tolerance, max_order=o.state_space_max_order, groups=groups,
                         kinds=self.index % 6 >= 3, still=still, fallback=True, sampling=sampling)
        self.state_space = fit
        self.report.order = fit.order
        self.report.kernel_error = fit.kernel_error
        memory = StateSpaceMemory(fit)
        if fit.convolution_blocks:
            left = np.zeros_like(self.kernel)
            for blk in fit.convolution_blocks:
                entries = (slice(None), blk.rows[:, None], blk.columns[None, :])
                left[entries] = self.kernel[entries]
                self.report.convolution_blocks.append((self.bodies[int(self.index[blk.rows[0]]) // 6],
                                                       self.bodies[int(self.index[blk.columns[0]]) // 6]))
                self.report.warnings.append(
                    f"radiation: the state-space fit of the force on {self.report.convolution_blocks[-1][0]} from the "
                    f"motion of {self.report.convolution_blocks[-1][1]} reaches no better than {blk.error:.3g} (order "
                    f"{blk.order}) against the tolerance {o.state_space_tolerance:g} within the order limit "
                    f"{o.state_space_max_order}: that block is the convolution (raise hydro.state_space_max_order or "
                    "hydro.state_space_tolerance to fit it)")
            memory = CombinedMemory(memory, RadiationMemory(left, self.dt))
        effective = fit if not fit.convolution_blocks else None
        table_b = self.hdb.radiation_damping[:, self.index][:, :, self.index]
        if effective is not None:
            self.report.frequency_error = frequency_error(fit, self.hdb.omega, added_mass, table_b,
                                                          self.added_mass_inf, self._scale_floors(table_b),
                                                          columns=~still)
        else:  # the combined model's A, B: the fit's transfer function plus the convolution blocks' transform
            self.report.frequency_error = _kernel_frequency_error(
                self.kernel_time, left, self.hdb.omega, added_mass, table_b, self.added_mass_inf,
                self._scale_floors(table_b), fit=fit, columns=~still)
        return memory

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
        zero = np.zeros(self.n)
        exc = self.excitation(t) if self.excitation is not None else zero
        rad = -self.radiation.force(v) if self.radiation is not None else zero
        visc = self.viscous(v) if self.viscous is not None else zero
        o, sw = self.options, self.switches
        hs = self.hydrostatics(x) if sw.hydrostatics and not o.nonlinear_hydrostatics else zero
        if self.nonlinear:
            hs_nl, fk = self._pressure_forces(t, x)
            if o.nonlinear_hydrostatics and sw.hydrostatics:
                hs = hs_nl
            if o.nonlinear_froude_krylov and sw.excitation:
                exc = exc + fk
        return HydroForces(total=exc + rad + hs + visc, excitation=exc, radiation=rad, hydrostatic=hs, viscous=visc)

    def evaluate(self, t: float, x: np.ndarray, v: np.ndarray) -> float:
        """The force components at time ``t`` (s) for ``x``, ``v`` written into :attr:`block` (rows in
        :data:`FORCE_ROWS` order: total, excitation, radiation, hydrostatic, viscous); returns the wave
        elevation at the origin (m).

        The same values as :meth:`forces` and :meth:`elevation` to round-off (only the order of some sums
        differs), in one pass over preallocated arrays: excitation and elevation from one product of the
        phasors with :meth:`_combined_phasor_table`, the radiation memory as one matrix-vector product into
        its row, the total as one sum over the rows. A nonlinear model, an imported record or the excitation
        convolution take the general path for those parts.
        """
        block = self.block
        exc, rad, hs, visc = block[1], block[2], block[3], block[4]
        o, sw = self.options, self.switches
        table = self._phasor_table
        if table is not None:
            r = 1.0 if t >= self.ramp.duration else self.ramp(t)
            z = np.dot(self._clock(t), table)
            np.multiply(z.real[: self.n], r, out=exc)
            eta = float(z.real[self.n]) * r
        else:
            if self.excitation is not None:
                exc[:] = self.excitation(t)
            eta = self.elevation(t)
        if self.radiation is not None:
            self.radiation.force(v, out=rad)
            np.negative(rad, out=rad)
        if self.viscous is not None:
            visc[:] = self.viscous(v)
        if sw.hydrostatics and not o.nonlinear_hydrostatics:
            np.dot(self._restoring, x, out=hs)
        if self.nonlinear:
            hs_nl, fk = self._pressure_forces(t, x)
            if o.nonlinear_hydrostatics and sw.hydrostatics:
                hs[:] = hs_nl
            if o.nonlinear_froude_krylov and sw.excitation:
                exc += fk
        np.sum(block[1:], axis=0, out=block[0])  # ((exc + rad) + hs) + visc, as forces()
        return eta

    @property
    def compiled(self) -> bool:
        """Whether :meth:`outputs` runs the compiled pass (:func:`hydro_fmu.kernels.point_outputs`): numba
        available and a linear model whose excitation and elevation are the components' superposition."""
        return COMPILED and self._phasor_table is not None and not self.nonlinear

    def outputs(self, t: float, x: np.ndarray, v: np.ndarray, rows: np.ndarray, out: np.ndarray,
                power: np.ndarray, account: WorkAccount, energy: np.ndarray) -> float:
        """Everything the FMU publishes at time ``t`` (s) for ``x``, ``v``: the force components into
        :attr:`block` (as :meth:`evaluate`), its rows ``rows`` copied into the rows of ``out``, the power of each
        component (W, :data:`hydro_fmu.work.COMPONENTS` order) into ``power`` and the work at ``t`` (J) from
        ``account`` into ``energy``; returns the wave elevation at the origin (m).

        One compiled call (:mod:`hydro_fmu.kernels`) when :attr:`compiled`; else :meth:`evaluate` and numpy.
        Both give the values of :meth:`forces`, :meth:`elevation` and :class:`hydro_fmu.work.WorkAccount` to
        round-off (tests/test_hydro_fast_path.py).
        """
        if not self.compiled:
            eta = self.evaluate(t, x, v)
            np.take(self.block, rows, axis=0, out=out)
            np.dot(self.block[1:], v, out=power)  # COMPONENTS order: the block's rows after the total
            account.value(t, power, out=energy)
            return eta
        rad = self.radiation
        mode, ring, last, steps, gap, weights = RADIATION_NONE, _NO_MATRIX, _NO_VECTOR, 0, 1, _NO_MATRIX
        history, block = _NO_MATRIX, _NO_BLOCK
        if isinstance(rad, RadiationMemory):
            mode, ring, last, steps, gap, weights = (RADIATION_CONVOLUTION, rad._ring, rad._last, rad.steps, rad.gap,
                                                     rad._all)
            try:
                history, block = rad._history, rad._block
            except AttributeError:  # decoded from a state saved before the blocks existed
                rad._clear_block()
                history, block = rad._history, rad._block
        elif rad is not None:
            mode = RADIATION_GIVEN
            rad.force(v, out=self.block[2])
        visc = self.viscous
        hydrostatics = self.switches.hydrostatics
        last_power = account.last_power
        return point_outputs(float(t), self._clock(t), self._phasor_table, float(self.ramp.duration), mode, ring, last,
                             steps, gap, weights, history, block, hydrostatics,
                             self._restoring if hydrostatics else _NO_MATRIX,
                             visc is not None, _NO_VECTOR if visc is None else visc.linear,
                             _NO_VECTOR if visc is None else visc.quadratic, x, v, self.block, rows, out, power,
                             account.committed, _NO_VECTOR if last_power is None else last_power,
                             float(account.last_time), last_power is not None, energy)

    def affine(self, t: float, x: np.ndarray, v: np.ndarray, pattern: CouplingPattern,
               forces: HydroForces | None = None) -> AffineForce:
        """The affine model of the force over the next step about (t, x, v), with the tangents restricted to
        ``pattern`` (:mod:`hydro_fmu.linearisation`); ``forces``: :meth:`forces` at the same point if known.
        Call it at every communication point: the memory rate is the difference between the last two calls
        at different times."""
        n = self.n
        f = forces if forces is not None else self.forces(t, x, v)
        dfdx = np.zeros((n, n))
        dfdv = np.zeros((n, n))
        o, sw = self.options, self.switches
        if sw.hydrostatics and not o.nonlinear_hydrostatics:
            dfdx -= self.hydrostatics.stiffness
        if self.nonlinear:
            dfdx += self._pressure_tangent(t, x)
        rate = self.excitation.rate(t) if self.excitation is not None else np.zeros(n)
        if self.nonlinear and o.nonlinear_froude_krylov and sw.excitation:
            delta = 1e-4
            ahead, behind = self._pressure_forces(t + delta, x)[1], self._pressure_forces(t - delta, x)[1]
            rate = rate + (ahead - behind) / (2 * delta)
        if self.radiation is not None:
            d = self.radiation.instantaneous_damping()
            dfdv -= d
            known = -f.radiation - d @ v  # memory of the committed velocities (mu = -F_rad), without v's share
            rate = rate - self._memory_rate.update(t, known)
        if self.viscous is not None:
            dfdv += np.diag(self.viscous.tangent(v))
        dfdx = np.where(pattern.mask(n, "stiffness"), dfdx, 0.0)
        dfdv = np.where(pattern.mask(n, "damping"), dfdv, 0.0)
        return AffineForce(f.total - dfdx @ x - dfdv @ v, rate, dfdx, dfdv)

    def _pressure_tangent(self, t: float, x: np.ndarray, delta: float = 1e-6) -> np.ndarray:
        """d(F_hs + F_FK)/dx of the nonlinear pressure forces by central differences within each body."""
        n = self.n
        out = np.zeros((n, n))
        start = 0
        for dofs in self.dofs:
            for j in range(start, start + len(dofs)):
                e = np.zeros(n)
                e[j] = delta
                fp = sum(self._pressure_forces(t, x + e))
                fm = sum(self._pressure_forces(t, x - e))
                out[start:start + len(dofs), j] = (fp - fm)[start:start + len(dofs)] / (2 * delta)
            start += len(dofs)
        return out

    def _pressure_forces(self, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Nonlinear hydrostatic and Froude-Krylov forces on the selected DOFs."""
        hs = np.zeros(self.n)
        fk = np.zeros(self.n)
        o = self.options
        start = 0
        for b, dofs in enumerate(self.dofs):
            pose = np.zeros(6)
            pose[dofs] = x[start : start + len(dofs)]
            f_hs, f_fk = self.pressure_models[b].forces(
                pose, t, self.waves, self.ramp, hydrostatics=o.nonlinear_hydrostatics and self.switches.hydrostatics,
                froude_krylov=o.nonlinear_froude_krylov and self.switches.excitation)
            hs[start : start + len(dofs)] = f_hs[dofs]
            fk[start : start + len(dofs)] = f_fk[dofs]
            start += len(dofs)
        return hs, fk

    def advance(self, t: float, h: float, v: np.ndarray) -> None:
        """Commit the velocity at time ``t`` and step to ``t + h`` (convolution: ``h`` a whole number
        of radiation steps ``dt``, any number, so variable communication steps work; state space: any h)."""
        expected = self.start_time + self._elapsed
        if abs(t - expected) > 1e-6 * max(self.dt, abs(h)):
            raise ValueError(f"step starts at t = {t:g} s but the radiation history is at t = {expected:g} s")
        if self.radiation is not None:
            self.radiation.step(v, h)
        elif not h > 0:
            raise ValueError(f"a step must be positive (got {h})")
        # compensated (Kahan) sum: a plain sum of ~1e6 steps drifts by ~n u t (3e-6 s after 26 000 s at 0.02 s,
        # beyond the check above); compensated, by ~2 u t whatever the number of steps
        y = h - getattr(self, "_elapsed_error", 0.0)
        total = self._elapsed + y
        self._elapsed_error = (total - self._elapsed) - y
        self._elapsed = total

    def elevation(self, t: float) -> float:
        """Incident wave elevation at the world origin (m): the record if imported, else the components."""
        if self.record is not None:
            return float(self.record(t)) * self.ramp(t)
        return float(np.real(self._clock(t) @ self.waves.complex_amplitude)) * self.ramp(t)


def _kernel_frequency_error(t: np.ndarray, kernel: np.ndarray, omega: np.ndarray, added_mass: np.ndarray,
                            damping: np.ndarray, added_mass_inf: np.ndarray, floors: np.ndarray,
                            fit=None, columns: np.ndarray | None = None) -> float:  # noqa: ANN001 - StateSpaceFit
    """Scaled error of the truncated, sampled kernel's A(omega), B(omega) (plus ``fit``'s transfer function, for a
    state space with blocks left to the convolution) against the database; ``columns``: the DOFs whose columns
    count (those that can move)."""
    from .state_space import dof_scales, scaled_error

    dt = t[1] - t[0]
    w = np.full(len(t), dt)
    w[0] = w[-1] = dt / 2
    b = np.einsum("wt,tij->wij", np.cos(np.outer(omega, t)) * w, kernel)
    wa = -np.einsum("wt,tij->wij", np.sin(np.outer(omega, t)) * w, kernel)
    if fit is not None and fit.order:
        k = fit.transfer(omega)
        b = b + k.real
        wa = wa + k.imag
    ref = np.concatenate([damping, omega[:, None, None] * (added_mass - added_mass_inf[None])], axis=0)
    approx = np.concatenate([b, wa], axis=0)
    scales = dof_scales(ref, floors)
    if columns is None:
        return scaled_error(ref, approx, scales)
    return scaled_error(ref[:, :, columns], approx[:, :, columns], scales, scales[columns])
