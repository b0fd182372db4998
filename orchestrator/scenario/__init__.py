"""Input stage: scenario files (TOML), their schema, sections, checks and keys named by path.

Modules: :mod:`.schema` (typed loading of TOML tables into dataclasses, errors that name file and key),
the sections (:mod:`.run_sections`, :mod:`.sea_sections`, :mod:`.body_sections`, :mod:`.multibody_sections`),
:mod:`.scenario` (the whole document), :mod:`.checks` (checks across keys), :mod:`.input_checks` (what the
machine can take: sizes, files, output paths), :mod:`.loading` (file -> checked :class:`Scenario`),
:mod:`.keys` and :mod:`.overrides` (``--set KEY=VALUE``, also the key rule of sweep grids),
:mod:`.reference_doc` (``docs/scenario.md``, ``python -m orchestrator.scenario``).

May import: :mod:`orchestrator.errors`, :mod:`orchestrator.control` (the run-id rule of the wire protocol),
:mod:`hydro_fmu`, :mod:`mbd_fmu`. Nothing here reads a hydrodynamic database or builds an FMU.
"""

from .body_sections import DOFS
from .loading import load_scenario, parse_scenario
from .overrides import apply_overrides
from .scenario import Scenario

__all__ = ["DOFS", "Scenario", "apply_overrides", "load_scenario", "parse_scenario"]
