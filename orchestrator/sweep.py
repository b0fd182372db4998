"""``wec-cosim sweep``: mean PTO power over a grid of one scenario key and regular-wave periods.

The same scenario file drives the run, the RAOs and the sweep: ``[sweep]`` names a key path
(``ptos.pto.damping``, ``waves.height``...) and its values, and the wave periods. Each point is
the scenario with that key and period changed and validated again, solved exactly in the
frequency domain (cheap) or co-simulated in the time domain (steady state over the last
``simulation.steady_periods`` periods, the duration extended to the ramp plus that window plus 15
periods of settling; points run in ``workers`` local processes).
Output (HDF5): ``/values`` (Nv,), ``/periods`` (Np,), ``/ptos/<name>/mean_power`` (Nv, Np) in W,
``/bodies/<name>/amplitude`` (Nv, Np, 6) steady amplitude per DOF (m, rad); attributes
``parameter``, ``method``, ``scenario``.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import h5py
import numpy as np

from . import frequency_domain
from .errors import ScenarioError
from .scenario import DOFS, Scenario, _check


def set_key(scenario: Scenario, path: str, value: float | str, *, what: str = "sweep.parameter") -> Scenario:
    """A copy of ``scenario`` with the key at ``path`` set to ``value`` (a number, or one of a text key's
    choices), validated again; ``what`` names the setting in error messages."""
    s = copy.deepcopy(scenario)
    parts = path.split(".")
    target: object = s
    try:
        if parts[0] in ("ptos", "bodies") and len(parts) == 3:
            target = next(x for x in getattr(s, parts[0]) if x.name == parts[1])
        elif len(parts) == 2:
            target = getattr(s, parts[0])
        else:
            raise AttributeError(path)
        key = parts[-1]
        field = {f.name: f for f in dataclasses.fields(target)}[key]
    except (AttributeError, StopIteration, KeyError, TypeError):
        raise ScenarioError(
            f"{scenario.file}: {what} {path!r} names no {'key' if isinstance(value, str) else 'numeric key'}; "
            "use `section.key` or "
            "`ptos.<name>.<key>` / `bodies.<name>.<key>`") from None
    current = getattr(target, key)
    choices = field.metadata.get("choices")
    if isinstance(current, str) and choices and isinstance(value, str):
        if value not in choices:
            raise ScenarioError(f"{scenario.file}: {what} {path}: {value!r} is not one of {', '.join(choices)}")
        setattr(target, key, value)
        _check(s)
        return s
    if not isinstance(current, (int, float)) or isinstance(current, bool):
        raise ScenarioError(f"{scenario.file}: {what} {path!r} is not a numeric key"
                            + (" or a key with choices" if isinstance(value, str) else ""))
    try:
        value = float(value)
    except ValueError:
        raise ScenarioError(f"{scenario.file}: {what} {path}: {value!r} is not a number") from None
    check = field.metadata.get("check")
    problem = check(value) if check else None
    if problem or not math.isfinite(value):
        raise ScenarioError(f"{scenario.file}: {what}: {path} {problem or 'must be finite'} (got {value})")
    setattr(target, key, type(current)(value))
    _check(s)
    return s


def apply_overrides(scenario: Scenario, items: list[str]) -> Scenario:
    """``scenario`` with ``KEY=VALUE`` items set (``wec-cosim run --set``), recorded in ``_overrides`` so that
    results files (and ``wec-cosim resume``) know the scene that ran."""
    for item in items:
        key, sep, value = item.partition("=")
        if not sep:
            raise ScenarioError(f"--set {item!r}: write KEY=VALUE, e.g. mooring_lines.model=quasi_static")
        scenario = set_key(scenario, key.strip(), value.strip(), what="--set")
        scenario._overrides.append(f"{key.strip()}={value.strip()}")
    return scenario


def _points(scenario: Scenario) -> tuple[list[float], list[float]]:
    sw = scenario.sweep
    if sw.parameter and not sw.values:
        raise ScenarioError(f"{scenario.file}: sweep.parameter is set but sweep.values is empty")
    if scenario.waves.kind != "regular":
        raise ScenarioError(f"{scenario.file}: a sweep needs regular waves ([waves] kind = 'regular')")
    values = list(sw.values) if sw.parameter else [math.nan]
    periods = list(sw.periods) or [scenario.waves.period]
    return values, periods


def _variant(scenario: Scenario, value: float, period: float) -> Scenario:
    s = set_key(scenario, scenario.sweep.parameter, value) if scenario.sweep.parameter else copy.deepcopy(scenario)
    s.waves.period = period
    return s


def _frequency_domain_point(scene_of, s: Scenario) -> tuple[dict, dict]:
    scene = scene_of(s)
    omega = 2 * math.pi / s.waves.period
    a = s.waves.height / 2
    fd = frequency_domain.solve(scene, np.array([omega]))
    power = {name: float(p[0] * a**2) for name, p in fd.pto_power.items()}
    amplitude = {b.name: np.abs(fd.body_rao(b.name)[0]) * a for b in s.bodies}
    return power, amplitude


def _time_domain_point(s: Scenario) -> tuple[dict, dict]:
    from .simulation import run_scenario

    sim = s.simulation
    sim.checkpoint_every = 0.0
    # Long enough for the transient to die out before the steady-state window (15 periods of settling).
    needed = s.ramp_time + (math.ceil(sim.steady_periods) + 15) * s.waves.period
    sim.duration = max(sim.duration, math.ceil(needed / sim.step - 1e-9) * sim.step)
    with tempfile.TemporaryDirectory(prefix="wec_sweep_") as tmp:
        result = run_scenario(s, Path(tmp) / "point.h5", progress=False, log=None)
    power = {c.label.removesuffix(" mean power"): float(c.measured) for c in result.comparisons
             if c.label.endswith(" mean power")}
    amplitude = {b.name: np.zeros(6) for b in s.bodies}
    for c in result.comparisons:
        name, _, dof = c.label.partition(" ")
        if dof in DOFS:
            amplitude[name][DOFS.index(dof)] = abs(c.measured)
    return power, amplitude


def run_sweep(scenario: Scenario, out: str | Path, log=print) -> Path:
    """Solve every point of the scenario's sweep and write the table (module docstring)."""
    from .scene import Scene, load_scene

    values, periods = _points(scenario)
    variants = [_variant(scenario, v, p) for v in values for p in periods]
    base = load_scene(scenario, log=log)
    if scenario.sweep.method == "frequency_domain":
        results = [_frequency_domain_point(lambda s: Scene(s, base.hdb, base.hdb_file), s) for s in variants]
    elif scenario.sweep.workers > 1:
        with ProcessPoolExecutor(scenario.sweep.workers) as pool:
            results = list(pool.map(_time_domain_point, variants))
    else:
        results = [_time_domain_point(s) for s in variants]
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    shape = (len(values), len(periods))
    with h5py.File(out, "w") as f:
        f.create_dataset("values", data=np.array(values, dtype=float))
        f.create_dataset("periods", data=np.array(periods, dtype=float)).attrs["unit"] = "s"
        for p in scenario.ptos:
            data = np.array([r[0][p.name] for r in results]).reshape(shape)
            f.create_dataset(f"ptos/{p.name}/mean_power", data=data).attrs["unit"] = "W"
        for b in scenario.bodies:
            data = np.array([r[1][b.name] for r in results]).reshape(shape + (6,))
            f.create_dataset(f"bodies/{b.name}/amplitude", data=data).attrs["unit"] = "m, rad"
        f.attrs.update(parameter=scenario.sweep.parameter, method=scenario.sweep.method, scenario=scenario.text,
                       scenario_file=str(scenario.file))
    return out
