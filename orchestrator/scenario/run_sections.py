"""Scenario sections of how a scene is run: time-domain settings (master, step, adaptive step, checkpoints),
the frequency-domain and steady-state settings, external control and sweeps."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from .schema import non_negative, option, positive
from .sea_sections import FrequencyGrid


def _order(value: int) -> str | None:
    return None if value in (0, 1, 2) else "must be 0, 1 or 2"


MASTERS = ("jacobi", "gauss_seidel", "aitken", "iqn_ils", "monolithic")
ADDED_MASS = ("mass_matrix", "explicit_force", "interface")


@dataclass
class AdaptiveSection:
    """Energy-based adaptive macro step (ECCO idea); `simulation.step` is then the smallest step."""

    enabled: bool = option(False, doc="adapt the macro step to the power mismatch on the force/velocity bonds")
    max_step: float = option(1.0, unit="s", check=positive,
                             doc="largest macro step; steps are whole multiples of `simulation.step` "
                                 "(the hydro FMU's radiation grid)")
    tolerance: float = option(
        0.01, check=positive,
        doc="largest energy mismatch over a step on any bond, relative to the energy flowing through the bond "
            "in that step")
    safety: float = option(0.8, check=positive, doc="safety factor of the step-size controller (< 1)")
    max_growth: float = option(2.0, check=positive, doc="largest ratio of two consecutive steps (> 1)")


@dataclass
class SimulationSection:
    """Time-domain co-simulation settings."""

    duration: float = option(unit="s", check=positive,
                             doc="simulated time; a duration that is not a whole number of steps is rounded to the "
                                 "nearest whole number of steps, and the run's summary says so")
    step: float = option(unit="s", doc="macro (communication) step of the master; with `[simulation.adaptive]` the "
                                       "smallest step and the radiation grid", check=positive)
    master: str = option(
        "jacobi", choices=MASTERS,
        doc="`jacobi`, `gauss_seidel`, `aitken` (iterative, fixed point with Aitken relaxation), `iqn_ils` "
            "(iterative, interface quasi-Newton) or `monolithic` (same physics in one process, no FMI)")
    extrapolation: int = option(
        2, check=_order,
        doc="degree of the polynomial that gives the multibody FMU's force input over a step, averaged over the "
            "step: extrapolated from past values (jacobi) or interpolated through the end value (gauss_seidel, "
            "iterative); 0 = hold")
    resolve_feedthrough: bool = option(
        True,
        doc="jacobi: set the motion at each communication point into the hydro FMU before reading its force; "
            "`false` reads every output right after the step, as generic FMI hosts do (fmpy's SSP simulator, "
            "libcosim fixedStep; first order, needs extrapolation = 0)")
    interface: str = option(
        "force", choices=("force", "linearised"),
        doc="what the hydro FMU hands the multibody FMU: `force`, the force (held or extrapolated by the master); "
            "`linearised`, the affine model F0 + F0_rate (t - t_n) + dF_dx x + dF_dv v that the multibody FMU "
            "integrates implicitly (second order and stable under any fixed-step host, the coupling `export-ssp` "
            "writes; jacobi with extrapolation = 0 only: the model carries its own time rate)")
    added_mass: str = option(
        "mass_matrix", choices=ADDED_MASS,
        doc="`mass_matrix`: A_inf in the multibody mass matrix (stable, default); `explicit_force`: A_inf applied "
            "as a force from the previous step's acceleration (unstable when A_inf > mass; a demonstration); "
            "`interface`: a third-party-style multibody FMU without A_inf, the added-mass force solved within "
            "each step (needs an iterative master)")
    tolerance: float = option(1e-10, check=positive,
                              doc="iterative masters: largest interface residual relative to each variable's "
                                  "running maximum")
    max_iterations: int = option(50, check=positive, doc="iterative masters: iteration cap per step")
    relaxation: float = option(0.5, check=positive,
                               doc="iterative masters: first relaxation factor (Aitken's start, IQN-ILS's first "
                                   "update)")
    iqn_reuse: int = option(4, check=non_negative, doc="IQN-ILS: previous steps whose secant data are reused")
    divergence_limit: float = option(
        1.0e8, check=positive,
        doc="an exchanged or recorded value larger than this times its scale in the scene stops the run as "
            "diverged; the scale is the larger of 1 and the value at the start (SI units), for energies also the "
            "bodies' weight and static loads times 1 m")
    adaptive: AdaptiveSection = field(default_factory=AdaptiveSection,
                                      metadata={"doc": "energy-based adaptive step"})
    output: str = option("", doc="results file (HDF5); default `results/<name>.h5` in the working directory")
    output_every: int = option(1, check=positive, doc="record every n-th macro step")
    flush_seconds: float = option(2.0, unit="s", check=positive,
                                  doc="longest wall time between two writes of the results file to disk")
    checkpoint_every: float = option(
        0.0, unit="s", check=non_negative,
        doc="simulated time between checkpoints of all FMU states (`<output>.checkpoint.h5`, for "
            "`wec-cosim resume`); 0 = none")
    steady_periods: float = option(
        10.0, check=positive,
        doc="number of wave periods at the end of the run used for the steady-state amplitude, phase and power")

    @property
    def iterative(self) -> bool:
        return self.master in ("aitken", "iqn_ils")


@dataclass
class RaoSection:
    """Frequency-domain (RAO) settings for `wec-cosim rao`."""

    omega: FrequencyGrid | None = field(default=None, metadata={"doc": "frequencies; default the database grid"})
    form: str = option("dae", choices=("dae", "ode"),
                       doc="constrained scenes: `dae` (motion and Lagrange multipliers solved together) or `ode` "
                           "(null-space reduced system, multipliers recovered); the same answer")
    headings_deg: list[float] = option(factory=list, unit="deg",
                                       doc="heading sweep (database headings); default the waves' heading")


@dataclass
class SteadySection:
    """Pseudo-spectral periodic steady state for `wec-cosim steady` (regular waves, nonlinear forces)."""

    harmonics: int = option(7, check=positive, doc="harmonics N of the wave frequency (2N + 1 collocation points)")
    form: str = option("dae", choices=("dae", "ode"),
                       doc="`dae`: motion and Lagrange multipliers expanded; `ode`: null-space reduced coordinates")
    periods: list[float] = option(factory=list, unit="s", check=positive,
                                  doc="wave periods to solve; default the waves' period")
    tolerance: float = option(1e-12, check=positive, doc="relative step tolerance of the nonlinear solver")


def _limits(value: list[float]) -> str | None:
    ok = len(value) == 2 and value[0] <= value[1]
    return None if ok else "needs two values [minimum, maximum] with minimum <= maximum"


@dataclass
class ControlSection:
    """External controller over zenoh (see docs/control.md)."""

    mode: str = option("off", choices=("off", "lockstep", "realtime"),
                       doc="`lockstep` (deterministic, waits for each command), `realtime` (paced to the "
                           "wall clock, never waits) or `off`")
    run_id: str = option("", doc="key-expression namespace `wec/<run_id>/...`; default the scenario name")
    period: float | None = option(None, unit="s", check=positive,
                                  doc="control period, a whole number of macro steps; default the macro step")
    ptos: list[str] = option(factory=list, doc="PTOs driven by the controller; default all")
    fallback: str = option("hold", choices=("hold", "passive", "stop"),
                           doc="on a controller fault: `hold` the last valid command, `passive` damping, or "
                               "`stop` the run (results kept)")
    passive_damping: float = option(0.0, unit="N s/m or N m s/rad", check=non_negative,
                                    doc="damping of the `passive` fallback")
    timeout: float = option(1.0, unit="s", check=positive,
                            doc="lock-step: wall time to wait for a command before it counts as late")
    connect_timeout: float = option(10.0, unit="s", check=non_negative,
                                    doc="wall time to wait for the controller at the start")
    max_age: int = option(5, check=positive,
                          doc="real time: a command older than this many control periods counts as late")
    realtime_factor: float = option(1.0, check=positive,
                                    doc="real time: simulated seconds per wall-clock second (1 = real time)")
    endpoints: list[str] = option(factory=lambda: ["tcp/127.0.0.1:7447"],
                                  doc="zenoh endpoints the master listens on (loopback by default)")
    zenoh_config: str = option("", doc="zenoh configuration file (endpoints, TLS, access control); "
                                       "replaces `endpoints`; relative to the scenario file")
    damping_limits: list[float] = option(factory=lambda: [0.0, math.inf], unit="N s/m or N m s/rad",
                                         allow_inf=True, check=_limits, doc="accepted damping commands")
    stiffness_limits: list[float] = option(factory=lambda: [-math.inf, math.inf], unit="N/m or N m/rad",
                                           allow_inf=True, check=_limits, doc="accepted stiffness commands")
    force_limits: list[float] = option(factory=lambda: [-math.inf, math.inf], unit="N or N m",
                                       allow_inf=True, check=_limits, doc="accepted force commands")


@dataclass
class SweepSection:
    """Sweep for `wec-cosim sweep`: one full run per combination of the grid's values (see docs/sweeps.md)."""

    grid: dict[str, Any] = option(
        factory=dict,
        doc="swept keys and their values: a table whose keys are key paths of this file and whose values are "
            "arrays, e.g. `waves.hs = [1.0, 2.0]`, `waves.tp = [6.0, 8.0]`, `ptos.pto.damping = [1e5, 2e5]`, "
            "`bodies.float.mass = [...]`, `waves.heading_deg = [...]`; one case per combination (the first key "
            "varies slowest); `--grid KEY=V1,V2` on the command line adds or replaces a key")
    seeds: int = option(
        1, check=positive,
        doc="time-domain runs in irregular seas: realisations per grid cell; the seed of each is derived from the "
            "case's sea state, the seed index and `waves.seed` (never from the order of execution)")
    method: str = option("frequency_domain", choices=("frequency_domain", "time_domain"),
                         doc="exact linear frequency-domain solution (regular or irregular seas), or one "
                             "time-domain co-simulation per case")
    transient: float | None = option(
        None, unit="s", check=non_negative,
        doc="time domain: start-up discarded before the statistics; default: regular waves the last "
            "`simulation.steady_periods` periods are analysed (the duration is extended to the ramp, 15 "
            "periods of settling and that window), other seas the ramp time plus `hydro.irf_duration`")
    time_series: bool = option(False, doc="also store each case's time series in the sweep file")
    workers: int = option(0, check=non_negative,
                          doc="worker processes of the local Dask cluster; 0 = one per core (`--workers`; "
                              "`--scheduler ADDRESS` uses a running cluster instead)")
