"""Write the bench report: ``README.md`` (Markdown), ``figures/*.png`` and ``points.csv`` (every point's raw
numbers and its rerun command) in one folder.

The first screen states the recommended settings and the speed and error they give on each case; then the
work-precision diagrams, model reduction, the hard cases, scaling and the anchors. Every number in it comes from
this run; the header names the machine, its load and the commit.
"""

from __future__ import annotations

import csv
import math
import os
import platform
import subprocess
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path

from . import anchors, scaling
from .cases import CASES
from .machine import load_text
from .points import ROOT, Point
from .reduction import reduction_rows
from .work_precision import Curve, PointCache, case_curves, default_point, fastest_within, figure

TOLERANCE = 0.01  # the error a "fastest within" figure allows (1 %)


@dataclass
class Report:
    """Everything the report shows; filled part by part so that a part's failure leaves the others."""

    quick: bool
    started: float = field(default_factory=time.time)
    header: list[str] = field(default_factory=list)
    csv_rows: list[dict] = field(default_factory=list)
    sections: list[str] = field(default_factory=list)
    first_screen: list[str] = field(default_factory=list)

    def record(self, part: str, point: Point, **labels: object) -> None:
        """One CSV row per point: what it is, what it measured, how to rerun it."""
        self.csv_rows.append({"part": part, **{k: labels.get(k, "") for k in ("case", "factor", "option", "step")},
                              "status": point.status, "wall_s": _num(point.wall_time),
                              "rtf": _num(point.real_time_factor), "error": _num(point.error),
                              "simulated_s": _num(point.simulated), "message": point.message,
                              "command": point.variant.command()})


def _num(x: float) -> str:
    return f"{x:.6g}" if isinstance(x, float) and math.isfinite(x) else ""


def machine_lines(command: str) -> list[str]:
    """Command, date, machine, processor, load and commit: what a reader needs to compare figures."""
    from .machine import cpu_model

    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip() or "unknown"
    load = load_text()
    return [f"- command: `{command}`",
            f"- date: {datetime.now(UTC):%Y-%m-%d %H:%M} UTC; git {commit}",
            f"- machine: {platform.machine()}, {cpu_model()}, {os.cpu_count()} cores, Python "
            f"{platform.python_version()}; load average at the start {load}"]


def build(out: Path, quick: bool, log: Callable[[str], None] = print, command: str = "") -> Path:
    """Run the suite and write the report into ``out``; returns the Markdown file."""
    out.mkdir(parents=True, exist_ok=True)
    (out / "figures").mkdir(exist_ok=True)
    rep = Report(quick)
    rep.header = machine_lines(command or f"wec-cosim bench{' --quick' if quick else ''} --out {out}")
    cache = PointCache()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curves: dict[str, list[Curve]] = {}

    def work_precision() -> str:
        for case in CASES:
            log(f"work-precision: {case.name}")
            curves[case.name] = case_curves(case, quick, cache, log)
            figure(case, curves[case.name], out / "figures" / f"work_precision_{case.name}.png", plt)
            for c in curves[case.name]:
                for p, h in zip(c.points, c.steps, strict=True):
                    rep.record("work_precision", p, case=case.name, factor=c.factor, option=c.option, step=h)
        rep.first_screen = recommended(curves, cache, quick)
        return work_precision_section(curves)

    parts = (("work-precision", work_precision), ("model reduction", lambda: reduction_section(rep, quick, log)),
             ("hard cases", lambda: hard_cases_section(rep, out, quick, log, plt)),
             ("scaling", lambda: scaling_section(rep, out, quick, log, plt)),
             ("anchors", lambda: anchors_section(rep, log)))
    run_parts(rep, parts, out, log)
    return write(rep, out)


def run_parts(rep: Report, parts, out: Path, log: Callable[[str], None]) -> None:  # noqa: ANN001
    """Each part's section in turn; a part that raises leaves a section saying so and the others run; on Ctrl-C
    the report of the parts done so far is written before the interrupt goes on."""
    try:
        for name, part in parts:
            log(name)
            try:
                rep.sections.append(part())
            except Exception as exc:  # noqa: BLE001 - one part's failure must not lose the others' points
                log(f"{name} failed: {exc}")
                rep.sections.append(f"## {name}\n\n**This part failed**: {type(exc).__name__}: {exc}")
    except KeyboardInterrupt:
        rep.sections.append("**Interrupted**: the parts above are complete, the rest did not run.")
        write(rep, out)
        raise


def recommended(curves: dict[str, list[Curve]], cache: PointCache, quick: bool) -> list[str]:
    """The first screen: the defaults, what they give per case, and the fastest settings within 1 %."""
    lines = ["## Recommended settings", "",
             "Use the scenario defaults: `simulation.master = \"jacobi\"` with `extrapolation = 2` (one call per FMU "
             "per macro step), the infinite-frequency added mass in the multibody mass matrix "
             "(`simulation.added_mass = \"mass_matrix\"`: stable at any mass ratio, see the hard cases), "
             "`multibody.formulation = \"index3\"` for jointed scenes and the radiation convolution, at the step the "
             "bundled scenario gives (about T/100 of the wave or natural period). What they give on each case, and "
             "the fastest point of this report within 1 % error:", "",
             "| case | defaults: step | RTF | error | fastest within 1 %: settings | RTF | error |",
             "|---|---|---|---|---|---|---|"]
    for case in CASES:
        d = default_point(case, quick, cache)
        f = fastest_within(curves[case.name], TOLERANCE)
        settings = ", ".join(o for o in f.variant.overrides if o not in case.variant(quick).overrides) if f else ""
        fast = (f"`{settings}` | {f.real_time_factor:.0f} | {100 * f.error:.3g} %" if f else "none | | ")
        lines.append(f"| {case.name} | {case.default_step:g} s | {d.real_time_factor:.0f} | {100 * d.error:.3g} % | "
                     f"{fast} |")
    lines += ["", "Error measures (each against an answer independent of the time stepping):", ""]
    lines += [f"- **{case.name}**: {case.error_name}." for case in CASES]
    return lines


def work_precision_section(curves: dict[str, list[Curve]]) -> str:
    lines = ["## Work-precision", "",
             "Error against the stepping loop's wall time (FMUs through fmpy; the monolithic curve: same physics in "
             "one process). Each panel varies one setting around the defaults over the case's macro steps (the "
             "number beside each point, s). Runs that did not finish are named in red in the figure and in bold in the "
             "table (their messages are in points.csv).", ""]
    for case in CASES:
        base = curves[case.name][0].points[0].variant.with_("simulation.step=H")
        lines += [f"### {case.title}", "", f"![{case.name}](figures/work_precision_{case.name}.png)", "",
                  f"Each point: `{base.command()}` plus the option's own `--set` items (the table's rows; every "
                  "point's exact command is in points.csv). Error: " + case.error_name + ".", "",
                  "| factor | option | " + " | ".join(f"h = {h:g} s: RTF / error" for h in curves[case.name][0].steps)
                  + " |", "|---|---|" + "---|" * len(curves[case.name][0].steps)]
        for c in curves[case.name]:
            cells = [f"{p.real_time_factor:.0f} / {100 * p.error:.2g} %" if p.stable else f"**{p.status}**"
                     for p in c.points]
            lines.append(f"| {c.factor} | {c.option} | " + " | ".join(cells) + " |")
        lines.append("")
    return "\n".join(lines)


def reduction_section(rep: Report, quick: bool, log: Callable[[str], None]) -> str:
    lines = ["## Model reduction", "",
             "The same device modelled in full and reduced, one choice at a time: wall time saved against error "
             "introduced (error against the same independent answer as the full model's).", "",
             "| device | model | RTF | wall time vs full | error | command |", "|---|---|---|---|---|---|"]
    for device, label, point, full in reduction_rows(quick, log):
        rep.record("reduction", point, case=device, option=label)
        ratio = point.wall_time / full.wall_time if point.stable and full.stable else math.nan
        err = f"{100 * point.error:.3g} %" if point.stable else point.status
        lines.append(f"| {device} | {label} | {point.real_time_factor:.0f} | {ratio:.2f} | {err} | "
                     f"`{point.variant.command()}` |")
    return "\n".join(lines)


def hard_cases_section(rep: Report, out: Path, quick: bool, log: Callable[[str], None], plt) -> str:  # noqa: ANN001
    from . import hard_cases

    lines = ["## Hard cases", "", "Stability maps: macro step x the case's hardness -> stable or not (a cross: the run "
             "diverged, its coupling iteration gave up, or it failed; its own message is in points.csv) and the "
             "error, per master and added-mass mode (`wec_cosim/benchreport/hard_cases.py`; "
             "`python -m wec_cosim.benchreport.hard_cases` "
             "runs this part alone).", ""]
    for m in hard_cases.stability_maps(quick, log):
        hard_cases.map_figure(m, out / "figures" / f"stability_{m.name}.png")
        lines += [f"### {m.title}", "", f"Error: {m.error_name}.", "", f"![{m.name}](figures/stability_{m.name}.png)",
                  "", *([hard_cases.READINGS[m.name], ""] if m.name in hard_cases.READINGS else []),
                  f"| series | stable runs | largest error of a stable run | at {m.hardness}, step |",
                  "|---|---|---|---|"]
        for series, grid in m.points.items():
            worst, where = -1.0, ""
            for value, row in zip(m.hardness_values, grid, strict=True):
                for h, p in zip(m.steps, row, strict=True):
                    rep.record(f"hard:{m.name}", p, case=m.name, factor=series, option=f"{m.hardness}={value:g}",
                               step=h)
                    if p.stable and p.error > worst:
                        worst, where = p.error, f"{value:g}, {h:g} s"
            cells = [p for row in grid for p in row]
            stable = sum(p.stable for p in cells)
            lines.append(f"| {series} | {stable} of {len(cells)} | "
                         + (f"{100 * worst:.3g} % | {where} |" if worst >= 0 else "none | |"))
        lines.append("")
    lines += long_run_lines(rep, hard_cases.long_run(quick, log))
    return "\n".join(lines)


def long_run_lines(rep: Report, run) -> list[str]:  # noqa: ANN001 - hard_cases.LongRun
    """The long irregular sea: wall time, constraint drift and energy balance."""
    rep.record("hard:long_run", run.point, case="hinge_barge long sea")
    p = run.point
    if not p.stable:
        return [f"### {run.title}", "", f"**{p.status}** at t = {p.simulated:g} s: {p.message}",
                f"(`{p.variant.command()}`)"]
    return [f"### {run.title}", "", f"`{p.variant.command()}`", "",
            f"| wall time | RTF | largest constraint residual | first / last window ({run.window:g} s) | growth | "
            "energy residual / work in (end; largest over the run) |", "|---|---|---|---|---|---|",
            f"| {p.wall_time:.1f} s | {p.real_time_factor:.1f} | {run.max_violation:.3g} | "
            f"{run.first_violation:.3g} / {run.last_violation:.3g} | {run.drift:.2f} | "
            f"{run.energy_residual:.3g}; {run.largest_energy_residual:.3g} |"]


def scaling_section(rep: Report, out: Path, quick: bool, log: Callable[[str], None], plt) -> str:  # noqa: ANN001
    rows = scaling.scene_scaling(quick, log)
    lines = ["## Scaling", "", "### Bodies: bundled scenes", "",
             f"Each scene as bundled for {rows[0].steps} macro steps at its own step; microseconds per macro step.",
             "", "| scene | bodies | " + " | ".join(f"{m} us/step" for m, _, _ in scaling.MODES) + " |",
             "|---|---|" + "---|" * len(scaling.MODES)]
    for r in rows:
        for mode, p in r.points.items():
            rep.record("scaling:bodies", p, case=r.scenario, option=mode)
        lines.append(f"| {r.scenario} | {r.bodies} | " + " | ".join(
            f"{r.us_per_step(m):.0f}" if r.points[m].stable else r.points[m].status for m, _, _ in scaling.MODES)
            + " |")
    refused = next((p for r in rows for p in r.points.values() if p.status == "unavailable"), None)
    if refused is not None:
        lines += ["", "unavailable: the scene refuses the setting, e.g. " + refused.message.split(": ", 1)[-1]]
    row = scaling.body_scaling(quick)
    lines += ["", "### Bodies: the multibody model alone", "",
              "A row of N hinged floating cubes on linear moorings, index-3, 0.01 s, a new input every step "
              "(`wec_cosim.benchreport.scaling.floating_row`; minimum of 3 runs):", "",
              "| N | us per step | us per body |",
              "|---|---|---|"] + [f"| {n} | {us:.0f} | {us / n:.1f} |" for n, us in row]
    durations = scaling.duration_scaling(quick, log)
    for d, p in durations:
        rep.record("scaling:duration", p, case="hinge_barge", option=f"duration={d:g}")
    lines += ["", "### Duration: the hinge barge at its defaults", "", "| simulated s | wall s | RTF |",
              "|---|---|---|"]
    lines += [f"| {d:g} | {p.wall_time:.2f} | {p.real_time_factor:.1f} |" for d, p in durations]
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6))
    for mode, _, _ in scaling.MODES:
        axes[0].loglog([r.bodies for r in rows], [r.us_per_step(mode) for r in rows], "o-", label=f"scenes, {mode}")
    axes[0].loglog([n for n, _ in row], [us for _, us in row], "s--", label="multibody alone (row of cubes)")
    axes[0].set(xlabel="bodies", ylabel="us per macro step")
    axes[0].legend(fontsize=7)
    axes[1].loglog([d for d, _ in durations], [p.wall_time for _, p in durations], "o-")
    axes[1].set(xlabel="simulated duration (s)", ylabel="wall time (s)", title="hinge barge")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "figures" / "scaling.png", dpi=110)
    plt.close(fig)
    lines += ["", "![scaling](figures/scaling.png)"]
    return "\n".join(lines)


def anchors_section(rep: Report, log: Callable[[str], None]) -> str:
    lines = ["## Anchors", "", "Figures other codes publish, beside ours on the nearest bundled case (measured in this "
             "run, on this report's machine; the devices differ as stated: an order-of-magnitude anchor, not a "
             "ranking).", "", "| published case | their RTF | source | our case | our RTF | difference |",
             "|---|---|---|---|---|---|"]
    for a, p in anchors.measure_anchors(log):
        rep.record("anchors", p, case=a.what)
        ours = f"{p.real_time_factor:.0f}" if p.stable else p.status
        lines.append(f"| {a.what} | {a.published_rtf:g} | {a.source} | `{a.ours.command()}` | {ours} | "
                     f"{a.difference} |")
    exu = anchors.exudyn_per_step()
    if exu is None:
        lines += ["", "Exudyn is not installed (`pip install exudyn==1.13.6`): its per-step figures are not in this "
                  "report; `benchmarks/results/speed.txt` holds the last recorded ones."]
    else:
        lines += ["", "Cost per step on the same mechanisms as Exudyn 1.13.6 (1 ms, generalised-alpha rho 0.8, "
                  "index-3; `benchmarks/bench_speed.py` part 1, minimum of 3 runs):", "",
                  "| mechanism | Exudyn us/step | ours us/step | ratio |", "|---|---|---|---|"]
        lines += [f"| {k} | {e:.1f} | {o:.1f} | {o / e:.2f} |" for k, (e, o) in exu.items()]
    lines += ["", "Paparella et al. compare computational times of their pseudo-spectral DAE/ODE forms with "
              "Runge-Kutta only in figures (their Figs. 6 and 7; no numbers in the text): our pseudo-spectral solver's "
              "timings are in `benchmarks/results/pseudo_spectral.txt` (`python benchmarks/bench_pseudo_spectral.py`)."]
    return "\n".join(lines)


def write(rep: Report, out: Path) -> Path:
    """README.md and points.csv into ``out``."""
    with open(out / "points.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rep.csv_rows[0]) if rep.csv_rows else ["part"])
        w.writeheader()
        w.writerows(rep.csv_rows)
    minutes = (time.time() - rep.started) / 60
    load = load_text()
    text = ["# Speed against error: the bench report", "", *rep.header,
            f"- {'quick' if rep.quick else 'full'} suite, {len(rep.csv_rows)} runs in {minutes:.1f} min; load average "
            f"at the end {load}; every point's numbers and rerun command: [points.csv](points.csv)", "",
            *rep.first_screen, "", "\n\n".join(rep.sections), ""]
    path = out / "README.md"
    path.write_text("\n".join(text))
    return path
