"""Linear hydrostatic restoring force about the equilibrium position.

    F_hs = - C x,

with C the block-diagonal matrix of the bodies' restoring matrices (database convention: about
each body's centre of gravity, buoyancy only, see :mod:`hydro_fmu.hdb`) and x the displacement
from equilibrium. The constant parts (weight and mean buoyancy) balance at equilibrium and are
left out.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import block_diag

from .hdb import HydroDatabase


class LinearHydrostatics:
    """Restoring force on the selected degrees of freedom (indices into the 6N numbering)."""

    def __init__(self, hdb: HydroDatabase, dofs: np.ndarray) -> None:
        full = block_diag(*hdb.hydrostatic_stiffness)
        self.stiffness = full[np.ix_(dofs, dofs)]

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Force (N, N m) for displacement ``x`` (m, rad)."""
        return -self.stiffness @ x
