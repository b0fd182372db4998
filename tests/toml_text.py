"""A small TOML writer for tests that derive scenario files from the bundled ones (tomllib only reads)."""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path
from typing import Any

from .conftest import SCENARIOS


def value(v: Any) -> str:
    """One TOML value (inline tables and arrays nested as needed)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return json.dumps(v)  # a JSON string is a valid TOML basic string
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k)} = {value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(value(x) for x in v) + "]"
    raise TypeError(f"no TOML for {type(v).__name__}")


def _key(k: str) -> str:
    return k if k and all(c.isalnum() or c in "_-" for c in k) else json.dumps(k)


def dumps(data: dict[str, Any]) -> str:
    """TOML text of a table: plain keys first, then sub-tables, then arrays of tables."""
    return "\n".join(_table(data, ())) + "\n"


def _table(data: dict[str, Any], path: tuple[str, ...]) -> list[str]:
    lines = []
    subs, arrays = [], []
    for k, v in data.items():
        if isinstance(v, dict):
            subs.append((k, v))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            arrays.append((k, v))
        else:
            lines.append(f"{_key(k)} = {value(v)}")
    for k, v in subs:
        name = ".".join(_key(p) for p in path + (k,))
        lines += ["", f"[{name}]"] + _table(v, path + (k,))
    for k, items in arrays:
        name = ".".join(_key(p) for p in path + (k,))
        for item in items:
            lines += ["", f"[[{name}]]"] + _table(item, path + (k,))
    return lines


def bundled(name: str) -> dict[str, Any]:
    """A bundled scenario as a dict, its hydro cache made absolute (so the copy can live anywhere)."""
    data = tomllib.loads((SCENARIOS / f"{name}.toml").read_text())
    data.setdefault("hydro", {})["cache_dir"] = str(SCENARIOS / "hydro_cache")
    if data["hydro"].get("database"):
        data["hydro"]["database"] = str(SCENARIOS / data["hydro"]["database"])
    return data


def write(path: Path, data: dict[str, Any]) -> Path:
    path.write_text(dumps(data))
    return path
