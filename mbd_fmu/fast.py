"""The compiled path of the multibody model: which models it covers, and the plan its kernels run on.

:mod:`mbd_fmu.kernels` evaluates the model (mass matrix, forces, constraints, tangents) and whole
generalised-alpha and RKMK steps in machine code (the null-space formulation's steps in
:mod:`mbd_fmu.nullspace_kernels`). It covers:

* rigid bodies and point masses on any subset of degrees of freedom, infinite-frequency added mass,
  gravity and static loads, gyroscopic moments;
* every joint kind (the four constraint primitives: point, perp, plane, distance), closed loops and
  redundant constraints (the kept rows, re-chosen along the motion as on the Python path);
* force elements :class:`~mbd_fmu.moorings.LinearMooring`,
  :class:`~mbd_fmu.force_elements.CoordinateSpringDamper` (spring-dampers, rotary spring-dampers,
  bushings, PTOs with their nonlinear law), :class:`~mbd_fmu.force_elements.Rope` (tension only) and
  :class:`~mbd_fmu.force_elements.CoulombFriction` on a distance, a slide, a joint angle or a
  rotation-vector component (relative rotations: bushings and PTOs on spherical joints, the arrays'
  link arms).

A model with anything else (prescribed motion, catenary lines, any element defined elsewhere) runs
on the Python path, unchanged; so
does every model when numba is missing or ``WEC_COSIM_NO_JIT`` is set. :func:`compiled_model`
returns None then. The plan is derived data: formulations rebuild it from the model (it is not part
of a saved state).
"""

from __future__ import annotations

import os

import numpy as np

from fmu_base._jit import AVAILABLE

from . import kernels
from .coordinates import Angle, Distance, RotationComponent, Slide
from .force_elements import CoordinateSpringDamper, CoulombFriction, Rope
from .model import MultibodyModel
from .moorings import LinearMooring

_COORDINATE_KIND = {Distance: 0, Slide: 1, Angle: 2, RotationComponent: 3}  # 3 + k: component k
_LAW = {CoordinateSpringDamper: 0, Rope: 1, CoulombFriction: 2}  # spring_par[:, 8] (mbd_fmu.kernels._element_law)
KINDS = {"point": 0, "perp": 1, "plane": 2, "distance": 3}


def unsupported(model: MultibodyModel) -> list[str]:
    """What keeps ``model`` off the compiled path (empty: covered)."""
    out = []
    if model.drivers:
        out.append("prescribed motion (drivers)")
    for e in model.elements:
        if type(e) is LinearMooring:
            continue
        if type(e).__name__ == "LinearisedInputForce" and not e.active:
            continue  # the host interface's input force before a host sets it: no force, no tangent
        if type(e) in _LAW and type(e.coordinate) in _COORDINATE_KIND:
            continue
        out.append(f"force element {e.name!r} ({type(e).__name__} on {type(getattr(e, 'coordinate', None)).__name__})")
    return out


def compiled_model(model: MultibodyModel) -> CompiledModel | None:
    """The compiled view of ``model``, or None if the model (or this installation) needs the Python path."""
    if not AVAILABLE or os.environ.get("WEC_COSIM_NO_JIT") or unsupported(model):
        return None
    return CompiledModel(model)


class CompiledModel:
    """Plan arrays of a model (module docstring of :mod:`mbd_fmu.kernels` for the layout), rebuilt when the
    kept constraint rows change; PTO commands and angle-unwrapping references are read from the elements'
    objects at every step and written back after it, so the Python objects stay the reference."""

    def __init__(self, model: MultibodyModel) -> None:
        self.model = model
        m = model
        m.mass_matrix(m.reference)  # builds the mass index
        n_full = 6 * (m.N + 1)
        colmap = -np.ones(n_full, dtype=np.int64)
        colmap[m.sel] = np.arange(m.n)
        rows, cols, b, lr, lc = m._mass_index
        fc = m.static.copy()
        fc[: m.N, :3] = m.mass[:, None] * m.gravity + m.static[: m.N, :3]
        self.base = [m.sel.astype(np.int64), colmap, m._mass_constant.copy(), m.inertia.copy(),
                     np.column_stack([rows, cols, b, lr, lc]).astype(np.int64).reshape(-1, 5), fc,
                     np.array([int(m._rotating), int(m._has_rotation())], dtype=np.int64)]
        kinds, bodies, vecs, c0, prim_rows = [], [], [], [], []
        for g in m.constraints.active:
            for i in range(len(g)):
                kinds.append(KINDS[g.kind])
                bodies.append((g.BI[i], g.BJ[i]))
                vecs.append((g.VI[i], g.VJ[i], g.NI[i]))
                c0.append(g.C0[i])
                r = -np.ones(3, dtype=np.int64)
                r[: g.ROW.shape[1]] = g.ROW[i]
                prim_rows.append(r)
        p = len(kinds)
        self.prim = [np.array(kinds, dtype=np.int64), np.array(bodies, dtype=np.int64).reshape(p, 2),
                     np.array(vecs, dtype=float).reshape(p, 3, 3), np.array(c0, dtype=float),
                     np.array(prim_rows, dtype=np.int64).reshape(p, 3)]
        moorings = [e for e in m.elements if isinstance(e, LinearMooring)]
        self.moor = [np.array([e.body for e in moorings], dtype=np.int64),
                     np.array([(e.stiffness, e.damping if e.damping is not None else np.zeros((6, 6)))
                               for e in moorings], dtype=float).reshape(-1, 2, 6, 6),
                     np.array([e.r0 for e in moorings], dtype=float).reshape(-1, 3)]
        self.springs = [e for e in m.elements if type(e) in _LAW]
        self.spring_position = {id(e): i for i, e in enumerate(self.springs)}
        coords: list = []
        for e in self.springs:
            if all(c is not e.coordinate for c in coords):
                coords.append(e.coordinate)
        for cj in m.joints:
            coords += [c for c in cj.coordinates if type(c) in _COORDINATE_KIND and all(c is not d for d in coords)]
        self.coordinates = coords
        self.coordinate_position = {id(c): i for i, c in enumerate(coords)}
        positions = [[self.coordinate_position.get(id(c)) for c in cj.coordinates] for cj in m.joints]
        # each joint's coordinates among the compiled ones (None: some are not compiled, read on the Python side)
        self.joint_coordinates = None if any(None in p for p in positions) else [
            np.array(p, dtype=np.int64) for p in positions]
        self.angles = [(s, c) for s, c in enumerate(coords) if type(c) is Angle]
        kind, cbody, cvec = [], [], []
        for c in coords:
            v = np.zeros((6, 3))
            if type(c) is Angle:
                v[2:5] = c.axes_i.T
                v[5] = c.x_j
            elif type(c) is RotationComponent:
                v[0:3], v[3:6] = c.axes_i, c.axes_j
            else:
                v[0], v[1] = c.si, c.sj
                if type(c) is Slide:
                    v[2] = c.n
                    v[3, 0] = c.offset
            kind.append(_COORDINATE_KIND[type(c)] + (c.k if type(c) is RotationComponent else 0))
            cbody.append((c.bi, c.bj))
            cvec.append(v)
        s = len(coords)
        self.coord = [np.array(kind, dtype=np.int64), np.array(cbody, dtype=np.int64).reshape(s, 2),
                      np.array(cvec, dtype=float).reshape(s, 6, 3),
                      np.array([next(i for i, c in enumerate(coords) if c is e.coordinate) for e in self.springs],
                               dtype=np.int64)]
        self.refs = np.zeros(s)
        joint_of_row = {r: j for j, cj in enumerate(m.joints) for r in cj.rows}
        self.outputs_part = [
            np.array([joint_of_row.get(int(r[0]), -1) for r in self.prim[4]], dtype=np.int64),
            np.array([cj.m2.body for cj in m.joints], dtype=np.int64),
            np.array([cj.m2.offset for cj in m.joints], dtype=float).reshape(-1, 3), m.static.copy(),
            np.concatenate([m.mass, m.gravity, m.cg.ravel()])]
        self.spring_par = np.zeros((len(self.springs), 9))
        self._plan = None
        self._kept = None

    def plan(self, refresh: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """The packed plan (:func:`mbd_fmu.kernels.pack`) for the model's current kept rows (cached per kept set),
        with the PTO commands and angle references of now (``refresh``: read them from the elements again)."""
        m = self.model
        if self._kept is not m.kept:
            kpos = -np.ones(m.m, dtype=np.int64)
            kpos[m.kept] = np.arange(len(m.kept))
            rows = self.prim[4]
            kept = np.where(rows >= 0, kpos[np.maximum(rows, 0)], -1)
            order, band = self._ordering(kept)
            plan = (*self.base, *self.prim, kept, *self.moor, *self.coord[:3], self.coord[3], self.refs,
                    self.spring_par, m.m, len(m.kept), order, band, *self.outputs_part)
            ip, fp = kernels.pack(plan)
            self._plan = (ip, fp)
            self.refs = _view(ip, fp, 20, self.refs.shape)
            self.spring_par = _view(ip, fp, 21, self.spring_par.shape)
            self._written = [None] * len(self.springs)  # spring parameters last written into this plan
            self._kept = m.kept
        elif not refresh:
            return self._plan
        self._refresh()
        return self._plan

    def _ordering(self, kept: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Band-reducing order of the saddle-point unknowns (slots, then kept rows) and the bandwidths in it of the
        iteration matrix and of the consistent-acceleration matrix ``[[M, C^T], [C, 0]]`` (4,). The structure:
        each body's slots together, bodies coupled by added mass, rows with the slots of their bodies; in the
        iteration matrix also bodies coupled by a constraint or a force element (tangents). Of reverse
        Cuthill-McKee of the unknowns and :func:`_body_blocks`, the order with the cheaper banded LUs; a dense
        order when the band is not narrow (small or densely coupled models)."""
        from scipy.sparse import csr_matrix
        from scipy.sparse.csgraph import reverse_cuthill_mckee

        m = self.model
        n, r = m.n, len(m.kept)
        nn = n + r
        body = m.sel // 6
        pattern = np.zeros((nn, nn), dtype=bool)
        pattern[:n, :n] = (self.base[2] != 0) | (body[:, None] == body[None, :])
        for (bi, bj), rows in zip(self.prim[1], kept, strict=True):
            for k in rows[rows >= 0]:
                pattern[n + k, :n] = (body == bi) | (body == bj)
                pattern[:n, n + k] = pattern[n + k, :n]
        acceleration = pattern.copy()

        def couple(a: int, b: int) -> None:
            pattern[np.ix_(body == a, body == b)] = True
            pattern[np.ix_(body == b, body == a)] = True

        for (bi, bj), rows in zip(self.prim[1], kept, strict=True):
            if np.any(rows >= 0):
                couple(bi, bj)
        for bi, bj in self.coord[1][self.coord[3]]:
            couple(bi, bj)
        dense = (np.arange(nn, dtype=np.int64), np.array([max(nn - 1, 0)] * 4, dtype=np.int64))
        if nn < 24:
            return dense

        def bands(order: np.ndarray) -> tuple[int, int]:
            out = []
            for structure in (pattern, acceleration):
                i, j = np.nonzero(structure[np.ix_(order, order)])
                out.append(int(np.max(np.abs(i - j))))
            return out[0], out[1]

        candidates = [reverse_cuthill_mckee(csr_matrix(pattern), symmetric_mode=True).astype(np.int64),
                      _body_blocks(pattern, body, m.N, n, r, kept, self.prim[1])]
        # cost of a banded LU ~ band^2: the acceleration matrix is factorised at every restart and RK stage, the
        # iteration matrix when refreshed; weigh them alike
        order = min(candidates, key=lambda o: sum(b * b for b in bands(o)))
        band, band_acceleration = bands(order)
        if band > nn // 3:
            return dense
        return order, np.array([band, band, band_acceleration, band_acceleration], dtype=np.int64)

    def _refresh(self) -> None:
        """PTO commands and angle references from the Python objects (they may change between steps: read at every
        step; a spring's row of the plan is rewritten only when its parameters differ from those last written)."""
        written = self._written
        for i, e in enumerate(self.springs):
            if type(e) is CoordinateSpringDamper:
                law = e.law
                values = (e.stiffness, e.damping, e.force_command, e.neutral, law.friction, law.quadratic,
                          law.force_limit, law.velocity_scale, 0.0)
            elif type(e) is Rope:
                values = (e.stiffness, e.damping, 0.0, e.length, 0.0, 0.0, 0.0, 1.0, 1.0)
            else:
                values = (0.0, 0.0, 0.0, 0.0, e.force, 0.0, 0.0, e.velocity, 2.0)
            if values != written[i]:  # (a NaN parameter is never equal: rewritten every time, as it is read)
                self.spring_par[i] = written[i] = values
        refs = self.refs
        for s, c in self.angles:
            refs[s] = c.reference

    def dependent_order(self, dep: np.ndarray) -> tuple[np.ndarray, np.ndarray, int, int]:
        """Order of the kept rows and of the dependent slots ``dep`` for a banded LU of C_d
        (:mod:`mbd_fmu.nullspace_kernels`), and its lower and upper bandwidths: bodies in breadth-first order
        along the rows that couple them, rows by their first and last body, slots by body. Dense (bandwidths
        r - 1) when the band is not narrow."""
        m = self.model
        kept = m.kept
        kpos = -np.ones(m.m, dtype=np.int64)
        kpos[kept] = np.arange(len(kept))
        pairs = np.zeros((len(kept), 2), dtype=np.int64)
        for (bi, bj), rows in zip(self.prim[1], self.prim[4], strict=True):
            for r in rows[rows >= 0]:
                if kpos[r] >= 0:
                    pairs[kpos[r]] = (bi, bj)
        rank = _breadth_first(m.N + 1, pairs)
        rank[m.N] = -1  # the ground first: its rows couple one body only
        body_of = (m.sel // 6)[dep]
        rows = np.lexsort((rank[pairs].max(axis=1), rank[pairs].min(axis=1))).astype(np.int64)
        cols = np.lexsort((dep, rank[body_of])).astype(np.int64)
        r = len(dep)
        if r == 0:
            return rows, cols, 0, 0
        touches = (body_of[cols][None, :] == pairs[rows][:, :1]) | (body_of[cols][None, :] == pairs[rows][:, 1:])
        i, j = np.nonzero(touches)
        kl, ku = int(max(0, np.max(i - j))), int(max(0, np.max(j - i)))
        if kl + ku > r // 2:
            kl = ku = r - 1
        return rows, cols, kl, ku

    def commit(self, refs: np.ndarray) -> None:
        """Angle references after an accepted step (what ``MultibodyModel.commit`` does on the Python path)."""
        if self.angles:
            values = refs.tolist()
            for s, c in self.angles:
                c.reference = values[s]


def _body_blocks(pattern: np.ndarray, body: np.ndarray, count: int, n: int, r: int, kept: np.ndarray,
                 pairs: np.ndarray) -> np.ndarray:
    """Order of the saddle-point unknowns by bodies: the bodies (and the ground, index ``count``) in reverse
    Cuthill-McKee order of their coupling graph, each body's slots together, each kept constraint row just
    before the slots of the later of its two bodies (between the bodies it joins). For a chain of rigid bodies
    on revolute joints the consistent-acceleration matrix's band is then 10 and the iteration matrix's 16,
    against 20 for both from reverse Cuthill-McKee of the unknowns."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    onehot = np.zeros((n, count), dtype=float)
    onehot[np.arange(n), body] = 1.0
    coupled = np.zeros((count + 1, count + 1), dtype=bool)  # the ground last: a node of the graph like a body
    coupled[:count, :count] = (onehot.T @ pattern[:n, :n].astype(float) @ onehot) != 0
    for (bi, bj), rows in zip(pairs, kept, strict=True):
        if np.any(rows >= 0):
            coupled[bi, bj] = coupled[bj, bi] = True
    rank = np.empty(count + 1, dtype=np.int64)
    rank[reverse_cuthill_mckee(csr_matrix(coupled), symmetric_mode=True)] = np.arange(count + 1)
    placed = np.empty(n + r, dtype=np.int64)  # the body rank each unknown goes with
    placed[:n] = 2 * rank[body] + 1
    for (bi, bj), rows in zip(pairs, kept, strict=True):
        placed[n + rows[rows >= 0]] = 2 * max(rank[bi], rank[bj])  # before the later body's slots
    return np.lexsort((np.arange(n + r), placed)).astype(np.int64)


def _breadth_first(count: int, pairs: np.ndarray) -> np.ndarray:
    """Rank of each of ``count`` nodes in a breadth-first walk of the graph with edges ``pairs`` (each connected
    component from its lowest node)."""
    neighbours: list[list[int]] = [[] for _ in range(count)]
    for a, b in pairs:
        neighbours[a].append(b)
        neighbours[b].append(a)
    rank = -np.ones(count, dtype=np.int64)
    k = 0
    for start in range(count):
        if rank[start] >= 0:
            continue
        rank[start] = k
        k += 1
        queue = [start]
        while queue:
            node = queue.pop(0)
            for other in neighbours[node]:
                if rank[other] < 0:
                    rank[other] = k
                    k += 1
                    queue.append(other)
    return rank


def _view(ip: np.ndarray, fp: np.ndarray, entry: int, shape: tuple) -> np.ndarray:
    """Writable view of a float entry of a packed plan."""
    offset = int(ip[kernels._HEAD * entry + 1])
    return fp[offset:offset + int(np.prod(shape))].reshape(shape)
