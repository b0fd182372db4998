"""Shared fixtures: bundled scenarios, a private FMU cache per test session."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SCENARIOS = ROOT / "scenarios"


@pytest.fixture(scope="session", autouse=True)
def private_fmu_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """FMUs built by the tests go to a temporary cache, not the user's. The compiled multibody kernels stay in the
    numba cache this process already uses (``WEC_COSIM_NUMBA_CACHE``, fmu_base/_jit.py), so the FMUs and host
    processes the tests start load them instead of each compiling them again (minutes of CPU on a fresh clone)."""
    from fmu_base._jit import cache_root

    path = tmp_path_factory.mktemp("fmu_cache")
    saved = {key: os.environ.get(key) for key in ("WEC_COSIM_CACHE", "WEC_COSIM_NUMBA_CACHE")}
    os.environ["WEC_COSIM_NUMBA_CACHE"] = str(cache_root())
    os.environ["WEC_COSIM_CACHE"] = str(path)
    yield path
    for key, old in saved.items():
        if old is None:
            os.environ.pop(key, None)
        else:
            os.environ[key] = old


@pytest.fixture(scope="session")
def cylinder_scenario_path() -> Path:
    return SCENARIOS / "cylinder_regular.toml"


@pytest.fixture(scope="session")
def disc_scenario_path() -> Path:
    return SCENARIOS / "disc_decay.toml"
