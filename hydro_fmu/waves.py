"""Incident waves as a sum of linear (Airy) components, plus the start-up ramp.

A sea state is a set of components ``(omega_k, a_k, phi_k)`` travelling at one heading
``beta`` (rad, 0 = towards +x). The elevation at a point (x, y) is

    eta(t, x, y) = r(t) * sum_k a_k cos(omega_k t - k_k (x cos beta + y sin beta) + phi_k),

with ``r(t)`` the ramp. Complex amplitudes use the ``exp(+i omega t)`` convention of
:mod:`hydro_fmu.hdb`: component k has complex amplitude ``a_k exp(i phi_k)`` at the origin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np


@dataclass(frozen=True)
class Ramp:
    """Half-cosine start-up ramp r(t) = (1 - cos(pi t / duration)) / 2 for t < duration, then 1.

    Its first derivative is continuous, so the ramp excites no spurious transient at its end.
    ``duration = 0`` means no ramp.
    """

    duration: float = 0.0

    def __call__(self, t: float | np.ndarray) -> float | np.ndarray:
        if isinstance(t, np.ndarray):
            if self.duration <= 0:
                return np.ones_like(t, dtype=float)
            return 0.5 * (1.0 - np.cos(np.pi * np.clip(t / self.duration, 0.0, 1.0)))
        if self.duration <= 0 or t >= self.duration:
            return 1.0
        return 0.5 * (1.0 - math.cos(math.pi * max(t, 0.0) / self.duration))


@dataclass(frozen=True)
class WaveComponents:
    """Linear wave components at one heading.

    Attributes:
        omega: angular frequencies (K,), rad/s.
        amplitude: amplitudes (K,), m.
        phase: phases (K,), rad, at the world origin.
        heading: propagation direction, rad (0 = towards +x).
    """

    omega: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    heading: float = 0.0

    @cached_property
    def complex_amplitude(self) -> np.ndarray:
        """a_k exp(i phi_k), m."""
        return self.amplitude * np.exp(1j * self.phase)

    def elevation(self, t: float | np.ndarray, ramp: Ramp = Ramp()) -> float | np.ndarray:
        """Elevation at the world origin, m (vectorised over ``t``)."""
        if np.ndim(t) == 0:
            return float(np.real(np.exp(1j * self.omega * t) @ self.complex_amplitude)) * ramp(float(t))
        tt = np.asarray(t, dtype=float)
        return np.real(np.exp(1j * np.outer(tt, self.omega)) @ self.complex_amplitude) * ramp(tt)


def regular_wave(height: float, period: float, phase: float = 0.0, heading: float = 0.0) -> WaveComponents:
    """A regular wave of height ``height`` (m, crest to trough), period (s), phase and heading (rad)."""
    if not (height >= 0 and period > 0):
        raise ValueError(f"regular wave needs height >= 0 and period > 0 (got H = {height}, T = {period})")
    return WaveComponents(
        omega=np.array([2 * math.pi / period]),
        amplitude=np.array([height / 2]),
        phase=np.array([phase]),
        heading=heading,
    )


def still_water() -> WaveComponents:
    """No incident wave (decay tests)."""
    return WaveComponents(omega=np.zeros(0), amplitude=np.zeros(0), phase=np.zeros(0))


def wavenumber(omega: np.ndarray | float, water_depth: float = math.inf, g: float = 9.81) -> np.ndarray:
    """Wavenumber k (rad/m) from the linear dispersion relation omega^2 = g k tanh(k h).

    Solved by Newton's method from the deep-water guess (quadratic convergence; 1e-14 relative).
    """
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    k = w**2 / g
    if math.isinf(water_depth):
        return k
    h = water_depth
    k = np.maximum(k, w / math.sqrt(g * h))
    for _ in range(50):
        th = np.tanh(k * h)
        f = g * k * th - w**2
        df = g * th + g * k * h * (1 - th**2)
        dk = f / df
        k = k - dk
        if np.all(np.abs(dk) <= 1e-14 * np.abs(k)):
            break
    return k
