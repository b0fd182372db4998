"""Port check of the compiled hydrodynamics runtime against the Python hydro model it replaces (issue 29).

For every bundled scenario with hydrodynamics (``scenarios/*.toml``) and a few variants that switch on what no
bundled scenario uses (nonlinear hydrostatics and Froude-Krylov force over the wetted mesh, the excitation
convolution on a synthetic sea and on an imported elevation record, a directionally spread sea, quadratic drag),
the Python model (``HydroModel.outputs``: the numba pass where it covers the model, else numpy; ``HydroModel.affine``:
numpy) and the runtime made from the same preparation (``hydro_fmu.runtime``) are driven side by side through the
same input histories (smooth multi-sine displacements and velocities on every DOF) at the scenario's macro step over
100 s, each point read, linearised and stepped (work committed) as the hydro FMU does. Reported per case: the largest
difference over the run relative to the largest magnitude of the Python value, for the force rows (total, excitation,
radiation, hydrostatic, viscous), the linearised outputs F0, F0_rate, dF_dx, dF_dv (the scene's coupling pattern),
the work of the four components and the elevation. Acceptance: <= 1e-12.

Run (about three minutes on two cores)::

    python benchmarks/hydro_port_check.py --out benchmarks/results/hydro_port_check.txt
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import math
import tempfile
import time
from pathlib import Path

import numpy as np
from common import ROOT, load, report_header, write_report

from hydro_fmu.model import FORCE_ROWS
from hydro_fmu.runtime import HydroRuntime
from hydro_fmu.runtime_input import runtime_input
from hydro_fmu.work import WorkAccount
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

DURATION = 100.0
QUANTITIES = (*FORCE_ROWS, "F0", "F0_rate", "dF_dx", "dF_dv", "work", "elevation")


def inputs(t: float, index: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Smooth multi-sine displacement and velocity on every DOF (rotations one tenth of translations)."""
    k = np.arange(1, len(index) + 1)
    size = np.where(index % 6 >= 3, 0.03, 0.3)
    x = size * (np.sin(0.61 * t + 0.7 * k) + 0.4 * np.sin(1.37 * t / k + 0.2))
    v = size * (0.61 * np.cos(0.61 * t + 0.7 * k) + 0.4 * 1.37 / k * np.cos(1.37 * t / k + 0.2))
    return x, v


class PythonSide:
    """The Python model behind the runtime's calls: outputs (numba pass or numpy), affine (numpy), advance."""

    def __init__(self, model, pattern) -> None:
        self.model, self.pattern = model, pattern
        self.account = WorkAccount()
        self.power, self.work = np.zeros(4), np.zeros(4)

    def outputs(self, t: float, x: np.ndarray, v: np.ndarray, rows: np.ndarray, out: np.ndarray) -> float:
        return self.model.outputs(t, x, v, rows, out, self.power, self.account, self.work)

    def linearise(self, t: float, x: np.ndarray, v: np.ndarray) -> tuple:
        a = self.model.affine(t, x, v, self.pattern)
        return a.constant, a.rate, a.dfdx, a.dfdv

    def step(self, t: float, h: float, x: np.ndarray, v: np.ndarray) -> None:
        self.account.commit(t, self.power, self.work)
        self.model.advance(t, h, v)


class RuntimeSide:
    """The runtime behind the same calls."""

    def __init__(self, model, pattern) -> None:
        self.runtime = HydroRuntime(runtime_input(model))
        n = model.n
        self.masks = pattern.mask(n, "stiffness"), pattern.mask(n, "damping")
        self.power, self.work = np.zeros(4), np.zeros(4)

    def outputs(self, t: float, x: np.ndarray, v: np.ndarray, rows: np.ndarray, out: np.ndarray) -> float:
        return self.runtime.outputs(t, x, v, rows.astype(np.int64), out, self.power, self.work)

    def linearise(self, t: float, x: np.ndarray, v: np.ndarray) -> tuple:
        return self.runtime.linearise(t, x, v, *self.masks)

    def step(self, t: float, h: float, x: np.ndarray, v: np.ndarray) -> None:
        self.runtime.do_step(t, h, x, v)


def reordered(model):
    """The same Python model with sums taken in another order (mathematically identical input): the hull's
    triangles in reverse order, the excitation kernel's lags reversed. Its difference from the model is the
    round-off floor of the Python model itself."""
    from hydro_fmu.meshes import SurfaceMesh
    from hydro_fmu.nonlinear_hydrostatics import BodyPressureModel

    for b, pm in list(model.pressure_models.items()):
        mesh = SurfaceMesh(pm.mesh.vertices, pm.mesh.faces[::-1].copy(), pm.mesh.name)
        model.pressure_models[b] = BodyPressureModel(mesh, pm.cg, pm.rho, pm.g, pm.water_depth)
    exc = model.excitation
    if hasattr(exc, "weighted"):
        exc.tau, exc.weighted = exc.tau[::-1].copy(), exc.weighted[::-1].copy()
    return model


def compare(scene, h: float, duration: float, floor: bool = False) -> tuple[dict, dict | None, int, bool]:
    """Largest relative difference per quantity over the run between the Python model and the runtime (and, with
    ``floor``, between the Python model and itself reordered); the number of points; whether numba computed."""
    model = scene.hydro_model(dt=h)
    pattern = scene.coupling_pattern()
    reference = PythonSide(model, pattern)
    others = {"runtime": RuntimeSide(model, pattern)}
    if floor:
        others["floor"] = PythonSide(reordered(scene.hydro_model(dt=h)), pattern)
    n = model.n
    rows = np.arange(len(FORCE_ROWS), dtype=np.intp)
    out = {key: np.zeros((len(rows), n)) for key in ("reference", *others)}
    diff = {key: dict.fromkeys(QUANTITIES, 0.0) for key in others}
    size = dict.fromkeys(QUANTITIES, 0.0)
    points = int(round(duration / h))
    for k in range(points):
        t = k * h
        x, v = inputs(t, model.index)
        eta = reference.outputs(t, x, v, rows, out["reference"])
        lin = reference.linearise(t, x, v)
        values = {"elevation": np.array([eta]), "work": reference.work, "F0": lin[0], "F0_rate": lin[1],
                  "dF_dx": lin[2], "dF_dv": lin[3], **dict(zip(FORCE_ROWS, out["reference"], strict=True))}
        for q in QUANTITIES:
            size[q] = max(size[q], float(np.max(np.abs(values[q]), initial=0.0)))
        for key, side in others.items():
            eta_o = side.outputs(t, x, v, rows, out[key])
            lin_o = side.linearise(t, x, v)
            got = {"elevation": np.array([eta_o]), "work": side.work, "F0": lin_o[0], "F0_rate": lin_o[1],
                   "dF_dx": lin_o[2], "dF_dv": lin_o[3], **dict(zip(FORCE_ROWS, out[key], strict=True))}
            for q in QUANTITIES:
                diff[key][q] = max(diff[key][q], float(np.max(np.abs(got[q] - values[q]), initial=0.0)))
            side.step(t, h, x, v)
        reference.step(t, h, x, v)

    def relative(d: dict) -> dict:
        return {q: (d[q] / size[q] if size[q] > 0 else (0.0 if d[q] == 0 else math.inf)) for q in QUANTITIES}

    return relative(diff["runtime"]), relative(diff["floor"]) if floor else None, points, model.compiled


@dataclasses.dataclass
class Case:
    label: str
    scenario: object
    duration: float | None = None  # None: the run's --duration
    floor: bool = False  # also the Python model against itself reordered (central differences inside)


def variants(tmp: Path) -> list[Case]:
    """The variants that switch on what no bundled scenario uses (cylinder in surge, heave and pitch)."""
    def cylinder(**changes):
        s = load_scenario(ROOT / "scenarios" / "cylinder_regular.toml")
        s.bodies[0] = dataclasses.replace(s.bodies[0], dofs=["surge", "heave", "pitch"])
        for key, value in changes.items():
            section, field = key.split(".")
            setattr(getattr(s, section), field, value)
        return s

    t = np.arange(0.0, 200.0, 0.1)
    eta = 0.6 * np.sin(2 * math.pi * t / 7.3) + 0.3 * np.cos(2 * math.pi * t / 5.1 + 1.0) + 0.1 * np.sin(1.9 * t)
    record = tmp / "eta.csv"
    record.write_text("t,eta\n" + "\n".join(f"{a:.17g},{b:.17g}" for a, b in zip(t, eta, strict=True)))
    irregular = {"waves.kind": "irregular", "waves.hs": 2.0, "waves.tp": 7.0}
    out = [
        Case("cylinder 3 DOF, nonlinear hydrostatics", cylinder(**{"hydro.nonlinear_hydrostatics": True}), None, True),
        Case("cylinder 3 DOF, nonlinear hydrostatics + FK, 6 components, 20 s",
             cylinder(**{"hydro.nonlinear_hydrostatics": True, "hydro.nonlinear_froude_krylov": True, **irregular,
                         "waves.n_components": 6, "waves.discretisation": "equal_energy"}), 20.0, True),
        Case("cylinder 3 DOF, excitation convolution, irregular sea",
             cylinder(**{"hydro.excitation_method": "convolution", **irregular}), None, True),
        Case("cylinder 3 DOF, elevation record, excitation convolution",
             cylinder(**{"waves.kind": "elevation", "waves.elevation_file": str(record),
                         "hydro.excitation_method": "convolution"}), None, True),
        Case("cylinder 3 DOF, elevation record, superposition",
             cylinder(**{"waves.kind": "elevation", "waves.elevation_file": str(record)})),
    ]
    spread = load_scenario(ROOT / "scenarios" / "two_cylinders_decay.toml")
    w = spread.waves
    w.kind, w.hs, w.tp, w.spreading_s, w.n_directions, w.heading_deg = "irregular", 1.5, 6.0, 6.0, 5, 20.0
    w.discretisation, w.n_components = "equal_energy", 40
    out.append(Case("two cylinders, spread sea (5 directions)", spread))
    spread_fk = copy.deepcopy(spread)
    spread_fk.hydro.nonlinear_froude_krylov = True
    spread_fk.waves.n_components = 2
    out.append(Case("two cylinders, spread sea (10 components), nonlinear FK, 20 s", spread_fk, 20.0, True))
    drag = cylinder(**irregular)
    drag.bodies[0] = dataclasses.replace(drag.bodies[0], linear_damping=[0, 0, 2e4, 0, 0, 0],
                                         drag_coefficient=[1.0, 0, 1.0, 0, 0, 0], drag_area=[20.0, 0, 78.5, 0, 0, 0])
    drag.hydro.radiation_method = "state_space"
    out.append(Case("cylinder 3 DOF, irregular sea, drag, state space", drag))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", help="also write the report here")
    parser.add_argument("--duration", type=float, default=DURATION)
    parser.add_argument("--only", help="cases whose label contains this text")
    args = parser.parse_args()
    lines = [*report_header("hydro_port_check.py"),
             f"# per case: max |runtime - python| / max |python| over {args.duration:g} s (unless the label says) at "
             "the macro step; python forces, work and elevation from HydroModel.outputs (the numba pass where "
             "'numba' says yes, numpy otherwise), F0 .. dF_dv from HydroModel.affine (numpy).",
             "# 'floor' rows: the Python model against itself with the same sums in another order (hull triangles, "
             "excitation kernel lags reversed): the round-off that central differences (tangent of the pressure "
             "forces, rate of the convolution and of the Froude-Krylov force) amplify in the Python model itself.", ""]
    head = f"{'case':62s} {'n':>3s} {'points':>6s} numba " + " ".join(f"{q[:9]:>9s}" for q in QUANTITIES)
    lines.append(head)
    worst = {"bundled": 0.0, "variants": 0.0}
    with tempfile.TemporaryDirectory() as tmp:
        bundled = [Case(p.stem, load_scenario(p)) for p in sorted((ROOT / "scenarios").glob("*.toml"))]
        for group, cases in (("bundled", bundled), ("variants", variants(Path(tmp)))):
            if group == "variants":
                lines += ["", "variants (options no bundled scenario uses):"]
            for case in cases:
                if args.only and args.only not in case.label:
                    continue
                start = time.perf_counter()
                scene = load_scene(case.scenario, log=None)
                if not scene.hydro_bodies:
                    continue
                relative, floor, points, compiled = compare(scene, case.scenario.simulation.step,
                                                            case.duration or args.duration, case.floor)
                worst[group] = max([worst[group], *relative.values()])
                rows = [(case.label, relative)] + ([("  floor: python vs python reordered", floor)] if floor else [])
                for i, (label, values) in enumerate(rows):
                    row = (f"{label[:62]:62s} {len(scene.hydro_index()) if i == 0 else '':>3} "
                           f"{points if i == 0 else '':>6} {('yes' if compiled else 'no') if i == 0 else '':5s} "
                           + " ".join(f"{values[q]:9.1e}" for q in QUANTITIES))
                    lines.append(row)
                    print(row, f"({time.perf_counter() - start:.0f} s)" if i == 0 else "", flush=True)
    lines += ["", f"largest relative difference, bundled scenarios: {worst['bundled']:.2e} (acceptance <= 1e-12)",
              f"largest relative difference, variants: {worst['variants']:.2e}", f"# load average at the end {load()}"]
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
