"""Scenario keys set by name: ``wec-cosim run --set KEY=VALUE`` (and ``resume``, which applies the overrides a
results file recorded), or :func:`apply_overrides` from Python. Keys are named as in a sweep grid
(``section.key``, ``<list>.<name>.key``: :func:`wec_cosim.sweeps.grid.resolve_key`); values are converted and
checked by the scenario schema, so an override gets the same errors as the same key in the file. A key that holds
a list takes a whole list (on the command line a TOML array: ``--set 'bodies.float.dofs=["heave", "pitch"]'``)."""

from __future__ import annotations

import copy
import json
import math
from collections.abc import Iterable, Mapping
from typing import Any

from orchestrator.errors import ScenarioError

from . import schema
from .checks import check_scenario
from .keys import resolve_key, toml_scalar
from .scenario import Scenario


def apply_overrides(scenario: Scenario, items: Iterable[str] | Mapping[str, Any], *,
                    what: str = "apply_overrides") -> Scenario:
    """A copy of ``scenario`` with each override set and every check run again; the overrides are recorded in
    ``_overrides`` (as ``KEY=VALUE`` with the value in TOML) so that results files (and ``wec-cosim resume``)
    know the scene that ran.

    Args:
        scenario: a loaded scenario (it is not changed).
        items: ``{"waves.height": 2.0, "ptos.pto.damping": 8e5}`` (Python values), or ``KEY=VALUE`` strings with
            the value written in TOML (``"bodies.float.dofs=['heave']"``, ``"simulation.master=gauss_seidel"``).
        what: how errors name the setting: ``"--set"`` on the command line, ``"apply_overrides"`` from Python.

    Raises:
        ScenarioError: a key names nothing settable, a value is refused by the key's check, or the changed scenario
            fails a check across keys.
    """
    pairs = _pairs(items, what)
    if not pairs:
        return scenario
    s = copy.deepcopy(scenario)
    for key, value, text in pairs:
        owner, name = resolve_key(s, key, what=what, lists=True)
        if what.startswith("-"):  # a command-line option: the file, then the option and the key
            where, label = str(s.file), f"{what} {key}"
        else:
            where, label = f"{what} on the scenario of {s.file}", key
        setattr(owner, name, schema.convert_field(type(owner), name, value, where, label))
        s._overrides.append(f"{key}={text}")
    check_scenario(s)
    return s


def _pairs(items: Iterable[str] | Mapping[str, Any], what: str) -> list[tuple[str, Any, str]]:
    """(key, value, the value as TOML text) of each override."""
    if isinstance(items, Mapping):
        return [(str(key).strip(), plain(value), toml_value(value)) for key, value in items.items()]
    if isinstance(items, str):
        items = [items]
    out = []
    for item in items:
        key, sep, text = item.partition("=")
        key, text = key.strip(), text.strip()
        if not sep or not key or not text:
            raise ScenarioError(f"{what} {item!r}: write KEY=VALUE, e.g. mooring_lines.model=quasi_static")
        out.append((key, toml_scalar(text, f"{what} {item}"), text))
    return out


def plain(value: Any) -> Any:
    """numpy scalars and arrays as Python numbers and lists (what the schema converts)."""
    if hasattr(value, "tolist") and callable(value.tolist):
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    return value


def toml_value(value: Any) -> str:
    """A Python value (number, string, boolean, list of them) written as a TOML value."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        v = float(value)
        if isinstance(value, float) or math.isinf(v) or math.isnan(v):
            return "nan" if math.isnan(v) else ("inf" if v == math.inf else "-inf" if math.isinf(v) else repr(v))
        return str(int(value))
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if hasattr(value, "tolist") and callable(value.tolist):  # numpy scalars and arrays
        return toml_value(value.tolist())
    raise ScenarioError(f"cannot write {value!r} ({type(value).__name__}) as a scenario value: give a number, a "
                        "string, true/false or a list of them")
