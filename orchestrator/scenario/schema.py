"""Typed loading of TOML tables into dataclasses, with errors that name the file and key path.

Each scenario section is a dataclass whose fields carry their unit, documentation and checks in
``field(metadata=...)`` (built with :func:`option`). :func:`load` walks a parsed TOML table,
rejects unknown keys (suggesting the closest known one), converts and checks every value, and
raises :class:`~orchestrator.errors.ScenarioError` naming the file, the key path and what was
expected. :func:`document` renders the same metadata as the Markdown reference in ``docs/``, so
the documentation cannot drift from the code.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import types
import typing
from collections.abc import Callable
from typing import Any

from orchestrator.errors import ScenarioError

Check = Callable[[Any], str | None]
MISSING = dataclasses.MISSING


def option(
    default: Any = MISSING,
    *,
    unit: str = "",
    doc: str = "",
    check: Check | None = None,
    choices: tuple[str, ...] | None = None,
    allow_inf: bool = False,
    factory: Callable[[], Any] | None = None,
) -> Any:
    """A dataclass field with its unit, documentation and validation."""
    metadata = {"unit": unit, "doc": doc, "check": check, "choices": choices, "allow_inf": allow_inf}
    if factory is not None:
        return dataclasses.field(default_factory=factory, metadata=metadata)
    return dataclasses.field(default=default, metadata=metadata)


def positive(value: Any) -> str | None:
    return None if _all(value, lambda v: v > 0) else "must be positive"


def non_negative(value: Any) -> str | None:
    return None if _all(value, lambda v: v >= 0) else "must not be negative"


def at_least_one(value: float) -> str | None:
    return None if value >= 1 else "must be at least 1"


def fraction(value: float) -> str | None:
    return None if 0 < value < 1 else "must be between 0 and 1"


def identifier(value: str) -> str | None:
    ok = value.isidentifier() and value.isascii()
    return None if ok else "must be a name of letters, digits and underscores, not starting with a digit"


def _all(value: Any, test: Callable[[float], bool]) -> bool:
    values = value if isinstance(value, (list, tuple)) else [value]
    return all(test(v) for v in values if v is not None)


def load(cls: type, data: Any, file: str, path: str = "") -> Any:
    """Build dataclass ``cls`` from the TOML table ``data``; ``path`` is the key path so far."""
    where = f"[{path}]" if path else "the top level"
    if not isinstance(data, dict):
        raise ScenarioError(f"{file}: {path or 'scenario'}: expected a table, got {_show(data)}")
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init and not f.name.startswith("_")}
    for key in data:
        if key not in fields:
            close = difflib.get_close_matches(key, fields, n=1)
            hint = f" Did you mean {close[0]!r}?" if close else ""
            raise ScenarioError(
                f"{file}: unknown key {_join(path, key)!r} in {where}.{hint} "
                f"Allowed keys: {', '.join(sorted(fields))}."
            )
    values = {}
    for name, f in fields.items():
        key_path = _join(path, name)
        if name not in data:
            if f.default is MISSING and f.default_factory is MISSING:
                raise ScenarioError(f"{file}: missing required key {key_path!r} ({_describe(hints[name], f)})")
            continue
        value = _convert(hints[name], data[name], file, key_path, f)
        problem = f.metadata.get("check") and f.metadata["check"](value)
        if problem:
            raise ScenarioError(f"{file}: {key_path} {problem} (got {_show(data[name])})")
        values[name] = value
    return cls(**values)


def convert_field(cls: type, name: str, value: Any, file: str, path: str) -> Any:
    """``value`` converted and checked as field ``name`` of dataclass ``cls`` would be when loaded
    (errors name ``file`` and the key ``path``)."""
    f = {f.name: f for f in dataclasses.fields(cls)}[name]
    converted = _convert(typing.get_type_hints(cls)[name], value, file, path, f)
    problem = f.metadata.get("check") and f.metadata["check"](converted)
    if problem:
        raise ScenarioError(f"{file}: {path} {problem} (got {_show(value)})")
    return converted


def _convert(tp: Any, value: Any, file: str, path: str, f: dataclasses.Field | None) -> Any:
    origin = typing.get_origin(tp)
    args = typing.get_args(tp)
    if origin in (typing.Union, types.UnionType):
        inner = [a for a in args if a is not type(None)]
        return _convert(inner[0], value, file, path, f)
    if dataclasses.is_dataclass(tp):
        return load(tp, value, file, path)
    if origin is dict:  # a free-form table, checked by its owner
        if not isinstance(value, dict):
            raise ScenarioError(f"{file}: {path}: expected a table, got {_show(value)}")
        return value
    if origin in (list, tuple):
        if not isinstance(value, list):
            raise ScenarioError(f"{file}: {path}: expected an array ({_describe(tp, f)}), got {_show(value)}")
        if origin is tuple and args and args[-1] is not Ellipsis:
            if len(value) != len(args):
                raise ScenarioError(f"{file}: {path}: expected {len(args)} values, got {len(value)}")
            pairs = enumerate(zip(args, value, strict=True))
            return tuple(_convert(a, v, file, f"{path}[{i}]", f) for i, (a, v) in pairs)
        item = args[0] if args else Any
        converted = [_convert(item, v, file, f"{path}[{i}]", f) for i, v in enumerate(value)]
        return tuple(converted) if origin is tuple else converted
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ScenarioError(f"{file}: {path}: expected a number, got {_show(value)}")
        value = float(value)
        allow_inf = bool(f and f.metadata.get("allow_inf"))
        if math.isnan(value) or (math.isinf(value) and not (allow_inf and value > 0)):
            raise ScenarioError(f"{file}: {path}: expected a finite number, got {value}")
        return value
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ScenarioError(f"{file}: {path}: expected an integer, got {_show(value)}")
        return value
    if tp is bool:
        if not isinstance(value, bool):
            raise ScenarioError(f"{file}: {path}: expected true or false, got {_show(value)}")
        return value
    if tp is str:
        if not isinstance(value, str):
            raise ScenarioError(f"{file}: {path}: expected a string, got {_show(value)}")
        choices = f.metadata.get("choices") if f else None
        if choices and value not in choices:
            raise ScenarioError(
                f"{file}: {path}: {value!r} is not one of {', '.join(repr(c) for c in choices)}")
        return value
    return value


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def _show(value: Any) -> str:
    kind = {dict: "a table", list: "an array", str: "a string", bool: "a boolean"}.get(type(value))
    return f"{kind} {value!r}" if kind and not isinstance(value, dict) else (kind or repr(value))


def _describe(tp: Any, f: dataclasses.Field | None) -> str:
    """Short human description of a field's type, unit and choices."""
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if origin in (typing.Union, types.UnionType):
        return _describe([a for a in args if a is not type(None)][0], f)
    if dataclasses.is_dataclass(tp) or origin is dict:
        return "table"
    if origin in (list, tuple):
        if origin is tuple and args and args[-1] is not Ellipsis:
            return f"array of {len(args)} {_describe(args[0], None)}s"
        inner = args[0] if args else Any
        return f"array of {'tables' if dataclasses.is_dataclass(inner) else _describe(inner, None) + 's'}"
    name = {float: "number", int: "integer", bool: "boolean", str: "string"}.get(tp, "value")
    if f is not None and f.metadata.get("choices"):
        name += " (" + " | ".join(f.metadata["choices"]) + ")"
    return name


def document(cls: type, title: str, path: str = "", array: bool = False, defaults: Any = None) -> list[str]:
    """Markdown reference of ``cls``: one table per section, nested sections after."""
    hints = typing.get_type_hints(cls)
    header = f"[[{path}]]" if array else (f"[{path}]" if path else "top level")
    lines = [f"### `{header}` - {title}", "", (cls.__doc__ or "").strip().split("\n\n")[0], "",
             "| key | type | unit | default | meaning |", "|---|---|---|---|---|"]
    nested = []
    for f in dataclasses.fields(cls):
        if not f.init or f.name.startswith("_"):
            continue
        tp = hints[f.name]
        inner = [a for a in typing.get_args(tp) if a is not type(None)] if typing.get_origin(tp) in (
            typing.Union, types.UnionType) else [tp]
        base = inner[0]
        if dataclasses.is_dataclass(base):
            default = f.default_factory() if f.default_factory is not MISSING else None
            nested.append((base, _join(path, f.name), False, default))
            continue
        if typing.get_origin(base) is list and dataclasses.is_dataclass(typing.get_args(base)[0]):
            nested.append((typing.get_args(base)[0], _join(path, f.name), True, None))
            continue
        if f.default is not MISSING:
            default = _toml_value(f.default)
        elif f.default_factory is not MISSING:
            default = _toml_value(f.default_factory())
        elif defaults is not None:  # a section with a default value: its fields have one too
            default = _toml_value(getattr(defaults, f.name)) + " (section default)"
        else:
            default = "**required**"
        doc = f.metadata.get("doc", "").replace("|", "\\|").replace("\n", " ")
        kind = _describe(tp, f).replace("|", "\\|")  # choices are listed with '|', a table separator
        lines.append(f"| `{f.name}` | {kind} | {f.metadata.get('unit', '') or ''} | {default} | {doc} |")
    lines.append("")
    for sub, sub_path, is_array, sub_defaults in nested:
        lines += document(sub, (sub.__doc__ or sub.__name__).strip().split("\n")[0].rstrip("."), sub_path, is_array,
                          sub_defaults)
    return lines


def _toml_value(value: Any) -> str:
    if value is None:
        return "(none)"
    if isinstance(value, bool):
        return f"`{str(value).lower()}`"
    if isinstance(value, str):
        return f'`"{value}"`' if value else '`""`'
    if isinstance(value, float) and math.isinf(value):
        return "`inf`" if value > 0 else "`-inf`"
    if isinstance(value, (list, tuple)):
        return "`[" + ", ".join(_toml_value(v).strip("`") for v in value) + "]`"
    if isinstance(value, dict):
        return "`{" + ", ".join(f"{k} = {_toml_value(v).strip('`')}" for k, v in value.items()) + "}`"
    return f"`{value}`"
