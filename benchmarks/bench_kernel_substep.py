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

With ``--baseline REV`` it runs the timing in alternating child processes, ``--rounds`` times each, on the kernels
of git revision ``REV`` (its ``mbd_fmu`` extracted to a temporary folder) and on this tree's, and says whether both
give bit-identical results on every variant (a hash of the returned tuple and the output array).

Run: python benchmarks/bench_kernel_substep.py --capture benchmarks/results/hb_kernel_state.npz   (once, ~10 s)
     python benchmarks/bench_kernel_substep.py --baseline main --out benchmarks/results/kernel_substep.txt
     (a few minutes when both revisions' kernels are in the numba cache; each cold compile ~2-3 min CPU)
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
    from orchestrator.cosim import simulation as S
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


def measure(st: dict, number: int, repeats: int, clock: str) -> dict:
    """{variant: (microseconds per call, status, iterations, keep, hash of the call's results)} with the
    ``mbd_fmu`` imported (this tree's or ``--tree``'s)."""
    import hashlib

    from mbd_fmu import kernels as K
    out = {}
    for name, kw in variants(st):
        call = [kw[k] for k in ARGS]
        lu0, piv0 = call[16].copy(), call[17].copy()
        res = K.ga_macro_step(*call)  # compile / warm
        digest = hashlib.sha1(np.concatenate([np.array(res, float), call[24]]).tobytes()).hexdigest()[:12]
        call[16][:], call[17][:] = lu0, piv0
        t = time_call(lambda: K.ga_macro_step(*call), number, repeats, clock)  # noqa: B023
        out[name] = (t, int(res[0]), int(res[2]), bool(res[4]), digest)
    return out


def baseline_tree(ref: str, tmp: Path) -> Path:
    """``mbd_fmu`` of git revision ``ref`` extracted into ``tmp`` (the kernels' cache is keyed on content)."""
    import subprocess
    archive = subprocess.run(["git", "archive", ref, "mbd_fmu"], cwd=ROOT, capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(tmp)], input=archive, check=True)
    return tmp


def ab(args: argparse.Namespace) -> list[str]:
    """Alternating processes: the baseline revision's kernels and this tree's, ``--rounds`` times each."""
    import json
    import subprocess
    runs: dict = {"baseline": [], "this tree": []}
    with tempfile.TemporaryDirectory() as tmp:
        trees = {"baseline": baseline_tree(args.baseline, Path(tmp)), "this tree": ROOT}
        for _ in range(args.rounds):
            for label, tree in trees.items():
                cmd = [sys.executable, __file__, "--tree", str(tree), "--json", "--state", str(args.state),
                       "--number", str(args.number), "--repeats", str(args.repeats), "--clock", args.clock]
                runs[label].append(json.loads(subprocess.run(cmd, capture_output=True, text=True,
                                                             check=True).stdout.splitlines()[-1]))
    lines = [f"A/B in alternating processes, {args.rounds} rounds: baseline = mbd_fmu of {args.baseline}, this tree "
             f"= the working tree; per call, min over the rounds of (min over {args.repeats} x {args.number} "
             f"calls), microseconds of {args.clock} time; median of the rounds in brackets",
             f"  {'variant':36s} {'baseline':>16s} {'this tree':>16s} {'ratio':>6s}  same results"]
    for name in runs["baseline"][0]:
        a = [r[name][0] for r in runs["baseline"]]
        b = [r[name][0] for r in runs["this tree"]]
        same = len({r[name][4] for r in runs["baseline"] + runs["this tree"]}) == 1
        lines.append(f"  {name:36s} {min(a):7.1f} ({np.median(a):6.1f}) {min(b):7.1f} ({np.median(b):6.1f}) "
                     f"{min(b) / min(a):6.2f}  {'bit-identical' if same else 'DIFFERENT'}")
    return lines


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
    ap.add_argument("--baseline", help="git revision to compare with (A/B in alternating processes), e.g. main")
    ap.add_argument("--rounds", type=int, default=3, help="A/B rounds (processes per side)")
    ap.add_argument("--tree", type=Path, help=argparse.SUPPRESS)  # (A/B child: import mbd_fmu from here)
    ap.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--out", type=Path, help="write the report here (else print)")
    args = ap.parse_args()
    if args.capture:
        capture(args.scenario, args.duration, args.capture)
        return
    if args.tree:
        sys.path.insert(0, str(args.tree.resolve()))
    st = load_state(args.state)
    head = [f"state: {args.state.name} (n {st['v'].size}, kept rows {st['lam'].size}, bodies {st['pr'].shape[0]}, "
            f"macro step {st['h']} s in {st['substeps']} substeps)"]
    if args.baseline:
        write_report(report_header("bench_kernel_substep.py") + head + ab(args), args.out)
        return
    res = measure(st, args.number, args.repeats, args.clock)
    if args.json:
        import json

        import mbd_fmu
        assert args.tree is None or Path(mbd_fmu.__file__).resolve().parent.parent == args.tree.resolve()
        print(json.dumps(res))
        return
    lines = head + [f"per call, min over {args.repeats} x {args.number} calls, microseconds of {args.clock} time:"]
    lines += [f"  {name:36s} {t:8.1f}   (status {s}, iterations {i}, keep {k})"
              for name, (t, s, i, k, _) in res.items()]
    write_report(report_header("bench_kernel_substep.py") + lines, args.out)


if __name__ == "__main__":
    main()
