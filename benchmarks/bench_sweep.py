"""Sweep throughput on Dask: cases per minute with 1 and 2 local workers, and the per-case overhead of
the sweep against the bare run of the same cases.

The cases: the floating cylinder in a JONSWAP sea (``scenarios/cylinder_irregular.toml``), Hs 2 m,
``--cases`` seeds of ``--duration`` s each (time domain, the state-space radiation model). Every
case has its own sea, hence its own hydrodynamic FMU to build, as in a power matrix; each
measurement starts from an empty FMU cache of its own so that all three pay the same builds.

* bare: ``run_scenario`` of every case one after another in this process (what ``wec-cosim run``
  does), plus the cost of reading the file back;
* sweep, 1 and 2 workers: start-up of the local cluster (timed apart), then ``run_sweep`` of the same
  cases on it (planning, sending, running, the summary, writing the sweep file, the matrices).

Per-case overhead = (sweep with 1 worker, start-up excluded) / cases - bare / cases. The speed-up
of 2 workers over 1 is bounded by the 2 cores (and by whatever else runs on them: the load average
is recorded before and after every measurement).

    python benchmarks/bench_sweep.py [--cases 8] [--duration 200] [--out benchmarks/results/sweep.txt]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import tempfile
import time
from datetime import date
from pathlib import Path

import h5py
from common import write_report

from orchestrator.cosim.simulation import run_scenario
from orchestrator.scenario import load_scenario
from wec_cosim.sweeps import run_sweep
from wec_cosim.sweeps.case import prepare_time_domain
from wec_cosim.sweeps.grid import case_scenario, plan_sweep
from wec_cosim.sweeps.scheduler import close_quietly, local_cluster

ROOT = Path(__file__).resolve().parent.parent


def load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def sweep_scenario(cases: int, duration: float):
    s = load_scenario(ROOT / "scenarios" / "cylinder_irregular.toml")
    s.simulation.duration = duration
    s.sweep.method, s.sweep.seeds, s.sweep.time_series = "time_domain", cases, False
    s.sweep.grid = {"waves": {"hs": [2.0]}}
    return s


def fresh_cache(folder: Path, name: str) -> None:
    """Every measurement builds its FMUs into an empty cache (workers inherit the environment)."""
    os.environ["WEC_COSIM_CACHE"] = str(folder / name)


def bare(s, folder: Path) -> tuple[float, list[float]]:
    """(total s, per-case s) of the cases run one after another in this process."""
    from orchestrator.results import read_results

    plan = plan_sweep(s)
    start = time.perf_counter()
    each = []
    for case in plan.cases:
        path = folder / f"bare_{case.id}.h5"
        t0 = time.perf_counter()
        run_scenario(prepare_time_domain(case_scenario(plan, case)), path, progress=False, log=None)
        read_results(path)
        each.append(time.perf_counter() - t0)
    return time.perf_counter() - start, each


def on_cluster(s, folder: Path, workers: int) -> tuple[float, float, int, list[float]]:
    """(cluster start-up s, sweep s, failed cases, the cases' wall times in the workers s)."""
    from distributed import Client

    start = time.perf_counter()
    cluster = local_cluster(workers, dashboard=False)
    client = Client(cluster)
    client.wait_for_workers(workers)
    startup = time.perf_counter() - start
    try:
        start = time.perf_counter()
        out = run_sweep(s, folder / f"sweep_{workers}.h5", client=client, progress=False, log=None)
        elapsed = time.perf_counter() - start
        with h5py.File(out.path) as f:
            in_workers = sorted((str(g.attrs["finished"]), float(g.attrs["wall_time"])) for g in f["cases"].values())
        return startup, elapsed, out.failed, [w for _, w in in_workers]
    finally:
        client.close()
        close_quietly(cluster)


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cases", type=int, default=8)
    p.add_argument("--duration", type=float, default=200.0, help="simulated s per case")
    p.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "sweep.txt"))
    a = p.parse_args(argv)
    s = sweep_scenario(a.cases, a.duration)
    lines = [f"# {' '.join(['python', *sys.argv])}",
             f"# date: {date.today()}  machine: {platform.machine()} {os.cpu_count()} cores, python "
             f"{platform.python_version()}",
             f"# cases: cylinder_irregular, Hs 2 m Tp 7 s, {a.cases} seeds x {a.duration:g} s (dt "
             f"{s.simulation.step:g} s), time domain; every case builds its hydro FMU (empty caches)"]
    rows = []
    inside: dict[int, list[float]] = {}
    with tempfile.TemporaryDirectory(prefix="bench_sweep_") as tmp:
        folder = Path(tmp)
        before = load()
        fresh_cache(folder, "bare")
        t_bare, each_bare = bare(s, folder)
        rows.append(("bare runs, this process", "-", t_bare, 0, before, load()))
        for workers in (1, 2):
            before = load()
            fresh_cache(folder, f"workers{workers}")
            startup, t_sweep, failed, in_workers = on_cluster(s, folder, workers)
            if failed:
                raise SystemExit(f"{failed} cases failed on {workers} workers")
            rows.append((f"sweep, {workers} worker{'s' if workers > 1 else ''}", f"{startup:.1f}", t_sweep,
                         startup, before, load()))
            inside[workers] = in_workers
    n = a.cases
    lines.append(f"{'how':<26}{'start-up s':>11}{'cases s':>9}{'s/case':>8}{'cases/min':>10}"
                 f"{'incl. start-up':>16}   load before -> after")
    for how, startup, t, st, before, after in rows:
        lines.append(f"{how:<26}{startup:>11}{t:>9.1f}{t / n:>8.2f}{60 * n / t:>10.2f}{60 * n / (t + st):>16.2f}"
                     f"   {before} -> {after}")
    t_bare, t_one, t_two = rows[0][2], rows[1][2], rows[2][2]
    lines.append(f"per-case overhead of the sweep (1 worker, start-up excluded) against the bare run: "
                 f"{(t_one - t_bare) / n:+.2f} s ({100 * (t_one / t_bare - 1):+.1f} %)")
    lines.append(f"  of which inside the worker's case function (run, reading back, summary): "
                 f"{(sum(inside[1]) - t_bare) / n:+.2f} s; scheduling, transfer and writing the sweep file: "
                 f"{(t_one - sum(inside[1])) / n:+.2f} s")
    lines.append(f"  per case, bare: first {each_bare[0]:.2f} s, median of the others "
                 f"{statistics.median(each_bare[1:]):.2f} s; in the 1-worker sweep: first {inside[1][0]:.2f} s "
                 f"(the worker's imports), median of the others {statistics.median(inside[1][1:]):.2f} s")
    lines.append(f"speed-up of 2 workers over 1: {t_one / t_two:.2f}")
    write_report(lines, a.out)


if __name__ == "__main__":
    main()
