"""A multibody model driven in macro steps with held inputs: what the FMU wraps.

:class:`MultibodySimulator` assembles the initial state (consistent poses and velocities,
mobility report), steps a formulation with ``ceil(H / max_step)`` equal substeps per macro
step ``H`` for an input held over the macro step (a changed input triggers the formulation's
restart), keeps the energy account and computes the outputs:

* displacement ``x`` (translation of the cg from equilibrium, rotation vector of the rotation
  from the equilibrium orientation) and world-frame velocity ``v`` on the model's coordinates;
* joint coordinates and their rates; joint reactions: force and moment (about the joint point)
  exerted by body 1 (or the ground) on body 2, world frame, from the kept constraint rows'
  multipliers (with redundant constraints the split between redundant joints is one of many
  statically admissible ones: the redundant rows carry none);
* PTO coordinate, rate, force and absorbed power; force element outputs;
* energy: kinetic ``T``, potential ``V`` (gravity, static loads, springs), dissipated ``D`` and
  external work ``W`` (inputs, PTO force commands, catenary lines, prescribed motion), the last
  two integrated by the trapezoidal rule over each substep (error O(h^2)); the balance
  ``T + V + D - W - (T0 + V0)`` is zero for exact solutions. ``pto`` is the part of ``D``
  dissipated by the PTOs' laws (their damping: the energy they convert), integrated the same way.
"""

from __future__ import annotations

import math

import numpy as np

from . import kernels
from .assembly import MobilityReport, analyse, assemble, check_start
from .force_elements import CoordinateSpringDamper
from .formulations import Index3, Settings, make_formulation
from .kinematics import Pose
from .model import MultibodyModel


class MultibodySimulator:
    """Model + formulation + substepping + outputs (module docstring)."""

    # The fused macro step also computes the outputs at its end (a host that reads them every step, as the FMU
    # does, saves a second call); False: outputs computed when first read (a loop that reads few of them).
    eager_outputs = False
    # defaults of attributes that states saved by earlier versions lack (plain attribute reads on the per-step path)
    fused = True  # False: never one compiled call per macro step (comparisons, benchmarks)
    _commands_changed = False  # PTO commands changed (set_pto_commands(defer=True)), not yet taken by a restart
    _buffers: FusedBuffers | None = None
    dissipated = work = pto_energy = energy0 = 0.0  # energy sums (J), set by start

    def __init__(self, model: MultibodyModel, settings: Settings, max_step: float = 0.0,
                 ptos: list[CoordinateSpringDamper] = ()) -> None:
        self.model = model
        self.settings = settings
        self.max_step = float(max_step)
        self.ptos = list(ptos)
        # positions of the PTOs among the model's elements (indices survive the deep copies of FMU states)
        self._pto_index = [i for i, e in enumerate(model.elements) if any(e is p for p in self.ptos)]
        self.formulation = make_formulation(model, settings)
        self.report: MobilityReport | None = None

    # ------------------------------------------------------------------ start
    def start(self, pose: Pose, v: np.ndarray, t: float = 0.0, inputs: np.ndarray | None = None) -> float:
        """Analyse mobility, assemble a consistent state and initialise; returns the assembly correction."""
        self.report = analyse(self.model, pose, t)
        given = pose
        pose, v, moved = assemble(self.model, pose, np.asarray(v, float), t)
        note = check_start(self.model, given, pose, t)
        self.report = analyse(self.model, pose, t)
        self.report.note = note
        k = self.model.kin(pose, v, t)
        for e in self.model.elements:
            e.start(k)
        self.formulation.initialize(pose, v, t, inputs)
        self.energy0 = self.mechanical_energy()
        self.dissipated = 0.0
        self.work = 0.0
        self.pto_energy = 0.0
        self._outputs = None  # computed before energy0 existed: their balance was not the balance
        self._powers = self.powers()
        return moved

    # ------------------------------------------------------------------ rollback (FMU states in memory)
    def rollback_state(self, previous=None):  # noqa: ANN001, ANN201 - fmu_base.rollback.Snapshot | None
        """What a step may change, saved in place (:func:`fmu_base.rollback.snapshot`; ``previous``: an earlier one,
        whose walk is reused while the graph keeps its shape), or None (MoorDyn lines: their state is MoorDyn's own;
        the FMU state is then a deep copy)."""
        from fmu_base.rollback import snapshot

        return snapshot(self, previous)

    def restore_rollback_state(self, data) -> None:  # noqa: ANN001 - fmu_base.rollback.Snapshot
        from fmu_base.rollback import restore

        restore(data)

    # ------------------------------------------------------------------ stepping
    def advance(self, h: float, inputs: np.ndarray | None = None, restart: bool = False) -> None:
        """Step over ``h`` seconds with ``inputs`` (generalised slot forces) held; ``restart``: a force element's
        input changed (e.g. :class:`LinearisedInputForce`), restart the formulation even if ``inputs`` did not.

        On the compiled index-3 path the whole macro step (restart, substeps, energy account, outputs) is one
        compiled call (:meth:`_advance_fused`); anything it does not cover takes the step by step path below,
        which gives the same state within round-off."""
        n = max(1, math.ceil(h / self.max_step - 1e-9)) if self.max_step > 0 else 1
        f = self.formulation
        if not restart and self._advance_fused(h, n, inputs):
            return
        if self._commands_changed:
            self._commands_changed = False
            f.on_restart()
        if inputs is not None or restart:
            if not (inputs is not None and f.set_inputs(inputs)) and restart:
                f.on_restart()
            # The held input's power at the start of the step (the trapezoidal rule below must pair the
            # same input at both ends of each substep: mixing in the previous step's input is an O(h) error).
            self._powers = self.powers()
        for _ in range(n):
            self._substep(h, n)

    def _substep(self, h: float, n: int) -> None:
        """One of the ``n`` substeps of a macro step ``h``, with the trapezoidal energy sums."""
        self.formulation.step(h / n)
        powers = self.powers()
        self.dissipated += 0.5 * h / n * (self._powers[0] + powers[0])
        self.work += 0.5 * h / n * (self._powers[1] + powers[1])
        self.pto_energy += 0.5 * h / n * (self._powers[2] + powers[2])
        self._powers = powers

    def _advance_fused(self, h: float, n: int, inputs: np.ndarray | None) -> bool:
        """The macro step in one compiled call (:func:`mbd_fmu.kernels.ga_macro_step`) on the compiled index-3
        path; False (nothing changed) where it does not apply: another formulation or the Python path, kept
        constraint rows due for re-selection, a singular consistent acceleration or a first substep that does not
        converge (the step by step path then repeats the step with its own fallbacks and error messages).

        The thin per-step path: the call's buffers, energy argument and layout are kept between steps
        (:class:`FusedBuffers`, rebuilt when the formulation, its compiled view, the kept rows, the PTOs or the
        outputs choice change) and the state reached is written in place into the arrays the formulation holds
        (:meth:`FusedBuffers.take`); a copy of the state (FMU state, checkpoint) holds copies of them."""
        f = self.formulation
        if not isinstance(f, Index3) or not self.fused:
            return False
        f.check_model()
        m = self.model
        cm = f.compiled
        if cm is None:
            return False
        if len(m.kept) != m.m:  # redundant constraints: only if the kept rows stay (Formulation.reselect_rows)
            quality = f._quality
            if quality is None or quality[0] != f.steps or not f.rows_hold(quality[1]):
                return False
        held = f.inputs
        if inputs is None:  # held
            inputs, changed = held, False
        else:
            inputs = np.asarray(inputs, dtype=float)
            changed = inputs.tolist() != held.tolist()  # (np.array_equal's answer, for a fraction of its cost)
            inputs = inputs.copy() if changed else held
        settings = f.settings
        mode = settings.restart
        consistent = mode != "none" and (self._commands_changed or changed)
        shift = 1 if f.a is None or (consistent and mode != "increment") else (2 if consistent else 0)
        buffers = self._buffers
        if buffers is None or not buffers.serves(f, cm, m.kept, self.eager_outputs):
            buffers = self._buffers = FusedBuffers(self)
        end = f.end_powers  # the powers now, from the step that led here (None after a restart or new commands)
        if not (consistent or changed) and end is not None and end[0] == f.steps:
            energy = buffers.energy  # with the start powers: the kernel need not evaluate them
            energy[:] = (self.dissipated, self.work, self.pto_energy, self.energy0, *self._powers)
        else:
            energy = buffers.energy_sums
            energy[:] = (self.dissipated, self.work, self.pto_energy, self.energy0)
        status, done, iterations, retries, _, stiff, _, _ = f.fused(  # (positional: the per-step path)
            h, n, consistent, shift, None, None, inputs, energy, buffers.ptos, False, buffers.target())
        if done == 0:
            return False
        self._commands_changed = False
        if changed:
            f.inputs = inputs
        f.newton_iterations += iterations
        f.newton_retries += retries
        if stiff:
            f.stiff_restarts += 1
        hs = h / n
        for _ in range(done):
            f.t += hs
        f.steps += done
        outputs = buffers.take(self)
        if done == n and self.eager_outputs:
            self._outputs = ((f.steps, f.t, id(f.pose), id(f.lam)), outputs)
        elif done == n:
            self._outputs = None  # computed when read (compiled_outputs)
        else:  # stopped early (rows to re-select, a substep that did not converge): the rest step by step
            self._outputs = None
            for _ in range(n - done):
                self._substep(h, n)
        return True

    def _energy_sums(self) -> np.ndarray:
        """(dissipated energy, external work, PTO energy, initial mechanical energy): the fused call's ``energy``."""
        return np.array([self.dissipated, self.work, self.pto_energy, self.energy0])

    def _pto_springs(self) -> np.ndarray:
        """Positions of the PTOs among the compiled springs (the fused call's PTO power and outputs; the same for
        every compiled view of the model: an FMU's input-force element is not a spring)."""
        positions = getattr(self, "_pto_positions", None)
        if positions is None:
            cm = self.formulation.compiled
            positions = self._pto_positions = np.array([cm.spring_position[id(self.model.elements[i])]
                                                        for i in self._pto_index], dtype=np.int64)
        return positions

    def _split_outputs(self, flat: np.ndarray, at: np.ndarray | None = None) -> dict:
        """The named parts (views, the scalars as 0-d arrays: the kept buffers of :class:`FusedBuffers` are
        rewritten in place) of :func:`mbd_fmu.kernels.outputs`' flat array, or (``at``: its offsets) of the fused
        call's output ``flat``, which then also serves :meth:`output_values`."""
        values = None
        if at is not None:
            values, flat = flat, flat[at[11]:at[12]]
        nb, nj, nc = self.model.N, len(self.model.joints), len(self.formulation.compiled.coordinates)
        k = self._outputs_offsets()
        scalar = {key: flat[k[key]:k[key] + 1].reshape(()) for key in ("kinetic", "potential", "violation")}  # views
        return {"values": values, "layout": at, "displacement": flat[:k["kinetic"]].reshape(nb, 6), **scalar,
                "reactions": flat[k["reactions"]:k["coordinates"]].reshape(nj, 6),
                "coordinates": flat[k["coordinates"]:k["spring_forces"]].reshape(nc, 2),
                "spring_forces": flat[k["spring_forces"]:]}

    def _outputs_offsets(self) -> dict[str, int]:
        """Offsets of the parts of :func:`mbd_fmu.kernels.outputs`' flat array: the bodies' displacements (N, 6)
        first, then kinetic and potential energy, constraint violation, joints' reactions (J, 6), compiled
        coordinates' values and rates (S, 2), compiled springs' forces (E,)."""
        nb, nj, nc = self.model.N, len(self.model.joints), len(self.formulation.compiled.coordinates)
        o = 6 * nb + 3
        return {"displacement": 0, "kinetic": 6 * nb, "potential": 6 * nb + 1, "violation": 6 * nb + 2,
                "reactions": o, "coordinates": o + 6 * nj, "spring_forces": o + 6 * nj + 2 * nc}

    def set_pto_commands(self, stiffness, damping, force, defer: bool = False) -> None:
        """New PTO law parameters (stiffness, damping, force command per PTO); a change restarts the formulation,
        now or (``defer``) at the start of the next :meth:`advance`, together with a change of its inputs."""
        changed = False
        for p, k, c, u in zip(self.ptos, stiffness, damping, force, strict=True):
            if (p.stiffness, p.damping, p.force_command) != (k, c, u):
                p.set_command(k, c, u)
                changed = True
        if changed:
            self.formulation.end_powers = None
            self._outputs = None  # the PTO forces of the kept outputs were those of the old commands
            if defer:
                self._commands_changed = True
            else:
                self.formulation.on_restart()

    # ------------------------------------------------------------------ outputs
    @property
    def kin(self):
        f = self.formulation
        return self.model.kin(f.pose, f.v, f.t)

    @property
    def time(self) -> float:
        return self.formulation.t

    def compiled_outputs(self) -> dict | None:
        """The outputs of the current state from one compiled call (:func:`mbd_fmu.kernels.outputs`), kept until
        the state changes; None on the Python path."""
        f = self.formulation
        cm = f.compiled
        if cm is None:
            return None
        key = (f.steps, f.t, id(f.pose), id(f.lam))  # set_pto_commands drops the kept outputs
        cached = getattr(self, "_outputs", None)
        if cached is not None and cached[0] == key:
            return cached[1]
        if isinstance(f, Index3):  # its one compiled entry point
            _, _, _, _, _, _, flat, at = f.fused(0.0, 0, energy=self._energy_sums(), ptos=self._pto_springs(),
                                                 outputs=True)
            out = self._split_outputs(flat, at)
        else:
            out = self._split_outputs(kernels.outputs(*cm.plan(), f.pose.r, f.pose.R, f.v, f.lam, cm.refs))
        self._outputs = (key, out)
        return out

    def output_values(self) -> np.ndarray | None:
        """Every output of the current state in one flat array (layout: :meth:`output_layout`): the fused call's
        output on the compiled index-3 path, None elsewhere."""
        out = self.compiled_outputs()
        return None if out is None else out["values"]

    def output_layout(self) -> dict[str, int]:
        """Offsets in :meth:`output_values` (:func:`mbd_fmu.kernels.macro_layout`): the cg positions (N, 3), the
        velocities (n,), dissipated energy, external work, PTO energy, the bodies' displacements (N, 6), kinetic and
        potential energy, constraint violation, joints' reactions (J, 6: force, moment), compiled coordinates'
        values and rates (S, 2), compiled springs' forces (E,) (:func:`mbd_fmu.kernels.outputs`), the energy
        balance and the PTOs' (coordinate from neutral, rate, force, absorbed power) (P, 4)."""
        at = self.formulation._offsets(len(self.ptos))
        o = int(at[11])
        return {"r": int(at[2]), "v": int(at[4]), "energy": int(at[7]), "balance": int(at[12]), "pto": int(at[12]) + 1,
                **{key: o + k for key, k in self._outputs_offsets().items()}}

    def displacement(self, d: np.ndarray | None = None) -> np.ndarray:
        """x on the model's coordinates: (n,), from the bodies' displacements ``d`` (N, 6) if already known."""
        if d is None:
            out = self.compiled_outputs()
            d = out["displacement"] if out is not None else self.model.displacement(self.formulation.pose)
        return np.array([d[self.model.index(b), dof] for b, dof in self.model.coordinates])

    def velocity(self) -> np.ndarray:
        return self.formulation.v.copy()

    def mechanical_energy(self) -> float:
        out = self.compiled_outputs()
        if out is not None:
            return float(out["kinetic"] + out["potential"])
        f = self.formulation
        return self.model.kinetic_energy(f.pose, f.v) + self.model.potential_energy(self.kin)

    def powers(self) -> tuple[float, float, float]:
        """(dissipated power, power supplied from outside, power dissipated by the PTOs) now."""
        m, f = self.model, self.formulation
        cm = f.compiled
        if cm is not None:
            end = getattr(f, "end_powers", None)  # (absent from states saved by earlier versions)
            if end is not None and end[0] == f.steps:  # computed by the step that led here
                diss, supply, springs = end[1:]
            elif isinstance(f, Index3):  # its one compiled entry point (PTO commands and references of now)
                _, _, _, _, _, _, out, at = f.fused(0.0, 0)
                diss, supply, springs = float(out[at[8]]), float(out[at[8] + 1]), out[at[9]:at[10]]
            else:
                diss, supply, springs = kernels.powers(*cm.plan(), f.pose.r, f.pose.R, f.v, f.inputs, cm.refs)
            return diss, supply, sum(float(springs[cm.spring_position[id(m.elements[i])]]) for i in self._pto_index)
        k = self.kin
        powers = [e.powers(k) for e in m.elements]
        diss = sum(p[0] for p in powers)
        pto = sum(powers[i][0] for i in self._pto_index)
        supply = sum(p[1] for p in powers) + float(f.inputs @ f.v)
        if len(f.lam) and m.drivers:  # -Phi_t is non-zero only on driver rows
            supply -= float(f.lam @ m.velocity_rhs(f.t))
        return diss, supply, pto

    def energy(self) -> dict[str, float]:
        f = self.formulation
        out = self.compiled_outputs()
        if out is not None:
            t, v = float(out["kinetic"]), float(out["potential"])
        else:
            t = self.model.kinetic_energy(f.pose, f.v)
            v = self.model.potential_energy(self.kin)
        return {"kinetic": t, "potential": v, "dissipated": self.dissipated, "external_work": self.work,
                "pto": self.pto_energy,
                "balance": t + v + self.dissipated - self.work - self.energy0}

    def constraint_violation(self) -> float:
        out = self.compiled_outputs()
        if out is not None:
            return float(out["violation"])
        phi = self.model.constraint_full(self.kin, gamma=False, jac=False)[0]
        return float(np.max(np.abs(phi))) if phi.size else 0.0

    def joint_coordinates(self) -> list[tuple[np.ndarray, np.ndarray]]:
        compiled = self.compiled_outputs()
        if compiled is not None and self.formulation.compiled.joint_coordinates is not None:
            values = compiled["coordinates"]
            return [(values[p, 0], values[p, 1]) for p in self.formulation.compiled.joint_coordinates]
        if compiled is not None:
            index = self.formulation.compiled.coordinate_position
            values = compiled["coordinates"]
        k = self.kin  # here some joint coordinate is not compiled (or nothing is): the Python side reads it
        out = []
        for cj in self.model.joints:
            if compiled is not None:
                vals = [values[index[id(c)]] if id(c) in index else c.rate(k)[:2] for c in cj.coordinates]
            else:
                vals = [c.rate(k) for c in cj.coordinates]
            out.append((np.array([v[0] for v in vals]), np.array([v[1] for v in vals])))
        return out

    def reactions(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Per joint: force and moment about the joint point on body 2 from body 1 (world)."""
        compiled = self.compiled_outputs()
        if compiled is not None:
            return [(r[:3].copy(), r[3:].copy()) for r in compiled["reactions"]]
        m, f = self.model, self.formulation
        k = self.kin
        lam = np.zeros(m.m)
        lam[m.kept] = f.lam
        _, jf, _, _ = m.constraint_full(k, gamma=False)
        out = []
        for cj in m.joints:
            b2 = cj.m2.body
            rows = cj.rows
            gen = -jf[rows, 6 * b2:6 * b2 + 6].T @ lam[rows]
            point = k.rr[b2] + k.RR[b2] @ cj.m2.offset
            moment = gen[3:] + np.cross(k.rr[b2] - point, gen[:3])
            out.append((gen[:3], moment))
        return out

    def element_outputs(self, elements: list | None = None) -> list[np.ndarray]:
        """Outputs of ``elements`` (default: every force element, in the model's order;
        :meth:`~mbd_fmu.force_elements.ForceElement.output`): from the compiled outputs where the element is
        compiled (ropes' tensions, springs' and friction's forces), else from the Python element (the kinematics
        built once, only if one needs it)."""
        compiled = self.compiled_outputs()
        position = self.formulation.compiled.spring_position if compiled is not None else {}
        k = None
        out = []
        for e in self.model.elements if elements is None else elements:
            i = position.get(id(e))
            if i is not None:
                out.append(compiled["spring_forces"][i:i + 1].copy())
                continue
            k = self.kin if k is None else k
            out.append(e.output(k))
        return out

    def pto_outputs(self) -> np.ndarray:
        """(n_pto, 4): coordinate from neutral, rate, force, absorbed power."""
        compiled = self.compiled_outputs()
        if compiled is not None:
            cm = self.formulation.compiled
            coords, forces = compiled["coordinates"], compiled["spring_forces"]
            out = np.empty((len(self.ptos), 4))
            for row, p in zip(out, self.ptos, strict=True):
                q, v = coords[cm.coordinate_position[id(p.coordinate)]].tolist()
                force = forces.item(cm.spring_position[id(p)])
                row[:] = (q - p.neutral, v, force, -force * v)
            return out
        k = self.kin
        rows = []
        for p in self.ptos:
            x, v, _ = p.state(k)
            force = p.law_force(x, v)
            rows.append((x, v, force, -force * v))
        return np.array(rows).reshape(len(self.ptos), 4)


class FusedBuffers:
    """What :meth:`MultibodySimulator._advance_fused` keeps between macro steps for one formulation, compiled view,
    kept-row set and outputs choice: the layout of the fused call's output (:func:`mbd_fmu.kernels.macro_layout`),
    two output buffers the calls write in turn (each call reads the state from the one the last call wrote: the
    formulation's pose, v', lambda, v and a are views of it, so no new arrays per step and no copy; a call that fails
    leaves the state untouched), the energy argument, the PTOs' spring positions and, with eager outputs, the named
    views of each buffer's outputs (:meth:`MultibodySimulator._split_outputs`).

    Derived data, not state: a copy (deep copy, FMU state, checkpoint) is an empty instance that serves nothing,
    and the next step builds new buffers; the copied formulation's arrays are copies, not views of these."""

    formulation = None  # (an empty instance serves nothing)

    def __init__(self, sim: MultibodySimulator) -> None:
        f, m = sim.formulation, sim.model
        cm = f.compiled
        self.formulation, self.compiled, self.kept, self.eager = f, cm, m.kept, sim.eager_outputs
        self.ptos = sim._pto_springs()
        at = self.at = f._offsets(len(self.ptos))
        nn = m.n + len(m.kept)
        if f._lu is None or f._lu.shape[0] != nn:
            f._lu, f._piv = np.empty((nn, nn)), np.zeros(nn, dtype=np.int64)
        self.sides = []  # per buffer: (the buffer, Index3.take_fused's views of it, its named outputs)
        for _ in range(2):
            out = np.empty(at[-1] if self.eager else at[11])
            self.sides.append((out, f.fused_views(out, at), sim._split_outputs(out, at) if self.eager else None))
        self.written = 1  # the side the last call wrote (the next call writes the other)
        self.energy = np.zeros(7)  # energy sums, initial energy, start powers (the kernel's ``energy``)
        self.energy_sums = self.energy[:4]

    def __getstate__(self) -> dict:
        return {}

    def __setstate__(self, state: dict) -> None:
        self.__dict__.clear()

    def serves(self, f: Index3, cm: object, kept: np.ndarray, eager: bool) -> bool:
        return f is self.formulation and cm is self.compiled and kept is self.kept and eager == self.eager

    def target(self) -> np.ndarray:
        """The buffer the next call writes: not the one the formulation's state is a view of."""
        return self.sides[1 - self.written][0]

    def take(self, sim: MultibodySimulator) -> dict | None:
        """The state the call reached (in :meth:`target`) into the simulator and its formulation (``t`` and
        ``steps`` are the caller's): v', lambda, pose, v, a as views of that buffer, the angle references' commit,
        the row quality, the end powers, the energy sums; returns that buffer's named outputs (eager outputs)."""
        self.written = w = 1 - self.written
        out, views, outputs = self.sides[w]
        sim.dissipated, sim.work, sim.pto_energy, diss, supply, pto = sim.formulation.take_fused(out, self.at, views)
        sim._powers = (diss, supply, pto)
        return outputs
