"""Scenario keys set from the command line: ``wec-cosim run --set KEY=VALUE`` (and ``resume``, which applies
the overrides a results file recorded). Keys are named as in a sweep grid (``section.key``,
``<list>.<name>.key``: :func:`wec_cosim.sweeps.grid.resolve_key`); values are read as TOML values and converted and
checked by the scenario schema, so an override gets the same errors as the same key in the file. A key that
holds a list takes a whole TOML array (``--set 'bodies.float.dofs=["heave", "pitch"]'``)."""

from __future__ import annotations

import copy

from orchestrator.errors import ScenarioError

from . import schema
from .checks import check_scenario
from .keys import resolve_key, toml_scalar
from .scenario import Scenario


def apply_overrides(scenario: Scenario, items: list[str]) -> Scenario:
    """A copy of ``scenario`` with each ``KEY=VALUE`` of ``items`` set and every check run again; the items are
    recorded in ``_overrides`` so that results files (and ``wec-cosim resume``) know the scene that ran."""
    if not items:
        return scenario
    s = copy.deepcopy(scenario)
    for item in items:
        key, sep, text = item.partition("=")
        key, text = key.strip(), text.strip()
        if not sep or not key or not text:
            raise ScenarioError(f"--set {item!r}: write KEY=VALUE, e.g. mooring_lines.model=quasi_static")
        owner, name = resolve_key(s, key, what="--set", lists=True)
        value = schema.convert_field(type(owner), name, toml_scalar(text, f"--set {item}"), str(s.file),
                                     f"--set {key}")
        setattr(owner, name, value)
        s._overrides.append(f"{key}={text}")
    check_scenario(s)
    return s
