"""Wave excitation force: frequency-domain superposition (default) or impulse-response convolution.

Superposition (:class:`ExcitationForce`):

    F_exc(t) = r(t) * Re[ sum_k a_k exp(i phi_k) X(omega_k, beta_k) exp(i omega_k t) ],

with X the excitation per metre of amplitude (``exp(+i omega t)`` convention), linear in
frequency (real and imaginary parts) and in heading between the database's values, and r(t) the
start-up ramp. Exact for the given components: no time-stepping error.

Convolution (:class:`ExcitationConvolution`, seed paper 000): with the excitation impulse response

    K_ex(tau) = (1/2 pi) int_{-inf}^{inf} X(omega) exp(i omega tau) domega
              = (1/pi) Re int_0^{omega_max} X(omega) exp(i omega tau) domega

(X(-omega) = conj X(omega)), the force is F_exc(t) = r(t) int K_ex(tau) eta(t - tau) dtau with
eta the elevation at the world origin. K_ex is non-causal (the body feels the wave before it
passes the origin), so the integral over tau in [-T, T] uses the elevation up to T ahead of t.
K_ex is computed exactly for X piecewise linear in omega (held at X(omega_1) below the first
frequency, zero above the last; :mod:`hydro_fmu.transforms`), and the convolution is the
trapezoidal rule with step dt: second order in dt for a smooth elevation, exact for each
component of frequency below pi / dt up to the truncation of K_ex at +-T (its tails decay like
1/tau from the cut at omega_max). Needs a unidirectional sea (one heading).
"""

from __future__ import annotations

import numpy as np

from .hdb import HydroDatabase
from .transforms import fourier_integral
from .waves import PhasorClock, Ramp, WaveComponents


class ExcitationForce:
    """Excitation force on the selected degrees of freedom, by superposition of components.

    Args:
        hdb: the hydrodynamic database.
        waves: incident wave components.
        dofs: indices of the selected degrees of freedom in the database's 6N numbering.
        ramp: start-up ramp.
        part: ``total`` (excitation), ``diffraction`` or ``froude_krylov``.
    """

    def __init__(self, hdb: HydroDatabase, waves: WaveComponents, dofs: np.ndarray, ramp: Ramp,
                 part: str = "total") -> None:
        self.ramp = ramp
        table = {"total": None, "diffraction": hdb.diffraction, "froude_krylov": hdb.froude_krylov}[part]
        if part != "total" and table is None:
            raise ValueError(f"the database {hdb.source} has no {part} part of the excitation")
        omega = np.asarray(waves.omega, dtype=float)
        # Components above the database's range have no excitation: leave them out of the sum.
        keep = omega <= hdb.omega[-1]
        self.omega = omega[keep]
        if len(self.omega):
            X = hdb.excitation_at(self.omega, waves.headings[keep], table)
            # (K, n_selected): complex force amplitude of each component.
            self.coefficients = waves.complex_amplitude[keep][:, None] * X[:, dofs]
        else:
            self.coefficients = np.zeros((0, len(dofs)), complex)
        self.clock = PhasorClock(self.omega)

    def __call__(self, t: float) -> np.ndarray:
        """Force vector (N or N m) at time ``t`` (s)."""
        if not len(self.omega):
            return np.zeros(self.coefficients.shape[1])
        return self.ramp(t) * np.real(self.clock(t) @ self.coefficients)

    def rate(self, t: float) -> np.ndarray:
        """dF/dt (N/s, N m/s) at time ``t``, exact: r' Re[sum c e^(i w t)] + r Re[sum i w c e^(i w t)]."""
        if not len(self.omega):
            return np.zeros(self.coefficients.shape[1])
        phasor = self.clock(t)
        return (self.ramp.rate(t) * np.real(phasor @ self.coefficients)
                + self.ramp(t) * np.real((1j * self.omega * phasor) @ self.coefficients))


def excitation_impulse_response(hdb: HydroDatabase, heading: float, dofs: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """K_ex(tau) (len(tau), n_selected), N/m/s (module docstring), exact for X linear in omega."""
    X = hdb.excitation_at(hdb.omega, heading)[:, dofs]
    w = np.concatenate([[0.0], hdb.omega])
    table = np.concatenate([X[:1], X], axis=0)  # X held at its first value down to omega = 0
    return np.real(fourier_integral(w, table, np.asarray(tau, dtype=float))) / np.pi


class ExcitationConvolution:
    """Excitation force by convolution of K_ex with the elevation at the origin (non-causal).

    Args:
        hdb, dofs: database and selected degrees of freedom (6N numbering).
        heading: wave heading (rad); the sea must be unidirectional.
        elevation: eta(t) at the world origin, vectorised over t (unramped).
        duration: half-length T of the kernel (s): tau in [-T, T].
        dt: quadrature step (s).
        ramp: start-up ramp applied to the force.
    """

    def __init__(self, hdb: HydroDatabase, dofs: np.ndarray, heading: float, elevation, duration: float,
                 dt: float, ramp: Ramp) -> None:
        if not (duration > 0 and dt > 0):
            raise ValueError(f"excitation kernel needs a positive duration and step (got {duration}, {dt})")
        m = int(np.ceil(duration / dt))
        self.tau = np.arange(-m, m + 1) * dt
        self.kernel = excitation_impulse_response(hdb, heading, dofs, self.tau)
        weights = np.full(len(self.tau), dt)
        weights[0] = weights[-1] = dt / 2
        self.weighted = self.kernel * weights[:, None]
        self.elevation = elevation
        self.ramp = ramp

    def __call__(self, t: float) -> np.ndarray:
        """Force vector (N or N m) at time ``t`` (s)."""
        eta = np.asarray(self.elevation(t - self.tau), dtype=float)
        return self.ramp(t) * (eta @ self.weighted)

    def rate(self, t: float, delta: float = 1e-4) -> np.ndarray:
        """dF/dt at time ``t`` by a central difference of step ``delta`` (s) of this pure function of time
        (error delta^2/6 times the third derivative: about 1e-8 of F for wave periods above 1 s)."""
        return (self(t + delta) - self(t - delta)) / (2 * delta)
