"""Time integrators on the configuration space (R^3 x SO(3))^N, one interface, several methods.

* :class:`GeneralizedAlphaCoefficients` - Chung & Hulbert (1993) generalised-alpha parameters
  from the user's spectral radius at infinite frequency ``rho_inf`` in [0, 1]:
  ``alpha_m = (2 rho - 1)/(rho + 1)``, ``alpha_f = rho/(rho + 1)``, ``gamma = 1/2 + alpha_f - alpha_m``,
  ``beta = (gamma + 1/2)^2 / 4``. Second order for any ``rho_inf``; unconditionally stable for
  linear problems; ``rho_inf = 1`` is the trapezoidal rule (no numerical dissipation, quadratic
  invariants of linear systems conserved), smaller values damp the unresolved high frequencies
  (``rho_inf = 0``: asymptotic annihilation). Used by the index-3 formulation in its Lie group
  form (Bruls, Cardona & Arnold 2012): ``q_{n+1} = q_n (+) h (v_n + h (1/2 - beta) a_n + h beta a_{n+1})``.
* :class:`ButcherTableau` / :func:`rkmk_step` - explicit Runge-Kutta methods in the
  Runge-Kutta-Munthe-Kaas form: stages in local coordinates ``R = exp(S(theta)) R_n`` with
  ``theta' = J_l(theta)^-1 w``, so the classical order is kept on SO(3). ``rk4`` (order 4),
  ``heun`` (order 2), ``euler`` (order 1); stability: the explicit methods' regions (RK4 reaches
  ``h lambda`` down to -2.79 on the real axis and up to 2.83 on the imaginary axis), so stiff force
  elements need small steps.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .kinematics import Pose
from .rotations import left_jacobian_inverse


@dataclass(frozen=True)
class GeneralizedAlphaCoefficients:
    """Generalised-alpha parameters (module docstring)."""

    rho_inf: float

    def __post_init__(self) -> None:
        if not 0.0 <= self.rho_inf <= 1.0:
            raise ValueError(f"spectral radius must be in [0, 1] (got {self.rho_inf})")

    @property
    def alpha_m(self) -> float:
        return (2 * self.rho_inf - 1) / (self.rho_inf + 1)

    @property
    def alpha_f(self) -> float:
        return self.rho_inf / (self.rho_inf + 1)

    @property
    def gamma(self) -> float:
        return 0.5 + self.alpha_f - self.alpha_m

    @property
    def beta(self) -> float:
        return 0.25 * (self.gamma + 0.5) ** 2


@dataclass(frozen=True)
class ButcherTableau:
    """Explicit Runge-Kutta method: ``a`` (s, s) strictly lower triangular, ``b``, ``c``, order."""

    a: tuple[tuple[float, ...], ...]
    b: tuple[float, ...]
    c: tuple[float, ...]
    order: int


TABLEAUS = {
    "rk4": ButcherTableau(((0, 0, 0, 0), (0.5, 0, 0, 0), (0, 0.5, 0, 0), (0, 0, 1, 0)),
                          (1 / 6, 1 / 3, 1 / 3, 1 / 6), (0, 0.5, 0.5, 1), 4),
    "heun": ButcherTableau(((0, 0), (1, 0)), (0.5, 0.5), (0, 1), 2),
    "euler": ButcherTableau(((0,),), (1.0,), (0,), 1),
}

Rates = Callable[[Pose, np.ndarray, float], tuple[np.ndarray, np.ndarray]]


def _local_rate(theta_full: np.ndarray, w_full: np.ndarray) -> np.ndarray:
    """Local-coordinate rate: translations as they are, rotations ``J_l(theta)^-1 w`` per body."""
    n = len(theta_full) // 6
    th = theta_full.reshape(n, 6)
    w = w_full.reshape(n, 6)
    out = w.copy()
    out[:, 3:] = np.einsum("kab,kb->ka", left_jacobian_inverse(th[:, 3:]), w[:, 3:])
    return out.reshape(-1)


def rkmk_step(tab: ButcherTableau, pose: Pose, y: np.ndarray, t: float, h: float, rates: Rates,
              to_full: Callable[[np.ndarray], np.ndarray]) -> tuple[Pose, np.ndarray, np.ndarray]:
    """One explicit RKMK step of ``(q, y)`` with ``rates(pose, y, t) -> (velocity slots, y')``.

    Returns the new pose, the new ``y`` and the last stage's slot velocity.
    """
    s = len(tab.b)
    size = 6 * (len(pose.r) + 1)
    kq: list[np.ndarray] = []
    ky: list[np.ndarray] = []
    w = np.zeros(0)
    for j in range(s):
        theta = np.zeros(size)
        yj = y.copy()
        for l in range(j):
            if tab.a[j][l]:
                theta += h * tab.a[j][l] * kq[l]
                yj += h * tab.a[j][l] * ky[l]
        pose_j = pose.retract(theta) if j else pose
        w, yd = rates(pose_j, yj, t + tab.c[j] * h)
        kq.append(_local_rate(theta, to_full(w)))
        ky.append(yd)
    theta = h * sum(tab.b[l] * kq[l] for l in range(s))
    y_new = y + h * sum(tab.b[l] * ky[l] for l in range(s))
    return pose.retract(theta), y_new, w
