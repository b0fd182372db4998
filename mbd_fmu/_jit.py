"""Moved to :mod:`fmu_base._jit` (shared by every FMU package); kept so that ``from ._jit import njit`` still works."""

from fmu_base._jit import AVAILABLE, cache_root, njit  # noqa: F401
