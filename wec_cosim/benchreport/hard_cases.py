"""Hard cases of the bench report: stability maps and the 3-hour sea.

A *stability map* runs one bundled scenario over a grid of macro steps x the case's hardness parameter, once
per series (master and added-mass mode), and records for every point whether the run finished (``ok``) or
stopped (``diverged``: the master's divergence check; ``failed``: another error, with the run's own message),
and its error against the exact frequency-domain answer (:func:`wec_cosim.benchreport.errors.regular_wave_error`, which
includes the scene's mass and PTO spring: no error is measured against another run of the same code).

* :func:`added_mass_map`: ``scenarios/light_float.toml`` with the float's mass set to A_inf / ratio, ratio from
  1 to 100 (A_inf read from the scene's database): the partitioned-coupling instability of explicit added
  mass against A_inf in the mass matrix, Gauss-Seidel, and the interface mode with IQN-ILS.
* :func:`stiff_pto_map`: ``scenarios/cylinder_regular.toml`` with a PTO spring whose natural period
  T_k = 2 pi sqrt((M + A_inf) / k) runs from 30 macro steps down to a third of one; the hardness is h / T_k
  (k is set per point from it). The grid holds integer and half-integer ratios on purpose: the force input is
  held or ramped over each macro step, and its step rhythm (kinks at multiples of 2 pi / h) drives the spring
  mode at resonance when h is a whole number of spring periods.
* :func:`close_bodies_map`: ``scenarios/two_cylinders_decay.toml`` (its database; no new BEM solve) in regular
  waves, both masses set to A_inf / ratio: closely spaced bodies whose interaction runs through the
  off-diagonal added mass.
* :func:`long_run`: the hinge barge (``scenarios/hinge_barge.toml``) in a JONSWAP sea for 3 hours: wall time
  and real-time factor, the largest constraint residual over the run and in the first and last windows
  (drift), and the wave-to-wire energy balance's residual relative to the work the waves did (physical
  invariants: the constraints hold exactly and the energy is conserved).
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import errors
from .cases import Option
from .points import ROOT, Point, Variant, run_point

REGULAR_ERROR_NAME = ("largest complex relative error |X - X_exact| / |X_exact| of the steady first harmonic of "
                      "every body's heave against the exact frequency-domain answer (which includes the masses, "
                      "the PTO spring and damper, and the bodies' hydrodynamic interaction)")


@dataclass
class StabilityMap:
    """One stability map: every point of every series, [hardness][step].

    Attributes:
        name: file-name stem.
        title: one sentence: the case and what is varied.
        hardness: axis label with unit.
        hardness_values: the hardness grid (ascending).
        steps: macro steps, s (descending).
        error_name: what the error is against.
        points: series label (master + added-mass mode) -> [hardness][step] points.
    """

    name: str
    title: str
    hardness: str
    hardness_values: list[float]
    steps: list[float]
    error_name: str
    points: dict[str, list[list[Point]]]

    def stable_fraction(self, series: str) -> float:
        """Share of the series' points that finished."""
        flat = [p for row in self.points[series] for p in row]
        return sum(p.stable for p in flat) / len(flat)


@dataclass(frozen=True)
class MapSpec:
    """How a map is built: the base scenario, its series and grids, and the overrides that set a point's
    hardness (``hardness_overrides(scene, hardness, step)``, from the scene's own database and masses)."""

    name: str
    title: str
    hardness: str
    base: Variant
    series: tuple[Option, ...]
    hardness_values: tuple[float, ...]
    quick_hardness_values: tuple[float, ...]
    steps: tuple[float, ...]
    quick_steps: tuple[float, ...]
    hardness_overrides: Callable[[object, float, float], tuple[str, ...]]


def _heave_bodies(scene) -> list[tuple[str, float, float]]:  # noqa: ANN001 - Scene
    """(body name, structural mass M, A_inf in heave) of every heaving body of the scene, A_inf from the scene's
    database (after its fits)."""
    idx = scene.hydro_index()
    out = []
    for j, (name, dof) in enumerate(scene.hydro_coordinates):
        if dof == 2:
            body = next(b for b in scene.scenario.hydro_bodies if b.name == name)
            out.append((name, float(scene.body_mass(body)), float(scene.hdb.added_mass_inf[idx[j], idx[j]])))
    if not out:
        raise ValueError(f"no heave coordinate among {scene.hydro_coordinates}")
    return out


def _mass_for_ratio(scene, ratio: float, step: float) -> tuple[str, ...]:  # noqa: ANN001
    """Every heaving body's mass set to its own heave A_inf / ratio."""
    return tuple(f"bodies.{name}.mass={a_inf / ratio:.6g}" for name, _, a_inf in _heave_bodies(scene))


def _spring_for_ratio(scene, ratio: float, step: float) -> tuple[str, ...]:  # noqa: ANN001
    """The PTO stiffness k whose natural period T_k = 2 pi sqrt((M + A_inf) / k) is step / ratio (the scene's
    single heaving body)."""
    ((_, mass, a_inf),) = _heave_bodies(scene)
    k = (mass + a_inf) * (2 * math.pi * ratio / step) ** 2
    return (f"ptos.{scene.scenario.ptos[0].name}.stiffness={k:.6g}",)


ADDED_MASS = MapSpec(
    "added_mass_ratio",
    "Light float (cylinder R 5 m, draft 5 m, heave, PTO damper, regular waves H 1 m T 5.6 s): structural mass "
    "M = A_inf / ratio, macro step and master / added-mass mode varied",
    "A_inf / M (heave)",
    Variant("scenarios/light_float.toml"),
    (Option("jacobi + mass_matrix"),
     Option("jacobi + explicit_force", ("simulation.added_mass=explicit_force",)),
     Option("gauss_seidel + mass_matrix", ("simulation.master=gauss_seidel",)),
     Option("iqn_ils + interface", ("simulation.master=iqn_ils", "simulation.added_mass=interface"))),
    hardness_values=(1.0, 3.0, 10.0, 30.0, 100.0), quick_hardness_values=(1.0, 3.0, 10.0, 100.0),
    steps=(0.2, 0.1, 0.05, 0.025), quick_steps=(0.2, 0.1, 0.05),
    hardness_overrides=_mass_for_ratio)

STIFF_PTO = MapSpec(
    "stiff_pto",
    "Floating cylinder (R 5 m, draft 5 m, heave, regular waves H 1 m T 5.6 s) with a PTO spring whose natural "
    "period T_k = 2 pi sqrt((M + A_inf) / k) runs from 30 macro steps to a third of one, per master",
    "h / T_k (macro step / PTO spring period)",
    Variant("scenarios/cylinder_regular.toml"),
    (Option("jacobi"), Option("gauss_seidel", ("simulation.master=gauss_seidel",)),
     Option("iqn_ils", ("simulation.master=iqn_ils",))),
    hardness_values=(0.03, 0.1, 0.3, 0.7, 1.0, 1.5, 3.0), quick_hardness_values=(0.03, 0.3, 1.0, 1.5),
    steps=(0.2, 0.1, 0.05, 0.025), quick_steps=(0.2, 0.1, 0.05),
    hardness_overrides=_spring_for_ratio)

CLOSE_BODIES = MapSpec(
    "close_bodies",
    "Two cylinders (R 2.5 m, draft 3 m, heave) 3 m apart in regular waves H 0.5 m T 4.5 s along their line: "
    "each mass set to its own A_inf / ratio, so the interaction's off-diagonal added mass weighs more and more",
    "A_inf / M (heave, each body)",
    Variant("scenarios/two_cylinders_decay.toml",
            ("waves.kind=regular", "waves.height=0.5", "waves.period=4.5", "simulation.duration=480")),
    ADDED_MASS.series,
    hardness_values=(0.5, 1.0, 3.0, 10.0, 30.0), quick_hardness_values=(0.5, 10.0),
    steps=(0.2, 0.1, 0.05, 0.025), quick_steps=(0.2, 0.05),
    hardness_overrides=_mass_for_ratio)

MAPS = (ADDED_MASS, STIFF_PTO, CLOSE_BODIES)


def _point_line(spec: MapSpec, series: str, hardness: float, step: float, p: Point) -> str:
    what = f"error {p.error:.3g}" if p.stable else p.message[:120]
    return (f"{spec.name} [{series}] {spec.hardness}={hardness:g} step={step:g}: {p.status}, {what}, "
            f"wall {p.wall_time:.2f} s")


def run_map(spec: MapSpec, quick: bool, log: Callable[[str], None] = print) -> StabilityMap:
    """Run every point of ``spec`` (one process at a time) and log each as it finishes."""
    from orchestrator.scenario import load_scenario
    from orchestrator.scene import load_scene

    scene = load_scene(load_scenario(ROOT / spec.base.scenario), log=None)
    hardness_values = list(spec.quick_hardness_values if quick else spec.hardness_values)
    steps = list(spec.quick_steps if quick else spec.steps)
    points: dict[str, list[list[Point]]] = {}
    for series in spec.series:
        rows = []
        for h in hardness_values:
            row = []
            for step in steps:
                variant = spec.base.with_(*series.overrides, *spec.hardness_overrides(scene, h, step),
                                          f"simulation.step={step:g}")
                p = run_point(variant, errors.regular_wave_error)
                log(_point_line(spec, series.label, h, step, p))
                row.append(p)
            rows.append(row)
        points[series.label] = rows
    return StabilityMap(spec.name, spec.title, spec.hardness, hardness_values, steps, REGULAR_ERROR_NAME, points)


def added_mass_map(quick: bool, log: Callable[[str], None] = print) -> StabilityMap:
    """Case 1: added mass far above the structural mass (light_float.toml)."""
    return run_map(ADDED_MASS, quick, log)


def stiff_pto_map(quick: bool, log: Callable[[str], None] = print) -> StabilityMap:
    """Case 2: a PTO spring much faster than the macro step (cylinder_regular.toml)."""
    return run_map(STIFF_PTO, quick, log)


def close_bodies_map(quick: bool, log: Callable[[str], None] = print) -> StabilityMap:
    """Case 4: closely spaced bodies with strong hydrodynamic interaction (two_cylinders_decay.toml's database,
    in regular waves). The fore cylinder's initial 0.2 m offset (kept as the scenario has it; ``--set`` takes lists
    since this map was built, so ``bodies.fore.initial_displacement`` could start it at rest and shorten the runs)
    starts a slowly decaying transient: 480 s of run leave it below 0.1 % of the steady response in the last ten
    periods (at 120 s it was 1.2 %, at 300 s 0.15 %, measured on A_inf / M = 10)."""
    return run_map(CLOSE_BODIES, quick, log)


# How to read a map where the figure alone may mislead (mechanisms checked when the maps were built, issue 19).
READINGS = {
    "added_mass_ratio": "With A_inf in the multibody mass matrix every master is stable at every ratio; the added "
                        "mass as an explicit force is the partitioned-coupling instability: stable only at "
                        "A_inf / M = 1 and first order there, diverging within seconds above it whatever the step.",
    "stiff_pto": "Every run is stable, but where the macro step is a whole number of spring periods (h / T_k = 1, 3) "
                 "the steady heave is wrong by ~99 % for every master, the monolithic mode included: the force "
                 "input is held or ramped over each step, and that rhythm drives the spring mode at resonance "
                 "(14.5 % at h / T_k = 0.95 and 1.05, within 0.1 % at 1.5 and 2.5). Keep the macro step away from "
                 "whole multiples of the PTO's period, or below half of it.",
    "close_bodies": "The interaction's off-diagonal added mass makes the largest eigenvalue of M^-1 A_inf exceed 1 "
                    "already at A_inf / M = 1 (1.06), so the explicit added-mass force diverges there, where a "
                    "single body was still stable.",
}


def stability_maps(quick: bool, log: Callable[[str], None] = print) -> list[StabilityMap]:
    """Every stability map of the report, in priority order."""
    return [run_map(spec, quick, log) for spec in MAPS]


# ---------------------------------------------------------------------------------------------- the 3-hour sea

LONG_SEA = ("waves.kind=irregular", "waves.spectrum=jonswap", "waves.hs=0.02", "waves.tp=2.0", "waves.seed=1")


@dataclass
class LongRun:
    """The hinge barge in a long irregular sea.

    Attributes:
        title: the case.
        point: the run (status, wall time, simulated time, message); its ``extra`` holds the figures below.
        window: length (s) of the first and last windows whose constraint residuals are compared (1 h in the
            full run, a third of the run in the quick one).
        max_violation: largest constraint residual (m or rad) over the run, every macro step.
        first_violation / last_violation: the largest residual in the first and in the last window.
        energy_residual: |residual of work in = PTO + radiated + dissipated + stored| at the end, relative to
            the work the waves did.
        largest_energy_residual: the largest |residual| over the run relative to the final work in.
    """

    title: str
    point: Point
    window: float
    max_violation: float = math.nan
    first_violation: float = math.nan
    last_violation: float = math.nan
    energy_residual: float = math.nan
    largest_energy_residual: float = math.nan

    @property
    def drift(self) -> float:
        """Growth of the constraint residual: last window's largest over the first window's."""
        return self.last_violation / self.first_violation if self.first_violation > 0 else math.nan

    @property
    def wall_time(self) -> float:
        return self.point.wall_time

    @property
    def real_time_factor(self) -> float:
        return self.point.real_time_factor


def _long_run_measures(window: float) -> Callable[[object, dict, object], dict[str, float]]:
    """Reads the constraint residuals and the energy balance's residual series from a finished run."""
    from orchestrator.results import wave_balance

    def measures(scene, data: dict, result) -> dict[str, float]:  # noqa: ANN001
        t = np.asarray(data["time"])
        v = np.abs(np.asarray(data["mbd/constraint_violation"]))
        first, last = t <= t[0] + window, t >= t[-1] - window
        out = {"max_violation": float(v.max()), "first_violation": float(v[first].max()),
               "last_violation": float(v[last].max())}
        work_in = abs(result.energy["work_in"]) if result.energy else math.nan
        residual = np.abs(wave_balance({k: np.asarray(data[k]) for k in data if k.startswith("energy/")}))
        out["energy_residual"] = abs(result.energy["residual"]) / work_in if result.energy else math.nan
        out["largest_energy_residual"] = float(residual.max()) / work_in
        return out

    return measures


def long_run(quick: bool, log: Callable[[str], None] = print) -> LongRun:
    """Case 3: the hinge barge in a JONSWAP sea Hs 0.02 m (the linear regime of its 0.02 m regular wave),
    Tp 2 s, for 10800 s (quick: 1200 s) at its own macro step, through fmpy."""
    duration = 1200.0 if quick else 10800.0
    window = duration / 3 if quick else 3600.0
    variant = Variant("scenarios/hinge_barge.toml", (*LONG_SEA, f"simulation.duration={duration:g}"))
    p = run_point(variant, measures=_long_run_measures(window))
    run = LongRun(f"Hinge barge (Paparella et al.) in a JONSWAP sea Hs 0.02 m Tp 2 s for {duration:g} s", p, window,
                  **{k: p.extra[k] for k in ("max_violation", "first_violation", "last_violation",
                                             "energy_residual", "largest_energy_residual") if k in p.extra})
    log(f"long run {duration:g} s: {p.status}, wall {p.wall_time:.1f} s, RTF {p.real_time_factor:.1f}, "
        f"largest constraint residual {run.max_violation:.3g} (first {window:g} s {run.first_violation:.3g}, "
        f"last {run.last_violation:.3g}), energy residual {run.energy_residual:.3g} of the work in "
        f"(largest over the run {run.largest_energy_residual:.3g}) {p.message}")
    return run


# ----------------------------------------------------------------------------------------------------- figure

def map_figure(m: StabilityMap, path: Path) -> None:
    """PNG of a map: one panel per series, x = macro step (log), y = hardness (log), colour = error (log
    scale, one scale for all panels), a cross for a diverged or failed run, an open square for a finished run
    whose error could not be measured."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    labels = list(m.points)
    errs = [p.error for rows in m.points.values() for row in rows for p in row
            if p.stable and math.isfinite(p.error) and p.error > 0]
    norm = LogNorm(vmin=min(errs), vmax=max(errs) if max(errs) > min(errs) else 10 * min(errs)) if errs else \
        LogNorm(1e-4, 1)
    fig, axes = plt.subplots(1, len(labels), figsize=(3.6 * len(labels) + 1.2, 3.8), sharey=True,
                             squeeze=False)
    scatter = None
    for ax, label in zip(axes[0], labels, strict=True):
        ok_x, ok_y, ok_c, bad_x, bad_y, nan_x, nan_y = [], [], [], [], [], [], []
        for h, row in zip(m.hardness_values, m.points[label], strict=True):
            for step, p in zip(m.steps, row, strict=True):
                if not p.stable:
                    bad_x.append(step), bad_y.append(h)
                elif math.isfinite(p.error) and p.error > 0:
                    ok_x.append(step), ok_y.append(h), ok_c.append(p.error)
                else:
                    nan_x.append(step), nan_y.append(h)
        if ok_x:
            scatter = ax.scatter(ok_x, ok_y, c=ok_c, norm=norm, cmap="viridis", marker="s", s=170)
        if bad_x:
            ax.scatter(bad_x, bad_y, marker="x", s=110, c="crimson", linewidths=2.5)
        if nan_x:
            ax.scatter(nan_x, nan_y, marker="s", s=170, facecolors="none", edgecolors="k")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xticks(m.steps, [f"{s:g}" for s in m.steps])
        ax.set_yticks(m.hardness_values, [f"{h:g}" for h in m.hardness_values])
        ax.minorticks_off()
        pad_x, pad_y = 1.35, 1.6
        ax.set_xlim(min(m.steps) / pad_x, max(m.steps) * pad_x)
        ax.set_ylim(min(m.hardness_values) / pad_y, max(m.hardness_values) * pad_y)
        ax.set_title(label, fontsize=10)
        ax.set_xlabel("macro step (s)")
    axes[0][0].set_ylabel(m.hardness)
    if scatter is not None:
        fig.colorbar(scatter, ax=axes[0].tolist(), label="error (relative)")
    width = 40 * len(labels) + 20  # characters per line of the title and the notes
    title = textwrap.wrap(m.title, width)
    fig.suptitle("\n".join(title), fontsize=9, y=1.0 + 0.045 * len(title))
    notes = ["red cross: diverged or failed; open square: finished, error not measured",
             *textwrap.wrap(f"error: {m.error_name}", int(width * 1.25))]
    fig.text(0.01, -0.02, "\n".join(notes), fontsize=7, va="top")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    """``python -m wec_cosim.benchreport.hard_cases [--quick] [--out DIR]``: every map (PNG in DIR) and the long
    run, each point printed as it finishes, the wall time of each part at the end."""
    import argparse
    import time

    from .points import quiet_threads

    parser = argparse.ArgumentParser(prog="python -m wec_cosim.benchreport.hard_cases", description=main.__doc__)
    parser.add_argument("--quick", action="store_true", help="the quick grids and a 1200 s sea")
    parser.add_argument("--out", type=Path, default=Path("hard_cases"), help="folder of the figures")
    args = parser.parse_args(argv)
    quiet_threads()
    start = time.perf_counter()
    for spec in MAPS:
        t = time.perf_counter()
        m = run_map(spec, args.quick, print)
        map_figure(m, args.out / f"{m.name}.png")
        print(f"== {m.name}: {time.perf_counter() - t:.1f} s; stable share "
              + ", ".join(f"{label} {m.stable_fraction(label):.0%}" for label in m.points), flush=True)
    t = time.perf_counter()
    long_run(args.quick, print)
    print(f"== long run: {time.perf_counter() - t:.1f} s; total {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
