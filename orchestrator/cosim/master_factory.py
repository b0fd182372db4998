"""A master by its scenario name (``simulation.master``): the explicit masters of :mod:`.masters` and the
iterative one of :mod:`.iterative_master`."""

from __future__ import annotations

from orchestrator.scene import Connection

from .iterative_master import IterativeMaster
from .masters import AddedMassForce, GaussSeidelMaster, JacobiMaster, Master, MasterSettings, SimpleJacobiMaster

MASTERS = {"jacobi": JacobiMaster, "gauss_seidel": GaussSeidelMaster}


def make_master(kind: str, components: dict, connections: list[Connection], settings: MasterSettings,
                observe: dict[str, list[str]] | None = None, added_mass: AddedMassForce | None = None,
                parameters: dict[str, dict[str, float]] | None = None) -> Master:
    """A master by scenario name: jacobi, gauss_seidel, aitken, iqn_ils, simple_jacobi; ``parameters``: values
    set in every initialisation (e.g. A_inf = 0 in the multibody FMU for added-mass mode b)."""
    if kind in ("aitken", "iqn_ils"):
        return IterativeMaster(components, connections, observe=observe, settings=settings,
                               added_mass=added_mass, solver=kind, parameters=parameters)
    if kind == "simple_jacobi":
        return SimpleJacobiMaster(components, connections, observe=observe, settings=settings, parameters=parameters)
    if kind not in MASTERS:
        raise ValueError(f"unknown master {kind!r}")
    return MASTERS[kind](components, connections, observe=observe, settings=settings, added_mass=added_mass,
                         parameters=parameters)
