"""One case of a sweep, run where it is sent (a Dask worker process, or this process).

:func:`run_case` takes the base scenario (dataclasses, sent to the worker by Dask), the case's
parameters and seed, and returns a :class:`CaseResult`; it never raises for a failing case: the error becomes the
result (status ``failed``), so one bad case does not stop the others. The time-domain method is a
full ``wec-cosim run`` of the case's scenario (FMUs built or taken from the cache and instantiated
in the worker), into a temporary results file that is read back and deleted.
"""

from __future__ import annotations

import math
import os
import socket
import tempfile
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from orchestrator.errors import WecCosimError
from orchestrator.scenario import Scenario

from .grid import Case, apply_params
from .summary import Summary, analysis_window, frequency_domain_summary, time_domain_summary

# Series kept with time_series = true (the others, velocities and hydrodynamic forces, stay out).
SERIES_PREFIXES = ("time", "bodies/", "ptos/", "wave/", "joints/")
SERIES_SKIPPED = ("/velocity", "/hydro_force", "/rate")


@dataclass(frozen=True)
class CaseTask:
    """What a worker needs to run one case."""

    scenario: Scenario
    case: Case
    method: str
    transient: float | None = None
    time_series: bool = False


@dataclass
class CaseResult:
    """The outcome of one case: ``ok`` with its summary (and series), or ``failed`` with the error."""

    case_id: str
    status: str
    error: str = ""
    summary: Summary = field(default_factory=dict)
    series: dict[str, np.ndarray] = field(default_factory=dict)
    wall_time: float = 0.0
    worker: str = ""
    host: str = ""
    pid: int = 0

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def run_case(task: CaseTask) -> CaseResult:
    """Run one case; a failure is returned as a result, not raised."""
    start = time.perf_counter()
    result = CaseResult(task.case.id, "ok", worker=_worker_address(), host=socket.gethostname(), pid=os.getpid())
    try:
        scenario = apply_params(task.scenario, task.case.params, task.case.seed)
        if task.method == "frequency_domain":
            from orchestrator.scene import load_scene

            result.summary = frequency_domain_summary(load_scene(scenario, log=None))
        else:
            result.summary, result.series = _time_domain(scenario, task.transient, task.time_series)
    except WecCosimError as exc:
        result.status, result.error = "failed", str(exc)
    except Exception as exc:  # noqa: BLE001 - any failure of one case is that case's result
        frame = traceback.extract_tb(exc.__traceback__)[-1]
        result.status = "failed"
        result.error = f"{type(exc).__name__}: {exc} (at {Path(frame.filename).name}:{frame.lineno})"
    result.wall_time = time.perf_counter() - start
    return result


def prepare_time_domain(scenario: Scenario) -> Scenario:
    """The case's run settings: no checkpoints, and for regular waves a duration long enough for the ramp,
    15 periods of settling and the steady-state window."""
    sim = scenario.simulation
    sim.checkpoint_every = 0.0
    if scenario.waves.kind == "regular":
        needed = scenario.ramp_time + (math.ceil(sim.steady_periods) + 15) * scenario.waves.period
        sim.duration = max(sim.duration, math.ceil(needed / sim.step - 1e-9) * sim.step)
    return scenario


def _time_domain(scenario: Scenario, transient: float | None, keep_series: bool) -> tuple[Summary, dict]:
    from orchestrator.cosim.simulation import run_scenario
    from orchestrator.results import read_results
    from orchestrator.scene import load_scene

    scenario = prepare_time_domain(scenario)
    scene = load_scene(scenario, log=None)
    with tempfile.TemporaryDirectory(prefix="wec_case_") as tmp:
        run_scenario(scenario, Path(tmp) / "case.h5", progress=False, log=None, scene=scene)
        data = read_results(Path(tmp) / "case.h5")
    summary = time_domain_summary(scene, data, analysis_window(scene, data["time"], transient))
    series = {k: v for k, v in data.items() if k != "attrs" and k.startswith(SERIES_PREFIXES)
              and not k.endswith(SERIES_SKIPPED)} if keep_series else {}
    return summary, series


def _worker_address() -> str:
    try:
        from distributed import get_worker

        return get_worker().address
    except (ImportError, ValueError):
        return "in-process"
