"""Post-processing of time series: steady-state harmonic amplitude and phase, mean power."""

from __future__ import annotations

import math

import numpy as np

from .scenario import DOFS


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


def steady_response(scenario, data: dict) -> dict[str, complex | float]:
    """First harmonics per metre of wave amplitude over the last ``simulation.steady_periods`` periods of a
    regular-wave results file: ``<body> <dof>`` and ``<joint> <k>`` (k-th joint coordinate, from 0) complex, and
    ``<pto> power`` the mean power per m^2 of amplitude."""
    w = scenario.waves
    omega, a = 2 * math.pi / w.period, w.height / 2
    t = data["time"]
    mask = steady_window(t, w.period, scenario.simulation.steady_periods)
    out: dict[str, complex | float] = {}
    for b in scenario.bodies:
        for d in b.dofs:
            y = data[f"bodies/{b.name}/displacement"][:, DOFS.index(d)]
            out[f"{b.name} {d}"] = harmonic_fit(t[mask], y[mask], omega)[0] / a
    for j in scenario.joints:
        if f"joints/{j.name}/coordinate" in data:
            series = np.asarray(data[f"joints/{j.name}/coordinate"]).reshape(len(t), -1)
            for k in range(series.shape[1]):
                out[f"{j.name} {k}"] = harmonic_fit(t[mask], series[mask, k], omega)[0] / a
    for p in scenario.ptos:
        out[f"{p.name} power"] = window_mean(t, data[f"ptos/{p.name}/power"], mask) / a**2
    return out
