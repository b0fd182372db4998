"""The report's cases and the settings it varies: data only (what runs), no running.

Each :class:`Case` is a bundled scenario plus the ``--set`` overrides that make it a benchmark case, the error
measure that scores it against an independent answer, the macro steps of its work-precision curves and the
factors varied around the defaults (one factor at a time: every curve differs from the defaults' curve in
exactly one setting, so a reader sees what each choice costs and buys).
"""

from __future__ import annotations

from dataclasses import dataclass

from . import errors
from .points import ErrorMeasure, Variant


@dataclass(frozen=True)
class Option:
    """One value of a factor: its label and the overrides that select it (empty: the scenario's default)."""

    label: str
    overrides: tuple[str, ...] = ()


@dataclass(frozen=True)
class Factor:
    """A setting varied one at a time; the first option is the default."""

    name: str
    options: tuple[Option, ...]


@dataclass(frozen=True)
class Case:
    """A benchmark case.

    Attributes:
        name: short name (file names of the report).
        title: what the case is, for the report.
        base: the scenario and the overrides that make it the case (duration, sea).
        quick_base: the same for ``--quick`` (shorter runs), or None for ``base``.
        error: the error measure (:mod:`wec_cosim.benchreport.errors`); ``error_name`` says what it is.
        steps / quick_steps: macro steps (s) of every work-precision curve; the scenario's own step among them.
        default_step: the scenario's own macro step.
        factors: the settings varied, each around the defaults.
    """

    name: str
    title: str
    base: Variant
    error: ErrorMeasure
    error_name: str
    steps: tuple[float, ...]
    quick_steps: tuple[float, ...]
    default_step: float
    factors: tuple[Factor, ...]
    quick_base: Variant | None = None

    def variant(self, quick: bool) -> Variant:
        return (self.quick_base or self.base) if quick else self.base


MASTER = Factor("master", (
    Option("jacobi (default)"), Option("gauss_seidel", ("simulation.master=gauss_seidel",)),
    Option("iqn_ils", ("simulation.master=iqn_ils",))))
# The monolithic mode steps the linear multibody model only (no joints): for the unconstrained case.
MASTER_AND_MONOLITHIC = Factor("master", (*MASTER.options, Option("monolithic (no FMI)",
                                                                  ("simulation.master=monolithic",))))
EXTRAPOLATION = Factor("extrapolation", (
    Option("order 2 (default)"), Option("order 1", ("simulation.extrapolation=1",)),
    Option("order 0 (hold)", ("simulation.extrapolation=0",))))
FORMULATION = Factor("formulation", (
    Option("index3 (default)"), Option("index1", ("multibody.formulation=index1",)),
    Option("nullspace", ("multibody.formulation=nullspace",))))
RADIATION = Factor("radiation", (
    Option("convolution (default)"),
    *(Option(f"state space tol {tol:g}", ("hydro.radiation_method=state_space", f"hydro.state_space_tolerance={tol:g}"))
      for tol in (0.1, 0.02, 0.005))))

IRREGULAR_SEA = ("waves.kind=irregular", "waves.spectrum=jonswap", "waves.hs=1.0", "waves.tp=6.0", "waves.seed=7")

CASES = (
    Case("hinge_barge", "Hinge barge (Paparella et al.), regular waves H 0.02 m T 2 s, two bodies, one hinge, index-3",
         Variant("scenarios/hinge_barge.toml"), errors.regular_wave_error,
         "largest complex relative error |X - X_exact| / |X_exact| of the steady first harmonic over the six body "
         "DOFs and the hinge angle, against the exact frequency-domain answer",
         steps=(0.08, 0.04, 0.02, 0.01), quick_steps=(0.04, 0.02, 0.01), default_step=0.02,
         factors=(MASTER, EXTRAPOLATION, FORMULATION, RADIATION)),
    Case("f3of_dt3", "F3OF decay test 3 (the InWave+H paper), base fixed, flap released from 10 deg, three bodies, "
                     "two hinges",
         Variant("scenarios/f3of_dt3.toml", ("simulation.duration=1500",)), errors.decay_error,
         "largest relative error of the period and damping ratio of the two free modes (fit after 300 s) "
         "against the roots of the linear model (a floor of about 1.7 % remains at small steps, the same for "
         "every master and formulation: the roots describe small motions, the run starts from 10 deg; not "
         "investigated further)",
         steps=(0.2, 0.1, 0.05, 0.025), quick_steps=(0.2, 0.1, 0.05), default_step=0.1,
         factors=(MASTER, EXTRAPOLATION, FORMULATION, RADIATION),
         quick_base=Variant("scenarios/f3of_dt3.toml", ("simulation.duration=900",))),
    Case("two_floats_irregular", "Two floats 12 m apart (heave, PTO dampers) in a JONSWAP sea Hs 1 m Tp 6 s",
         Variant("scenarios/two_floats.toml", (*IRREGULAR_SEA, "simulation.duration=400")), errors.irregular_error,
         "largest RMS deviation from the exact linear response to the realised sea (superposition of the "
         "frequency-domain RAOs), relative to the largest RMS response, after the ramp and the 40 s radiation "
         "memory",
         steps=(0.2, 0.1, 0.05, 0.025), quick_steps=(0.2, 0.1, 0.05), default_step=0.1,
         factors=(MASTER_AND_MONOLITHIC, EXTRAPOLATION, RADIATION),
         quick_base=Variant("scenarios/two_floats.toml", (*IRREGULAR_SEA, "simulation.duration=200"))),
)
