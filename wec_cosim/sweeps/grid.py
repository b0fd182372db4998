"""The cases of a sweep: axes from the scenario's ``[sweep.grid]``, the scenario of each case, its seed.

A grid is a list of axes, each a key path of the scenario (``waves.hs``, ``ptos.pto.damping``,
``bodies.float.mass``, ``simulation.adaptive.max_step``...) with its values, converted and checked
exactly as the scenario loader would. The cases are every combination of the axes' values (the
first axis varies slowest), times ``seeds`` realisations for time-domain runs in irregular seas.

Identity and seeds never depend on the order of execution:

* a case's **id** is a hash of its parameters (sorted by key), its seed index, the method and the
  transient: the same case has the same id in every run, which is what makes a sweep resumable;
* the **seed** of the random wave phases is a hash of the case's sea state (its ``waves.*``
  parameters), the seed index and the scenario's own ``waves.seed``. Cells that differ only in a
  PTO or a body see the same waves (common random numbers: a PTO study compares like with like);
  cells of different sea states get independent phases. A grid that sweeps ``waves.seed`` itself
  keeps its values.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import itertools
import json
import math
from dataclasses import dataclass, field
from typing import Any

from orchestrator.errors import ScenarioError
from orchestrator.scenario import Scenario, schema
from orchestrator.scenario.checks import check_scenario
from orchestrator.scenario.input_checks import MAX_SWEEP_POINTS
from orchestrator.scenario.keys import resolve_key, toml_scalar

METHODS = ("frequency_domain", "time_domain")
REGULAR_ONLY = frozenset({"height", "period", "phase_deg"})
IRREGULAR_ONLY = frozenset({"hs", "tp", "gamma", "spectrum", "spectrum_file", "seed", "discretisation",
                            "repeat_period", "n_components", "omega_min", "omega_max", "spreading_s",
                            "n_directions"})


@dataclass(frozen=True)
class Axis:
    """One swept key: its path, its values (converted as the scenario loader does) and unit."""

    key: str
    values: tuple[Any, ...]
    unit: str = ""


@dataclass(frozen=True)
class Case:
    """One run: the value of every axis, its grid position, its seed index and derived seed.

    ``seed`` is None when the case's sea has no random phases (regular waves, frequency domain) or the
    grid sets ``waves.seed`` itself.
    """

    params: tuple[tuple[str, Any], ...]
    index: tuple[int, ...]
    seed_index: int
    seed: int | None
    id: str

    def label(self) -> str:
        text = ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}" for k, v in self.params)
        return text + (f", seed #{self.seed_index}" if self.seed is not None else "")


@dataclass
class SweepPlan:
    """Everything that defines a sweep's cases: the base scenario, axes, seeds and method."""

    scenario: Scenario
    axes: list[Axis]
    seeds: int
    method: str
    transient: float | None
    time_series: bool
    cases: list[Case] = field(default_factory=list)
    fingerprint: str = ""

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(a.values) for a in self.axes)


def plan_sweep(scenario: Scenario) -> SweepPlan:
    """The cases of the scenario's ``[sweep]`` table, every one validated as a scenario of its own."""
    sw = scenario.sweep
    axes = grid_axes(scenario, sw.grid)
    plan = SweepPlan(scenario, axes, sw.seeds, sw.method, sw.transient, sw.time_series,
                     fingerprint=fingerprint(scenario))
    keys = [a.key for a in axes]
    n_cases = math.prod(len(a.values) for a in axes) * sw.seeds
    if n_cases > MAX_SWEEP_POINTS:
        raise ScenarioError(f"{scenario.file}: sweep.grid: {' x '.join(str(len(a.values)) for a in axes)} values "
                            f"and {sw.seeds} seeds make {n_cases} cases (at most {MAX_SWEEP_POINTS}); split the "
                            "sweep into several files")
    if "waves.seed" in keys and sw.seeds > 1:
        raise ScenarioError(f"{scenario.file}: sweep.seeds = {sw.seeds} and a swept waves.seed contradict each "
                            "other: give either the seeds yourself (sweep.grid) or their number (sweep.seeds)")
    for index in itertools.product(*(range(len(a.values)) for a in axes)):
        params = tuple((a.key, a.values[i]) for a, i in zip(axes, index, strict=True))
        variant = apply_params(scenario, params)
        _check_case(scenario, variant, params, sw.method)
        random_sea = variant.waves.kind == "irregular" and sw.method == "time_domain" and "waves.seed" not in keys
        for k in range(sw.seeds if random_sea else 1):
            seed = derive_seed(scenario.waves.seed, params, k) if random_sea else None
            plan.cases.append(Case(params, index, k, seed, case_id(params, k, sw.method, sw.transient)))
    return plan


def grid_axes(scenario: Scenario, grid: dict[str, Any]) -> list[Axis]:
    """Axes of a ``[sweep.grid]`` table (nested tables or dotted keys), values converted and checked."""
    axes = []
    for key, values in _flatten(grid, scenario):
        owner, name = resolve_key(scenario, key)
        where = f"sweep.grid.{key}"
        if not isinstance(values, list) or not values:
            raise ScenarioError(f"{scenario.file}: {where}: expected a non-empty array of values, got {values!r}")
        converted = tuple(schema.convert_field(type(owner), name, v, str(scenario.file), f"{where}[{i}]")
                          for i, v in enumerate(values))
        if len(set(converted)) != len(converted):
            raise ScenarioError(f"{scenario.file}: {where}: a value appears twice ({list(converted)})")
        unit = {f.name: f for f in dataclasses.fields(owner)}[name].metadata.get("unit", "")
        axes.append(Axis(key, converted, unit))
    return axes


def _flatten(grid: dict[str, Any], scenario: Scenario, prefix: str = "") -> list[tuple[str, Any]]:
    out = []
    for k, v in grid.items():
        key = f"{prefix}.{k}" if prefix else k
        if isinstance(v, dict):
            out += _flatten(v, scenario, key)
        else:
            out.append((key, v))
    return out


def apply_params(scenario: Scenario, params: tuple[tuple[str, Any], ...], seed: int | None = None) -> Scenario:
    """A copy of ``scenario`` with the case's parameters (and seed) set and every check run again."""
    s = copy.deepcopy(scenario)
    for key, value in params:
        owner, name = resolve_key(s, key)
        setattr(owner, name, value)
    if seed is not None:
        s.waves.seed = seed
    check_scenario(s)
    return s


def case_scenario(plan: SweepPlan, case: Case) -> Scenario:
    """The scenario that case ``case`` runs."""
    return apply_params(plan.scenario, case.params, case.seed)


def _check_case(base: Scenario, s: Scenario, params: tuple, method: str) -> None:
    where = f"{base.file}: sweep.grid"
    kind = s.waves.kind
    for key, _ in params:
        section, _, name = key.partition(".")
        if section != "waves":
            continue
        if (name in REGULAR_ONLY and kind != "regular") or (name in IRREGULAR_ONLY and kind != "irregular"):
            other = "regular" if name in REGULAR_ONLY else "irregular"
            instead = "waves.hs and waves.tp" if kind == "irregular" else "waves.height and waves.period"
            raise ScenarioError(f"{where}: {key} applies to {other} waves but the case's sea is {kind!r} "
                                f"(waves.kind); sweep {instead} instead")
    if method == "frequency_domain" and kind not in ("regular", "irregular"):
        raise ScenarioError(f"{where}: the frequency-domain method needs regular or irregular waves (waves.kind "
                            f"is {kind!r}); set sweep.method = 'time_domain'")
    if method == "frequency_domain" and kind == "irregular" and s.waves.spreading_s > 0:
        raise ScenarioError(f"{where}: the frequency-domain irregular-sea statistics are for unidirectional seas; "
                            "set waves.spreading_s = 0 or sweep.method = 'time_domain'")


def _canonical(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    return value


def derive_seed(base_seed: int, params: tuple[tuple[str, Any], ...], seed_index: int) -> int:
    """Seed of the wave phases of a case: a hash of its sea state, the seed index and ``waves.seed``."""
    sea = sorted((k, _canonical(v)) for k, v in params if k.startswith("waves."))
    text = json.dumps({"waves.seed": base_seed, "sea": sea, "seed_index": seed_index}, sort_keys=True)
    return int(hashlib.sha256(text.encode()).hexdigest()[:8], 16) & 0x7FFFFFFF  # an FMI Integer is 32-bit


def case_id(params: tuple[tuple[str, Any], ...], seed_index: int, method: str, transient: float | None) -> str:
    """Stable identity of a case within a sweep file (hex, 16 characters)."""
    text = json.dumps({"params": sorted((k, _canonical(v)) for k, v in params), "seed_index": seed_index,
                       "method": method, "transient": transient}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def base_json(scenario: Scenario) -> str:
    """The scenario outside ``[sweep]`` as canonical JSON (what every case of a sweep file shares)."""
    data = {f.name: getattr(scenario, f.name) for f in dataclasses.fields(scenario)
            if not f.name.startswith("_") and f.name != "sweep"}
    plain = {k: dataclasses.asdict(v) if dataclasses.is_dataclass(v)
             else [dataclasses.asdict(x) for x in v] if isinstance(v, list) else v for k, v in data.items()}
    return json.dumps(plain, sort_keys=True, default=str)


def fingerprint(scenario: Scenario) -> str:
    """Hash of :func:`base_json`: the cases of a sweep file belong to one base scene."""
    return hashlib.sha256(base_json(scenario).encode()).hexdigest()[:16]


def parse_grid_option(text: str) -> tuple[str, list[Any]]:
    """``KEY=V1,V2,...`` or ``KEY=START:STOP:COUNT`` (COUNT values, both ends included) from the command
    line; values are read as TOML values (numbers, true/false, quoted or bare strings)."""
    key, sep, rest = text.partition("=")
    key = key.strip()
    if not sep or not key or not rest.strip():
        raise ScenarioError(f"--grid {text!r}: expected KEY=V1,V2,... or KEY=START:STOP:COUNT")
    parts = rest.split(":")
    if len(parts) == 3:
        try:
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
        except ValueError:
            raise ScenarioError(f"--grid {text!r}: START:STOP:COUNT needs two numbers and an integer") from None
        if count < 1:
            raise ScenarioError(f"--grid {text!r}: COUNT must be at least 1")
        step = (stop - start) / (count - 1) if count > 1 else 0.0
        return key, [round(start + i * step, 12) for i in range(count)]
    return key, [toml_scalar(v.strip(), text) for v in rest.split(",")]


def set_grid(scenario: Scenario, key: str, values: list[Any]) -> None:
    """Add or replace axis ``key`` of the scenario's ``[sweep.grid]`` (command-line override)."""
    flat = dict(_flatten(scenario.sweep.grid, scenario))
    flat[key] = values
    scenario.sweep.grid = flat
