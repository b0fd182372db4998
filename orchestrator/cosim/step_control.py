"""Macro-step controllers: fixed steps, and the energy-based adaptive step (the ECCO idea).

Every step is a whole multiple of a grid step (the hydro FMU's radiation grid) and the last one
ends exactly at the stop time. A controller proposes the next step; after the master has taken it,
:meth:`StepController.accept` sees the master's data at the new point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass
class Bond:
    """A force/velocity bond: a sampler's force output drives an integrator's force input,
    whose velocity output goes back (names as in the connections)."""

    force_source: tuple[str, str]
    force_input: tuple[str, str]
    velocity: tuple[str, str]


class StepController:
    """Chooses macro steps; whole multiples of ``grid`` ending exactly at the stop time."""

    def __init__(self, grid: float, start_time: float) -> None:
        self.grid = grid
        self.start = start_time
        self.steps = 0
        self.ticks = 0  # grid steps since the start
        self.sizes: list[float] = []
        self._last_query = (math.nan, 0)  # (time, grid steps from the start to it)

    def remaining(self, t: float, stop_time: float) -> bool:
        return self._ticks_to(stop_time) > self.ticks

    def _ticks_to(self, time: float) -> int:
        if time != self._last_query[0]:  # asked twice per step, always for the stop time
            self._last_query = (time, int(round((time - self.start) / self.grid)))
        return self._last_query[1]

    def proposed_ticks(self) -> int:  # pragma: no cover - overridden
        return 1

    def begin(self, master: Any) -> None:
        """Called once before the first step."""

    def next_step(self, t: float, stop_time: float) -> tuple[float, float]:
        k = max(1, min(self.proposed_ticks(), self._ticks_to(stop_time) - self.ticks))
        self._pending = k
        return k * self.grid, self.start + (self.ticks + k) * self.grid

    def accept(self, master: Any) -> None:
        self.ticks += self._pending
        self.steps += 1
        self.sizes.append(self._pending * self.grid)

    def state(self) -> dict:
        return {"steps": self.steps, "ticks": self.ticks, "sizes": list(self.sizes)}

    def set_state(self, state: dict) -> None:
        self.steps, self.ticks, self.sizes = state["steps"], state["ticks"], list(state["sizes"])


class FixedStepController(StepController):
    """Constant macro step (the grid itself)."""

    def proposed_ticks(self) -> int:
        return 1


class EnergyStepController(StepController):
    """Energy-based adaptive macro step (the ECCO idea, Sadjina et al. 2017, without its quirks).

    After a step of length h, on every bond (sampler force F -> integrator input u, integrator
    velocity v back) the energy the integrator received, h/2 [u v_n + u v_{n+1}] (its input is
    constant over the step), is compared with the energy the sampler's force delivered,
    h/2 [F_n v_n + F_{n+1} v_{n+1}] (trapezoidal rule): delta E = h/2 [(u - F_n) v_n + (u - F_{n+1}) v_{n+1}].
    The error of the bond is |delta E| / (h P_ref) with P_ref the larger of the mean power through
    the bond over the step and ``floor`` times its running RMS (so that the tolerance is relative to
    the power flowing through the bond, and a bond passing through zero power does not stall the
    step). With e = max over bonds / ``tolerance`` the next step is h * clip(safety e^(-1/q), 1/4,
    ``max_growth``), q the order of the error in h (q = 1 for a zero-order hold, 2 otherwise),
    rounded down to a whole number of grid steps within [grid, ``max_step``]. Non-iterative: a step
    is never repeated; the error of the step just taken sets the next one.
    """

    def __init__(self, grid: float, start_time: float, max_step: float, tolerance: float, bonds: list[Bond],
                 order: int, initial_step: float | None = None, safety: float = 0.8, max_growth: float = 2.0,
                 floor: float = 0.1) -> None:
        super().__init__(grid, start_time)
        self.max_ticks = max(1, int(round(max_step / grid)))
        self.tolerance = tolerance
        self.bonds = bonds
        self.order = max(1, order)
        self.safety = safety
        self.max_growth = max_growth
        self.floor = floor
        self.ticks_next = max(1, min(self.max_ticks, int(round((initial_step or grid) / grid))))
        self.errors: list[float] = []
        self._power_sq = np.zeros(len(bonds))
        self._time = 0.0
        self._prev: dict | None = None
        self._index: list | None = None

    def proposed_ticks(self) -> int:
        return self.ticks_next

    def _bind(self, master: Any) -> None:
        idx = []
        for b in self.bonds:
            fc, fv = b.force_source
            ic, iv = b.force_input
            vc, vv = b.velocity
            idx.append((fc, master.output_names[fc].index(fv), ic, master.wiring[ic].port.names.index(iv),
                        vc, master.output_names[vc].index(vv)))
        self._index = idx

    def snapshot(self, master: Any) -> dict:
        """Force and velocity on every bond at the master's current point."""
        if self._index is None:
            self._bind(master)
        f = np.array([master.outputs[fc][fi] for fc, fi, _, _, _, _ in self._index])
        v = np.array([master.outputs[vc][vi] for _, _, _, _, vc, vi in self._index])
        return {"F": f, "v": v}

    def begin(self, master: Any) -> None:
        self._prev = self.snapshot(master)

    def accept(self, master: Any) -> None:
        h = self._pending * self.grid
        super().accept(master)
        now = self.snapshot(master)
        u = np.array([master.last_step.inputs[ic][ii] for _, _, ic, ii, _, _ in self._index])
        f0, v0, f1, v1 = self._prev["F"], self._prev["v"], now["F"], now["v"]
        mismatch = 0.5 * h * ((u - f0) * v0 + (u - f1) * v1)
        power = 0.5 * (f0 * v0 + f1 * v1)
        self._power_sq = self._power_sq + h * power**2
        self._time += h
        rms = np.sqrt(self._power_sq / self._time)
        ref = np.maximum(np.abs(power), self.floor * rms)
        with np.errstate(divide="ignore", invalid="ignore"):
            errors = np.where(ref > 0, np.abs(mismatch) / (h * ref), 0.0)
        e = float(np.max(errors, initial=0.0)) / self.tolerance
        self.errors.append(e * self.tolerance)
        factor = self.max_growth if e == 0 else float(np.clip(self.safety * e ** (-1.0 / self.order), 0.25,
                                                               self.max_growth))
        self.ticks_next = int(max(1, min(self.max_ticks, math.floor(self._pending * factor + 1e-9))))
        self._prev = now

    def state(self) -> dict:
        out = super().state()
        out.update(ticks_next=self.ticks_next, errors=list(self.errors), power_sq=self._power_sq.copy(),
                   time=self._time, prev=None if self._prev is None else {k: v.copy() for k, v in self._prev.items()})
        return out

    def set_state(self, state: dict) -> None:
        super().set_state(state)
        self.ticks_next = state["ticks_next"]
        self.errors = list(state["errors"])
        self._power_sq = state["power_sq"].copy()
        self._time = state["time"]
        self._prev = state["prev"]
