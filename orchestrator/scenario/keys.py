"""Scenario keys named by path, as ``--set`` and sweep grids name them: ``section.key``, ``section.sub.key``
and ``<list>.<name>.key`` for named items (``ptos.pto.damping``, ``bodies.float.geometry.radius``); values
read as TOML scalars."""

from __future__ import annotations

import dataclasses
import functools
import tomllib
import types
import typing
from typing import Any

from orchestrator.errors import ScenarioError

from .scenario import Scenario

SCALARS = (float, int, str, bool)


def resolve_key(scenario: Scenario, path: str, what: str = "sweep.grid", lists: bool = False) -> tuple[Any, str]:
    """The dataclass holding key ``path`` and the field's name; lists of named items by name
    (``ptos.<name>.damping``, ``bodies.<name>.geometry.radius``); ``what`` names the setting in errors.
    ``lists``: also accept keys holding a list of numbers or strings (``bodies.<name>.dofs``: ``--set`` takes a
    whole TOML array; sweep grids keep their own rule)."""
    parts = path.split(".")
    target: Any = scenario
    i = 0
    try:
        while i < len(parts) - 1:
            value = getattr(target, parts[i]) if not parts[i].startswith("_") else None
            if isinstance(value, list) and value and dataclasses.is_dataclass(value[0]):
                target = next(x for x in value if getattr(x, "name", None) == parts[i + 1])
                i += 2
            elif dataclasses.is_dataclass(value):
                target, i = value, i + 1
            else:
                raise AttributeError(path)
        name = parts[-1]
        if i != len(parts) - 1 or not dataclasses.is_dataclass(target):
            raise AttributeError(path)
        if name not in {f.name for f in dataclasses.fields(target) if f.init and not f.name.startswith("_")}:
            raise KeyError(name)
    except (AttributeError, StopIteration, KeyError):
        raise ScenarioError(
            f"{scenario.file}: {what}: {path!r} names no key of this scenario; use `section.key` (e.g. "
            "`waves.hs`) or `<list>.<name>.key` for named items (e.g. `ptos.pto.damping`, `bodies.float.mass`)"
        ) from None
    hint = _scalar_type(target, name) or (_scalar_list_type(target, name) if lists else None)
    if hint is None or name == "name":
        kinds = "a single number, string or boolean, or a list of them" if lists else \
            "a single number, string or boolean"
        raise ScenarioError(f"{scenario.file}: {what}: {path!r} is not {kinds} and cannot be set")
    return target, name


@functools.cache
def _type_hints(cls: type) -> dict[str, Any]:
    """The resolved field types of a scenario dataclass (fixed for the class: computed once; a sweep of ten
    thousand cases resolved them twice per case)."""
    return typing.get_type_hints(cls)


def _scalar_type(owner: Any, name: str) -> type | None:
    hint = _type_hints(type(owner))[name]
    inner = [a for a in typing.get_args(hint) if a is not type(None)] if typing.get_origin(hint) else [hint]
    return inner[0] if len(inner) == 1 and inner[0] in SCALARS else None


def _scalar_list_type(owner: Any, name: str) -> type | None:
    """The element type of a ``list[float]``-like field (optional or not), else None."""
    hint = _type_hints(type(owner))[name]
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        inner = [a for a in typing.get_args(hint) if a is not type(None)]
        hint = inner[0] if len(inner) == 1 else hint
    args = typing.get_args(hint)
    return args[0] if typing.get_origin(hint) is list and len(args) == 1 and args[0] in SCALARS else None




def toml_scalar(value: str, text: str) -> Any:
    try:
        return tomllib.loads(f"v = {value}")["v"]
    except tomllib.TOMLDecodeError:
        if value and all(c.isalnum() or c in "_-" for c in value):
            return value  # a bare word: a string choice such as jacobi
        raise ScenarioError(f"{text!r}: cannot read the value {value!r}") from None


