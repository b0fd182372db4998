"""Wave excitation force by frequency-domain superposition.

    F_exc(t) = r(t) * Re[ sum_k a_k exp(i phi_k) X(omega_k, beta) exp(i omega_k t) ],

with X the excitation per metre of amplitude (``exp(+i omega t)`` convention), linearly
interpolated in frequency from the database (real and imaginary parts separately), and r(t)
the start-up ramp. The sum is exact for the given components: there is no time-stepping error.
"""

from __future__ import annotations

import numpy as np

from .hdb import HydroDatabase
from .waves import Ramp, WaveComponents


class ExcitationForce:
    """Excitation force on the selected degrees of freedom.

    Args:
        hdb: the hydrodynamic database.
        waves: incident wave components (one heading, which the database must tabulate).
        dofs: indices of the selected degrees of freedom in the database's 6N numbering.
        ramp: start-up ramp.
    """

    def __init__(self, hdb: HydroDatabase, waves: WaveComponents, dofs: np.ndarray, ramp: Ramp) -> None:
        self.ramp = ramp
        self.omega = np.asarray(waves.omega, dtype=float)
        if len(self.omega):
            _, _, X = hdb.interpolate(self.omega, waves.heading)
            # (K, n_selected): complex force amplitude of each component.
            self.coefficients = waves.complex_amplitude[:, None] * X[:, dofs]
        else:
            self.coefficients = np.zeros((0, len(dofs)), complex)

    def __call__(self, t: float) -> np.ndarray:
        """Force vector (N or N m) at time ``t`` (s)."""
        if not len(self.omega):
            return np.zeros(self.coefficients.shape[1])
        phasor = np.exp(1j * self.omega * t)
        return self.ramp(t) * np.real(phasor @ self.coefficients)
