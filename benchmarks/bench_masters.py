"""Work-precision of the masters: co-simulation error against wall time on the two-body scene.

Every master (FMUs through fmpy; the monolithic mode without FMI) at several fixed macro steps,
extrapolation order 2 (the default) and 1, plus the energy-based adaptive Jacobi at several
tolerances (smallest step = radiation grid 0.025 s). Error: largest displacement deviation from
the Richardson-extrapolated monolithic reference over the whole run (transient included),
relative to the largest displacement (``orchestrator.cosim.study``). Wall time: the median of
``--repeat`` runs, stepping only (no results file, initialisation excluded). Prints a table, writes it and a
work-precision plot (PNG). Run from the repository root:

    python benchmarks/bench_masters.py [--duration 30] [--repeat 3] [--out benchmarks/results/masters]
"""

from __future__ import annotations

import argparse
import platform
import statistics
import sys
from datetime import date
from pathlib import Path

import numpy as np

from orchestrator.cosim import study
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent
STEPS = [0.2, 0.1, 0.05, 0.025]
MASTERS = ["jacobi", "gauss_seidel", "aitken", "iqn_ils", "monolithic"]
TOLERANCES = [0.1, 0.03, 0.01, 0.003]


def adaptive(s, scene, tol: float, ref: study.Series) -> tuple[float, float, float]:
    v = study.variant(s, "jacobi", 0.025)
    v.simulation.adaptive.enabled = True
    v.simulation.adaptive.max_step = 0.4
    v.simulation.adaptive.tolerance = tol
    series = study.run_series(v, scene=scene)
    exact = np.column_stack([np.interp(series.time, ref.time, ref.displacement[:, j])
                             for j in range(ref.displacement.shape[1])])
    err = float(np.max(np.abs(series.displacement - exact)) / np.max(np.abs(ref.displacement)))
    return err, series.wall_time, len(series.time) - 1


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--duration", type=float, default=30.0)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "masters"))
    a = p.parse_args()
    s = load_scenario(ROOT / "scenarios" / "two_floats.toml")
    s.simulation.duration = a.duration
    scene = load_scene(s, log=None)
    ref = study.reference(s, 0.00625, scene)
    rows = []  # (label, extrapolation, step, steps, error, wall, evaluations)
    for master in MASTERS:
        for p_ in ((2,) if master == "monolithic" else (2, 1)):
            for h in STEPS:
                runs = [study.run_series(study.variant(s, master, h, p_), scene=scene) for _ in range(a.repeat)]
                wall = statistics.median(r.wall_time for r in runs)
                rows.append((master, p_, h, int(round(a.duration / h)), study.error(runs[0], ref), wall,
                             runs[0].evaluations))
                print(*rows[-1], flush=True, file=sys.stderr)
    for tol in TOLERANCES:
        res = [adaptive(s, scene, tol, ref) for _ in range(a.repeat)]
        rows.append((f"jacobi adaptive tol={tol:g}", 2, float("nan"), res[0][2], res[0][0],
                     statistics.median(r[1] for r in res), 1.0))
    lines = [
        f"# command: python benchmarks/bench_masters.py --duration {a.duration:g} --repeat {a.repeat}",
        f"# date: {date.today()}  machine: {platform.machine()} python {platform.python_version()} "
        f"(2 cores shared with other jobs: wall times are medians of {a.repeat})",
        f"# scene: two_floats.toml, {a.duration:g} s simulated; error = max |x - x_ref| / max |x_ref| over both "
        "heaves, reference = monolithic at 0.00625 s and 0.003125 s, Richardson-extrapolated",
        "",
        f"{'master':<28}{'p':>3}{'step s':>8}{'steps':>7}{'error':>11}{'wall s':>9}{'us/step':>9}{'evals':>7}",
    ]
    for label, p_, h, n, err, wall, ev in rows:
        step = f"{h:8.3f}" if np.isfinite(h) else f"{'adapt':>8}"
        lines.append(f"{label:<28}{p_:>3}{step}{n:>7}{err:>11.3e}{wall:>9.3f}{1e6 * wall / n:>9.0f}{ev:>7.2f}")
    report = "\n".join(lines)
    print(report)
    out = Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.with_suffix(".txt").write_text(report + "\n")
    plot(rows, out.with_name(out.name + "_work_precision.png"), a.duration)


def plot(rows: list, target: Path, duration: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 6))
    labels = dict.fromkeys((r[0] if "adaptive" not in r[0] else "jacobi adaptive", r[1]) for r in rows)
    for label, p_ in labels:
        pts = [r for r in rows if (r[0] == label or (label == "jacobi adaptive" and "adaptive" in r[0])) and r[1] == p_]
        ax.loglog([r[5] for r in pts], [r[4] for r in pts], "o-" if p_ == 2 else "s--",
                  label=f"{label}" + ("" if label == "monolithic" else f", p = {p_}"))
    ax.set_xlabel(f"wall time for {duration:g} s simulated (s)")
    ax.set_ylabel("relative displacement error against the monolithic reference")
    ax.set_title("two_floats: work-precision of the masters (steps 0.2 .. 0.025 s)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(target, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
