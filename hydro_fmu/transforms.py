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
    """I(t) (len(t), ...) for a table ``values`` (Nw, ...) real or complex at increasing ``omega``.

    Evaluated segment by segment in the stable form exp(i a t) h [f_a (E1 - E2) + f_b E2](h t) with
    E1(x) = int_0^1 exp(i x s) ds and E2(x) = int_0^1 s exp(i x s) ds, by their power series for
    |h t| < 0.02 (so there is no cancellation at small t) and in closed form otherwise (both
    accurate to about 1e-12 relative).
    """
    w = np.asarray(omega, dtype=float)
    flat = np.asarray(values).reshape(len(w), -1)
    h = np.diff(w)
    t = np.asarray(t, dtype=float)
    out = np.empty((len(t), flat.shape[1]), complex)
    for start in range(0, len(t), chunk):
        tt = t[start : start + chunk]
        x = np.outer(tt, h)  # (T, S)
        e1, e2 = _moments(x)
        phase = np.exp(1j * np.outer(tt, w[:-1])) * h
        out[start : start + chunk] = (phase * (e1 - e2)) @ flat[:-1] + (phase * e2) @ flat[1:]
    return out.reshape((len(t),) + np.asarray(values).shape[1:])


def _moments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """E1(x) = int_0^1 exp(i x s) ds and E2(x) = int_0^1 s exp(i x s) ds, elementwise."""
    small = np.abs(x) < 0.02
    ix = 1j * x
    # Series: E1 = sum (ix)^n / (n + 1)!, E2 = sum (ix)^n / (n! (n + 2)), truncated after (ix)^5.
    s1 = 1 + ix / 2 + ix**2 / 6 + ix**3 / 24 + ix**4 / 120 + ix**5 / 720
    s2 = 0.5 + ix / 3 + ix**2 / 8 + ix**3 / 30 + ix**4 / 144 + ix**5 / 840
    safe = np.where(small, 1.0, x)
    e = np.exp(1j * safe)
    c1 = (e - 1) / (1j * safe)
    c2 = e / (1j * safe) + (e - 1) / safe**2
    return np.where(small, s1, c1), np.where(small, s2, c2)
