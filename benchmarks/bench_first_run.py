"""First run on a fresh machine: CPU time of a whole ``wec-cosim run`` with an empty cache, then warm.

The compiled multibody kernels (numba) are compiled at the first call of each entry point and cached
on disk (fmu_base/_jit.py: ``$WEC_COSIM_CACHE/numba``, keyed on the kernels' source); the FMUs are
built once into ``$WEC_COSIM_CACHE/fmus``. This benchmark runs each scene twice in a fresh process
with a fresh, empty ``WEC_COSIM_CACHE``: the first run pays for the FMU builds and every compilation
the scene needs, the second loads both from the cache. Figures: user + system CPU seconds of the
child process (steadier than the wall clock on a loaded machine) and the wall clock.

With ``--entry-points`` it also runs each scene once in this process (in-process slaves, 2 s of
simulation, another empty cache) and lists the CPU seconds numba spends compiling each entry point
at its first call (numba's ``numba:compile`` events, outermost ones only): where a cold start goes.

Run: python benchmarks/bench_first_run.py --out benchmarks/results/first_run.txt   (about 5-10 min)
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks.common import load, report_header, timed_child, write_report  # noqa: E402

# (scenario, simulated seconds or None for the scenario's own)
SCENES = (("hinge_barge", None), ("array_4n3la", 20.0))


def child_run(scenario: str, duration: float | None, cache: Path, out: Path) -> tuple[float, float]:
    """(user + system CPU seconds, wall seconds) of one ``wec-cosim run`` in a child process."""
    cmd = [sys.executable, "-m", "wec_cosim.cli", "run", str(ROOT / "scenarios" / f"{scenario}.toml"), "--quiet",
           "--out", str(out)]
    if duration is not None:
        cmd += ["--duration", str(duration)]
    env = dict(os.environ, WEC_COSIM_CACHE=str(cache))
    env.pop("WEC_COSIM_NO_JIT", None)
    env.pop("WEC_COSIM_NUMBA_CACHE", None)
    wall, cpu = timed_child(cmd, ROOT, env)
    return cpu, wall


def entry_points(scenario: str, cache: Path) -> tuple[float, list[tuple[str, float]]]:
    """(process CPU of a 2 s in-process run, [(entry point, CPU seconds compiling it)]) with an empty cache."""
    code = f"""
import os, sys, time
sys.path.insert(0, {str(ROOT)!r})
from numba.core import event
from orchestrator.scenario.overrides import apply_overrides
from orchestrator.scenario import load_scenario
from orchestrator.cosim.simulation import run_scenario
s = apply_overrides(load_scenario({str(ROOT / 'scenarios' / (scenario + '.toml'))!r}), ["simulation.duration=2"])
stack, tops = [], []
class Listener(event.Listener):
    def on_start(self, e):
        stack.append((time.process_time(), e.data["dispatcher"].py_func.__name__))
    def on_end(self, e):
        c0, name = stack.pop()
        if not stack:
            tops.append((name, time.process_time() - c0))
t0 = time.process_time()
with event.install_listener("numba:compile", Listener()):
    run_scenario(s, {str(cache / 'run.h5')!r}, in_process=True, progress=False, log=lambda *a: None)
print(time.process_time() - t0)
for name, dt in tops:
    print(name, dt)
"""
    env = dict(os.environ, WEC_COSIM_CACHE=str(cache))
    env.pop("WEC_COSIM_NO_JIT", None)
    env.pop("WEC_COSIM_NUMBA_CACHE", None)
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(proc.stderr[-2000:])
    rows = proc.stdout.split("\n")
    total = float(rows[0])
    return total, [(r.split()[0], float(r.split()[1])) for r in rows[1:] if r.strip()]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default="", help="also write the report to this file")
    p.add_argument("--entry-points", action="store_true", help="also list the compile time of each entry point")
    args = p.parse_args()
    import numba

    lines = [*report_header("bench_first_run.py", f", numba {numba.__version__}"),
             "", "## whole `wec-cosim run` (through fmpy) with an empty WEC_COSIM_CACHE, then again with it warm",
             f"{'scene':<14}{'simulated':>10}{'cold CPU s':>12}{'wall s':>8}{'warm CPU s':>12}{'wall s':>8}  load"]
    for scenario, duration in SCENES:
        with tempfile.TemporaryDirectory() as tmp:
            cache = Path(tmp) / "cache"
            cold = child_run(scenario, duration, cache, Path(tmp) / "cold.h5")
            warm = child_run(scenario, duration, cache, Path(tmp) / "warm.h5")
        simulated = "own" if duration is None else f"{duration:g} s"
        lines.append(f"{scenario:<14}{simulated:>10}{cold[0]:12.1f}{cold[1]:8.1f}{warm[0]:12.1f}{warm[1]:8.1f}  "
                     f"{load()}")
        print(lines[-1], flush=True)
    if args.entry_points:
        lines += ["", "## numba compile CPU per entry point (first call, outermost compilations), 2 s in process, "
                  "empty cache"]
        for scenario, _ in SCENES:
            with tempfile.TemporaryDirectory() as tmp:
                total, tops = entry_points(scenario, Path(tmp))
            compiled = sum(t for _, t in tops)
            lines.append(f"{scenario}: process CPU {total:.1f} s, of which compiling {compiled:.1f} s in {len(tops)} "
                         f"entry points (load {load()})")
            lines += [f"  {name:<24}{dt:7.2f} s" for name, dt in sorted(tops, key=lambda x: -x[1])]
            print("\n".join(lines[-len(tops) - 1:]), flush=True)
    lines.append(f"# load average at the end {load()}")
    write_report(lines, args.out or None)


if __name__ == "__main__":
    main()
