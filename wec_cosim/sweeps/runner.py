"""``wec-cosim sweep``: plan the cases, run the missing ones, record each, assemble the matrices."""

from __future__ import annotations

import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from orchestrator.errors import WecCosimError
from orchestrator.scenario import Scenario

from .case import CaseTask
from .grid import Case, SweepPlan, plan_sweep
from .matrices import assemble
from .progress import SweepProgress
from .scheduler import (
    SchedulerLost,
    ctrl_c_interrupts,
    dask_client,
    deaf_to_ctrl_c,
    results_in_process,
    results_on_dask,
)
from .store import SweepStore


class SweepInterrupted(WecCosimError):
    """The sweep was stopped (Ctrl-C); the finished cases are in the file, the next start runs the rest."""


@dataclass
class SweepOutcome:
    """What one session of a sweep did."""

    path: Path
    plan: SweepPlan
    already: int
    ran: int
    failed: int
    duplicates: int
    wall_time: float

    @property
    def total(self) -> int:
        return len(self.plan.cases)


def run_sweep(scenario: Scenario, out: str | Path, *, scheduler: str | None = None, workers: int | None = None,
              in_process: bool | None = None, client=None, retry_failed: bool = False, progress: bool = True,
              log=print) -> SweepOutcome:
    """Run every case of the scenario's ``[sweep]`` that ``out`` does not hold yet and update its matrices.

    Where the cases run: on ``client`` if given; else in this process if ``in_process`` (default: for
    the frequency-domain method, whose cases take milliseconds, unless ``scheduler`` or ``workers`` is
    given); else on the Dask cluster at ``scheduler``, or on a new local cluster of ``workers``
    processes (default ``sweep.workers``, 0 = one per core). ``retry_failed`` runs failed cases again.
    Raises :class:`SweepInterrupted` on Ctrl-C, after recording what finished.
    """
    plan = plan_sweep(scenario)
    store = SweepStore.open(out, plan)
    try:  # from here on an interruption leaves the file whole, with what finished, status "interrupted"
        with ctrl_c_interrupts():
            return _run(plan, store, scenario, client, in_process, scheduler, workers, retry_failed, progress, log)
    except KeyboardInterrupt:
        done = _stop(store, "interrupted")
        raise SweepInterrupted(
            f"interrupted: {done} of {len(plan.cases)} cases are in {store.path}; run the same command again "
            f"to run the {len(plan.cases) - done} missing ones") from None


def _run(plan: SweepPlan, store: SweepStore, scenario: Scenario, client, in_process: bool | None,  # noqa: ANN001
         scheduler: str | None, workers: int | None, retry_failed: bool, progress: bool, log) -> SweepOutcome:  # noqa: ANN001
    statuses = store.statuses()
    todo = [c for c in plan.cases if c.id not in statuses or (retry_failed and statuses[c.id] != "ok")]
    todo.sort(key=lambda c: c.seed_index)  # a full grid of first seeds first: a usable matrix early
    already = len(plan.cases) - len(todo)
    if log:
        log(_plan_line(plan, already, len(todo), store.path))
        for note in _notes(plan):
            log(f"note: {note}")
    if in_process is None:
        in_process = plan.method == "frequency_domain" and not scheduler and not workers and client is None
    tasks = [CaseTask(plan.scenario, c, plan.method, plan.transient, plan.time_series) for c in todo]
    bar = SweepProgress(len(plan.cases), already, enabled=progress)
    by_id: dict[str, Case] = {c.id: c for c in todo}
    start = time.perf_counter()
    failed = 0
    try:
        with _results(tasks, client, in_process, scheduler, workers or scenario.sweep.workers, log) as results:
            for result in results:
                store.write(by_id[result.case_id], result)
                failed += not result.ok
                bar.update(result.ok)
    except KeyboardInterrupt:
        bar.close()
        raise
    except SchedulerLost as exc:
        bar.close()
        done = _stop(store, "interrupted: the connection to the Dask scheduler was lost")
        raise WecCosimError(
            f"{exc}: the sweep stopped; {done} of {len(plan.cases)} cases are in {store.path} (the cases that were "
            f"running have no result, none is recorded as failed); run the same command again to run the "
            f"{len(plan.cases) - done} missing ones (check the scheduler and workers first)") from None
    bar.close()
    assemble(store)
    statuses = store.statuses()
    complete = all(c.id in statuses for c in plan.cases)
    n_failed = sum(s != "ok" for s in statuses.values())
    store.finish(("completed" if not n_failed else f"completed, {n_failed} cases failed") if complete
                 else "incomplete")
    return SweepOutcome(store.path, plan, already, len(todo), failed, store.duplicates, time.perf_counter() - start)


def _stop(store: SweepStore, status: str) -> int:
    """Record a stopped sweep (matrices of what finished, ``status``), deaf to a further Ctrl-C; the number of
    cases in the file."""
    with deaf_to_ctrl_c():
        assemble(store)
        store.finish(status)
        return len(store.statuses())


@contextmanager
def _results(tasks: list[CaseTask], client, in_process: bool, scheduler: str | None, workers: int, log):
    if not tasks:
        yield iter(())
    elif client is not None:
        yield results_on_dask(client, tasks)
    elif in_process:
        yield results_in_process(tasks)
    else:
        with dask_client(scheduler, workers, log) as own:
            yield results_on_dask(own, tasks)


def _plan_line(plan: SweepPlan, already: int, todo: int, path: Path) -> str:
    grid = " x ".join(f"{a.key} ({len(a.values)})" for a in plan.axes) or "no grid"
    seeds = f", {plan.seeds} seeds per irregular-sea cell" if plan.seeds > 1 else ""
    n = len(plan.cases)
    return (f"sweep ({plan.method.replace('_', ' ')}): {grid}{seeds} = {n} case{'s' if n != 1 else ''}; "
            f"{already} already in {path}, {todo} to run")



def _notes(plan: SweepPlan) -> list[str]:
    """What the frequency-domain method leaves out of this scene."""
    if plan.method != "frequency_domain":
        return []
    s = plan.scenario
    out = []
    if plan.seeds > 1:
        out.append("sweep.seeds is not used by the frequency-domain method: its irregular-sea statistics are the "
                   "expectation over all realisations")
    left_out = [f"quadratic drag on {b.name}" for b in s.bodies if b.drag_coefficient and any(b.drag_coefficient)]
    left_out += [f"the nonlinear law of PTO {p.name}" for p in s.ptos if p.nonlinear]
    if s.hydro.nonlinear_hydrostatics or s.hydro.nonlinear_froude_krylov:
        left_out.append("nonlinear hydrostatic and Froude-Krylov forces")
    if left_out:
        out.append(f"the frequency-domain method is linear and leaves out {', '.join(left_out)}; "
                   "sweep.method = 'time_domain' includes them (docs/sweeps.md)")
    return out
