"""The scenario reference page (``docs/scenario.md``), generated from the schema: ``python -m
orchestrator.scenario > docs/scenario.md``."""

from __future__ import annotations

from . import schema
from .scenario import Scenario


def reference_markdown() -> str:
    """The scenario reference page (``docs/scenario.md``), generated from the schema."""
    head = [
        "# Scenario file reference",
        "",
        "Generated from `orchestrator/scenario/` by `python -m orchestrator.scenario > docs/scenario.md`;",
        "a test checks that this page matches the code. Units are SI except where a key says `_deg`.",
        "Paths are relative to the scenario file. Unknown keys, wrong types, non-finite numbers and",
        "out-of-range values are errors that name the file and the key.",
        "",
    ]
    return "\n".join(head + schema.document(Scenario, "scenario")) + "\n"
