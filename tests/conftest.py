"""Shared fixtures: bundled scenarios, a private FMU cache per test session."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SCENARIOS = ROOT / "scenarios"


@pytest.fixture(scope="session", autouse=True)
def private_fmu_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """FMUs built by the tests go to a temporary cache, not the user's."""
    path = tmp_path_factory.mktemp("fmu_cache")
    old = os.environ.get("WEC_COSIM_CACHE")
    os.environ["WEC_COSIM_CACHE"] = str(path)
    yield path
    if old is None:
        os.environ.pop("WEC_COSIM_CACHE", None)
    else:
        os.environ["WEC_COSIM_CACHE"] = old


@pytest.fixture(scope="session")
def cylinder_scenario_path() -> Path:
    return SCENARIOS / "cylinder_regular.toml"


@pytest.fixture(scope="session")
def disc_scenario_path() -> Path:
    return SCENARIOS / "disc_decay.toml"
