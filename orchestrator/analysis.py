"""Post-processing of time series: steady-state harmonic amplitude and phase, mean power."""

from __future__ import annotations

import numpy as np


def harmonic_fit(t: np.ndarray, y: np.ndarray, omega: float) -> tuple[complex, float]:
    """Least-squares fit y(t) ~ Re[Y exp(i omega t)] + c over the samples given.

    Returns ``(Y, c)``: the complex amplitude (``exp(+i omega t)`` convention, as the
    frequency-domain solution) and the mean. Exact for a pure harmonic sampled over any window;
    use a whole number of periods to reject other frequencies best.
    """
    t = np.asarray(t, dtype=float)
    g = np.column_stack([np.cos(omega * t), np.sin(omega * t), np.ones_like(t)])
    coef, *_ = np.linalg.lstsq(g, np.asarray(y, dtype=float), rcond=None)
    return complex(coef[0], -coef[1]), float(coef[2])


def steady_window(t: np.ndarray, period: float, periods: float) -> np.ndarray:
    """Boolean mask of the last ``periods`` whole periods of ``t`` (at least one sample)."""
    t = np.asarray(t)
    n = max(1, int(np.floor(periods)))
    start = t[-1] - n * period
    return t >= start - 1e-9 * period


def window_mean(t: np.ndarray, y: np.ndarray, mask: np.ndarray) -> float:
    """Time average of ``y`` over the masked samples (trapezoidal rule)."""
    tt, yy = t[mask], y[mask]
    if len(tt) < 2:
        return float(yy.mean())
    return float(np.trapezoid(yy, tt) / (tt[-1] - tt[0]))
