"""Work-precision curves: the error of each case against the stepping loop's wall time, one curve per setting.

Every curve runs the case at each of its macro steps with the defaults except one factor (master, extrapolation
order, multibody formulation, radiation method), so each curve shows what one choice costs and buys. The
defaults' curve is shared by every factor (run once). Each point runs once: on a quiet machine the stepping loop's
wall time repeats within a few per cent, and the error does not vary at all (runs are deterministic).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from .cases import Case
from .points import Point, Variant, run_point


@dataclass
class Curve:
    """One setting of one case over the case's macro steps."""

    case: str
    factor: str
    option: str
    steps: list[float]
    points: list[Point]


class PointCache:
    """Points by variant: the defaults' curve (and any repeated variant) runs once per report."""

    def __init__(self) -> None:
        self.points: dict[Variant, Point] = {}

    def get(self, variant: Variant, error, log: Callable[[str], None] | None = None,  # noqa: ANN001
            estimate=None) -> Point:  # noqa: ANN001
        point = self.points.get(variant)
        if point is None:
            point = self.points[variant] = run_point(variant, error, estimate=estimate)
            if log is not None:
                log(describe(point))
        return point


def describe(point: Point) -> str:
    """One line per point for the progress log."""
    figures = (f"RTF {point.real_time_factor:8.1f}  error {point.error:9.2e}  estimate {point.estimate:9.2e}"
               if point.stable
               else f"{point.status} at t = {point.simulated:g} s: {point.message[:100]}")
    return f"  {figures}  {point.variant.command()}"


def case_curves(case: Case, quick: bool, cache: PointCache, log: Callable[[str], None] | None = print) -> list[Curve]:
    """Every factor's curves for ``case`` (``--quick``: the shorter run and fewer steps)."""
    base = case.variant(quick)
    steps = list(case.quick_steps if quick else case.steps)
    out = []
    for factor in case.factors:
        for option in factor.options:
            points = [cache.get(base.with_(*option.overrides, f"simulation.step={h:g}"), case.error, log,
                                case.estimate) for h in steps]
            out.append(Curve(case.name, factor.name, option.label, steps, points))
    return out


def default_point(case: Case, quick: bool, cache: PointCache) -> Point:
    """The case at its scenario's defaults and own step (the point the report's first screen quotes)."""
    return cache.get(case.variant(quick).with_(f"simulation.step={case.default_step:g}"), case.error,
                     estimate=case.estimate)


def fastest_within(curves: list[Curve], tolerance: float) -> Point | None:
    """The stable point of highest real-time factor whose error is at most ``tolerance``."""
    candidates = [p for c in curves for p in c.points if p.stable and p.error <= tolerance]
    return max(candidates, key=lambda p: p.real_time_factor, default=None)


def figure(case: Case, curves: list[Curve], path, plt) -> None:  # noqa: ANN001 - Path, matplotlib.pyplot
    """One panel per factor: error against wall time, one line per option, macro steps annotated; runs that did
    not finish are named in red at the bottom of their panel."""
    factors = list(dict.fromkeys(c.factor for c in curves))
    fig, axes = plt.subplots(1, len(factors), figsize=(4.2 * len(factors), 3.8), squeeze=False)
    from matplotlib.ticker import NullFormatter

    for ax, factor in zip(axes[0], factors, strict=True):
        notes = []
        for c in (c for c in curves if c.factor == factor):
            ok = [(p.wall_time, p.error, h) for p, h in zip(c.points, c.steps, strict=True)
                  if p.stable and p.error > 0]
            if ok:
                line, = ax.loglog([w for w, _, _ in ok], [e for _, e, _ in ok], "o-", label=c.option, ms=4)
                for w, e, h in ok:
                    ax.annotate(f"{h:g}", (w, e), fontsize=6, xytext=(2, 2), textcoords="offset points",
                                color=line.get_color())
            bad = [f"{h:g}" for p, h in zip(c.points, c.steps, strict=True) if not p.stable]
            if bad:
                statuses = "/".join(sorted({p.status for p in c.points if not p.stable}))
                notes.append(f"{c.option}: {statuses} at h = {', '.join(bad)} s")
        for i, note in enumerate(notes):
            ax.annotate(note, (0.02, 0.02 + 0.06 * i), xycoords="axes fraction", fontsize=6, color="red")
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_title(f"{case.name}: {factor}", fontsize=9)
        ax.set_xlabel("wall time of the stepping loop (s)")
        ax.set_ylabel("error (relative)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"{case.title} (labels: macro step, s)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
