"""Joints: kinematic pairs between two bodies (or a body and the ground), and time functions
for prescribed motion.

A joint is placed at a world point at equilibrium (where every body's axes are the world axes),
with its axis (``z`` of the joint frame) and, where it matters, a second axis (``x`` of the
joint frame; for a universal joint the cross axis on body 2). Each kind is a combination of the
primitives of :mod:`mbd_fmu.constraints` (the number of equations in brackets):

========== ==================================================================== ====
kind       equations                                                            DOF
========== ==================================================================== ====
fixed      point (3), z_1 . x_2, z_1 . y_2, x_1 . y_2 = 0                        0
revolute   point (3), z_1 . x_2 = z_1 . y_2 = 0                                  1
prismatic  z_1 . x_2 = z_1 . y_2 = x_1 . y_2 = 0, x_1 . d = y_1 . d = 0          1
cylindrical z_1 . x_2 = z_1 . y_2 = 0, x_1 . d = y_1 . d = 0                     2
universal  point (3), z_1 . a_2 = 0 (a_2 the cross axis on body 2)              2
spherical  point (3)                                                            3
planar     z_1 . x_2 = z_1 . y_2 = 0, z_1 . d = 0                                3
distance   |p_2 - p_1| = L (a massless rigid rod between two points)            5
========== ==================================================================== ====

(``d = p_2 - p_1``.) A *locked* joint becomes a fixed joint at the relative pose the bodies have
at the start of the run. Joint coordinates (outputs, and what springs, PTOs, friction and drivers
act on): revolute - angle; prismatic - displacement along z; cylindrical - displacement, angle;
universal, spherical - rotation vector of body 2's joint frame relative to body 1's (3);
planar - x, y displacement in the plane, angle about z; distance - length; fixed - none.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import CubicSpline

from .coordinates import Angle, Coordinate, Distance, RotationComponent, Slide
from .spec_checks import ModelError, direction, distance_problem, universal_axes_problem

JOINT_KINDS = ("fixed", "revolute", "prismatic", "cylindrical", "universal", "spherical", "planar", "distance")
JOINT_DOF = {"fixed": 0, "revolute": 1, "prismatic": 1, "cylindrical": 2, "universal": 2, "spherical": 3,
             "planar": 3, "distance": 5}
# (position unit, rate unit) of each coordinate a joint kind reports (FMU outputs, results files)
JOINT_COORDINATE_UNITS = {
    "fixed": [], "revolute": [("rad", "rad/s")], "prismatic": [("m", "m/s")],
    "cylindrical": [("m", "m/s"), ("rad", "rad/s")], "universal": [("rad", "rad/s")] * 3,
    "spherical": [("rad", "rad/s")] * 3, "planar": [("m", "m/s"), ("m", "m/s"), ("rad", "rad/s")],
    "distance": [("m", "m/s")],
}
# The names of each kind's coordinates (FMU ``<joint>.coordinate[k]``, in order; units above).
JOINT_COORDINATE_NAMES = {
    "fixed": [], "revolute": ["angle"], "prismatic": ["displacement"], "cylindrical": ["displacement", "angle"],
    "universal": ["rotation_x", "rotation_y", "rotation_z"], "spherical": ["rotation_x", "rotation_y", "rotation_z"],
    "planar": ["x", "y", "angle"], "distance": ["length"],
}


def joint_frame(axis, axis2=None) -> np.ndarray:
    """Orthonormal frame (columns x, y, z) with z along ``axis`` and x along ``axis2`` projected."""
    z = direction(axis, "joint axis")
    x2 = direction(axis2, "joint axis2") if axis2 is not None else None
    if x2 is not None and np.linalg.norm(np.cross(z, x2)) > 1e-9:
        x = x2 - (x2 @ z) * z
    else:
        trial = np.eye(3)[int(np.argmin(np.abs(z)))]
        x = trial - (trial @ z) * z
    x = x / np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


@dataclass(frozen=True)
class Joint:
    """A joint between ``body1`` (``None`` = ground) and ``body2``.

    Attributes:
        position: world point of the joint at equilibrium (m); for ``distance`` the point on body 1.
        axis: joint axis (revolute, prismatic, cylindrical; plane normal for planar; first axis
            of a universal joint, on body 1).
        axis2: x axis of the joint frame (optional); for a universal joint the cross axis on body 2.
        position2: for ``distance``, the point on body 2 (world, at equilibrium).
        locked: held fixed at the relative pose of the start of the run.
    """

    name: str
    kind: str
    body1: str | None
    body2: str
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    axis2: tuple[float, float, float] | None = None
    position2: tuple[float, float, float] | None = None
    locked: bool = False

    def __post_init__(self) -> None:
        if self.kind not in JOINT_KINDS:
            raise ModelError(
                f"joint {self.name!r}: unknown kind {self.kind!r}; expected one of {', '.join(JOINT_KINDS)}")
        if self.body1 == self.body2:
            raise ModelError(f"joint {self.name!r}: body1 and body2 are the same body {self.body2!r}")
        if not np.all(np.isfinite(self.position)):
            raise ModelError(f"joint {self.name!r}: position must be finite")
        if self.kind == "distance" and self.position2 is None:
            raise ModelError(f"joint {self.name!r}: a distance joint needs position2 (the point on body 2)")
        try:
            joint_frame(self.axis, self.axis2)
            problem = None
            if self.kind == "universal" and self.axis2 is not None:
                problem = universal_axes_problem(self.axis, self.axis2)
            if self.kind == "distance":
                problem = distance_problem(self.position, self.position2)
        except ModelError as exc:
            problem = str(exc)
        if problem:
            raise ModelError(f"joint {self.name!r}: {problem}")


@dataclass
class Marker:
    """A joint frame on a body: body index (N = ground), body-fixed offset from the cg and axes."""

    body: int
    offset: np.ndarray
    axes: np.ndarray


@dataclass
class CompiledJoint:
    """A joint's primitives (kind, vectors on body 1, on body 2, normal), rows and coordinates."""

    joint: Joint
    m1: Marker
    m2: Marker
    primitives: list[tuple] = field(default_factory=list)
    rows: list[int] = field(default_factory=list)
    coordinates: list[Coordinate] = field(default_factory=list)
    coordinate_names: list[str] = field(default_factory=list)


def compile_joint(joint: Joint, m1: Marker, m2: Marker, length: float = 0.0) -> CompiledJoint:
    """Primitives and coordinates of ``joint`` between markers ``m1`` (body 1) and ``m2`` (body 2)."""
    cj = CompiledJoint(joint, m1, m2)
    a1, a2 = m1.axes, m2.axes
    x1, y1, z1 = a1[:, 0], a1[:, 1], a1[:, 2]
    x2, y2 = a2[:, 0], a2[:, 1]
    kind = "fixed" if joint.locked else joint.kind
    point = ("point", m1.offset, m2.offset, None)
    align = [("perp", z1, x2, None), ("perp", z1, y2, None)]
    on_line = [("plane", m1.offset, m2.offset, x1), ("plane", m1.offset, m2.offset, y1)]
    prims = {
        "fixed": [point, *align, ("perp", x1, y2, None)],
        "revolute": [point, *align],
        "prismatic": [*align, ("perp", x1, y2, None), *on_line],
        "cylindrical": [*align, *on_line],
        "universal": [point, ("perp", z1, a2[:, 0], None)],
        "spherical": [point],
        "planar": [*align, ("plane", m1.offset, m2.offset, z1)],
        "distance": [("distance", m1.offset, m2.offset, None, length)],
    }[kind]
    cj.primitives = prims
    b1, b2 = m1.body, m2.body
    slide = lambda n: Slide(b1, b2, n, m1.offset, m2.offset)  # noqa: E731
    angle = Angle(b1, b2, a1, x2)
    rotation = [RotationComponent(b1, b2, a1, a2, k) for k in range(3)]
    coordinates = {
        "fixed": [],
        "revolute": [angle],
        "prismatic": [slide(z1)],
        "cylindrical": [slide(z1), angle],
        "universal": rotation,
        "spherical": rotation,
        "planar": [slide(x1), slide(y1), angle],
        "distance": [Distance(b1, b2, m1.offset, m2.offset)],
    }[joint.kind]
    cj.coordinates, cj.coordinate_names = coordinates, list(JOINT_COORDINATE_NAMES[joint.kind])
    return cj


# ---------------------------------------------------------------------- time functions
class TimeFunction:
    """A smooth function of time with its first two derivatives (prescribed motion)."""

    def value(self, t: float) -> float:  # pragma: no cover - abstract
        raise NotImplementedError

    def d1(self, t: float) -> float:  # pragma: no cover - abstract
        raise NotImplementedError

    def d2(self, t: float) -> float:  # pragma: no cover - abstract
        raise NotImplementedError


@dataclass(frozen=True)
class Harmonic(TimeFunction):
    """``offset + rate t + amplitude sin(omega t + phase)``; ``integral`` gives a velocity law's position."""

    amplitude: float = 0.0
    omega: float = 0.0
    phase: float = 0.0
    offset: float = 0.0
    rate: float = 0.0

    def value(self, t: float) -> float:
        return self.offset + self.rate * t + self.amplitude * math.sin(self.omega * t + self.phase)

    def d1(self, t: float) -> float:
        return self.rate + self.amplitude * self.omega * math.cos(self.omega * t + self.phase)

    def d2(self, t: float) -> float:
        return -self.amplitude * self.omega**2 * math.sin(self.omega * t + self.phase)

    def integral(self, t0: float, start: float) -> Harmonic:
        """The position whose velocity is this function, equal to ``start`` at ``t0``."""
        if self.rate != 0.0:
            raise ValueError("a velocity law with a linear rate term is not supported")
        if self.omega == 0.0:
            return Harmonic(offset=start - self.value(t0) * t0, rate=self.value(t0))
        amp = -self.amplitude / self.omega
        f = Harmonic(amp, self.omega, self.phase + math.pi / 2, 0.0, self.offset)
        return Harmonic(amp, self.omega, self.phase + math.pi / 2, start - f.value(t0), self.offset)


class Table(TimeFunction):
    """Cubic spline through ``(times, values)`` (natural end conditions), constant outside."""

    def __init__(self, times, values) -> None:
        times, values = np.asarray(times, float), np.asarray(values, float)
        if len(times) < 2 or np.any(np.diff(times) <= 0) or not np.all(np.isfinite(values)):
            raise ValueError("a table needs at least two strictly increasing times and finite values")
        self.times, self.values = times, values
        self.spline = CubicSpline(times, values, bc_type="natural")

    def _clip(self, t: float) -> float:
        return min(max(t, self.times[0]), self.times[-1])

    def value(self, t: float) -> float:
        return float(self.spline(self._clip(t)))

    def d1(self, t: float) -> float:
        return float(self.spline(self._clip(t), 1)) if self.times[0] <= t <= self.times[-1] else 0.0

    def d2(self, t: float) -> float:
        return float(self.spline(self._clip(t), 2)) if self.times[0] <= t <= self.times[-1] else 0.0

    def integral(self, t0: float, start: float) -> TimeFunction:
        """The position whose velocity is this table (held at its end values outside), ``start`` at ``t0``."""
        return _TableIntegral(self, t0, start)


class _TableIntegral(TimeFunction):
    """Exact antiderivative of a :class:`Table` (the spline's own antiderivative, linear outside)."""

    def __init__(self, table: Table, t0: float, start: float) -> None:
        self.table = table
        self.anti = table.spline.antiderivative()
        self.offset = start - self._raw(t0)

    def _raw(self, t: float) -> float:
        lo, hi = self.table.times[0], self.table.times[-1]
        tc = min(max(t, lo), hi)
        return float(self.anti(tc)) + self.table.value(t) * (t - tc)

    def value(self, t: float) -> float:
        return self.offset + self._raw(t)

    def d1(self, t: float) -> float:
        return self.table.value(t)

    def d2(self, t: float) -> float:
        return self.table.d1(t)


@dataclass
class Driver:
    """Prescribed motion: ``coordinate(q) - function(t) = 0`` (one constraint equation)."""

    name: str
    coordinate: Coordinate
    function: TimeFunction
