"""Model reduction: the same device in full and reduced, one choice at a time, scored by the same error measure.

"Full" is every body in all six degrees of freedom (the database holds them: no new BEM solve); the reductions
are the bundled planar model (surge, heave, pitch: head seas excite nothing else in linear theory), the
state-space radiation on top of it, and for the hinge barge one multibody step per macro step. Not here: a
linear constrained formulation (``multibody.formulation = "linear"`` covers unconstrained scenes only) and
"hydro only where needed" (no bundled jointed device has a body without wetted surface).
"""

from __future__ import annotations

from collections.abc import Callable

from . import errors
from .cases import CASES
from .points import Point, Variant, run_point

SIX = '["surge", "sway", "heave", "roll", "pitch", "yaw"]'
STATE_SPACE = ("hydro.radiation_method=state_space", "hydro.state_space_tolerance=0.02")


def devices(quick: bool) -> list[tuple[str, Variant, list[str], list[tuple[str, tuple[str, ...]]], object]]:
    """(device, bundled variant, bodies to make six-DOF, reductions (label, overrides), error measure)."""
    f3of = next(c for c in CASES if c.name == "f3of_dt3").variant(quick)
    return [
        ("hinge_barge", Variant("scenarios/hinge_barge.toml"), ["barge1", "barge2"],
         [("planar 3 + 3 (bundled)", ()), ("planar, state space 0.02", STATE_SPACE),
          ("planar, one multibody step per macro step", ("multibody.max_step=0.02",))],
         errors.regular_wave_error),
        ("f3of_dt3", f3of, ["flap1", "flap2"],
         [("planar flaps (bundled)", ()), ("planar, state space 0.02", STATE_SPACE)], errors.decay_error),
    ]


def reduction_rows(quick: bool, log: Callable[[str], None] | None = print) -> list[tuple[str, str, Point, Point]]:
    """(device, model, point, the full model's point) per model, the full model first."""
    rows = []
    for device, bundled, bodies, reductions, error in devices(quick):
        full = run_point(bundled.with_(*(f"bodies.{b}.dofs={SIX}" for b in bodies)), error)
        rows.append((device, "full: 6 DOF per body", full, full))
        for label, overrides in reductions:
            rows.append((device, label, run_point(bundled.with_(*overrides), error), full))
        if log is not None:
            for _, label, p, _ in rows[-1 - len(reductions):]:
                log(f"  {device} {label}: {p.status} RTF {p.real_time_factor:.0f} error {p.error:.2e} {p.message[:80]}")
    return rows
