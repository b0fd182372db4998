"""Dynamic mooring lines: MoorDyn (lumped-mass line dynamics) stepped inside the multibody model.

MoorDyn v2 (Hall & Goupee 2015; the ``moordyn`` package) discretises each line into lumped
masses joined by axial spring-dampers, with hydrodynamic drag and added mass (Morison, normal
and axial), buoyancy, and a penalty sea bed (stiffness and damping per unit area), and
integrates them with an explicit scheme (default RK2, 2nd order) at its own step ``dtM``, which
must stay below the axial wave's Courant limit (segment length / sqrt(EA / mass per length)).

Coupling (:class:`MoorDynSystem`): every line's fairlead is a MoorDyn *coupled point* (3 DOF);
its position and velocity follow from the body it is attached to, so MoorDyn never sees an
angle convention. The multibody model steps MoorDyn when it accepts a step: from the fairleads
at ``t_n`` to those at ``t_n+1`` (MoorDyn moves each coupled point linearly between them, with
the chord velocity, sub-cycling ``ceil(h / dtM)`` steps of its own), and MoorDyn returns the line
forces at ``t_n+1``. During the next step the force on the body is the linear extrapolation
of the last two accepted forces, ``F(t) = F_n + (F_n - F_n-1) (t - t_n) / (t_n - t_n-1)``, a
function of time only: the implicit integrator's Newton iterations and rejected steps never
touch MoorDyn. The coupling is explicit (a one-step lag, second order by the extrapolation);
it is stable while the fairlead's instantaneous stiffness (EA over the first segment's length)
times h^2 stays small against the body's mass (added mass included), which the RM3 mooring
satisfies by orders of magnitude (docs/scenarios.md). The line's work on the body is booked as
external work, like the quasi-static catenary's.

State: MoorDyn's own state (node positions and velocities, time) is serialised by MoorDyn
(``moordyn.Serialize``) into bytes; with the fairlead positions, the last two forces and times
it is the element's whole state, plain data (:meth:`MoorDynSystem.__getstate__`). Copies of the
model (an FMU state) share one live MoorDyn instance: a copy holds a snapshot, and the copy that
is used next loads it into the instance (saving the current user's state first), so rollback,
checkpoints and resumes restore the lines exactly.
"""

from __future__ import annotations

import contextlib
import copy
import ctypes
import dataclasses
import math
import os
import shutil
import tempfile
import weakref
from dataclasses import dataclass

import numpy as np

from .force_elements import ForceElement
from .kinematics import Kin
from .rotations import cross

SCHEMES = ("RK2", "RK4", "Euler", "Heun", "AB3", "AB4")


@dataclass(frozen=True)
class LineSpec:
    """One line from an anchor on the sea bed to a fairlead on a body.

    Attributes:
        name: line name.
        body: index of the body of the fairlead.
        offset: fairlead from the body's centre of gravity, body axes (m).
        anchor: anchor (world, m); MoorDyn's sea bed is at the anchors' depth.
        length: unstretched length (m).
        weight: submerged weight per length (N/m); MoorDyn's mass per length is
            ``weight / g + rho pi d^2 / 4``, so both mooring models see the same weight.
        ea: axial stiffness (N).
        diameter: volume-equivalent diameter (m): buoyancy, drag and added mass.
        normal_drag, axial_drag: drag coefficients on ``diameter`` (normal) and ``pi diameter`` (axial).
        normal_added_mass, axial_added_mass: added-mass coefficients.
        segments: number of segments.
        damping_ratio: axial internal damping of each segment, fraction of critical.
    """

    name: str
    body: int
    offset: np.ndarray
    anchor: np.ndarray
    length: float
    weight: float
    ea: float
    diameter: float
    normal_drag: float = 1.2
    axial_drag: float = 0.4
    normal_added_mass: float = 1.0
    axial_added_mass: float = 0.0
    segments: int = 40
    damping_ratio: float = 0.8


@dataclass(frozen=True)
class MoorDynSettings:
    """MoorDyn's solver options.

    Attributes:
        time_step: MoorDyn's step dtM (s).
        scheme: time scheme (MoorDyn's ``tScheme``; RK2 is MoorDyn's default).
        seabed_stiffness: sea-bed contact stiffness per unit area (Pa/m).
        seabed_damping: sea-bed contact damping per unit area (Pa s/m).
        ic_time: longest dynamic relaxation for the initial shape (s).
        ic_tolerance: relaxation stops when the largest node acceleration falls below this (m/s^2).
        rho, g: water density (kg/m^3), gravity (m/s^2).
    """

    time_step: float = 0.002
    scheme: str = "RK2"
    seabed_stiffness: float = 3.0e6
    seabed_damping: float = 3.0e5
    ic_time: float = 120.0
    ic_tolerance: float = 1e-4
    rho: float = 1025.0
    g: float = 9.81


class MoorDynError(RuntimeError):
    """MoorDyn failed (the message carries MoorDyn's own explanation)."""


def moordyn_input(lines: list[LineSpec], settings: MoorDynSettings, fairleads: np.ndarray) -> str:
    """MoorDyn v2 input file: one line type and one line per :class:`LineSpec`, fairleads (world,
    at the start) as coupled points 1..n, anchors as fixed points n+1..2n."""
    depths = {round(-float(s.anchor[2]), 9) for s in lines}
    if len(depths) != 1:
        raise ValueError(f"MoorDyn lines need every anchor on one sea bed (anchor depths {sorted(depths)} m)")
    depth = depths.pop()
    s = settings
    out = ["MoorDyn v2 input file written by wec-cosim (mbd_fmu.moordyn_lines)",
           "---------------------- LINE TYPES ----------------------",
           "TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx",
           "(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)"]
    for i, ln in enumerate(lines):
        mass = ln.weight / s.g + s.rho * math.pi * ln.diameter ** 2 / 4
        out.append(f"type{i + 1} {ln.diameter!r} {mass!r} {ln.ea!r} {-ln.damping_ratio!r} 0.0 {ln.normal_drag!r} "
                   f"{ln.normal_added_mass!r} {ln.axial_drag!r} {ln.axial_added_mass!r}")
    out += ["---------------------- POINTS ----------------------",
            "ID Attachment X Y Z Mass Volume CdA CA",
            "(#) (-) (m) (m) (m) (kg) (m^3) (m^2) (-)"]
    n = len(lines)
    for i, p in enumerate(fairleads):
        out.append(f"{i + 1} Coupled {p[0]!r} {p[1]!r} {p[2]!r} 0 0 0 0")
    for i, ln in enumerate(lines):
        a = ln.anchor
        out.append(f"{n + i + 1} Fixed {float(a[0])!r} {float(a[1])!r} {float(a[2])!r} 0 0 0 0")
    out += ["---------------------- LINES ----------------------",
            "ID LineType AttachA AttachB UnstrLen NumSegs Outputs",
            "(#) (name) (#) (#) (m) (-) (-)"]
    for i, ln in enumerate(lines):
        out.append(f"{i + 1} type{i + 1} {n + i + 1} {i + 1} {ln.length!r} {int(ln.segments)} -")
    out += ["---------------------- OPTIONS ----------------------",
            f"{s.time_step!r} dtM", f"{s.scheme} tScheme", f"{s.rho!r} WtrDnsty", f"{s.g!r} g", f"{depth!r} WtrDpth",
            f"{s.seabed_stiffness!r} kBot", f"{s.seabed_damping!r} cBot", f"{s.ic_time!r} TmaxIC",
            f"{s.ic_tolerance!r} threshIC", "0 writeLog", "1 disableOutput", "1 disableOutTime",
            "---------------------- END ----------------------"]
    return "\n".join(out) + "\n"


@contextlib.contextmanager
def _captured(path: str):
    """Redirect the process's stdout and stderr (file descriptors: MoorDyn prints from C++) to ``path``."""
    import sys

    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    with open(path, "wb") as f:
        os.dup2(f.fileno(), 1)
        os.dup2(f.fileno(), 2)
        try:
            yield
        finally:
            with contextlib.suppress(Exception):
                ctypes.CDLL(None).fflush(None)
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])


def _tail(path: str, lines: int = 6) -> str:
    """The last error lines MoorDyn wrote (for messages)."""
    try:
        text = open(path, errors="replace").read().splitlines()
    except OSError:
        return ""
    errors = [t.strip() for t in text if t.startswith(("ERR", "Error", "WRN"))] or [t.strip() for t in text if t]
    return "; ".join(errors[-lines:])


class _Instance:
    """A live MoorDyn system (C object) and its folder; closed when the last user is gone."""

    def __init__(self, text: str, x: np.ndarray, v: np.ndarray, *, compute_ic: bool) -> None:
        import moordyn

        self.folder = tempfile.mkdtemp(prefix="wec-cosim-moordyn-")
        path = os.path.join(self.folder, "lines.txt")
        with open(path, "w") as f:
            f.write(text)
        self.console = os.path.join(self.folder, "console.txt")
        self.system = None
        self.owner: weakref.ref | None = None
        try:
            with _captured(self.console):
                self.system = moordyn.Create(path)
                moordyn.SetVerbosity(self.system, moordyn.LEVEL_NONE)
                (moordyn.Init if compute_ic else moordyn.Init_NoIC)(self.system, list(x), list(v))
            self.log = os.path.join(self.folder, "errors.txt")
            moordyn.SetLogFile(self.system, self.log)
            moordyn.SetLogLevel(self.system, moordyn.LEVEL_ERR)
        except RuntimeError as exc:
            detail = _tail(self.console)
            self.close()
            raise MoorDynError(f"MoorDyn could not set up the mooring lines: {exc}"
                               + (f" ({detail})" if detail else "")) from None

    def close(self) -> None:
        if self.system is not None:
            import moordyn

            with contextlib.suppress(Exception), _captured(os.devnull):
                moordyn.Close(self.system)
            self.system = None
        shutil.rmtree(self.folder, ignore_errors=True)

    def __del__(self) -> None:
        with contextlib.suppress(Exception):
            self.close()


class MoorDynSystem:
    """All MoorDyn lines of a model, stepped together (module docstring)."""

    def __init__(self, lines: list[LineSpec], settings: MoorDynSettings, *, file_text: str = "",
                 bodies: np.ndarray | None = None, offsets: np.ndarray | None = None) -> None:
        """``lines``: one line per :class:`LineSpec` (its fairlead a coupled point, the input file written here);
        or, with ``file_text``, a user's MoorDyn input file whose coupled points (in ID order) are attached to
        ``bodies`` (n,) at ``offsets`` (n, 3) from their cgs (body axes); ``lines`` is then empty."""
        self.lines = list(lines)
        self.settings = settings
        self.file_text = file_text
        if file_text:
            self.offsets = np.asarray(offsets, float).reshape(-1, 3)
            self.bodies = np.asarray(bodies, dtype=int)
        else:
            self.offsets = np.array([ln.offset for ln in lines], float).reshape(len(lines), 3)
            self.bodies = np.array([ln.body for ln in lines], dtype=int)
        n = len(self.bodies)
        self.end_tensions = np.zeros((0, 2))  # tension at end A and end B of every line (N), last accepted state
        # MoorDyn's input file: the user's file (from the scenario) or written by moordyn_input from the lines;
        # never read from a state
        self.text = ""
        self.start_fairleads = np.zeros((n, 3))  # fairleads at the start (coupled points of the input file)
        self.t = math.nan  # time of the last accepted state
        self.t_prev = math.nan
        self.x = np.zeros((n, 3))  # fairleads at t
        self.v = np.zeros((n, 3))  # and their velocities
        self.force = np.zeros((n, 3))  # line forces on the bodies at t
        self.force_prev = np.zeros((n, 3))
        self._instance: _Instance | None = None
        self._snapshot: bytes | None = None

    # ------------------------------------------------------------------ kinematics
    def fairleads(self, k: Kin) -> tuple[np.ndarray, np.ndarray]:
        """World positions and velocities (n, 3) of the fairleads."""
        b = self.bodies
        arm = np.einsum("nij,nj->ni", k.RR[b], self.offsets)
        return k.rr[b] + arm, k.W[b, :3] + cross(k.W[b, 3:], arm)

    @property
    def started(self) -> bool:
        return not math.isnan(self.t)

    def start(self, k: Kin) -> None:
        """Create MoorDyn and compute the lines' static shape for the fairleads at ``k`` (at rest)."""
        if self.started:
            return
        x, _ = self.fairleads(k)
        self.start_fairleads = x.copy()
        self.text = self.file_text or moordyn_input(self.lines, self.settings, x)
        instance = _Instance(self.text, x.ravel(), np.zeros(x.size), compute_ic=True)
        self._adopt(instance)
        self.x = x
        self.t = self.t_prev = float(k.t)
        self.v = np.zeros_like(x)
        self.force = self.force_prev = self._step(x, self.v, self.t, 0.0)
        self.end_tensions = self._end_tensions()

    # ------------------------------------------------------------------ forces
    def force_at(self, line: int, t: float) -> np.ndarray:
        """Force of ``line`` on its body at time ``t``: linear extrapolation of the accepted forces."""
        dt = self.t - self.t_prev
        if dt <= 0.0:
            return self.force[line]
        return self.force[line] + (self.force[line] - self.force_prev[line]) * ((t - self.t) / dt)

    def advance(self, k: Kin) -> None:
        """Step MoorDyn to the accepted state ``k`` (once per time; other lines' commits are no-ops).

        The fairleads follow the cubic Hermite path through their positions and velocities at both
        ends, sampled at MoorDyn's own step: ``m = ceil(h / dtM)`` calls, each moving the fairleads
        along a chord of the path (MoorDyn's coupled points move linearly within a call)."""
        h = float(k.t) - self.t
        if h <= 1e-12 * max(1.0, abs(self.t)):
            return
        x1, v1 = self.fairleads(k)
        m = max(1, math.ceil(h / self.settings.time_step - 1e-9))
        s = np.arange(m + 1) / m
        s2, s3 = s * s, s * s * s
        path = (np.multiply.outer(2 * s3 - 3 * s2 + 1, self.x) + np.multiply.outer(s3 - 2 * s2 + s, h * self.v)
                + np.multiply.outer(-2 * s3 + 3 * s2, x1) + np.multiply.outer(s3 - s2, h * v1))
        path[-1] = x1
        dt = h / m
        for j in range(m):
            force = self._step(path[j], (path[j + 1] - path[j]) / dt, self.t + j * dt, dt)
        self.force_prev, self.force = self.force, force
        self.t_prev, self.t = self.t, float(k.t)
        self.x, self.v = x1, v1
        self.end_tensions = self._end_tensions()

    def _step(self, x: np.ndarray, v: np.ndarray, t: float, h: float) -> np.ndarray:
        import moordyn

        instance = self._active()
        try:
            f = moordyn.Step(instance.system, x.ravel().tolist(), v.ravel().tolist(), t, h)
        except RuntimeError as exc:
            detail = _tail(instance.log)
            raise MoorDynError(f"MoorDyn failed at t = {t:g} s: {exc}" + (f" ({detail})" if detail else "")) from None
        return np.asarray(f, float).reshape(len(self.bodies), 3)

    def _end_tensions(self) -> np.ndarray:
        """(n_lines, 2): tension at end A and end B of every line (N; MoorDyn's anchor and fairlead ends)."""
        import moordyn

        system = self._active().system
        n = moordyn.GetNumberLines(system)
        fh, fv, ah, av = (np.asarray(v, float) for v in moordyn.GetFASTtens(system, n))
        return np.column_stack([np.hypot(ah, av), np.hypot(fh, fv)])

    def tensions(self) -> np.ndarray:
        """Fairlead tension of each line at the last accepted state (N)."""
        return np.linalg.norm(self.force, axis=1)

    # ------------------------------------------------------------------ shared instance and state
    def _adopt(self, instance: _Instance) -> None:
        self._instance = instance
        instance.owner = weakref.ref(self)
        self._snapshot = None

    def _active(self) -> _Instance:
        """The live instance, holding this object's state (loading its snapshot if another copy used it)."""
        import moordyn

        instance = self._instance
        if instance is None:  # restored from data: a fresh instance, then the saved state
            instance = _Instance(self.text, self.x.ravel(), np.zeros(self.x.size), compute_ic=False)
            self._instance = instance
        owner = instance.owner() if instance.owner is not None else None
        if owner is self:
            return instance
        if owner is not None and owner._snapshot is None:
            owner._snapshot = moordyn.Serialize(instance.system)
        expected = len(owner._snapshot) if owner is not None else len(moordyn.Serialize(instance.system))
        if self._snapshot is None or len(self._snapshot) != expected:  # checked before MoorDyn reads it
            raise MoorDynError(
                f"the saved MoorDyn state has {len(self._snapshot or b'')} bytes where these lines' state has "
                f"{expected}: the state is damaged or belongs to other mooring lines")
        moordyn.Deserialize(instance.system, self._snapshot)
        instance.owner = weakref.ref(self)
        self._snapshot = None
        return instance

    def serialized(self) -> bytes:
        """MoorDyn's state as bytes (this object's, whether or not it holds the live instance)."""
        import moordyn

        if self._snapshot is not None:
            return self._snapshot
        instance = self._instance
        if instance is None or not self.started:
            return b""
        return moordyn.Serialize(instance.system)

    def __deepcopy__(self, memo: dict) -> MoorDynSystem:
        new = copy.copy(self)
        memo[id(self)] = new
        for key in ("x", "v", "force", "force_prev", "end_tensions"):
            setattr(new, key, getattr(self, key).copy())
        new._snapshot = self.serialized()
        return new

    def __getstate__(self) -> dict:
        """Plain data: line and solver settings (as dicts), fairleads, forces, times (numbers, arrays) and
        MoorDyn's serialised state as a uint8 array. Not the input file's text: it is written again from the
        lines, or is the user's input file, which a state restored into a model must match
        (:meth:`__setstate__`), so a state cannot choose what MoorDyn reads."""
        state = {k: v for k, v in self.__dict__.items()
                 if k not in ("_instance", "_snapshot", "lines", "settings", "text")}
        state["lines"] = [dataclasses.asdict(ln) for ln in self.lines]  # dicts, not objects: data only
        state["settings"] = dataclasses.asdict(self.settings)
        state["moordyn_state"] = np.frombuffer(self.serialized(), dtype=np.uint8).copy()
        return state

    def __setstate__(self, state: dict) -> None:
        """From :meth:`__getstate__`'s data. Decoded onto a live copy (which shares a MoorDyn instance) the
        instance is kept and the state loaded into it when this object is used; otherwise a new instance is
        created then."""
        state = dict(state)
        state.pop("text", None)
        state.setdefault("file_text", "")  # states saved before MoorDyn input files were read
        state.setdefault("end_tensions", np.zeros((0, 2)))
        snapshot = bytes(np.asarray(state.pop("moordyn_state"), dtype=np.uint8))
        try:
            lines = [LineSpec(**d) for d in state["lines"]]
            settings = MoorDynSettings(**state["settings"])
            start = np.asarray(state.get("start_fairleads", np.zeros((len(lines), 3))), dtype=float).reshape(-1, 3)
        except (TypeError, ValueError, KeyError) as exc:
            raise MoorDynError(f"the saved mooring-line state is not one of these lines ({exc})") from None
        own_file = self.__dict__.get("file_text", "")
        if self.__dict__.get("lines") is not None and not (
                _same(lines, self.lines) and settings == self.settings and state["file_text"] == own_file):
            raise MoorDynError("the saved mooring-line state belongs to other lines, another MoorDyn input file "
                               "or other MoorDyn settings than this model's")
        state["lines"], state["settings"], state["start_fairleads"] = lines, settings, start
        started = not math.isnan(float(state.get("t", math.nan)))
        state["text"] = (state["file_text"] or moordyn_input(lines, settings, start)) if started else ""
        instance = self.__dict__.get("_instance")
        self.__dict__.update(state)
        if instance is not None and instance.owner is not None and instance.owner() is self:
            instance.owner = None  # this object's old state in the instance is stale now
        self._instance = instance
        self._snapshot = snapshot or None


def _same(a: list[LineSpec], b: list[LineSpec]) -> bool:
    """Whether two lists of lines are the same lines (arrays compared by value)."""
    return len(a) == len(b) and all(
        all(np.array_equal(np.asarray(x), np.asarray(y)) for x, y in zip(dataclasses.astuple(p), dataclasses.astuple(q),
                                                                          strict=True))
        for p, q in zip(a, b, strict=True))


@dataclass
class MoorDynLine(ForceElement):
    """One line of a :class:`MoorDynSystem` as a force element: its fairlead force on its body."""

    nonlinear = True

    name: str
    system: MoorDynSystem
    index: int

    def _force(self, k: Kin) -> tuple[np.ndarray, np.ndarray, int]:
        s = self.system
        if not s.started:
            s.start(k)
        b = int(s.bodies[self.index])
        return s.force_at(self.index, float(k.t)), k.RR[b] @ s.offsets[self.index], b

    def start(self, k: Kin) -> None:
        self.system.start(k)

    def apply(self, k: Kin, f: np.ndarray) -> None:
        force, a, b = self._force(k)
        f[6 * b:6 * b + 3] += force
        f[6 * b + 3:6 * b + 6] += cross(a, force)

    def supply(self, k: Kin) -> float:
        force, a, b = self._force(k)
        return float(force @ (k.W[b, :3] + cross(k.W[b, 3:], a)))

    def output(self, k: Kin) -> np.ndarray:
        return self._force(k)[0]

    def commit(self, k: Kin) -> None:
        self.system.advance(k)


@dataclass
class MoorDynTensions(ForceElement):
    """The tension at both ends of every line of a :class:`MoorDynSystem` as outputs (no force of its own):
    ``[A_1, B_1, A_2, B_2, ...]`` (N), end A and end B of each line in the input file's order, at the last
    accepted state."""

    name: str
    system: MoorDynSystem
    n_lines: int

    def apply(self, k: Kin, f: np.ndarray) -> None:
        return None

    def output(self, k: Kin) -> np.ndarray:
        if not self.system.started:
            self.system.start(k)
        values = self.system.end_tensions.ravel()
        return values if len(values) == 2 * self.n_lines else np.zeros(2 * self.n_lines)

