"""Per-call cost of the compiled index-3 macro step (``mbd_fmu.kernels.ga_macro_step``) on a real state, no Python
glue: what one hinge-barge macro step costs inside the kernel, by part.

1. ``--capture FILE`` runs the scenario in process (default: the hinge barge, 20 s) and saves the arguments of the
   last ``ga_macro_step`` call of the multibody formulation (plan arrays, state, inputs, factors) to ``FILE``
   (``.npz``, plain arrays: no pickle);
2. the timing (default) loads that file and times, with ``timeit`` (minimum over ``--repeats`` of ``--number``
   calls, microseconds per call), the kernel on that state in the variants the master uses: 2 substeps with the
   restart (consistent acceleration + Taylor shift), 2 substeps without it, 1 substep, the restart alone, nothing
   (0 substeps: the call's fixed cost), each with and without the outputs. The factors ``lu``, ``piv`` are
   restored before each variant (the captured ones: reused while ``have_lu``).

Run: python benchmarks/bench_kernel_substep.py --capture benchmarks/results/hb_kernel_state.npz   (once, ~30 s)
     python benchmarks/bench_kernel_substep.py --state benchmarks/results/hb_kernel_state.npz --out \
benchmarks/results/kernel_substep.txt
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import timeit
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from benchmarks.common import report_header, write_report  # noqa: E402

# ga_macro_step's positional arguments, in order
ARGS = ("ip", "fp", "pr", "pR", "v", "vdot", "a", "lam", "inputs", "refs", "h", "substeps", "coef",
        "newton_tolerance", "length", "max_iterations", "lu", "piv", "have_lu", "consistent", "shift", "delta",
        "pto_springs", "energy", "out")


def capture(scenario_path: Path, duration: float, path: Path) -> None:
    """Run the scenario in process and save the last macro step's kernel arguments to ``path``."""
    from mbd_fmu import kernels
    from orchestrator import simulation as S
    from orchestrator.scenario import load_scenario

    scenario = load_scenario(scenario_path)
    scenario.simulation.duration = duration
    last: dict = {}
    original = kernels.ga_macro_step

    def spy(*args):  # noqa: ANN002, ANN202
        if args[11] > 0:  # a real macro step (not an evaluation of the state)
            last.clear()
            last.update({k: (np.array(a, copy=True) if isinstance(a, np.ndarray) else a)
                         for k, a in zip(ARGS, args, strict=True)})
        return original(*args)

    kernels.ga_macro_step = spy
    try:
        with tempfile.TemporaryDirectory() as tmp:
            S.run_scenario(scenario, Path(tmp) / "r.h5", progress=False, log=None, in_process=True)
    finally:
        kernels.ga_macro_step = original
    np.savez(path, **{k: np.asarray(v) for k, v in last.items()})
    print(f"saved {path}: substeps {last['substeps']}, n {last['v'].size}, rows {last['lam'].size}")


def load_state(path: Path) -> dict:
    with np.load(path, allow_pickle=False) as z:
        st = {k: z[k] for k in z.files}
    for k in ("h", "newton_tolerance", "length", "delta"):
        st[k] = float(st[k])
    for k in ("substeps", "max_iterations", "shift"):
        st[k] = int(st[k])
    for k in ("have_lu", "consistent"):
        st[k] = bool(st[k])
    return st


def variants(st: dict) -> list[tuple[str, dict]]:
    """(name, arguments) of the variants timed: the master's kinds of macro step, with and without outputs."""
    from mbd_fmu.kernels import macro_layout, unpack
    n, r, nb = st["v"].size, st["lam"].size, st["pr"].shape[0]
    springs = unpack(st["ip"], st["fp"])[19].shape[0]
    short = int(macro_layout(n, r, nb, st["refs"].size, springs, 0, 0)[11])  # no room for the outputs
    out = []
    for name, sub, cons, shift in (("2 substeps + restart", 2, True, 1), ("2 substeps, no restart", 2, False, 0),
                                   ("1 substep, no restart", 1, False, 0), ("restart only", 0, True, 1),
                                   ("nothing (0 substeps)", 0, False, 0)):
        h = st["h"] * sub / st["substeps"] if sub else st["h"]  # the captured substep length
        for outputs in (True, False):
            kw = dict(st, substeps=sub, consistent=cons, shift=shift, h=h,
                      out=np.empty(st["out"].size if outputs else short))
            out.append((f"{name}{', outputs' if outputs else ''}", kw))
    return out


def time_call(f, number: int, repeats: int, clock: str = "cpu") -> float:  # noqa: ANN001
    """Microseconds per call of ``f``: minimum over ``repeats`` of ``number`` calls, by the thread's CPU time
    (``clock`` "cpu": what the call costs, not the waits for a core on a shared machine) or wall time."""
    timer = time.thread_time if clock == "cpu" else time.perf_counter
    return min(timeit.repeat(f, number=number, repeat=repeats, timer=timer)) / number * 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--capture", type=Path, help="run the scenario and save the last macro step's state here")
    ap.add_argument("--scenario", type=Path, default=ROOT / "scenarios" / "hinge_barge.toml")
    ap.add_argument("--duration", type=float, default=20.0)
    ap.add_argument("--state", type=Path, default=ROOT / "benchmarks" / "results" / "hb_kernel_state.npz")
    ap.add_argument("--number", type=int, default=2000)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--clock", choices=("cpu", "wall"), default="cpu",
                    help="timer: the thread's CPU time (default; robust to a loaded machine) or wall time")
    ap.add_argument("--out", type=Path, help="write the report here (else print)")
    args = ap.parse_args()
    if args.capture:
        capture(args.scenario, args.duration, args.capture)
        return
    from mbd_fmu import kernels as K
    st = load_state(args.state)
    lines = [f"state: {args.state.name} (n {st['v'].size}, kept rows {st['lam'].size}, bodies {st['pr'].shape[0]}, "
             f"macro step {st['h']} s in {st['substeps']} substeps)",
             f"per call, min over {args.repeats} x {args.number} calls, microseconds of {args.clock} time:"]
    for name, kw in variants(st):
        call = [kw[k] for k in ARGS]
        lu0, piv0 = call[16].copy(), call[17].copy()
        res = K.ga_macro_step(*call)  # compile / warm
        call[16][:], call[17][:] = lu0, piv0
        t = time_call(lambda: K.ga_macro_step(*call), args.number, args.repeats, args.clock)  # noqa: B023
        lines.append(f"  {name:36s} {t:8.1f}   (status {res[0]}, iterations {res[2]}, keep {res[4]})")
    write_report(report_header("bench_kernel_substep.py") + lines, args.out)


if __name__ == "__main__":
    main()
