"""MoorDyn input files used as they are: what a file holds, and MoorDyn's own static solve of it.

A MoorDyn v2 input file (Hall, "MoorDyn V2 user's guide"; the ``moordyn`` package reads it) describes the
whole mooring: line types, points (``Fixed`` anchors, ``Free`` points: buoys and clump weights through their
mass and volume, and joints of several lines), rods, bodies, lines between any two of them, the sea bed
(``WtrDpth``, ``kBot``, ``cBot``) and solver options. A scene couples it to its bodies through the file's
``Coupled`` points (``Vessel`` in MoorDyn v1 files): each is attached to one scenario body at its position in
the file (world coordinates at equilibrium), moves with that body, and returns the lines' force on it. Coupled
MoorDyn *bodies* and *rods* (6-DOF coupling) are not supported: a file that has them is refused with the
fix (attach the lines to ``Coupled`` points instead).

:func:`read_moordyn_file` reads and checks a file (errors name the file, the line and the fix);
:func:`run_text` is the text MoorDyn runs: the file with its own output files switched off
(``disableOutput``, ``writeLog 0``), since the run records every line's end tensions itself;
:func:`static_solve` is MoorDyn's own static solution of the file (its initial-condition solve) for given
coupled point positions; :func:`body_stiffness` the linearised quasi-static stiffness of the lines on each
coupled body, by central differences of static solves.
"""

from __future__ import annotations

import math
import os
import re
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

COUPLED = ("coupled", "vessel", "cpld")
SECTIONS = {"line types": "line_types", "line dictionary": "line_types", "rod types": "rod_types",
            "rod dictionary": "rod_types", "bodies": "bodies", "body list": "bodies", "body properties": "bodies",
            "rods": "rods", "rod list": "rods", "rod properties": "rods", "points": "points",
            "point list": "points", "point properties": "points", "connection properties": "points",
            "node properties": "points", "lines": "lines", "line list": "lines", "line properties": "lines",
            "options": "options", "outputs": "outputs", "failure": "failure"}


class MoorDynFileError(ValueError):
    """A MoorDyn input file that cannot be used; the message names the file, the line and the fix."""


@dataclass(frozen=True)
class MoorDynFile:
    """A MoorDyn input file as read.

    Attributes:
        path: the file.
        text: its text.
        coupled: (point ID, world position (3,) m) of each ``Coupled`` point, in ID order.
        line_ids: IDs of the lines, in file order (the order of MoorDyn's line numbering).
        kinds: number of points by attachment kind (``fixed``, ``free``, ``coupled``, ``body``), and ``rods``.
        options: the OPTIONS section, lower-case key -> value text.
    """

    path: str
    text: str
    coupled: list[tuple[int, np.ndarray]]
    line_ids: list[int]
    kinds: dict[str, int] = field(default_factory=dict)
    options: dict[str, str] = field(default_factory=dict)

    def option(self, key: str, default: float) -> float:
        value = self.options.get(key.lower())
        return default if value is None else float(value)

    @property
    def time_step(self) -> float:
        """MoorDyn's step dtM (s)."""
        return self.option("dtM", 0.001)

    @property
    def depth(self) -> float:
        """Water depth of the sea bed (m)."""
        return self.option("WtrDpth", math.inf)


def _section(line: str) -> str | None:
    if not line.lstrip().startswith("--"):
        return None
    words = re.sub(r"[-=]+", " ", line).strip().lower()
    words = re.sub(r"\s+", " ", words)
    for key, name in SECTIONS.items():
        if words.startswith(key) or f" {key}" in f" {words}":
            return name
    return "other"


def read_moordyn_file(path: str | Path) -> MoorDynFile:
    """Read and check a MoorDyn v2 (or v1) input file (module docstring)."""
    path = Path(path)
    if not path.is_file():
        raise MoorDynFileError(f"MoorDyn input file {path} does not exist")
    try:
        text = path.read_text(encoding="utf-8", errors="strict")
    except UnicodeDecodeError:
        raise MoorDynFileError(f"{path}: not a text file (a MoorDyn input file is plain text)") from None
    section, header_left = None, 0
    coupled, line_ids, options = [], [], {}
    kinds = {"fixed": 0, "free": 0, "coupled": 0, "body": 0, "rods": 0, "bodies": 0}
    seen = set()
    for number, raw in enumerate(text.splitlines(), start=1):
        name = _section(raw)
        if name is not None:
            section, header_left = name, (0 if name == "options" else 2)
            seen.add(name)
            continue
        line = raw.strip()
        if not line or section is None:
            continue
        if header_left:
            header_left -= 1
            continue
        parts = line.split()
        where = f"{path}:{number}"
        if section == "points":
            if len(parts) < 5:
                raise MoorDynFileError(f"{where}: a point needs ID Attachment X Y Z ... (got {line!r})")
            kind = parts[1].lower()
            try:
                position = np.array([float(v) for v in parts[2:5]])
            except ValueError:
                raise MoorDynFileError(f"{where}: the point's X Y Z are not numbers ({line!r})") from None
            if kind.startswith(COUPLED):
                coupled.append((_integer(parts[0], where), position))
                kinds["coupled"] += 1
            elif kind.startswith(("fix", "anchor")):
                kinds["fixed"] += 1
            elif kind.startswith(("free", "connect")):
                kinds["free"] += 1
            elif kind.startswith(("body", "turbine")):
                kinds["body"] += 1
            else:
                raise MoorDynFileError(f"{where}: unknown point attachment {parts[1]!r} (Fixed, Free, Coupled or "
                                       "Body<N>)")
        elif section == "bodies":
            kinds["bodies"] += 1
            if len(parts) > 1 and parts[1].lower().startswith(COUPLED):
                raise MoorDynFileError(
                    f"{where}: body {parts[0]} is Coupled: a 6-DOF coupled MoorDyn body is not supported; attach the "
                    "lines to Coupled points at the fairleads instead (one per fairlead, each named in "
                    "mooring_lines.coupled_bodies)")
        elif section == "rods":
            kinds["rods"] += 1
            if len(parts) > 2 and parts[2].lower().startswith(("coupled", "vessel", "cpld")):
                raise MoorDynFileError(
                    f"{where}: rod {parts[0]} is coupled ({parts[2]}): coupled MoorDyn rods are not supported; make it "
                    "Free, Pinned or Fixed, or attach its lines to Coupled points")
        elif section == "lines":
            line_ids.append(_integer(parts[0], where))
        elif section == "options":
            if len(parts) >= 2:
                options[parts[1].lower()] = parts[0]
    if "points" not in seen or "lines" not in seen:
        raise MoorDynFileError(f"{path}: no POINTS or no LINES section: not a MoorDyn v2 input file (section headers "
                               "are lines of dashes with the section's name, e.g. '--- POINTS ---')")
    if not coupled:
        raise MoorDynFileError(
            f"{path}: no Coupled point: the scene moves the file's Coupled points with its bodies (the fairleads); "
            "make each fairlead a point with attachment Coupled")
    if "wtrdpth" not in options:
        raise MoorDynFileError(f"{path}: the OPTIONS section sets no WtrDpth (the sea bed's depth, m); add a line "
                               "'70.0  WtrDpth' with the depth of the anchors")
    coupled.sort(key=lambda c: c[0])
    return MoorDynFile(str(path), text, coupled, line_ids, kinds, options)


def _integer(text: str, where: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise MoorDynFileError(f"{where}: expected an integer ID, got {text!r}") from None


def run_text(f: MoorDynFile, rho: float | None = None, g: float | None = None) -> str:
    """The file's text with MoorDyn's own output off (``disableOutput 1``, ``writeLog 0``) and, if given, the
    water density and gravity set (``WtrDnsty``, ``g``); every other option as the file has it."""
    forced = {"disableOutput": "1", "writeLog": "0"}
    if rho is not None:
        forced["WtrDnsty"] = repr(float(rho))
    if g is not None:
        forced["g"] = repr(float(g))
    names = {key.lower() for key in forced}
    out, section = [], None
    for raw in f.text.splitlines():
        name = _section(raw)
        if name is not None and section == "options":
            out += [f"{value} {key}" for key, value in forced.items()]
            forced = {}
        if name is not None:
            section = name
        if section == "options" and name is None:
            parts = raw.split()
            if len(parts) >= 2 and parts[1].lower() in names:
                continue
        out.append(raw)
    if forced:  # the options section was the last one and had no closing line
        out += [f"{value} {key}" for key, value in forced.items()]
    return "\n".join(out) + "\n"


@dataclass
class StaticSolution:
    """MoorDyn's static solve of a file: the lines' force on each coupled point (n, 3) N; the tension at end A
    and end B of every line (n_lines, 2) N (MoorDyn's anchor and fairlead ends, its GetFASTtens); the free
    points' positions (m, by point ID)."""

    forces: np.ndarray
    end_tensions: np.ndarray
    free_points: dict[int, np.ndarray]


def static_solve(text: str, positions: np.ndarray) -> StaticSolution:
    """MoorDyn's own static solution (its initial-condition solve, settings from the file) with the coupled
    points at ``positions`` (n, 3) m."""
    import moordyn

    from .moordyn_lines import MoorDynError, _captured, _tail

    folder = tempfile.mkdtemp(prefix="wec-cosim-moordyn-static-")
    console = os.path.join(folder, "console.txt")
    system = None
    try:
        with open(os.path.join(folder, "lines.txt"), "w") as handle:
            handle.write(text)
        with _captured(console):
            system = moordyn.Create(os.path.join(folder, "lines.txt"))
            moordyn.SetVerbosity(system, moordyn.LEVEL_NONE)
            x = np.asarray(positions, float).ravel()
            moordyn.Init(system, x.tolist(), [0.0] * len(x))
            forces = np.asarray(moordyn.Step(system, x.tolist(), [0.0] * len(x), 0.0, 0.0), float)
            n_lines = moordyn.GetNumberLines(system)
            fh, fv, ah, av = (np.asarray(v, float) for v in moordyn.GetFASTtens(system, n_lines))
            free = {}
            for i in range(1, moordyn.GetNumberPoints(system) + 1):
                point = moordyn.GetPoint(system, i)
                if moordyn.GetPointType(point) == moordyn.POINT_TYPE_FREE:
                    free[moordyn.GetPointID(point)] = np.asarray(moordyn.GetPointPos(point), float)
    except RuntimeError as exc:
        detail = _tail(console)
        raise MoorDynError(f"MoorDyn could not solve the lines' statics: {exc}" + (f" ({detail})" if detail else "")
                           ) from None
    finally:
        if system is not None:
            import contextlib

            with contextlib.suppress(Exception), _captured(os.devnull):
                moordyn.Close(system)
        shutil.rmtree(folder, ignore_errors=True)
    return StaticSolution(forces.reshape(-1, 3), np.column_stack([np.hypot(ah, av), np.hypot(fh, fv)]), free)


def body_stiffness(text: str, positions: np.ndarray, bodies: np.ndarray, centres: np.ndarray, n_bodies: int,
                   dofs: list[list[int]], step: tuple[float, float] = (0.05, 0.005)) -> tuple[np.ndarray, np.ndarray]:
    """The lines' quasi-static stiffness on each body about its cg: K_b (6, 6) = -dF_b/dq_b, with F_b the wrench
    (force and moment about the cg) of the coupled points attached to body b and q_b its displacement (surge..yaw,
    small rotations), by central differences of :func:`static_solve` (steps ``step`` = (m, rad)) on the degrees
    of freedom ``dofs[b]``; and the wrench at the reference positions (n_bodies, 6). ``bodies`` (n,) is each
    coupled point's body, ``centres`` (n_bodies, 3) the centres of gravity."""
    positions = np.asarray(positions, float)
    arms = positions - centres[bodies]

    def wrenches(x: np.ndarray, cg: np.ndarray) -> np.ndarray:
        f = static_solve(text, x).forces
        out = np.zeros((n_bodies, 6))
        for p, b in enumerate(bodies):
            out[b, :3] += f[p]
            out[b, 3:] += np.cross(x[p] - cg[b], f[p])
        return out

    centres = np.asarray(centres, float)
    base = wrenches(positions, centres)
    stiffness = np.zeros((n_bodies, 6, 6))
    for b in range(n_bodies):
        on = bodies == b
        for d in dofs[b]:
            h = step[0] if d < 3 else step[1]
            moved = []
            for sign in (1.0, -1.0):
                x, cg = positions.copy(), centres.copy()
                if d < 3:
                    x[on, d] += sign * h
                    cg[b, d] += sign * h
                else:
                    axis = np.zeros(3)
                    axis[d - 3] = sign * h
                    x[on] += np.cross(axis, arms[on])
                moved.append(wrenches(x, cg)[b])
            stiffness[b][:, d] = -(moved[0] - moved[1]) / (2 * h)
    return stiffness, base
