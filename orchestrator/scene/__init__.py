"""Scene stage: a scenario resolved against its hydrodynamic database.

Modules: :mod:`.database` (read or compute the database, match it to the scenario's bodies, environment and
wave range, A_inf fits), :mod:`.fit_cache` (the slow fits kept on disk), :mod:`.scene` (:class:`Scene`: the
FMUs' specifications, connections, the physics objects the reference solvers use), :mod:`.equilibrium`
(static equilibrium of the scene's multibody model), :mod:`.still` (coordinates that cannot move: no state-space
memory for them).

May import: :mod:`orchestrator.scenario`, :mod:`orchestrator.errors`, :mod:`orchestrator.progress`,
:mod:`hydro_fmu`, :mod:`mbd_fmu`, :mod:`fmu_base`.
"""

from .database import load_database
from .scene import HYDRO, MBD, Connection, Scene, load_scene

__all__ = ["HYDRO", "MBD", "Connection", "Scene", "load_database", "load_scene"]
