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

A/B against another checkout: ``PYTHONPATH=<checkout> python benchmarks/bench_step_glue.py`` run from that
checkout's root, alternating with this one (this VM's timings drift between processes: compare the ratios, several
alternating runs).

Run: python benchmarks/bench_step_glue.py --out benchmarks/results/step_glue.txt  (about 1 min, compiled kernels
cached)
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

from benchmarks.common import report_header, write_report  # noqa: E402


class KernelClock:
    """Times every call of ``kernels.ga_macro_step`` (the compiled entry point the fused path calls) while active."""

    def __init__(self) -> None:
        from mbd_fmu import kernels

        self.kernels, self.real, self.seconds = kernels, kernels.ga_macro_step, 0.0

    def __enter__(self) -> KernelClock:
        real = self.real

        def timed(*args):  # noqa: ANN002, ANN202
            t0 = time.perf_counter()
            try:
                return real(*args)
            finally:
                self.seconds += time.perf_counter() - t0

        self.kernels.ga_macro_step = timed
        return self

    def __exit__(self, *exc: object) -> None:
        self.kernels.ga_macro_step = self.real


def blocks(step, count: int, repeats: int, clock: KernelClock) -> tuple[float, float]:  # noqa: ANN001
    """Median over ``repeats`` blocks of ``count`` calls of ``step``: (whole us per call, kernel us per call)."""
    whole, kernel = [], []
    for _ in range(repeats):
        clock.seconds = 0.0
        t0 = time.perf_counter()
        for _ in range(count):
            step()
        whole.append((time.perf_counter() - t0) / count * 1e6)
        kernel.append(clock.seconds / count * 1e6)
    order = np.argsort(np.array(whole) - np.array(kernel))
    k = order[len(order) // 2]
    return whole[k], kernel[k]


def mechanism(build, repeats: int, clock: KernelClock) -> tuple[float, float]:  # noqa: ANN001
    from bench_speed import run_ours

    _, sim = run_ours(build, "index3", 1e-3, 300)
    return blocks(lambda: sim.advance(1e-3), 2000, repeats, clock)


def hinge_barge_fmu(repeats: int, clock: KernelClock) -> tuple[float, float]:
    from orchestrator import components as C
    from orchestrator import simulation as S
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
    return blocks(step, 300, repeats, clock)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--out", default="")
    args = parser.parse_args()
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from bench_speed import four_bar_model, pendulum_model

    import mbd_fmu

    lines = [*report_header("bench_step_glue.py"), f"# mbd_fmu from {Path(mbd_fmu.__file__).parent.parent}",
             "# us per step, median block: whole call, kernel (ga_macro_step) inside it, around = whole - kernel",
             f"{'case':<20} {'whole':>8} {'kernel':>8} {'around':>8}"]
    with KernelClock() as clock:
        for name, measure in (("pendulum", lambda: mechanism(pendulum_model, args.repeats, clock)),
                              ("four-bar", lambda: mechanism(four_bar_model, args.repeats, clock)),
                              ("hinge barge (FMU)", lambda: hinge_barge_fmu(args.repeats, clock))):
            whole, kernel = measure()
            lines.append(f"{name:<20} {whole:8.1f} {kernel:8.1f} {whole - kernel:8.1f}")
    from benchmarks.common import load

    lines.append(f"# load average at the end {load()}")
    write_report(lines, args.out or None)


if __name__ == "__main__":
    main()
