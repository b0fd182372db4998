"""The README quick start's whole-process wall time before and after the compiled hydro runtime, side by side.

``wec-cosim run scenarios/cylinder_regular.toml`` (two FMUs through fmpy, 200 s of regular waves) as a user runs it,
in a child process, from two trees: revision :data:`BEFORE` (the hydro model on its numba pass) extracted into a
temporary folder, and this tree (the hydro model on the compiled runtime). Each tree has its own empty cache
(``WEC_COSIM_CACHE``: FMU builds and numba kernels): the first run of each is the cold start (FMUs built, kernels
compiled), the next ``--rounds`` runs of the two trees alternate with warm caches. Reported: wall seconds of the whole
process (and its user + system CPU seconds, steadier on a shared machine), medians and the ratio before / after.
Not a timed assertion anywhere: the load is in the header and footer.

    python benchmarks/bench_quick_start.py --rounds 7 --out benchmarks/results/quick_start.txt   (about 3 minutes)
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from common import ROOT, cpu_model, load, report_header, revision_tree, timed_child, write_report

BEFORE = "a4bdb99"  # the numba hydro path, in the package layout of this tree
SCENARIO = "scenarios/cylinder_regular.toml"


def run(tree: Path, cache: Path, out: Path) -> tuple[float, float]:
    """(wall seconds, user + system CPU seconds) of one ``wec-cosim run`` of the quick start from ``tree``."""
    env = {**os.environ, "PYTHONPATH": str(tree), "WEC_COSIM_CACHE": str(cache)}
    for key in ("WEC_COSIM_NO_JIT", "WEC_COSIM_NUMBA_CACHE"):
        env.pop(key, None)
    cmd = [sys.executable, "-m", "wec_cosim.cli", "run", SCENARIO, "--out", str(out)]
    return timed_child(cmd, tree, env)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", help="also write the report here")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    uptime = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    lines = [*report_header("bench_quick_start.py"), f"# lscpu model name: {cpu_model()}",
             f"# uptime at start: {uptime}",
             f"# `wec-cosim run {SCENARIO}` in a child process; before: revision {BEFORE} (numba hydro pass), after: "
             "this tree (compiled hydro runtime); each tree its own cache, cold first run, then "
             f"{args.rounds} alternating warm runs", ""]
    with tempfile.TemporaryDirectory(prefix="wec_quick_start_") as tmp:
        base = Path(tmp)
        (base / "before").mkdir()
        old = revision_tree(BEFORE, base / "before", None)
        (old / "scenarios").mkdir()
        for name in ("cylinder_regular.toml",):
            (old / "scenarios" / name).write_bytes(
                subprocess.run(["git", "show", f"{BEFORE}:scenarios/{name}"], cwd=ROOT, capture_output=True,
                               check=True).stdout)
        (old / "scenarios" / "hydro_cache").symlink_to(ROOT / "scenarios" / "hydro_cache")
        trees = {"before": old, "after": ROOT}
        caches = {label: base / f"cache_{label}" for label in trees}
        cold = {label: run(tree, caches[label], base / f"{label}.h5") for label, tree in trees.items()}
        warm: dict[str, list[tuple[float, float]]] = {label: [] for label in trees}
        for r in range(args.rounds):
            for label in (("before", "after") if r % 2 == 0 else ("after", "before")):
                warm[label].append(run(trees[label], caches[label], base / f"{label}.h5"))
                print(label, f"{warm[label][-1][0]:.1f} s wall, {warm[label][-1][1]:.1f} s CPU", flush=True)
    lines.append(f"{'run':<28}{'before wall s':>14}{'after wall s':>13}{'ratio':>7}{'before CPU s':>13}"
                 f"{'after CPU s':>12}{'ratio':>7}")
    rows = [("cold (empty cache)", cold["before"], cold["after"]),
            (f"warm (median of {args.rounds})",
             tuple(statistics.median(v[i] for v in warm["before"]) for i in (0, 1)),
             tuple(statistics.median(v[i] for v in warm["after"]) for i in (0, 1)))]
    for label, b, a in rows:
        lines.append(f"{label:<28}{b[0]:14.1f}{a[0]:13.1f}{b[0] / a[0]:7.2f}{b[1]:13.1f}{a[1]:12.1f}{b[1] / a[1]:7.2f}")
    for label in trees:
        lines.append(f"# {label} warm runs (wall s, CPU s): "
                     + " ".join(f"({w:.1f}, {c:.1f})" for w, c in warm[label]))
    uptime = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    lines += ["", f"# uptime at the end: {uptime}", f"# load average at the end {load()}"]
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
