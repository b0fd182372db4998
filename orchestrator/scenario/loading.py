"""Reading a scenario file: TOML text checked for what the machine can take, parsed into a :class:`Scenario`,
every key converted by the schema, then every check that involves several keys."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

from orchestrator.errors import ScenarioError

from . import input_checks, schema
from .checks import check_scenario
from .scenario import Scenario


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario file; raises :class:`ScenarioError` on any problem."""
    path = Path(path)
    return parse_scenario(input_checks.read_scenario_text(path), path)


def parse_scenario(text: str, path: Path) -> Scenario:
    input_checks.check_nesting(text, path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML: {exc}") from None
    except RecursionError:
        raise ScenarioError(f"{path}: arrays or tables nested too deeply") from None
    _refuse_old_sweep_keys(data, path)
    scenario = schema.load(Scenario, data, str(path))
    scenario._file = path
    scenario._text = text
    if not scenario.name:
        scenario.name = re.sub(r"[^A-Za-z0-9_.+-]", "_", path.stem).lstrip(".-")[:100] or "scenario"
    check_scenario(scenario)
    return scenario


def _refuse_old_sweep_keys(data: dict, path: Path) -> None:
    """The one-key sweep table of earlier versions (parameter, values, periods) with its replacement."""
    sw = data.get("sweep")
    if not isinstance(sw, dict) or not {"parameter", "values", "periods"} & set(sw):
        return
    def array(values: object) -> str:
        text = str(values)
        return text if len(text) <= 80 else text[:60] + " ...]"

    lines = []
    if sw.get("parameter"):
        lines.append(f"{sw['parameter']} = {array(sw.get('values', []))}")
    if sw.get("periods"):
        lines.append(f"waves.period = {array(sw['periods'])}")
    raise ScenarioError(
        f"{path}: [sweep] keys parameter, values and periods were replaced by the [sweep.grid] table of key paths "
        "and values; write instead: [sweep.grid] " + "; ".join(lines) + " (see docs/sweeps.md)")
