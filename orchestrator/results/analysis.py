"""Post-processing of time series: steady-state harmonic amplitude and phase, mean power."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from orchestrator.scenario import Scenario


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


def steady_response(scenario: Scenario, data: dict) -> dict[str, complex | float]:
    """First harmonics per metre of wave amplitude over the last ``simulation.steady_periods`` periods of a
    regular-wave results file: ``<body> <dof>`` and ``<joint> <k>`` (k-th joint coordinate, from 0) complex, and
    ``<pto> power`` the mean power per m^2 of amplitude."""
    from orchestrator.scenario import DOFS

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


def averaging_window(scenario: Scenario, t: np.ndarray) -> tuple[np.ndarray, str]:
    """Samples of a run over which its summary and its figures average (mean PTO power), and their
    description: in regular waves the last ``simulation.steady_periods`` whole wave periods (the
    window compared with the exact steady state); in any other sea everything after the wave ramp
    (the whole run if it is shorter than the ramp)."""
    t = np.asarray(t, dtype=float)
    w, sim = scenario.waves, scenario.simulation
    ramp = scenario.ramp_time
    if w.kind == "regular":
        n = max(1, int(math.floor(sim.steady_periods)))
        mask = steady_window(t, w.period, sim.steady_periods)
        inside = " (partly inside the wave ramp)" if t[mask][0] < ramp - 1e-9 else ""
        return mask, f"last {n} wave period{'s' if n > 1 else ''}, t >= {t[mask][0]:g} s{inside}"
    mask = t >= ramp - 1e-9
    if ramp <= 0 or np.count_nonzero(mask) < 2:
        return np.ones_like(t, dtype=bool), "whole run" + (" (shorter than the wave ramp)" if ramp > 0 else "")
    return mask, f"after the {ramp:g} s wave ramp"


def mean_pto_powers(scenario: Scenario, data: Mapping[str, Any]) -> tuple[dict[str, float], str]:
    """Mean power (W) of each PTO over :func:`averaging_window`, from a results file's ``time`` and
    ``ptos/<name>/power`` (a dict of arrays or an open HDF5 file), and the window's description."""
    t = np.asarray(data["time"][()], dtype=float)
    mask, where = averaging_window(scenario, t)
    return {p.name: window_mean(t, np.asarray(data[f"ptos/{p.name}/power"][()], dtype=float), mask)
            for p in scenario.ptos if f"ptos/{p.name}/power" in data}, where
