"""``python -m orchestrator.scenario > docs/scenario.md``: print the scenario reference page."""

from .reference_doc import reference_markdown

print(reference_markdown(), end="")
