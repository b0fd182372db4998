"""Anchors: figures other codes publish, beside ours on the nearest bundled case measured in the same report run.

The published figures are quoted as the issue (19) gives them, with the hardware they were measured on; the
devices are not identical to ours (a sphere is not our disc or cylinder, their RM3 mooring is not ours), so the
table is an order-of-magnitude anchor, not a ranking. Each row names what differs.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from .points import Point, Variant, run_point


@dataclass(frozen=True)
class Anchor:
    """A published real-time factor and our nearest case."""

    what: str
    published_rtf: float
    source: str
    ours: Variant
    difference: str


CHRONO = "a C++ code built on Project Chrono, as reported for an AMD Ryzen 9 9950X (quoted, not measured here)"
ANCHORS = (
    Anchor("sphere free decay, dt 0.015 s", 659.0, CHRONO,
           Variant("scenarios/disc_decay.toml", ("simulation.step=0.015", "simulation.duration=29.985")),
           "our thin disc (heave decay, A_inf ~ 8 x mass), not a sphere"),
    Anchor("sphere in irregular waves, convolution", 74.0, CHRONO,
           Variant("scenarios/cylinder_irregular.toml", ("hydro.radiation_method=convolution",)),
           "our heaving cylinder with quadratic drag, JONSWAP Hs 2 m, 600 s at 0.1 s"),
    Anchor("sphere in irregular waves, state space", 97.0, CHRONO, Variant("scenarios/cylinder_irregular.toml"),
           "our heaving cylinder, state-space radiation (tolerance 0.02), as bundled"),
    Anchor("RM3 with MoorDyn", 15.0, CHRONO, Variant("scenarios/rm3_irregular.toml"),
           "our RM3 (float, spar, PTO) with MoorDyn lines as bundled, 600 s irregular sea"),
    Anchor("F3OF free decay, dt 0.02 s", 21.0, CHRONO,
           Variant("scenarios/f3of_dt3.toml", ("simulation.step=0.02",)),
           "our F3OF decay test 3 (base fixed, two flaps), 120 s"),
)


def measure_anchors(log: Callable[[str], None] | None = print) -> list[tuple[Anchor, Point]]:
    """Our nearest case of each anchor, run once."""
    out = []
    for a in ANCHORS:
        p = run_point(a.ours)
        out.append((a, p))
        if log is not None:
            log(f"  anchor {a.what}: ours {p.status} RTF {p.real_time_factor:.1f} (published {a.published_rtf:g})")
    return out


def exudyn_per_step() -> dict[str, tuple[float, float]] | None:
    """(Exudyn, ours) microseconds per step on the pendulum and the four-bar of ``benchmarks/bench_speed.py`` part 1,
    if Exudyn is installed (a benchmark-only dependency: ``pip install exudyn==1.13.6``), else None."""
    try:
        import exudyn  # noqa: F401
    except ImportError:
        return None
    import sys

    from .points import ROOT

    sys.path.insert(0, str(ROOT))
    try:
        from benchmarks import bench_speed as b
    finally:
        sys.path.remove(str(ROOT))
    steps = int(b.T_END / b.H)
    out = {}
    for name, build, exu in (("pendulum", b.pendulum_model, b.exudyn_pendulum),
                             ("four-bar", b.four_bar_model, b.exudyn_four_bar)):
        ours = min(b.run_ours(build, "index3", b.H, steps)[0][0] for _ in range(3))
        theirs = min(exu(b.H, steps)[0][0] for _ in range(3))
        out[name] = (1e6 * theirs, 1e6 * ours)
    return out
