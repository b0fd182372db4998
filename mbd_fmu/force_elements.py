"""Force elements acting on the bodies' degrees of freedom."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class LinearPTO:
    """Linear power take-off between one degree of freedom of a body and the ground.

    Force on the body ``F = -k x - c v + u`` (N or N m) for displacement ``x`` and velocity ``v``
    of that degree of freedom and a commanded force ``u``; absorbed power ``P = -F v`` (W). With
    ``u = 0`` the mean over a period is ``c <v^2>`` since the spring part averages to zero.
    ``k``, ``c`` and ``u`` are the controllable part: a controller changes them between steps.

    Attributes:
        name: identifier (FMI variable prefix).
        body: name of the body.
        dof: 0 = surge ... 5 = yaw.
        stiffness: k, N/m or N m/rad.
        damping: c, N s/m or N m s/rad.
    """

    name: str
    body: str
    dof: int
    stiffness: float = 0.0
    damping: float = 0.0
    force_command: float = 0.0

    def force(self, x: float, v: float) -> float:
        return -self.stiffness * x - self.damping * v + self.force_command

    def power(self, x: float, v: float) -> float:
        return -self.force(x, v) * v
