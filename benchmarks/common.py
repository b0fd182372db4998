"""Shared by the benchmark scripts: print a report and keep a copy under ``benchmarks/results/``."""

from __future__ import annotations

import os
import platform
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from wec_cosim.benchreport.machine import cpu_model  # noqa: E402, F401 - re-exported for the scripts
from wec_cosim.benchreport.machine import load_text as load  # noqa: E402 - the load averages (1, 5, 15 min) as text


def revision_tree(ref: str, tmp: Path, paths: list[str] | None = None) -> Path:
    """The files of git revision ``ref`` (the toolkit's packages, or ``paths`` that exist at that revision)
    extracted into ``tmp``, for A/B runs against an earlier state in alternating processes."""
    paths = paths or [  # "sweeps": its place before the layout of wec_cosim/
            "fmu_base", "hydro_fmu", "mbd_fmu", "plain_mbd_fmu", "orchestrator", "sweeps", "wec_cosim"]
    present = [p for p in paths if subprocess.run(["git", "cat-file", "-e", f"{ref}:{p}"], cwd=ROOT,
                                                  capture_output=True).returncode == 0]
    archive = subprocess.run(["git", "archive", ref, *present], cwd=ROOT, capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(tmp)], input=archive, check=True)
    return tmp


def run_with_current_library(ref: str, script: str, args: list[str]) -> int:
    """Run ``benchmarks/<script>`` as it was at git revision ``ref`` (its packages, scenarios and benchmarks
    extracted into a temporary folder) with the current compiled runtime (``fmu_base/_wecrt.so``) beside that
    revision's ``fmu_base``, and return its exit status. For side-by-side checks of the runtime against the Python
    path it replaced: the revision's binding calls only functions the library still has, with the same signatures.
    An ``--out`` path is made absolute first (the report lands where the caller means it)."""
    import shutil
    import tempfile

    from fmu_base import native

    args = list(args)
    if "--out" in args and args.index("--out") + 1 < len(args):
        i = args.index("--out") + 1
        args[i] = str(Path(args[i]).resolve())
    library = native.library_path()
    if library is None:
        native.library()  # raises with the message saying how to build it
    paths = ["fmu_base", "hydro_fmu", "mbd_fmu", "plain_mbd_fmu", "orchestrator", "sweeps", "benchreport",
             "benchmarks", "scenarios"]
    with tempfile.TemporaryDirectory(prefix="wec_revision_") as tmp:
        tree = revision_tree(ref, Path(tmp), paths)
        shutil.copy(library, tree / "fmu_base" / library.name)
        return subprocess.run([sys.executable, str(tree / "benchmarks" / script), *args],
                              cwd=tree / "benchmarks").returncode


def timed_child(cmd: list[str], cwd: str | Path, env: dict[str, str]) -> tuple[float, float]:
    """(wall seconds, user + system CPU seconds) of one child process ``cmd``; a failure raises with its stderr."""
    import resource
    import time

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode:
        raise RuntimeError(f"{' '.join(cmd)} in {cwd} failed:\n{proc.stderr[-2000:]}")
    return wall, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime


def report_header(script: str, versions: str = "") -> list[str]:
    """The first lines of a benchmark record: the command that produced it, then the machine, Python, the
    ``versions`` given, the git commit and the load at the start."""
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                            cwd=ROOT).stdout.strip()
    return [f"# command: python benchmarks/{script} {' '.join(sys.argv[1:])}".rstrip(),
            f"# machine: {platform.node()}, {platform.machine()}, {cpu_model()}, {os.cpu_count()} cores, python "
            f"{platform.python_version()}{versions}; git {commit}; load average at start {load()}"]


def write_report(lines: list[str], out: str | None) -> str:
    """Print the report; also write it to ``out`` if given. Returns the text."""
    report = "\n".join(lines)
    print(report)
    if out:
        Path(out).parent.mkdir(parents=True, exist_ok=True)
        Path(out).write_text(report + "\n")
    return report


def physics_loop(hydro, system, h: float, steps: int, record: bool = False):
    """The scene's hydro model and multibody model stepped together without a master: the force at
    each point held over the step as the master's step-averaged quadratic extrapolation.

    Returns ``(positions (steps, n) or None, seconds)``.
    """
    import time

    import numpy as np

    from orchestrator.cosim.masters import step_average_weights

    weights = step_average_weights([0.0, -h, -2 * h], h)
    history: list[np.ndarray] = []
    out = []
    start = time.perf_counter()
    for k in range(steps):
        t = k * h
        force = hydro.forces(t, system.q, system.qd).total
        history.insert(0, force)
        del history[3:]
        hold = sum(w * f for w, f in zip(weights, history, strict=False)) if len(history) == 3 else force
        hydro.advance(t, h, system.qd.copy())
        system.step(h, hold)
        if record:
            out.append(system.q.copy())
    elapsed = time.perf_counter() - start
    return (np.array(out) if record else None), elapsed


def pyplot():
    """matplotlib.pyplot on the file-only backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, target) -> None:  # noqa: ANN001
    """Lay out, write the PNG (folders created), close the figure and say where it went."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    Path(target).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(target, dpi=110)
    plt.close(fig)
    print(f"figure: {target}")
