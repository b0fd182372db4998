"""The hydrodynamic force model of a scene: what the hydro FMU computes, usable without FMI.

For the selected degrees of freedom of the hydrodynamic bodies,

    F(t) = F_exc(t) - mu(t) - C x(t),

excitation (:mod:`hydro_fmu.excitation`), radiation memory (:mod:`hydro_fmu.radiation`) and
linear hydrostatics (:mod:`hydro_fmu.hydrostatics`). The infinite-frequency added mass is not
in F: :attr:`HydroModel.added_mass_inf` is published for the multibody mass matrix.

Time stepping: inputs (x, v) are samples at communication points; the force at a point uses
the inputs at that point (direct feedthrough). :meth:`HydroModel.advance` stores the velocity
of the current point in the radiation history and moves on by a whole number of steps ``dt``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .excitation import ExcitationForce
from .hdb import HydroDatabase
from .hydrostatics import LinearHydrostatics
from .radiation import RadiationMemory, impulse_response
from .waves import Ramp, WaveComponents


@dataclass(frozen=True)
class ForceSwitches:
    """Which force components the model computes (all on by default)."""

    excitation: bool = True
    radiation: bool = True
    hydrostatics: bool = True


@dataclass
class HydroForces:
    """Force components (N, N m) on the selected degrees of freedom at one instant."""

    total: np.ndarray
    excitation: np.ndarray
    radiation: np.ndarray
    hydrostatic: np.ndarray


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
    ) -> None:
        if not dt > 0:
            raise ValueError(f"radiation time step must be positive (got {dt})")
        sub = hdb.select_bodies(bodies)
        self.hdb = sub
        self.index = np.array([6 * b + d for b, ds in enumerate(dofs) for d in ds], dtype=int)
        self.switches = switches
        self.waves = waves
        self.ramp = ramp
        self.dt = float(dt)
        self.excitation = ExcitationForce(sub, waves, self.index, ramp)
        self.hydrostatics = LinearHydrostatics(sub, self.index)
        n_kernel = max(2, int(math.ceil(irf_duration / dt)) + 1)
        t_kernel = np.arange(n_kernel) * dt
        damping = sub.radiation_damping[:, self.index][:, :, self.index]
        self.kernel_time = t_kernel
        self.kernel = impulse_response(sub.omega, damping, t_kernel)
        self.radiation = RadiationMemory(self.kernel, dt)
        self.added_mass_inf = sub.added_mass_inf[np.ix_(self.index, self.index)]
        self.start_time = 0.0
        self._grid_steps = 0

    @property
    def n(self) -> int:
        """Number of selected degrees of freedom."""
        return len(self.index)

    def forces(self, t: float, x: np.ndarray, v: np.ndarray) -> HydroForces:
        """Force components at time ``t`` (s) for displacement ``x`` and velocity ``v``."""
        zero = np.zeros(self.n)
        exc = self.excitation(t) if self.switches.excitation else zero
        rad = -self.radiation.force(v) if self.switches.radiation else zero
        hs = self.hydrostatics(x) if self.switches.hydrostatics else zero
        return HydroForces(total=exc + rad + hs, excitation=exc, radiation=rad, hydrostatic=hs)

    def advance(self, t: float, h: float, v: np.ndarray) -> None:
        """Commit the velocity at time ``t`` and step to ``t + h``; ``h`` must be a whole number
        of radiation steps ``dt`` (any number, so variable communication steps work)."""
        q = int(round(h / self.dt))
        if q < 1 or abs(h - q * self.dt) > 1e-9 * self.dt:
            raise ValueError(
                f"communication step {h:g} s is not a whole multiple of the radiation convolution step "
                f"{self.dt:g} s; set the hydro FMU parameter radiation.dt to the master's (smallest) macro step"
            )
        expected = self.start_time + self._grid_steps * self.dt
        if abs(t - expected) > 1e-6 * self.dt:
            raise ValueError(f"step starts at t = {t:g} s but the radiation history is at t = {expected:g} s")
        self.radiation.advance(v, q)
        self._grid_steps += q

    def elevation(self, t: float) -> float:
        """Incident wave elevation at the world origin (m)."""
        return self.waves.elevation(t, self.ramp)
