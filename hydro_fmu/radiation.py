"""Radiation memory of the Cummins equation: impulse response function and convolution.

The radiation force beyond the infinite-frequency added mass (which the multibody side carries
in its mass matrix) is the memory integral

    F_rad(t) = - mu(t),   mu(t) = int_0^t K(t - tau) v(tau) dtau,

    K(t) = (2/pi) int_0^inf B(omega) cos(omega t) domega.

Impulse response: B(omega) is taken piecewise linear between the database frequencies (and
linear from B(0) = 0 to the first frequency, zero above the last one) and the cosine integral is
evaluated exactly on each segment (Filon-type). On a uniform grid this equals the trapezoidal
cosine sum times sinc^2(Delta omega t / 2): the periodic images of K that the trapezoidal sum
produces at t = 2 pi m / Delta omega are suppressed (to zero at those times), and for
t << pi / Delta omega the error is second order in Delta omega. Keep the kernel shorter than
about pi / Delta omega. Truncation at the highest database frequency shows as a ripple of period
2 pi / omega_max in K(t).

Convolution: trapezoidal rule on a uniform grid t_j = j * dt over the kernel length T_K
(``irf_duration``): second-order accurate in dt for a smooth velocity, no stability limit of its
own (it is an explicit sum over past velocities); the current velocity enters with weight
K(0) dt / 2, so the force depends directly on the current velocity input. Velocities before
t = 0 are zero (the device starts from rest). Communication steps may be any integer multiple q
of dt: the velocity between two communication points is interpolated linearly onto the grid
(still second order).
"""

from __future__ import annotations

import numpy as np

from .transforms import fourier_integral


def impulse_response(omega: np.ndarray, damping: np.ndarray, t: np.ndarray) -> np.ndarray:
    """K(t) (len(t), n, n) from B(omega) (Nw, n, n) by exact integration of the linear interpolant.

    Args:
        omega: increasing frequencies (Nw,), rad/s, all positive.
        damping: radiation damping B at those frequencies (Nw, n, n).
        t: times (s), >= 0.
    """
    w = np.concatenate([[0.0], np.asarray(omega, dtype=float)])
    B = np.concatenate([np.zeros((1,) + damping.shape[1:]), damping], axis=0)
    return (2.0 / np.pi) * np.real(fourier_integral(w, B, t))


class RadiationMemory:
    """Trapezoidal convolution of the impulse response with the velocity history.

    Args:
        kernel: K sampled at t_j = j dt, j = 0..m-1, shape (m, n, n).
        dt: sampling step (s).

    Use: at each communication point call :meth:`force` with the current velocity (as often as
    needed: it changes nothing), then :meth:`advance` with that velocity and the number q >= 1 of
    grid steps to the next communication point.
    """

    def __init__(self, kernel: np.ndarray, dt: float) -> None:
        m, n, _ = kernel.shape
        if m < 2:
            raise ValueError("the impulse response needs at least two samples")
        self.dt = float(dt)
        self.n = n
        self.m = m
        weights = np.full(m, dt)
        weights[0] = weights[-1] = dt / 2
        w = kernel * weights[:, None, None]
        self._k0 = w[0]  # weight of the current velocity
        # History weights, oldest first, as one (n, (m-1) n) matrix for a single mat-vec.
        self._past = np.ascontiguousarray(np.transpose(w[1:][::-1], (1, 0, 2)).reshape(n, (m - 1) * n))
        # Double-length ring buffer: the last m-1 grid velocities are always contiguous.
        self._buffer = np.zeros((2 * (m - 1), n))
        self._head = 0  # index of the oldest sample of the current window
        self._last = np.zeros(n)  # velocity at the last committed grid point
        self.gap = 1  # grid steps from the last committed point to the current time
        self.steps = 0  # grid points committed so far

    def _window(self, v_now: np.ndarray) -> np.ndarray:
        """Velocities at lags m-1 .. 1 grid steps before now, oldest first."""
        k = self.m - 1
        window = self._buffer[self._head : self._head + k]
        if self.gap <= 1:
            return window
        q = self.gap
        lags = np.arange(q - 1, 0, -1)  # intermediate points, oldest first
        inner = v_now + np.outer(lags / q, self._last - v_now)
        keep = max(0, k - (q - 1))
        return np.concatenate([window[k - keep :], inner[-k:] if q - 1 > k else inner])

    def force(self, v_now: np.ndarray) -> np.ndarray:
        """mu at the current time given the current velocity (N; the radiation force is -mu)."""
        return self._past @ self._window(v_now).reshape(-1) + self._k0 @ v_now

    def _push(self, v: np.ndarray) -> None:
        k = self.m - 1
        self._buffer[self._head] = v
        self._buffer[self._head + k] = v
        self._head = (self._head + 1) % k
        self.steps += 1

    def advance(self, v_now: np.ndarray, q: int = 1) -> None:
        """Commit the velocity of the current time (and the interpolated points since the last
        commit), then move ``q`` grid steps forward."""
        if q < 1:
            raise ValueError("a step must span at least one grid step")
        for lag in range(self.gap - 1, 0, -1):
            self._push(v_now + (lag / self.gap) * (self._last - v_now))
        self._push(v_now)
        self._last = np.array(v_now, dtype=float)
        self.gap = q
