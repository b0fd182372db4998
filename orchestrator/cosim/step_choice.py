"""``simulation.error_tolerance``: the macro step chosen from the run's own error estimate.

The step is fixed for the run and a whole fraction of the duration (an even number of steps, so that the coarse
shadow of :mod:`.error_estimate` ends with the run). The first run takes ``simulation.step``; its estimate is
e = e_t + e_m, the time stepping's part e_t, which scales as h^p (p the run's order,
:func:`orchestrator.cosim.error_estimate.richardson_order`), and the radiation model's e_m, which no step changes.
The next run takes

    h' = h (target / e_t)^(1/p),   target = SAFETY tolerance - e_m      (at most 4 h, at least h / 8),

and if e_m alone is above ``REACHABLE`` times the tolerance no step can meet it: the search stops there and says so
(the radiation model must be improved: a longer impulse response, a finer frequency grid, a tighter state-space fit).

and so on until an estimate meets the tolerance (at most ``MAX_RUNS`` runs). A first run that already meets it
with room to spare is followed by one at the larger step the same formula gives, and the larger of the two that
meets the tolerance is kept. A run or shadow that does not finish at a step (diverged, not converged) counts as
an error above the tolerance and the next step is half as large. The results file of the accepted run is the
one written; the summary and the file's ``step_choice`` attribute list every step tried, its estimate and its
wall time (run and shadow).
"""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import h5py

from orchestrator.errors import MasterError, WecCosimError
from orchestrator.scenario import Scenario

from .error_estimate import richardson_order

SAFETY = 0.7
REACHABLE = 0.5  # the radiation model's share above this fraction of the tolerance: no step meets it
MAX_RUNS = 4
GROWTH = 4.0  # largest step increase between two runs
SHRINK = 8.0  # largest step decrease between two runs


@dataclass
class Attempt:
    """One run of the search: its step (s), its estimate (relative; inf if it or its shadow did not finish), the
    wall time of the run and of its shadow (s), and why it did not finish."""

    step: float
    estimate: float
    wall_time: float
    failure: str = ""
    time_part: float = math.nan
    model_part: float = math.nan


def fitting_step(duration: float, step: float) -> float:
    """The largest step at most ``step`` that divides ``duration`` into an even number of steps."""
    n = max(2, 2 * math.ceil(duration / (2 * step) - 1e-9))
    return duration / n


def next_step(step: float, time_part: float, model_part: float, tolerance: float, order: int) -> float:
    """The step the estimate's order predicts for its time-stepping part to meet ``SAFETY`` times the tolerance less
    the radiation model's part (module docstring)."""
    if not math.isfinite(time_part):
        return step / 2
    if time_part <= 0:
        return step * GROWTH
    target = SAFETY * tolerance - (model_part if math.isfinite(model_part) else 0.0)
    factor = (max(target, 0.1 * tolerance) / time_part) ** (1.0 / order)
    return step * min(GROWTH, max(1.0 / SHRINK, factor))


def run_to_tolerance(scenario: Scenario, output: Path, run: Callable[[Scenario, Path], Any],
                     log: Callable[[str], None] | None = print) -> Any:
    """Runs of ``scenario`` at chosen steps until the error estimate meets ``simulation.error_tolerance``
    (module docstring); ``run(scenario, results path)`` makes one run (its scenario has no tolerance). Returns the
    accepted run's result with ``step_choice`` (the attempts) set."""
    import copy

    tolerance = scenario.simulation.error_tolerance
    order = richardson_order(scenario)
    duration = scenario.simulation.duration
    attempts: list[Attempt] = []
    accepted: tuple[Any, Path, float] | None = None  # (result, file, step)
    best_failed: tuple[Any, Path, float] | None = None  # the smallest estimate above the tolerance
    step = fitting_step(duration, scenario.simulation.step)
    tried: set[float] = set()
    unreachable = False
    for k in range(MAX_RUNS):
        s = copy.deepcopy(scenario)
        s.simulation.step = step
        s.simulation.error_tolerance = 0.0
        s.simulation.error_estimate = "richardson"
        part = output.with_name(f"{output.stem}.step{k}{output.suffix}")
        start = time.perf_counter()
        try:
            result = run(s, part)
        except (MasterError, WecCosimError) as exc:
            text = " ".join(str(exc).split())
            attempts.append(Attempt(step, math.inf, time.perf_counter() - start, text[:200]))
            _discard(part)
            if log is not None:
                log(f"error tolerance {tolerance:g}: the run at {step:g} s did not finish ({text[:120]})")
        else:
            e = result.error_estimate
            value = e.value if e is not None and e.available else math.inf
            failure = "" if math.isfinite(value) else (e.method if e is not None else "no estimate")
            attempts.append(Attempt(step, value, time.perf_counter() - start, failure,
                                    e.time_discretisation if e is not None else math.nan,
                                    e.radiation_model if e is not None else math.nan))
            if log is not None:
                log(f"error tolerance {tolerance:g}: step {step:g} s, estimate "
                    f"{'none' if not math.isfinite(value) else f'{value:.3g}'}")
            if value <= tolerance and (accepted is None or step > accepted[2]):
                if accepted is not None:
                    _discard(accepted[1])
                accepted = (result, part, step)
            elif best_failed is None or value < best_failed[0].error_estimate.value:
                if best_failed is not None:
                    _discard(best_failed[1])
                best_failed = (result, part, step)
            else:
                _discard(part)
        tried.add(step)
        last = attempts[-1]
        met_now = accepted is not None and accepted[2] == step
        if accepted is not None and not met_now:
            break  # a larger step than one that met the tolerance did not: keep that one
        if met_now and (k > 0 or last.estimate > 0.5 * SAFETY * tolerance):
            break  # met, without room for a step larger by a useful factor
        if not met_now and last.model_part > REACHABLE * tolerance:
            unreachable = True
            break  # the radiation model alone is near or above the tolerance: no step meets it
        proposal = fitting_step(duration, next_step(step, last.time_part if math.isfinite(last.estimate) else math.nan,
                                                    last.model_part, tolerance, order))
        if proposal in tried or (met_now and proposal <= 1.25 * step):
            break
        step = proposal
    chosen = accepted or best_failed
    if chosen is None:
        raise WecCosimError(
            f"{scenario.file}: simulation.error_tolerance = {tolerance:g}: no run finished at the steps tried ("
            + "; ".join(f"{a.step:g} s: {a.failure}" for a in attempts) + "); set a smaller simulation.step")
    result, part, step = chosen
    if best_failed is not None and chosen is not best_failed:
        _discard(best_failed[1])
    os.replace(part, output)
    result.path = output
    result.step_choice = StepChoice(tolerance, step, accepted is not None, attempts, unreachable)
    with h5py.File(output, "a") as f:
        f.attrs["step_choice"] = json.dumps(result.step_choice.to_json())
    return result


@dataclass
class StepChoice:
    """What :func:`run_to_tolerance` did: the tolerance, the step of the run kept, whether its estimate met the
    tolerance, and every attempt."""

    tolerance: float
    step: float
    met: bool
    attempts: list[Attempt]
    unreachable: bool = False  # the radiation model's share alone was near or above the tolerance

    def to_json(self) -> dict:
        return {"tolerance": self.tolerance, "step": self.step, "met": self.met, "unreachable": self.unreachable,
                "attempts": [asdict(a) | {"estimate": a.estimate if math.isfinite(a.estimate) else None}
                             for a in self.attempts]}

    def text(self) -> str:
        """The summary line: the step chosen, the estimate reached, every step tried, the total wall time."""
        reached = next((a.estimate for a in self.attempts if a.step == self.step), math.nan)
        tried = ", ".join(f"{a.step:.4g} s: " + (f"{100 * a.estimate:.3g} %" if math.isfinite(a.estimate)
                                                 else "did not finish") for a in self.attempts)
        total = sum(a.wall_time for a in self.attempts)
        why = ""
        if not self.met and self.unreachable:
            model = next((a.model_part for a in self.attempts if a.step == self.step), math.nan)
            why = (f": the radiation model's share alone is {100 * model:.3g} %, which no step changes (lengthen "
                   "hydro.irf_duration, refine the database's frequencies or tighten the state-space fit)")
        return (f"error tolerance {100 * self.tolerance:g} %: step {self.step:.4g} s chosen, estimate "
                f"{100 * reached:.3g} %"
                + ("" if self.met else f" (NOT met{why}; the run with the smallest estimate is kept)")
                + f"; steps tried {tried}; wall time of all runs with their shadows {total:.2f} s")


def _discard(path: Path) -> None:
    for p in (path, path.with_name(path.name + ".checkpoint.h5")):
        try:
            p.unlink()
        except OSError:
            pass
