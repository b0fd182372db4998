"""Holonomic constraint primitives, evaluated for all instances of a kind at once (numpy).

Every joint is a combination of four primitives between a point/vector of body i and one of
body j (either may be the ground). With ``a = R s`` the world offset of a body-fixed point
``s`` from the centre of gravity, ``p = r + a``, and body-fixed unit vectors ``u = R u0``:

* ``point``: ``p_i - p_j = 0`` (3 equations);
* ``perp``: ``u_i . w_j = c0`` (1 equation; c0 = 0 for perpendicular axes);
* ``plane``: ``n_i . (p_j - p_i) = c0`` (1 equation; point of j on a plane of i);
* ``distance``: ``|p_j - p_i| = L`` (1 equation).

For each the value, the Jacobian with respect to the world-frame slots (velocities and position
increments alike) of both bodies, and ``gamma`` (minus the velocity-quadratic part of the
second time derivative, the right-hand side of the acceleration constraint ``C a = gamma``) are
analytic. Jacobian blocks are scattered into a dense (m, 6 (N + 1)) matrix by precomputed
index arrays.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .kinematics import Kin
from .rotations import cross as _cross
from .rotations import skew as _skew

ROWS = {"point": 3, "perp": 1, "plane": 1, "distance": 1}



def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.add.reduce(a * b, axis=-1)


def _centripetal(w: np.ndarray, a: np.ndarray) -> np.ndarray:
    """``w x (w x a) = w (w . a) - a (w . w)`` for stacks of vectors (k, 3)."""
    return w * _dot(w, a)[:, None] - a * _dot(w, w)[:, None]


def _rotate(rot: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``rot @ v`` for stacks of matrices (k, 3, 3) and vectors (k, 3)."""
    return (rot @ v[..., None])[..., 0]


@dataclass
class PrimitiveGroup:
    """All primitives of one kind: body indices, body-fixed vectors, targets and their rows."""

    kind: str
    bi: list[int] = field(default_factory=list)
    bj: list[int] = field(default_factory=list)
    vi: list[np.ndarray] = field(default_factory=list)  # point offset (point, plane, distance) or axis (perp)
    vj: list[np.ndarray] = field(default_factory=list)
    ni: list[np.ndarray] = field(default_factory=list)  # plane normal on body i
    c0: list[float] = field(default_factory=list)
    rows: list[int] = field(default_factory=list)  # first row of each instance

    def freeze(self) -> None:
        """Convert the lists to arrays and build the scatter indices (call once)."""
        k = len(self.bi)
        c = ROWS[self.kind]
        self.BI = np.array(self.bi, dtype=int)
        self.BJ = np.array(self.bj, dtype=int)
        self.VI = np.array(self.vi, dtype=float).reshape(k, 3)
        self.VJ = np.array(self.vj, dtype=float).reshape(k, 3)
        self.NI = np.array(self.ni, dtype=float).reshape(k, 3) if self.ni else np.zeros((k, 3))
        self.C0 = np.array(self.c0, dtype=float)
        self.ROW = (np.array(self.rows, dtype=int)[:, None] + np.arange(c)[None, :]).reshape(k, c)
        cols = np.concatenate([6 * self.BI[:, None] + np.arange(6), 6 * self.BJ[:, None] + np.arange(6)], axis=1)
        self.COLS = cols  # (k, 12)
        self.BIJ = np.concatenate([self.BI, self.BJ])  # bodies i then j: one indexing serves both ends
        self.VIJ = np.concatenate([self.VI, self.VJ])
        self.SCATTER = (np.broadcast_to(self.ROW[:, :, None], (k, c, 12)),
                        np.broadcast_to(cols[:, None, :], (k, c, 12)))
        self.TEMPLATE = np.zeros((k, c, 12))  # constant Jacobian entries (the point's translations)
        if self.kind == "point":
            self.TEMPLATE[:, :, 0:3] = np.eye(3)
            self.TEMPLATE[:, :, 6:9] = -np.eye(3)

    def __len__(self) -> int:
        return len(self.bi)


class ConstraintSet:
    """The primitives of all joints, and rows appended by coordinate drivers (see :mod:`mbd_fmu.coordinates`)."""

    def __init__(self) -> None:
        self.groups = {kind: PrimitiveGroup(kind) for kind in ROWS}
        self.m = 0

    def add(self, kind: str, bi: int, bj: int, vi, vj, ni=None, c0: float = 0.0) -> int:
        g = self.groups[kind]
        g.bi.append(bi)
        g.bj.append(bj)
        g.vi.append(np.asarray(vi, dtype=float))
        g.vj.append(np.asarray(vj, dtype=float))
        if ni is not None:
            g.ni.append(np.asarray(ni, dtype=float))
        g.c0.append(float(c0))
        g.rows.append(self.m)
        self.m += ROWS[kind]
        return self.m - ROWS[kind]

    def freeze(self) -> None:
        self.active = [g for g in self.groups.values() if len(g)]
        for g in self.active:
            g.freeze()

    # ------------------------------------------------------------------ evaluation
    def geometric_stiffness(self, k: Kin, lam: np.ndarray, out: np.ndarray) -> None:
        """Add d(C^T lambda)/dq of the ``point`` and ``perp`` primitives (rotation blocks) into ``out``
        (full slots); ``lam`` holds the multipliers of all rows (zeros for dropped ones)."""
        g = self.groups["point"]
        if len(g):
            eye = np.eye(3)
            for sign, b, v in ((1.0, g.BI, g.VI), (-1.0, g.BJ, g.VJ)):
                a = _rotate(k.RR[b], v)
                lk = lam[g.ROW]
                blocks = sign * (a[:, :, None] * lk[:, None, :] - _dot(a, lk)[:, None, None] * eye)
                _add_blocks(out, b, b, blocks)
        g = self.groups["perp"]
        if len(g):
            u = _rotate(k.RR[g.BI], g.VI)
            w = _rotate(k.RR[g.BJ], g.VJ)
            lk = lam[g.ROW[:, 0]]
            uw = _dot(u, w)[:, None, None] * np.eye(3)
            ii = lk[:, None, None] * (u[:, :, None] * w[:, None, :] - uw)
            ij = lk[:, None, None] * (uw - w[:, :, None] * u[:, None, :])
            _add_blocks(out, g.BI, g.BI, ii)
            _add_blocks(out, g.BI, g.BJ, ij)
            _add_blocks(out, g.BJ, g.BI, -ii)
            _add_blocks(out, g.BJ, g.BJ, -ij)

    def evaluate(self, k: Kin, phi: np.ndarray, jac: np.ndarray | None, gamma: np.ndarray | None,
                 groups: list[PrimitiveGroup] | None = None) -> None:
        """Fill ``phi`` (m,), ``jac`` (m, 6(N+1)) and ``gamma`` (m,) in place (any may be None) for the rows of
        ``groups`` (default: all)."""
        for g in self.active if groups is None else groups:
            _EVALUATORS[g.kind](g, k, phi, jac, gamma)


def _add_blocks(out: np.ndarray, bi: np.ndarray, bj: np.ndarray, blocks: np.ndarray) -> None:
    """out[rot(bi), rot(bj)] += blocks, for all instances at once (repeated bodies accumulate)."""
    r = 6 * bi[:, None, None] + 3 + np.arange(3)[None, :, None]
    c = 6 * bj[:, None, None] + 3 + np.arange(3)[None, None, :]
    flat = (r * out.shape[1] + c).ravel()
    out += np.bincount(flat, weights=blocks.ravel(), minlength=out.size).reshape(out.shape)


def _point(g: PrimitiveGroup, k: Kin, phi, jac, gamma) -> None:
    n = len(g)
    a = _rotate(k.RR[g.BIJ], g.VIJ)  # offsets a_i (first n rows), then a_j
    ai, aj = a[:n], a[n:]
    if phi is not None:
        r = k.rr[g.BIJ]
        phi[g.ROW] = r[:n] + ai - r[n:] - aj
    if jac is not None:
        blocks = g.TEMPLATE.copy()  # translation parts: I and -I
        s = _skew(a)
        blocks[:, :, 3:6] = -s[:n]
        blocks[:, :, 9:12] = s[n:]
        jac[g.SCATTER] = blocks
    if gamma is not None:
        c = _centripetal(k.W[g.BIJ, 3:], a)
        gamma[g.ROW] = c[n:] - c[:n]


def _perp(g: PrimitiveGroup, k: Kin, phi, jac, gamma) -> None:
    n = len(g)
    uw = _rotate(k.RR[g.BIJ], g.VIJ)
    u, w = uw[:n], uw[n:]
    rows = g.ROW[:, 0]
    if phi is not None:
        phi[rows] = _dot(u, w) - g.C0
    uxw = _cross(u, w)
    if jac is not None:
        blocks = g.TEMPLATE.copy()
        blocks[:, 0, 3:6] = uxw
        blocks[:, 0, 9:12] = -uxw
        jac[g.SCATTER] = blocks
    if gamma is not None:
        om = k.W[g.BIJ, 3:]
        wi, wj = om[:n], om[n:]
        d = _cross(_cross(wi, u), w) + _cross(u, _cross(wj, w))
        gamma[rows] = -_dot(d, wi - wj)


def _offsets(g: PrimitiveGroup, k: Kin) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """World offsets of the two points from their cgs (stacked: i then j, and each) and the vector from
    point i to point j."""
    n = len(g)
    a = _rotate(k.RR[g.BIJ], g.VIJ)
    r = k.rr[g.BIJ]
    ai, aj = a[:n], a[n:]
    return a, ai, aj, r[n:] + aj - r[:n] - ai


def _relative_motion(g: PrimitiveGroup, k: Kin, a: np.ndarray) -> tuple:
    """Angular velocities of both bodies, rate of the point-to-point vector, and its centripetal part."""
    n = len(g)
    vel = k.W[g.BIJ]
    om = vel[:, 3:]
    wxa = _cross(om, a)
    c = _centripetal(om, a)
    dd = vel[n:, :3] + wxa[n:] - vel[:n, :3] - wxa[:n]
    return om[:n], om[n:], dd, c[n:] - c[:n]


def _plane(g: PrimitiveGroup, k: Kin, phi, jac, gamma) -> None:
    n = _rotate(k.RR[g.BI], g.NI)
    a, ai, aj, d = _offsets(g, k)
    rows = g.ROW[:, 0]
    if phi is not None:
        phi[rows] = _dot(n, d) - g.C0
    if jac is not None:
        blocks = g.TEMPLATE.copy()
        blocks[:, 0, 0:3] = -n
        blocks[:, 0, 3:6] = _cross(n, d + ai)
        blocks[:, 0, 6:9] = n
        blocks[:, 0, 9:12] = _cross(aj, n)
        jac[g.SCATTER] = blocks
    if gamma is not None:
        wi, _, dd, centripetal = _relative_motion(g, k, a)
        quad = _dot(_cross(wi, _cross(wi, n)), d) + 2 * _dot(_cross(wi, n), dd) + _dot(n, centripetal)
        gamma[rows] = -quad


def _distance(g: PrimitiveGroup, k: Kin, phi, jac, gamma) -> None:
    a, ai, aj, d = _offsets(g, k)
    length = np.sqrt(_dot(d, d))
    e = d / length[:, None]
    rows = g.ROW[:, 0]
    if phi is not None:
        phi[rows] = length - g.C0
    if jac is not None:
        blocks = g.TEMPLATE.copy()
        blocks[:, 0, 0:3] = -e
        blocks[:, 0, 3:6] = -_cross(ai, e)
        blocks[:, 0, 6:9] = e
        blocks[:, 0, 9:12] = _cross(aj, e)
        jac[g.SCATTER] = blocks
    if gamma is not None:
        _, _, dd, centripetal = _relative_motion(g, k, a)
        gamma[rows] = -(_dot(e, centripetal) + (_dot(dd, dd) - _dot(e, dd) ** 2) / length)


_EVALUATORS = {"point": _point, "perp": _perp, "plane": _plane, "distance": _distance}
