"""Work done on the bodies by each hydrodynamic force component: the hydro side of the energy account.

With the multibody side's kinetic, potential and dissipated energy (``mbd_fmu.simulator``) it closes
the wave-to-wire balance

    W_exc = E_pto + E_radiated + E_dissipated + (E_stored - E_stored,0),

where ``E_radiated = -W_rad`` (work of the radiation memory force: the energy the bodies' radiated
waves carry away; the A_inf part is kinetic energy of the multibody mass matrix), the hydrostatic
energy stored is ``-W_hs`` and viscous losses are ``-W_visc`` (docs/results.md).

Method: trapezoidal rule over the communication points, ``W(t_{n+1}) = W(t_n) + h/2 (P_n + P_{n+1})``
with ``P = F . v`` from the force and velocity at each point (second order in the step for smooth
motion; exact for the hydrostatic part of a linear motion between points only in the limit).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

# Force components in the order of the work vector (names of the FMU outputs ``energy.<name>``).
COMPONENTS = ("excitation_work", "radiation_work", "hydrostatic_work", "viscous_work")


@dataclass
class WorkAccount:
    """Cumulative work (J) of each component of :data:`COMPONENTS` since the first committed point."""

    committed: np.ndarray = field(default_factory=lambda: np.zeros(len(COMPONENTS)))
    last_time: float = 0.0
    last_power: np.ndarray | None = None

    @staticmethod
    def powers(excitation: np.ndarray, radiation: np.ndarray, hydrostatic: np.ndarray, viscous: np.ndarray,
               v: np.ndarray) -> np.ndarray:
        """Power (W) of each component on velocity ``v`` (forces and velocities on the same DOFs)."""
        return np.array([excitation @ v, radiation @ v, hydrostatic @ v, viscous @ v], dtype=float)

    def value(self, t: float, power: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """Work at time ``t`` (s) given the power there (the step since the last committed point added);
        written into ``out`` (len(COMPONENTS),) if given."""
        if self.last_power is None:
            if out is None:
                return self.committed.copy()
            out[:] = self.committed
            return out
        out = np.add(self.last_power, power, out=out)
        out *= 0.5 * (t - self.last_time)
        out += self.committed
        return out

    def commit(self, t: float, power: np.ndarray, work: np.ndarray | None = None) -> None:
        """Accept the point ``t`` (the start of the next step); ``work``: :meth:`value` ``(t, power)`` if already
        computed (copied)."""
        self.committed = self.value(t, power) if work is None else np.array(work, dtype=float)
        self.last_time, self.last_power = float(t), np.array(power, dtype=float)
