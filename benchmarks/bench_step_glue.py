"""The Python around the fused multibody step: per macro step, the whole call against the compiled kernel inside it.

Issue 15's pendulum and four-bar regressed while the kernel (``mbd_fmu.kernels.ga_macro_step``) did not: the cost
was the Python around the call. This benchmark measures that part directly, in one process, on states from real
runs:

* ``pendulum``, ``four-bar``: the mechanisms of ``bench_speed.py`` section 1 (1 ms step, index-3, spectral radius
  0.8), ``MultibodySimulator.advance`` after 300 steps;
* ``hinge barge (FMU)``: the multibody FMU's slave of ``scenarios/hinge_barge.toml`` after a 4 s in-process run
  (the master's set_real calls of two consecutive macro steps replayed alternately: a new input, hence a restart, at
  every step, as in the run), per macro step ``set_real`` + ``do_step`` + ``get_real`` as the master calls them.

The kernel's own time is taken by timing each of its calls inside the same steps (a wrapper around
``kernels.ga_macro_step``, about 0.3 us of its own); "around" = whole - kernel is the Python glue (argument
assembly, state update, outputs, the FMU wrapper's input and command handling; PythonFMU's and fmpy's own call
overhead, ~10 us per call, is not in it: in process). Figures: the median over ``--repeats`` blocks of the
microseconds per step (each block 2000 steps for the mechanisms, 300 macro steps for the FMU).

A/B against a git revision: ``--baseline REV`` runs the measurement in alternating child processes, ``--rounds``
times each, on the packages of REV (extracted with ``git archive``) and on this tree, with the thread's CPU time
as the clock (robust to a loaded machine; ``--clock wall`` for wall time) and two more figures per mechanism:
``glue only``, the same ``advance`` calls with ``ga_macro_step`` replaced by a stub that reports one substep done
(the Python around the call alone, without the kernel's cache effects on it), and the minimum over the blocks
besides their median. Reported: min over the rounds and the median of the rounds.

Run: python benchmarks/bench_step_glue.py --out benchmarks/results/step_glue.txt  (about 1 min, compiled kernels
cached); A/B: python benchmarks/bench_step_glue.py --baseline main --out benchmarks/results/step_glue_ab.txt
(about 3 min)
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks.common import report_header, revision_tree, write_report  # noqa: E402

TIMER = time.perf_counter  # wall clock (default); --clock cpu: the calling thread's CPU time


class KernelClock:
    """Times every call of ``kernels.ga_macro_step`` (the compiled entry point the fused path calls) while active."""

    def __init__(self) -> None:
        from mbd_fmu import kernels

        self.kernels, self.real, self.seconds = kernels, kernels.ga_macro_step, 0.0

    def __enter__(self) -> KernelClock:
        real = self.real

        def timed(*args):  # noqa: ANN002, ANN202
            t0 = TIMER()
            try:
                return real(*args)
            finally:
                self.seconds += TIMER() - t0

        self.kernels.ga_macro_step = timed
        return self

    def __exit__(self, *exc: object) -> None:
        self.kernels.ga_macro_step = self.real


def blocks(step, count: int, repeats: int, clock: KernelClock, best: bool = False) -> tuple[float, float]:  # noqa: ANN001
    """Median (``best``: minimum) over ``repeats`` blocks of ``count`` calls of ``step`` of the Python around the
    kernel: (whole us per call, kernel us per call) of that block."""
    whole, kernel = [], []
    for _ in range(repeats):
        clock.seconds = 0.0
        t0 = TIMER()
        for _ in range(count):
            step()
        whole.append((TIMER() - t0) / count * 1e6)
        kernel.append(clock.seconds / count * 1e6)
    order = np.argsort(np.array(whole) - np.array(kernel))
    k = order[0 if best else len(order) // 2]
    return whole[k], kernel[k]


def glue_only(build, repeats: int) -> float:  # noqa: ANN001
    """us per ``advance`` of a mechanism with ``ga_macro_step`` replaced by a stub that reports one substep done and
    the factors kept (the state is not moved): the Python around the call alone; minimum over ``repeats`` blocks of
    2000 calls."""
    from bench_speed import run_ours

    from mbd_fmu import kernels

    _, sim = run_ours(build, "index3", 1e-3, 300)
    f, real = sim.formulation, kernels.ga_macro_step
    steps = f.steps
    kernels.ga_macro_step = lambda *args: (0, 1, 2, 0, True, False)
    try:
        times = []
        for _ in range(repeats):
            t0 = TIMER()
            for _ in range(2000):
                f.steps, f._quality = steps, (steps, 1.0)  # (redundant rows: their quality stays current)
                sim.advance(1e-3)
            times.append((TIMER() - t0) / 2000 * 1e6)
    finally:
        kernels.ga_macro_step = real
    return min(times)


def mechanism(build, repeats: int, clock: KernelClock, best: bool = False) -> tuple[float, float]:  # noqa: ANN001
    from bench_speed import run_ours

    _, sim = run_ours(build, "index3", 1e-3, 300)
    return blocks(lambda: sim.advance(1e-3), 2000, repeats, clock, best)


def hinge_barge_fmu(repeats: int, clock: KernelClock, best: bool = False) -> tuple[float, float]:
    from orchestrator.cosim import simulation as S
    from orchestrator.fmi import components as C
    from orchestrator.scenario import load_scenario

    scenario = load_scenario(ROOT / "scenarios" / "hinge_barge.toml")
    scenario.simulation.duration = 4.0
    kept, sets, gets = {}, [], []
    saved = {name: getattr(C.InProcessComponent, name) for name in ("terminate", "set_reals", "get_reals")}

    def set_reals(self, port, values):  # noqa: ANN001, ANN202
        if self.name == "mbd":
            sets.append((list(port.vrs), values.tolist()))
        return saved["set_reals"](self, port, values)

    def get_reals(self, port):  # noqa: ANN001, ANN202
        if self.name == "mbd":
            gets.append(list(port.vrs))
        return saved["get_reals"](self, port)

    C.InProcessComponent.terminate = lambda self: kept.setdefault(self.name, self)  # keep the slave alive
    C.InProcessComponent.set_reals, C.InProcessComponent.get_reals = set_reals, get_reals
    try:
        with tempfile.TemporaryDirectory() as tmp:
            S.run_scenario(scenario, Path(tmp) / "run.h5", progress=False, log=None, in_process=True)
    finally:
        for name, f in saved.items():
            setattr(C.InProcessComponent, name, f)
    slave, h = kept["mbd"].slave, scenario.simulation.step
    steps = round(scenario.simulation.duration / h)
    per_step = len(sets) // steps
    replay, read = sets[-2 * per_step:], gets[-1]
    state = {"t": scenario.simulation.duration, "k": 0}

    def step() -> None:
        k = state["k"] % 2
        for vrs, values in replay[k * per_step:(k + 1) * per_step]:
            slave.set_real(vrs, values)
        slave.do_step(state["t"], h)
        state["t"] += h
        slave.get_real(read)
        state["k"] += 1

    for _ in range(100):
        step()
    return blocks(step, 300, repeats, clock, best)


def measure(repeats: int) -> dict[str, dict[str, float]]:
    """Per case, us per step: whole call, kernel inside it and the Python around it, of the median and of the
    fastest block; per mechanism also the glue alone (stubbed kernel)."""
    from bench_speed import four_bar_model, pendulum_model

    cases = {"pendulum": lambda clock, best: mechanism(pendulum_model, repeats, clock, best),
             "four-bar": lambda clock, best: mechanism(four_bar_model, repeats, clock, best),
             "hinge barge (FMU)": lambda clock, best: hinge_barge_fmu(repeats, clock, best)}
    out: dict[str, dict[str, float]] = {}
    with KernelClock() as clock:
        for name, run in cases.items():
            out[name] = {}
            for block, best in (("median block", False), ("best block", True)):
                whole, kernel = run(clock, best)
                out[name].update({f"whole ({block})": whole, f"kernel ({block})": kernel,
                                  f"around ({block})": whole - kernel})
    for name, build in (("pendulum", pendulum_model), ("four-bar", four_bar_model)):
        out[name]["glue only (best block)"] = glue_only(build, repeats)
    return out


def ab(args: argparse.Namespace) -> list[str]:
    """Alternating child processes on the baseline revision's packages and this tree's, ``--rounds`` times each."""
    import json
    import subprocess

    runs: dict[str, list[dict]] = {"baseline": [], "this tree": []}
    with tempfile.TemporaryDirectory() as tmp:
        trees = {"baseline": revision_tree(args.baseline, Path(tmp)), "this tree": ROOT}
        for _ in range(args.rounds):
            for label, tree in trees.items():
                cmd = [sys.executable, __file__, "--tree", str(tree), "--json", "--repeats", str(args.repeats),
                       "--clock", args.clock]
                result = subprocess.run(cmd, capture_output=True, text=True, check=True)
                runs[label].append(json.loads(result.stdout.splitlines()[-1]))
    lines = [f"# A/B in alternating processes, {args.rounds} rounds: baseline = the packages of {args.baseline}, this "
             f"tree = the working tree; us per step of {args.clock} time, min over the rounds (median of the rounds)",
             f"{'case':<20} {'figure':<24} {'baseline':>16} {'this tree':>16} {'ratio':>6}"]
    for case, figures in runs["baseline"][0].items():
        for figure in figures:
            a = [r[case][figure] for r in runs["baseline"]]
            b = [r[case][figure] for r in runs["this tree"]]
            lines.append(f"{case:<20} {figure:<24} {min(a):7.1f} ({np.median(a):6.1f}) {min(b):7.1f} "
                         f"({np.median(b):6.1f}) {min(b) / min(a):6.2f}")
    return lines


def main() -> None:
    global TIMER
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--clock", choices=("wall", "cpu"), default=None,
                        help="timer: wall clock (default) or the thread's CPU time (default with --baseline)")
    parser.add_argument("--baseline", help="git revision to compare with in alternating processes, e.g. main")
    parser.add_argument("--rounds", type=int, default=3, help="A/B rounds (processes per side)")
    parser.add_argument("--tree", type=Path, help=argparse.SUPPRESS)  # (A/B child: the packages from here)
    parser.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--out", default="")
    args = parser.parse_args()
    args.clock = args.clock or ("cpu" if args.baseline or args.json else "wall")
    if args.clock == "cpu":
        TIMER = time.thread_time
    if args.tree:
        sys.path.insert(0, str(args.tree.resolve()))
    sys.path.insert(1 if args.tree else 0, str(ROOT / "benchmarks"))
    from benchmarks.common import load

    if args.baseline:
        lines = [*report_header("bench_step_glue.py"), *ab(args), f"# load average at the end {load()}"]
        write_report(lines, args.out or None)
        return
    if args.json:
        import json

        import mbd_fmu
        assert args.tree is None or Path(mbd_fmu.__file__).resolve().parent.parent == args.tree.resolve()
        print(json.dumps(measure(args.repeats)))
        return
    from bench_speed import four_bar_model, pendulum_model

    import mbd_fmu

    lines = [*report_header("bench_step_glue.py"), f"# mbd_fmu from {Path(mbd_fmu.__file__).parent.parent}",
             f"# us per step ({args.clock} time), median block: whole call, kernel (ga_macro_step) inside it, "
             "around = whole - kernel",
             f"{'case':<20} {'whole':>8} {'kernel':>8} {'around':>8}"]
    with KernelClock() as clock:
        for name, measure_case in (("pendulum", lambda: mechanism(pendulum_model, args.repeats, clock)),
                                   ("four-bar", lambda: mechanism(four_bar_model, args.repeats, clock)),
                                   ("hinge barge (FMU)", lambda: hinge_barge_fmu(args.repeats, clock))):
            whole, kernel = measure_case()
            lines.append(f"{name:<20} {whole:8.1f} {kernel:8.1f} {whole - kernel:8.1f}")
    lines.append(f"# load average at the end {load()}")
    write_report(lines, args.out or None)


if __name__ == "__main__":
    main()
