"""Scenario values changed in Python after loading (``s.waves.height = 1.5``): found, checked with the scenario's
own checks (errors worded for Python: the attribute and the value set, not the file, which is unchanged) and
recorded so that the results file knows the scene that ran.

A loaded :class:`Scenario` keeps its file's text and the overrides applied to it; :func:`python_changes` compares
the scenario with the one that text and those overrides give. :func:`check_python_changes` checks each changed
value as the file's key would be checked (type, unit range, choices), then every check across keys, and records
the changes: as overrides (``KEY=VALUE``, what ``wec-cosim resume`` applies again) when every change is a value of
a key, or else (a body or PTO added, a table replaced) as the scenario's whole text written again in TOML
(:func:`scenario_toml`).
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass
from typing import Any

from orchestrator.errors import ScenarioError

from . import schema
from .checks import check_scenario
from .overrides import toml_value
from .scenario import Scenario


@dataclass
class Change:
    """One value of a scenario that differs from its file (and recorded overrides)."""

    key: str  # key path, as ``--set`` and sweep grids name it (``waves.height``, ``ptos.pto.damping``)
    owner: Any  # the section (dataclass) holding it; None for a structural change
    name: str  # the field's name in ``owner``
    value: Any  # the value now
    before: Any  # the file's value


def _fields(obj: Any) -> list[dataclasses.Field]:
    return [f for f in dataclasses.fields(obj) if f.init and not f.name.startswith("_")]


def _named_items(value: Any) -> list[str] | None:
    """The names of a list of named sections (``bodies``, ``ptos``...), None for anything else."""
    if isinstance(value, list) and value and all(dataclasses.is_dataclass(v) and hasattr(v, "name") for v in value):
        return [v.name for v in value]
    return None


def _diff(now: Any, before: Any, path: str, out: list[Change], structural: list[str]) -> None:
    for f in _fields(now):
        key = f"{path}.{f.name}" if path else f.name
        a, b = getattr(now, f.name), getattr(before, f.name)
        if dataclasses.is_dataclass(a) and dataclasses.is_dataclass(b) and type(a) is type(b):
            _diff(a, b, key, out, structural)
        elif _named_items(a) is not None and _named_items(a) == _named_items(b):
            for x, y in zip(a, b, strict=True):
                _diff(x, y, f"{key}.{x.name}", out, structural)
        elif not _same(a, b):
            if dataclasses.is_dataclass(a) or dataclasses.is_dataclass(b) or _named_items(a) or _named_items(b):
                structural.append(key)
            else:
                out.append(Change(key, now, f.name, a, b))


def _same(a: Any, b: Any) -> bool:
    """Equal and of one type (an integer set where the file has a float is a change: it is converted)."""
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    try:
        return type(a) is type(b) and bool(a == b)
    except (TypeError, ValueError):  # e.g. a numpy array set in Python
        return False


def reference(scenario: Scenario) -> Scenario | None:
    """The scenario as its file's text and its recorded overrides give it (None for a scenario built in code,
    without a file's text)."""
    if not scenario.text:
        return None
    from .loading import parse_scenario
    from .overrides import apply_overrides

    return apply_overrides(parse_scenario(scenario.text, scenario.file), list(scenario._overrides), what="--set")


def python_changes(scenario: Scenario) -> tuple[list[Change], list[str]]:
    """The values changed since loading (key by key), and the keys of structural changes (lists of bodies, PTOs,
    joints... of other names or length, tables added, removed or replaced)."""
    before = reference(scenario)
    changes: list[Change] = []
    structural: list[str] = []
    if before is not None:
        _diff(scenario, before, "", changes, structural)
    return changes, structural


def _label(scenario: Scenario) -> str:
    return f"the scenario of {scenario.file}" if scenario.text else "a scenario built in Python"


def _python_error(exc: ScenarioError, marker: str, key: str, value: Any) -> ScenarioError:
    """The schema's message about the value set in Python (``marker`` stands where the file's name would)."""
    text = str(exc)
    rest = text[len(marker):].lstrip(": ") if text.startswith(marker) else text
    rest = rest[len(key):].lstrip(": ") if rest.startswith(key) else rest
    return ScenarioError(f"{key} = {value!r}, set in Python: {rest}")


def check_python_changes(scenario: Scenario) -> Scenario:
    """Check what was changed in Python since loading; raise :class:`ScenarioError` worded for Python, or record
    the changes (module docstring) and return the same scenario, every value converted as the file's would be
    (an integer set for a float becomes a float; a tuple for a list becomes a list)."""
    changes, structural = python_changes(scenario)
    marker = "\0scenario"
    for c in changes:
        try:
            converted = schema.convert_field(type(c.owner), c.name, _plain(c.value), marker, c.key)
        except ScenarioError as exc:
            raise _python_error(exc, marker, c.key, c.value) from None
        setattr(c.owner, c.name, converted)
        c.value = converted
    if structural or not scenario.text:
        _check_tree(scenario, marker)
    changed = [c.key for c in changes] + structural
    try:
        check_scenario(scenario)
    except ScenarioError as exc:
        text = str(exc)
        prefix = f"{scenario.file}: "
        text = text[len(prefix):] if text.startswith(prefix) else text
        where = f"{_label(scenario)}, changed in Python ({', '.join(changed)})" if changed else _label(scenario)
        raise ScenarioError(f"{text} ({where})") from None
    if structural:
        scenario._text = scenario_toml(scenario)
        scenario._overrides = []
    else:
        scenario._overrides += [f"{c.key}={toml_value(c.value)}" for c in changes]
    return scenario


def _check_tree(scenario: Scenario, marker: str) -> None:
    """Every value of the scenario through the schema (what loading its TOML would check)."""
    try:
        schema.load(Scenario, as_table(scenario), marker)
    except ScenarioError as exc:
        text = str(exc)
        text = text[len(marker):].lstrip(": ") if text.startswith(marker) else text
        raise ScenarioError(f"{text} (a value set in Python on {_label(scenario)})") from None


def _plain(value: Any) -> Any:
    from .overrides import plain

    value = plain(value)
    return list(value) if isinstance(value, tuple) else value


# ----------------------------------------------------------------------------- TOML
def _default(f: dataclasses.Field) -> Any:
    if f.default is not dataclasses.MISSING:
        return f.default
    if f.default_factory is not dataclasses.MISSING:
        return f.default_factory()
    return dataclasses.MISSING


def as_table(section: Any) -> dict[str, Any]:
    """A section (dataclass) as the TOML table that loads into it: the values that differ from the defaults,
    sections nested."""
    out: dict[str, Any] = {}
    for f in _fields(section):
        value = getattr(section, f.name)
        if value is None or _same(value, _default(f)):
            continue
        if dataclasses.is_dataclass(value):
            out[f.name] = as_table(value)
        elif isinstance(value, (list, tuple)) and value and dataclasses.is_dataclass(value[0]):
            out[f.name] = [as_table(v) for v in value]
        else:
            out[f.name] = _plain(value)
    return out


def scenario_toml(scenario: Scenario) -> str:
    """The scenario written as a TOML file that loads into the same values (comments of the original are lost)."""
    lines = [f"# {scenario.name}: written by wec-cosim from {scenario.file} and the values changed in Python", ""]
    _write_table(as_table(scenario), "", lines, array=False)
    return "\n".join(lines).rstrip() + "\n"


def _write_table(table: dict[str, Any], path: str, lines: list[str], array: bool) -> None:
    scalars = {k: v for k, v in table.items() if not _is_table(v) and not _is_table_array(v)}
    if path:
        lines.append(f"[[{path}]]" if array else f"[{path}]")
    for key, value in scalars.items():
        lines.append(f"{_key(key)} = {_inline(value)}")
    lines.append("")
    for key, value in table.items():
        sub = f"{path}.{_key(key)}" if path else _key(key)
        if _is_table(value):
            _write_table(value, sub, lines, array=False)
        elif _is_table_array(value):
            for item in value:
                _write_table(item, sub, lines, array=True)


def _is_table(value: Any) -> bool:
    return isinstance(value, dict)


def _is_table_array(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def _key(key: str) -> str:
    return key if key.replace("_", "").replace("-", "").isalnum() and key.isascii() else json.dumps(key)


def _inline(value: Any) -> str:
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_inline(v)}" for k, v in value.items()) + " }"
    if isinstance(value, list):
        return "[" + ", ".join(_inline(v) for v in value) + "]"
    return toml_value(value)
