"""One compiled call per multibody macro step against the substep-by-substep path, side by side in one process.

For each scene (default: the hinge barge, 20 s) the scenario runs in process (the FMUs' slaves in this process,
the master and results as in a real run) alternately with

* ``fused``: the multibody FMU as built (``MultibodySimulator._advance_fused``: restart, substeps, energy sums and
  outputs in one call of ``mbd_fmu.kernels.ga_macro_step``; outputs gathered from its flat array);
* ``step by step``: the same code with the fused macro step and the flat-array gather switched off (the substep
  loop in Python, one compiled call per substep, the outputs by groups: what main did before),

``--repeats`` times each, timing every component call (set_reals, do_step, get_reals); the report gives the
minimum over the repeats of the microseconds per macro step of each, the wall time per macro step and the real-time
factor, and the largest difference between the two variants' multibody outputs over the whole run (relative to
each output's largest magnitude: round-off, the same answers).

Run: python benchmarks/bench_macro_step.py --out benchmarks/results/macro_step.txt  (about 1-2 min)
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks.common import load, report_header, write_report  # noqa: E402


def run_once(scenario, fused: bool) -> tuple[dict, float, np.ndarray]:
    """(us per macro step of each (component, call), wall seconds, the multibody outputs read (steps, k))."""
    from mbd_fmu.simulator import MultibodySimulator
    from mbd_fmu.slave import MultibodySlave
    from orchestrator.cosim import simulation as S
    from orchestrator.fmi import components as C

    acc: dict = defaultdict(float)
    read: list[np.ndarray] = []
    saved = {name: getattr(C.InProcessComponent, name) for name in ("set_reals", "get_reals", "do_step")}
    advance, get_real = MultibodySimulator._advance_fused, MultibodySlave.get_real

    def timed(name, f):  # noqa: ANN001, ANN202
        def call(self, *args):  # noqa: ANN001, ANN002, ANN202
            t0 = time.perf_counter()
            try:
                out = f(self, *args)
            finally:
                acc[(self.name, name)] += time.perf_counter() - t0
            if name == "get_reals" and self.name == "mbd" and len(out) > 20:
                read.append(np.array(out, dtype=float))
            return out
        return call

    try:
        for name, f in saved.items():
            setattr(C.InProcessComponent, name, timed(name, f))
        if not fused:
            MultibodySimulator._advance_fused = lambda self, *args: False
            MultibodySlave.get_real = lambda self, vrs: (MultibodySlave.__bases__[0].get_real(self, vrs)
                                                         if not (self.nonlinear and self._ready)
                                                         else self._get_real_grouped(vrs))
        with tempfile.TemporaryDirectory() as tmp:
            result = S.run_scenario(scenario, Path(tmp) / "run.h5", progress=False, log=None, in_process=True)
    finally:
        for name, f in saved.items():
            setattr(C.InProcessComponent, name, f)
        MultibodySimulator._advance_fused, MultibodySlave.get_real = advance, get_real
    steps = round(scenario.simulation.duration / scenario.simulation.step)
    return {k: v / steps * 1e6 for k, v in acc.items()}, result.wall_time, np.array(read)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenarios", nargs="+", default=["hinge_barge"], help="bundled scenarios (file stems)")
    p.add_argument("--duration", type=float, default=20.0, help="simulated seconds per run")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--out", default="", help="also write the report to this file")
    args = p.parse_args()
    from orchestrator.scenario import load_scenario

    lines = [*report_header("bench_macro_step.py"),
             "# in-process runs (slaves in this process), minimum over the repeats of us per macro step"]
    for name in args.scenarios:
        scenario = load_scenario(ROOT / "scenarios" / f"{name}.toml")
        scenario.simulation.duration = args.duration
        run_once(scenario, True)  # warm-up: the scene's database and compiled kernels
        best: dict = {}
        outputs = {}
        for _ in range(args.repeats):
            for fused in (False, True):
                calls, wall, read = run_once(scenario, fused)
                outputs[fused] = read
                row = best.setdefault(fused, {"wall": np.inf})
                row["wall"] = min(row["wall"], wall)
                for key, value in calls.items():
                    row[key] = min(row.get(key, np.inf), value)
        steps = round(args.duration / scenario.simulation.step)
        lines += ["", f"## {name}: {args.duration:g} s, step {scenario.simulation.step:g} s ({steps} macro steps), "
                  f"load {load()}",
                  f"{'us per macro step':<24}{'step by step':>14}{'fused':>10}{'ratio':>8}"]
        keys = sorted(k for k in best[True] if k != "wall")
        for key in keys:
            a, b = best[False].get(key, np.nan), best[True][key]
            lines.append(f"{key[0] + ' ' + key[1]:<24}{a:14.1f}{b:10.1f}{a / b:8.2f}")
        a = sum(best[False].get(k, 0.0) for k in keys if k[0] == "mbd" and k[1] in ("do_step", "get_reals"))
        b = sum(best[True][k] for k in keys if k[0] == "mbd" and k[1] in ("do_step", "get_reals"))
        lines.append(f"{'mbd do_step + get_reals':<24}{a:14.1f}{b:10.1f}{a / b:8.2f}")
        wa, wb = best[False]["wall"] / steps * 1e6, best[True]["wall"] / steps * 1e6
        lines.append(f"{'wall (whole run)':<24}{wa:14.1f}{wb:10.1f}{wa / wb:8.2f}")
        lines.append(f"{'real-time factor':<24}{args.duration / best[False]['wall']:14.1f}"
                     f"{args.duration / best[True]['wall']:10.1f}")
        x, y = outputs[True], outputs[False]
        scale = np.maximum(np.max(np.abs(y), axis=0), 1e-300)
        lines.append(f"largest difference of the {x.shape[1]} multibody outputs read over the run (each relative to "
                     f"its largest magnitude): {np.max(np.abs(x - y) / scale):.2e}")
        print("\n".join(lines[-len(keys) - 7:]), flush=True)
    lines.append(f"# load average at the end {load()}")
    write_report(lines, args.out or None)


if __name__ == "__main__":
    main()
