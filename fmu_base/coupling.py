"""Variables of the linearised force interface, shared by the hydro FMU (outputs) and the multibody
FMU (inputs of the same names): the affine model

    F(t, x, v) ~= F0 + F0_rate (t - t_n) + dF_dx x + dF_dv v

of the hydrodynamic force over the next communication step (``hydro_fmu.linearisation``).

* ``<b>.F0[i]``, ``<b>.F0_rate[i]`` per hydrodynamic degree of freedom (body ``b``, DOF ``i``
  1 surge ... 6 yaw);
* ``dF_dx[k,l]``, ``dF_dv[k,l]`` for the entries of the coupling pattern only, ``k, l`` the scene's
  hydrodynamic DOF numbers (as for ``A_inf[k,l]``): force on DOF k per displacement or velocity of
  DOF l.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

FORCE = ("N", "N.m")
RATE = ("N/s", "N.m/s")
# [force is a moment][motion is a rotation]
STIFFNESS = (("N/m", "N/rad"), ("N", "N.m/rad"))
DAMPING = (("N.s/m", "N.s/rad"), ("N.s", "N.m.s/rad"))


@dataclass(frozen=True)
class CouplingVariables:
    """Names and units of one group of interface variables (array key, names, units, description)."""

    key: str
    names: list[str]
    units: list[str]
    description: str


def coupling_variables(coordinates: Sequence[tuple[str, int]], labels: Sequence[int],
                       stiffness: Sequence[Sequence[int]], damping: Sequence[Sequence[int]]) -> list[CouplingVariables]:
    """The four groups for hydrodynamic ``coordinates`` ((body, dof 0-5) per selected DOF), their scene DOF
    numbers ``labels`` (1-based) and the pattern's (row, column) positions of dF_dx and dF_dv."""
    rot = [d >= 3 for _, d in coordinates]

    def matrix(prefix: str, pairs: Sequence[Sequence[int]], table) -> tuple[list[str], list[str]]:
        names = [f"{prefix}[{labels[i]},{labels[j]}]" for i, j in pairs]
        return names, [table[rot[i]][rot[j]] for i, j in pairs]

    kx, ux = matrix("dF_dx", stiffness, STIFFNESS)
    kv, uv = matrix("dF_dv", damping, DAMPING)
    return [
        CouplingVariables("F0", [f"{b}.F0[{d + 1}]" for b, d in coordinates], [FORCE[r] for r in rot],
                          "linearised force: value at zero displacement and velocity (F - dF_dx x - dF_dv v)"),
        CouplingVariables("F0_rate", [f"{b}.F0_rate[{d + 1}]" for b, d in coordinates], [RATE[r] for r in rot],
                          "linearised force: time rate of F0 over the next step"),
        CouplingVariables("dF_dx", kx, ux, "linearised force: derivative with respect to the displacement"),
        CouplingVariables("dF_dv", kv, uv, "linearised force: derivative with respect to the velocity"),
    ]
