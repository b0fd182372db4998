"""Force elements acting on the bodies.

:class:`LinearPTO` is the small-motion PTO of the linear model (a body DOF to the ground). The
nonlinear models use :class:`ForceElement` subclasses, which add their generalised force into
a full slot vector (six world-frame slots per body: force at the cg, moment about the cg) and
report their energy terms:

* :class:`CoordinateSpringDamper` - ``F = -k (q - q0) - c q' + u`` on any scalar coordinate
  (:mod:`mbd_fmu.coordinates`): point-to-point spring-dampers (distance), rotary spring-dampers
  (joint angle), penalty/bushing components (relative translations and rotations of two frames,
  seed 000's relative pitch and yaw PTO), and the controllable PTOs (``k``, ``c``, ``u`` are
  changed between steps by :meth:`set_command`), optionally with a nonlinear law
  (:class:`PtoLaw`: Coulomb friction, quadratic damping, force saturation);
* :class:`Rope` - tension-only spring-damper on a distance;
* :class:`CoulombFriction` - regularised Coulomb friction ``F = -F_c tanh(q'/v_reg)`` on a
  joint coordinate (constant friction force or torque magnitude ``F_c``).

Energy bookkeeping: ``potential`` is the stored energy, ``dissipation`` the power dissipated
(>= 0) and ``supply`` the power put in by commanded forces, so that along any motion
``d/dt potential = -(power of the element on the bodies) - dissipation + supply``... more
precisely ``P_bodies = -dV/dt - dissipation + supply`` where ``P_bodies = F q'``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .coordinates import Coordinate
from .kinematics import Kin
from .rotations import log_so3


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


class ForceElement:
    """Base class of the nonlinear models' force elements (see the module docstring)."""

    name: str
    nonlinear = False  # force not linear in the coordinates and rates (the pseudo-spectral solver evaluates it)

    def apply(self, k: Kin, f: np.ndarray) -> None:  # pragma: no cover - abstract
        """Add the generalised force into the full slot vector ``f`` (6 (N + 1))."""
        raise NotImplementedError

    def tangent(self, k: Kin) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """Approximate ``(cols, K, D)``: -df/dq and -df/dv over slot columns ``cols`` (for Newton)."""
        return None

    def potential(self, k: Kin) -> float:
        return 0.0

    def dissipation(self, k: Kin) -> float:
        return 0.0

    def supply(self, k: Kin) -> float:
        return 0.0

    def powers(self, k: Kin) -> tuple[float, float]:
        """``(dissipation, supply)`` (W) in one evaluation where the element can share the work."""
        return self.dissipation(k), self.supply(k)

    def output(self, k: Kin) -> np.ndarray:
        """Force components reported as FMU outputs."""
        return np.zeros(0)

    def start(self, k: Kin) -> None:
        """Once, at the assembled initial state, before the first force evaluation (elements with
        their own dynamics, e.g. MoorDyn lines, set up their initial state here)."""

    def commit(self, k: Kin) -> None:
        """After an accepted step."""


@dataclass(frozen=True)
class PtoLaw:
    """Nonlinear additions to a PTO's linear law ``g = -k x - c v + u`` (x from neutral, v the rate):

        g_nl = g - F_c tanh(v / v_s) - c_q |v| v,      F = F_max tanh(g_nl / F_max)  (if F_max > 0),

    ``F_c`` a regularised Coulomb friction force (N or N m; ``v_s`` its velocity scale, m/s or
    rad/s), ``c_q`` a quadratic damping (N s^2/m^2; with ``F_c`` a hydraulic-like PTO: a constant
    pressure difference plus orifice losses), ``F_max`` a smooth saturation (N or N m; 0 = none).
    All parameters zero: the linear law. ``force`` and ``derivatives`` are scalar functions,
    shared by the time-domain element and the pseudo-spectral solver.
    """

    friction: float = 0.0
    quadratic: float = 0.0
    force_limit: float = 0.0
    velocity_scale: float = 0.01

    @property
    def nonlinear(self) -> bool:
        return bool(self.friction or self.quadratic or self.force_limit)

    def _unsaturated(self, linear, v):
        """``g``: the linear law's value plus friction and quadratic damping."""
        return linear - self.friction * np.tanh(v / self.velocity_scale) - self.quadratic * np.abs(v) * v

    def force(self, linear: np.ndarray | float, v: np.ndarray | float) -> np.ndarray | float:
        """F from the linear law's value ``linear`` and the rate ``v``."""
        if not self.nonlinear:
            return linear
        g = self._unsaturated(linear, v)
        return self.force_limit * np.tanh(g / self.force_limit) if self.force_limit > 0 else g

    def derivatives(self, linear, v, dlinear_dx, dlinear_dv) -> tuple:
        """(dF/dx, dF/dv) given the linear law's derivatives."""
        g = self._unsaturated(linear, v)
        dg_dv = (dlinear_dv - self.friction / self.velocity_scale / np.cosh(v / self.velocity_scale) ** 2
                 - 2 * self.quadratic * np.abs(v))
        slope = 1.0 / np.cosh(g / self.force_limit) ** 2 if self.force_limit > 0 else 1.0
        return slope * dlinear_dx, slope * dg_dv


@dataclass
class CoordinateSpringDamper(ForceElement):
    """``F = -k (q - q0) - c q' + u`` on a scalar coordinate (a PTO when ``k``, ``c``, ``u`` are commanded),
    optionally through a nonlinear :class:`PtoLaw`."""

    name: str
    coordinate: Coordinate
    stiffness: float = 0.0
    damping: float = 0.0
    force_command: float = 0.0
    neutral: float = 0.0
    law: PtoLaw = PtoLaw()

    @property
    def nonlinear(self) -> bool:
        return self.law.nonlinear

    def law_force(self, x, v):
        """Force (N or N m) at displacement ``x`` from neutral and rate ``v`` (scalars or arrays)."""
        return self.law.force(-self.stiffness * x - self.damping * v + self.force_command, v)

    def law_derivatives(self, x, v) -> tuple:
        """(dF/dx, dF/dv) of :meth:`law_force`."""
        return self.law.derivatives(-self.stiffness * x - self.damping * v + self.force_command, v,
                                    -self.stiffness, -self.damping)

    def set_command(self, stiffness: float, damping: float, force: float) -> None:
        self.stiffness, self.damping, self.force_command = float(stiffness), float(damping), float(force)

    def state(self, k: Kin) -> tuple[float, float, np.ndarray]:
        """Displacement from neutral, rate and Jacobian."""
        q, qd, jac = self.coordinate.rate(k)
        return q - self.neutral, qd, jac

    def force(self, k: Kin) -> float:
        x, v, _ = self.state(k)
        return self.law_force(x, v)

    def apply(self, k: Kin, f: np.ndarray) -> None:
        x, v, jac = self.state(k)
        f[self.coordinate.cols()] += jac * self.law_force(x, v)

    def tangent(self, k: Kin):
        x, v, jac = self.state(k)
        outer = np.outer(jac, jac)
        if not self.law.nonlinear:
            return self.coordinate.cols(), self.stiffness * outer, self.damping * outer
        dfdx, dfdv = self.law_derivatives(x, v)
        return self.coordinate.cols(), -dfdx * outer, -dfdv * outer

    def potential(self, k: Kin) -> float:
        x, _, _ = self.state(k)
        return 0.5 * self.stiffness * x * x

    def dissipation(self, k: Kin) -> float:
        """``-(F + k x - u) q'``: ``c q'^2`` for the linear law."""
        x, v, _ = self.state(k)
        return -(self.law_force(x, v) + self.stiffness * x - self.force_command) * v

    def supply(self, k: Kin) -> float:
        _, v, _ = self.state(k)
        return self.force_command * v

    def powers(self, k: Kin) -> tuple[float, float]:
        x, v, _ = self.state(k)
        if self.law.nonlinear:
            return -(self.law_force(x, v) + self.stiffness * x - self.force_command) * v, self.force_command * v
        return self.damping * v * v, self.force_command * v

    def power(self, k: Kin) -> float:
        """Power absorbed from the bodies, ``-F q'`` (W)."""
        x, v, _ = self.state(k)
        return -self.law_force(x, v) * v

    def output(self, k: Kin) -> np.ndarray:
        return np.array([self.force(k)])

    def commit(self, k: Kin) -> None:
        self.coordinate.commit(k)


@dataclass
class Rope(ForceElement):
    """Tension-only rope on a distance coordinate: tension ``T = max(0, k (l - L) + c l')`` when ``l > L``."""

    nonlinear = True

    name: str
    coordinate: Coordinate
    stiffness: float
    damping: float = 0.0
    length: float = 0.0

    def tension(self, k: Kin) -> tuple[float, float, float, np.ndarray]:
        l, ld, jac = self.coordinate.rate(k)
        stretch = l - self.length
        t = max(0.0, self.stiffness * stretch + self.damping * ld) if stretch > 0 else 0.0
        return t, stretch, ld, jac

    def apply(self, k: Kin, f: np.ndarray) -> None:
        t, _, _, jac = self.tension(k)
        f[self.coordinate.cols()] -= jac * t

    def tangent(self, k: Kin):
        t, stretch, _, jac = self.tension(k)
        outer = np.outer(jac, jac) if t > 0 else np.zeros((12, 12))
        return self.coordinate.cols(), self.stiffness * outer, self.damping * outer

    def potential(self, k: Kin) -> float:
        _, stretch, _, _ = self.tension(k)
        return 0.5 * self.stiffness * max(stretch, 0.0) ** 2

    def dissipation(self, k: Kin) -> float:
        t, stretch, ld, _ = self.tension(k)
        return (t - self.stiffness * max(stretch, 0.0)) * ld if t > 0 else 0.0

    def output(self, k: Kin) -> np.ndarray:
        return np.array([self.tension(k)[0]])


@dataclass
class CoulombFriction(ForceElement):
    """Regularised Coulomb friction on a joint coordinate: ``F = -F_c tanh(q' / v_reg)``."""

    nonlinear = True

    name: str
    coordinate: Coordinate
    force: float
    velocity: float = 1e-3

    def _f(self, k: Kin) -> tuple[float, float, np.ndarray]:
        _, qd, jac = self.coordinate.rate(k)
        return -self.force * math.tanh(qd / self.velocity), qd, jac

    def apply(self, k: Kin, f: np.ndarray) -> None:
        fr, _, jac = self._f(k)
        f[self.coordinate.cols()] += jac * fr

    def tangent(self, k: Kin):
        _, qd, jac = self._f(k)
        slope = self.force / self.velocity / math.cosh(min(qd / self.velocity, 50.0)) ** 2
        return self.coordinate.cols(), np.zeros((12, 12)), slope * np.outer(jac, jac)

    def dissipation(self, k: Kin) -> float:
        fr, qd, _ = self._f(k)
        return -fr * qd

    def output(self, k: Kin) -> np.ndarray:
        return np.array([self._f(k)[0]])

    def commit(self, k: Kin) -> None:
        self.coordinate.commit(k)


class LinearisedInputForce(ForceElement):
    """An external force given as an affine model over the macro step (the linearised force interface of
    ``hydro_fmu.linearisation``), on chosen body degrees of freedom:

        F = F0 + F0_rate (t - t_n) + dF_dx x + dF_dv v,

    ``x`` the displacement from equilibrium (cg translation, rotation vector; as the ``<b>.x[i]``
    outputs), ``v`` the world-frame velocity, t_n the start of the macro step. Its tangent
    (-dF_dx, -dF_dv) enters the formulations' Newton matrix, so the motion-dependent part is
    integrated implicitly with the rest of the model. The power it delivers counts as external
    work in the energy account, as the held force input's does.

    Args:
        bodies: body index of each degree of freedom (m,).
        dofs: DOF of each (0 surge ... 5 yaw).
        cg: (N, 3) equilibrium centres of gravity.
    """

    name = "linearised_input"

    def __init__(self, bodies: np.ndarray, dofs: np.ndarray, cg: np.ndarray) -> None:
        self.bodies = np.asarray(bodies, dtype=int)
        self.dofs = np.asarray(dofs, dtype=int)
        self.cg = np.asarray(cg, dtype=float)
        self.cols = 6 * self.bodies + self.dofs
        m = len(self.cols)
        self.constant, self.rate = np.zeros(m), np.zeros(m)
        self.dfdx, self.dfdv = np.zeros((m, m)), np.zeros((m, m))
        self.t0 = 0.0
        self.active = False
        self._rotating = self.dofs >= 3
        self._rot_bodies = self.bodies[self._rotating]

    def set(self, t0: float, constant: np.ndarray, rate: np.ndarray, dfdx: np.ndarray, dfdv: np.ndarray) -> bool:
        """Hold a new affine model from ``t0`` (s); returns True if anything but the start time changed."""
        new = [np.asarray(a, dtype=float) for a in (constant, rate, dfdx, dfdv)]
        changed = not all(np.array_equal(a, b) for a, b in zip(new, (self.constant, self.rate, self.dfdx, self.dfdv),
                                                                  strict=True))
        self.constant, self.rate, self.dfdx, self.dfdv = (a.copy() for a in new)
        changed = changed or (bool(np.any(self.rate)) and t0 != self.t0)
        self.t0 = float(t0)
        self.active = bool(np.any(self.constant) or np.any(self.rate) or np.any(self.dfdx) or np.any(self.dfdv))
        return changed

    def motion(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        """(x, v) on the element's degrees of freedom."""
        x = np.empty(len(self.cols))
        trans = ~self._rotating
        x[trans] = k.rr[self.bodies[trans], self.dofs[trans]] - self.cg[self.bodies[trans], self.dofs[trans]]
        if self._rot_bodies.size:
            x[self._rotating] = log_so3(k.RR[self._rot_bodies])[np.arange(self._rot_bodies.size),
                                                                  self.dofs[self._rotating] - 3]
        return x, k.W[self.bodies, self.dofs]

    def force(self, k: Kin) -> np.ndarray:
        x, v = self.motion(k)
        return self.constant + self.rate * (k.t - self.t0) + self.dfdx @ x + self.dfdv @ v

    def apply(self, k: Kin, f: np.ndarray) -> None:
        if self.active:
            f[self.cols] += self.force(k)

    def tangent(self, k: Kin) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        if not self.active:
            return None
        return self.cols, -self.dfdx, -self.dfdv

    def powers(self, k: Kin) -> tuple[float, float]:
        if not self.active:
            return 0.0, 0.0
        return 0.0, float(self.force(k) @ k.W[self.bodies, self.dofs])

    def supply(self, k: Kin) -> float:
        return self.powers(k)[1]
