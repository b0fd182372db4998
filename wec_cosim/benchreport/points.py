"""One point of the report: a bundled scenario with ``--set`` overrides, run once, timed and scored.

A :class:`Variant` is exactly what a reader types to rerun the point (:meth:`Variant.command`); a
:class:`Point` is what one run of it measured: the stepping loop's wall time (initialisation excluded, as the
run's own summary prints it), its real-time factor, the run's status, and the error given by the case's
error measure (:mod:`wec_cosim.benchreport.errors`). A run that diverges or fails is a point too (status ``diverged`` or
``failed`` with the run's own message): the hard cases map exactly that.
"""

from __future__ import annotations

import math
import os
import shlex
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# a point's message when the state-space fit fell back
CONVOLUTION_BLOCKS = "state-space blocks no order fits (the radiation ran as the convolution)"


@dataclass(frozen=True)
class Variant:
    """A scenario file (relative to the repository root) and the ``--set KEY=VALUE`` items that make one point;
    ``in_process``: the FMU slaves called in process instead of through fmpy (``wec-cosim run --in-process``)."""

    scenario: str
    overrides: tuple[str, ...] = ()
    in_process: bool = False

    def command(self) -> str:
        """The command that reruns this point, quoted for a POSIX shell."""
        return " ".join(["wec-cosim run", shlex.quote(self.scenario),
                         *(f"--set {shlex.quote(o)}" for o in self.overrides),
                         *(["--in-process"] if self.in_process else [])])

    def with_(self, *items: str) -> Variant:
        """This variant with more overrides (a later item for the same key wins, as on the command line)."""
        keys = {i.partition("=")[0] for i in items}
        return Variant(self.scenario, tuple(o for o in self.overrides if o.partition("=")[0] not in keys) + items,
                       self.in_process)


@dataclass
class Point:
    """What one run of a variant measured.

    Attributes:
        variant: what ran.
        status: ``ok``, ``diverged``, ``not converged`` or ``failed`` (:func:`classify`), or ``unavailable``
            (the scenario refuses these settings, e.g. the
            monolithic mode on a scene with joints).
        wall_time: wall-clock seconds of the stepping loop (initialisation excluded); NaN if it did not start.
        simulated: simulated seconds reached.
        error: the case's error measure (dimensionless, relative), NaN unless ``ok``.
        estimate: the run's own estimate of that error (:mod:`orchestrator.cosim.error_estimate`), NaN if none.
        message: the run's own message when it did not finish, else notes of the error measure.
        extra: other figures of the run (a ``measures`` function's, e.g. the long run's constraint drift).
    """

    variant: Variant
    status: str
    wall_time: float
    simulated: float
    error: float = math.nan
    estimate: float = math.nan
    message: str = ""
    extra: dict[str, float] = field(default_factory=dict)

    @property
    def real_time_factor(self) -> float:
        return self.simulated / self.wall_time if self.wall_time > 0 else math.nan

    @property
    def stable(self) -> bool:
        return self.status == "ok"


ErrorMeasure = Callable[["object", dict, "object"], float]  # (scene, results data, RunResult) -> relative error
Measures = Callable[["object", dict, "object"], dict[str, float]]  # (scene, results data, RunResult) -> figures


def run_point(variant: Variant, error: ErrorMeasure | None = None, *, measures: Measures | None = None,
              estimate: ErrorMeasure | None = None, shadow: bool = True) -> Point:
    """Run ``variant`` (through fmpy, the product's default path, unless ``variant.in_process``) and score it with
    ``error``.

    The results file goes to a temporary folder; the scene (hydro database, fits) comes from the caches, so
    a point costs its FMUs' start-up plus the stepping loop. ``measures``, if given, reads more figures from
    the finished run's results (e.g. a long run's constraint drift) into :attr:`Point.extra`; ``estimate`` scores
    the run's own estimate of ``error`` into :attr:`Point.estimate`. ``shadow=False``: the run makes no error estimate
    (``simulation.error_estimate = "none"``, for the parts that measure stability or speed alone: the stepping loop is
    the same, the report takes less time)."""
    from orchestrator.cosim.simulation import run_scenario
    from orchestrator.errors import WecCosimError
    from orchestrator.results import read_results
    from orchestrator.scenario import apply_overrides, load_scenario
    from orchestrator.scene import load_scene

    try:
        scenario = apply_overrides(load_scenario(ROOT / variant.scenario),
                                   list(variant.overrides) + ([] if shadow else ["simulation.error_estimate=none"]))
        scene = load_scene(scenario, log=None)
    except WecCosimError as exc:  # the settings do not apply to this scene (e.g. monolithic with joints)
        return Point(variant, "unavailable", math.nan, 0.0, message=" ".join(str(exc).split())[:300])
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "point.h5"
        try:
            result = run_scenario(scenario, out, in_process=variant.in_process, log=None, progress=False, scene=scene)
        except (WecCosimError, RuntimeError, ValueError, FloatingPointError, OSError) as exc:
            return _unfinished(variant, classify(exc), out, exc)
        data = read_results(result.path)
        point = Point(variant, "ok", result.wall_time, result.simulated_time)
        blocks = [w for w in result.radiation.get("warnings", []) if "the radiation is the convolution" in w]
        if blocks:
            point.message = f"{CONVOLUTION_BLOCKS}: " + "; ".join(w.split(" reaches")[0].split("fit of ")[-1]
                                                                 for w in blocks)
        if error is not None:
            try:
                point.error = float(error(scene, data, result))
            except (ValueError, ArithmeticError, KeyError, IndexError, StopIteration) as exc:
                point.message = f"error measure failed: {exc}"
        if estimate is not None:
            try:
                point.estimate = float(estimate(scene, data, result))
            except (ValueError, ArithmeticError, KeyError, IndexError, StopIteration) as exc:
                point.message += f" error estimate failed: {exc}"
            e = getattr(result, "error_estimate", None)
            if e is not None and not e.available:
                point.message += f" no error estimate: {e.method}"
            elif e is not None:
                point.extra["shadow_wall_time"] = e.shadow_wall_time
                point.extra["shadow_distance"] = e.shadow_distance
        if measures is not None:
            point.extra.update(measures(scene, data, result))
    return point


def classify(exc: BaseException) -> str:
    """``diverged`` (the master's divergence check: an output beyond its limit or not finite), ``not converged``
    (a coupling or Newton iteration gave up) or ``failed`` (anything else, e.g. an FMU that could not start)."""
    from orchestrator.errors import MasterError

    text = str(exc)
    if isinstance(exc, MasterError) and ("diverged" in text or "not finite" in text):
        return "diverged"
    if isinstance(exc, MasterError) and "did not converge" in text:
        return "not converged"
    return "failed"


def _unfinished(variant: Variant, status: str, out: Path, exc: BaseException) -> Point:
    """A run that stopped: the simulated time it reached (from the rows it kept) and its message."""
    from orchestrator.results import read_results

    reached = math.nan
    if out.exists():
        try:
            t = read_results(out)["time"]
            reached = float(t[-1]) if len(t) else 0.0
        except (OSError, KeyError, ValueError):
            pass
    message = " ".join(str(exc).split())
    return Point(variant, status, math.nan, reached, message=message[:300])


def quiet_threads() -> None:
    """One BLAS thread (set before numpy loads): on this 2-core machine helper threads only add noise."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
