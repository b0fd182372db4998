"""Per-macro-step cost of each FMU call (set_reals, do_step, get_reals) through fmpy, this tree against a base
revision, side by side in one run.

For each scenario the run alternates between the base revision's sources (``git archive`` into a temporary
folder, imported through PYTHONPATH) and this tree's, each in a fresh process that runs the scenario through
fmpy and times every component call; per scenario and tree it keeps the minimum over the repeats of each
call's microseconds per macro step (and of the whole stepping loop's wall time per step). FMUs come from the
shared cache (its key hashes the sources, so each tree gets its own FMUs); compiled multibody kernels from the
shared numba cache.

    python benchmarks/bench_hydro_calls.py --out benchmarks/results/hydro_calls.txt
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))

# name[:simulated seconds] (default --duration)
DEFAULT_SCENARIOS = ("hinge_barge", "f3of_dt3", "array_4n3la:4", "cylinder_irregular", "cylinder_regular")


def child(scenario: str, duration: float) -> None:
    """Run one scenario through fmpy, print per-call microseconds per macro step as JSON."""
    from orchestrator.cosim import simulation as S
    from orchestrator.fmi import components as C
    from orchestrator.scenario import load_scenario

    s = load_scenario(Path(os.environ["BENCH_SCENARIOS"]) / f"{scenario}.toml")
    s.simulation.duration = duration
    acc: dict[tuple[str, str], float] = defaultdict(float)
    for meth in ("set_reals", "get_reals", "do_step"):
        f = getattr(C.FmuComponent, meth)

        def timed(self, *a, _f=f, _m=meth):  # noqa: ANN001, ANN002, ANN202
            t0, c0 = time.perf_counter(), time.thread_time()
            try:
                return _f(self, *a)
            finally:
                acc[(self.name, _m)] += time.perf_counter() - t0
                acc[(self.name, _m + ".cpu")] += time.thread_time() - c0
        setattr(C.FmuComponent, meth, timed)
    best: dict[str, float] = {}
    for _ in range(2):  # the first run builds or loads the FMUs and warms everything
        acc.clear()
        with tempfile.TemporaryDirectory() as tmp:
            r = S.run_scenario(s, Path(tmp) / "w.h5", progress=False, log=None)
        steps = round(duration / s.simulation.step)
        row = {f"{c}.{m}": v / steps * 1e6 for (c, m), v in acc.items()}
        row["wall"] = r.wall_time / steps * 1e6
        best = row if not best else {k: min(v, best.get(k, v)) for k, v in row.items()}
    print("RESULT " + json.dumps(best))


def run_tree(tree: Path, scenario: str, duration: float) -> dict[str, float]:
    env = dict(os.environ, PYTHONPATH=str(tree), BENCH_SCENARIOS=str(ROOT / "scenarios"))
    out = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--child", scenario, str(duration)],
                         capture_output=True, text=True, env=env, cwd=tree)
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith("RESULT ")]
    if out.returncode or not lines:
        raise RuntimeError(f"{scenario} in {tree} failed:\n{out.stderr[-3000:]}")
    return json.loads(lines[-1][len("RESULT "):])


def main() -> None:
    from common import write_report

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--base", default="main", help="git revision to compare with (default main)")
    p.add_argument("--this", default="", help="git revision to measure (default: this working tree as it is)")
    p.add_argument("--scenarios", default=",".join(DEFAULT_SCENARIOS),
                   help="comma-separated scenario names, each optionally with :seconds")
    p.add_argument("--duration", type=float, default=20.0, help="simulated seconds per run")
    p.add_argument("--repeats", type=int, default=3, help="alternating runs per tree (minimum kept)")
    p.add_argument("--out", default="", help="also write the report to this file")
    p.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.child:
        child(args.child[0], float(args.child[1]))
        return
    git = lambda *a: subprocess.run(["git", *a], capture_output=True, text=True, cwd=ROOT, check=True).stdout.strip()  # noqa: E731
    head, base = git("rev-parse", "--short", args.this or "HEAD"), git("rev-parse", "--short", args.base)
    dirty = not args.this and git("status", "--porcelain")
    lines = [f"# command: python benchmarks/bench_hydro_calls.py {' '.join(sys.argv[1:])}".rstrip(),
             f"# machine: {platform.node()}, {platform.machine()}, {os.cpu_count()} cores, python "
             f"{platform.python_version()}; load average at start {' '.join(f'{x:.2f}' for x in os.getloadavg())}",
             f"# this tree: git {head}{' (with uncommitted changes)' if dirty else ''}; "
             f"base: {args.base} = {base}; minimum over {args.repeats} alternating runs (default {args.duration:g} s) "
             "(each run: the better of two passes), microseconds per macro step through fmpy",
             "# rows 'cpu': the calling thread's CPU time in the same calls (less sensitive to other processes)",
             "", f"{'scenario':<20}{'tree':<9}{'hydro set':>10}{'step':>8}{'get':>8}{'sum':>8}"
             f"{'mbd set':>9}{'step':>8}{'get':>8}{'loop':>9}"]
    with tempfile.TemporaryDirectory() as tmp:
        trees = {}
        for label, rev in (("base", args.base), ("this", args.this)):
            trees[label] = ROOT
            if rev:  # a revision's sources, as they are in git
                trees[label] = Path(tmp) / label
                trees[label].mkdir()
                archive = subprocess.run(["git", "archive", rev], capture_output=True, cwd=ROOT, check=True).stdout
                subprocess.run(["tar", "-x", "-C", str(trees[label])], input=archive, check=True)
        for item in args.scenarios.split(","):
            scenario, _, seconds = item.partition(":")
            duration = float(seconds) if seconds else args.duration
            results: dict[str, dict[str, float]] = {}
            for _ in range(args.repeats):
                for label, tree in trees.items():
                    row = run_tree(tree, scenario, duration)
                    old = results.get(label)
                    results[label] = row if old is None else {k: min(v, old.get(k, v)) for k, v in row.items()}
            for label in ("base", "this"):
                for clock in ("", ".cpu"):
                    r = results[label]
                    hydro = [r.get(f"hydro.{m}{clock}", float("nan")) for m in ("set_reals", "do_step", "get_reals")]
                    mbd = [r.get(f"mbd.{m}{clock}", float("nan")) for m in ("set_reals", "do_step", "get_reals")]
                    lines.append(f"{scenario:<20}{label + (' cpu' if clock else ''):<9}"
                                 + "".join(f"{x:10.1f}" if i == 0 else f"{x:8.1f}" for i, x in enumerate(hydro))
                                 + f"{sum(hydro):8.1f}{mbd[0]:9.1f}{mbd[1]:8.1f}{mbd[2]:8.1f}"
                                 + (f"{r['wall']:9.1f}" if not clock else ""))
                    print(lines[-1], flush=True)
            b, t = results["base"], results["this"]
            hb, ht, cb, ct = (sum(r.get(f"hydro.{m}{c}", 0.0) for m in ("set_reals", "do_step", "get_reals"))
                              for r, c in ((b, ""), (t, ""), (b, ".cpu"), (t, ".cpu")))
            lines.append(f"{'':<20}hydro calls base/this = {hb / ht:.2f} (cpu {cb / ct:.2f}); "
                         f"loop base/this = {b['wall'] / t['wall']:.2f}; "
                         f"load average now {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
            print(lines[-1], flush=True)
    lines.append(f"# load average at the end {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
