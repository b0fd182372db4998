"""Fourier integrals of frequency tables that are piecewise linear in omega (Filon-type, exact).

    I(t) = int_{omega_0}^{omega_N} f(omega) exp(i omega t) domega,

with f the linear interpolant of its values at the nodes omega_0 < ... < omega_N. On each
segment [a, b] with slope s, for t != 0,

    int_a^b (f_a + s (omega - a)) exp(i omega t) domega = [f exp(i omega t) / (i t)]_a^b + s [exp(i omega t) / t^2]_a^b,

and the trapezoidal rule (exact) at t = 0. No sampling of the integrand in time: the result has
no aliasing images; on a uniform grid it equals the trapezoidal sum times sinc^2(d_omega t / 2)
(so it is second order in d_omega for t << pi / d_omega). The truncation at omega_N shows as a
ripple of period 2 pi / omega_N unless f vanishes there.
"""

from __future__ import annotations

import numpy as np


def fourier_integral(omega: np.ndarray, values: np.ndarray, t: np.ndarray, chunk: int = 64) -> np.ndarray:
    """I(t) (len(t), ...) for a table ``values`` (Nw, ...) real or complex at increasing ``omega``."""
    w = np.asarray(omega, dtype=float)
    flat = np.asarray(values).reshape(len(w), -1)
    slope = np.diff(flat, axis=0) / np.diff(w)[:, None]
    t = np.asarray(t, dtype=float)
    out = np.empty((len(t), flat.shape[1]), complex)
    zero = t == 0.0
    if zero.any():
        out[zero] = np.trapezoid(flat, w, axis=0)
    nonzero = np.flatnonzero(~zero)
    for start in range(0, len(nonzero), chunk):
        rows = nonzero[start : start + chunk]
        tt = t[rows]
        e = np.exp(1j * np.outer(tt, w))  # (T, Nw)
        # sum over segments of [f e/(i t)]_a^b telescopes to the end values.
        ends = (e[:, -1:] * flat[-1] - e[:, :1] * flat[0]) / (1j * tt[:, None])
        de = (e[:, 1:] - e[:, :-1]) / tt[:, None] ** 2  # (T, Nw-1)
        out[rows] = ends + de @ slope
    return out.reshape((len(t),) + np.asarray(values).shape[1:])
