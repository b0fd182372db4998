"""Time-domain run of a scenario: database -> FMUs -> master -> results file -> summary."""

from __future__ import annotations

import math
import platform
import sys
import time
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

import numpy as np

from . import frequency_domain
from .analysis import harmonic_fit, steady_window, window_mean
from .components import FmuComponent, InProcessComponent
from .control.loop import control_loop
from .errors import MasterError
from .fmu_builder import build_scene_fmus
from .masters import JacobiMaster
from .results import ResultsWriter, read_results
from .scenario import DOFS, Scenario
from .scene import HYDRO, MBD, Scene, load_scene


def versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for pkg in ("wec-cosim", "numpy", "scipy", "h5py", "fmpy", "pythonfmu", "capytaine", "eclipse-zenoh"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    return out


class Recorder:
    """Maps the master's output vectors onto rows of the results file."""

    def __init__(self, scene: Scene, master: JacobiMaster) -> None:
        self.plan: list[tuple[str, str, np.ndarray, np.ndarray | None]] = []
        self.series: dict[str, tuple[int, ...]] = {"time": ()}
        names = master.output_names
        for b in scene.scenario.bodies:
            dofs = [DOFS.index(d) for d in b.dofs]
            for key, var, comp in (("displacement", "x", MBD), ("velocity", "v", MBD), ("hydro_force", "F", HYDRO)):
                if comp == HYDRO and not b.hydro:
                    continue
                out = [names[comp].index(f"{b.name}.{var}[{d + 1}]") for d in dofs]
                self._add(f"bodies/{b.name}/{key}", (6,), comp, out, dofs)
        for p in scene.scenario.ptos:
            self._add(f"ptos/{p.name}/force", (), MBD, [names[MBD].index(f"{p.name}.force")], None)
            self._add(f"ptos/{p.name}/power", (), MBD, [names[MBD].index(f"{p.name}.power")], None)
        self._add("wave/elevation", (), HYDRO, [names[HYDRO].index("wave.elevation")], None)

    def _add(self, name: str, shape: tuple[int, ...], comp: str, out: list[int], cols: list[int] | None) -> None:
        self.series[name] = shape
        self.plan.append((name, comp, np.array(out), None if cols is None else np.array(cols)))

    @staticmethod
    def observed(scene: Scene) -> dict[str, list[str]]:
        """Outputs the master must read at each point for the results file."""
        mbd = [f"{b.name}.{v}[{DOFS.index(d) + 1}]" for b in scene.scenario.bodies for v in ("x", "v") for d in b.dofs]
        mbd += [f"{p.name}.{k}" for p in scene.scenario.ptos for k in ("force", "power")]
        hydro = [f"{b.name}.F[{DOFS.index(d) + 1}]" for b in scene.scenario.hydro_bodies for d in b.dofs]
        return {MBD: mbd, HYDRO: hydro + ["wave.elevation"]}

    def row(self, t: float, outputs: dict[str, np.ndarray]) -> dict[str, np.ndarray | float]:
        row: dict[str, np.ndarray | float] = {"time": t}
        for name, comp, out, cols in self.plan:
            values = outputs[comp][out]
            if cols is None:
                row[name] = values[0]
            else:
                full = np.zeros(6)
                full[cols] = values
                row[name] = full
        return row


@dataclass
class Comparison:
    """Steady-state time-domain result against the exact frequency-domain one."""

    label: str
    unit: str
    measured: complex | float
    exact: complex | float

    @property
    def amplitude_error(self) -> float:
        return abs(self.measured) / abs(self.exact) - 1 if abs(self.exact) > 0 else math.nan

    @property
    def phase_error_deg(self) -> float:
        if isinstance(self.measured, complex) and abs(self.exact) > 0:
            return math.degrees(np.angle(self.measured / self.exact))
        return math.nan


@dataclass
class RunResult:
    path: Path
    wall_time: float
    simulated_time: float
    steps: int
    comparisons: list[Comparison] = field(default_factory=list)

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per wall-clock second."""
        return self.simulated_time / self.wall_time if self.wall_time > 0 else math.inf


def make_components(fmus: dict[str, Path], in_process: bool = False) -> dict:
    kind = InProcessComponent if in_process else FmuComponent
    return {name: kind(name, path) for name, path in fmus.items()}


def run_scenario(
    scenario: Scenario,
    output: str | Path | None = None,
    *,
    in_process: bool = False,
    log=print,
    progress: bool = True,
) -> RunResult:
    """Run the scenario's co-simulation, write the results file, compare with the exact answer."""
    scene = load_scene(scenario, log=log)
    fmus = build_scene_fmus(scene)
    sim = scenario.simulation
    path = Path(output or sim.output or Path("results") / f"{scenario.name}.h5")
    components = make_components(fmus, in_process)
    master = JacobiMaster(components, scene.connections(), sim.extrapolation, Recorder.observed(scene))
    recorder = Recorder(scene, master)
    control = control_loop(scene, master)
    series = recorder.series | (control.series if control else {})
    settings = {"master": sim.master, "step": sim.step, "duration": sim.duration,
                "extrapolation": sim.extrapolation, "output_every": sim.output_every,
                "fmi": "in-process" if in_process else "fmpy", "fmus": {k: str(v) for k, v in fmus.items()}}
    attrs = {"scenario": scenario.text, "scenario_file": str(scenario.file), "versions": versions(),
             "settings": settings, "hydro_database": str(scene.hdb_file)}
    if control:
        attrs["control_manifest"] = control.manifest.to_json()
    writer = ResultsWriter(path, series, attrs)
    n_steps = int(round(sim.duration / sim.step))
    counter = {"k": 0, "last": time.monotonic(), "shown": False}

    def observe(t: float, outputs: dict[str, np.ndarray]) -> None:
        k = counter["k"]
        if control:
            control.on_point(t, outputs)
        if k % sim.output_every == 0 or k == n_steps:
            row = recorder.row(t, outputs)
            writer.append(row | control.row() if control else row)
        counter["k"] = k + 1
        if progress and time.monotonic() - counter["last"] > 2.0:
            counter["last"], counter["shown"] = time.monotonic(), True
            print(f"\r  t = {t:8.2f} s  ({100 * t / sim.duration:5.1f} %)", end="", file=sys.stderr, flush=True)

    start = time.perf_counter()
    final = {}
    try:
        if control:
            control.start()
        master.initialize(0.0, sim.duration, scene.parameter_links())
        master.run(sim.duration, sim.step, observe)
    except MasterError as exc:
        final = control.close("failed") if control else {}
        writer.close(status=f"failed: {exc}", wall_time=time.perf_counter() - start,
                     attrs={"control_statistics": final} if control else None)
        raise MasterError(f"{exc} (results up to t = {master.time:g} s are in {path})") from None
    except KeyboardInterrupt:
        final = control.close("failed") if control else {}
        writer.close(status="interrupted", wall_time=time.perf_counter() - start,
                     attrs={"control_statistics": final} if control else None)
        raise
    finally:
        master.terminate()
        if counter["shown"]:
            print("\r" + " " * 40 + "\r", end="", file=sys.stderr)
    wall = time.perf_counter() - start
    if control:
        final = control.close("finished")
    writer.close(status="completed", wall_time=wall, attrs={"control_statistics": final} if control else None)
    result = RunResult(path, wall, sim.duration, n_steps)
    if scenario.waves.kind == "regular" and not control:  # an external law has no frequency-domain answer
        result.comparisons = compare_with_frequency_domain(scene, read_results(path))
    return result


def compare_with_frequency_domain(scene: Scene, data: dict) -> list[Comparison]:
    """Steady-state amplitude and phase of every active DOF and mean PTO power, against the FD solution."""
    s = scene.scenario
    w = s.waves
    omega = 2 * math.pi / w.period
    amplitude = w.height / 2
    fd = frequency_domain.solve(scene, np.array([omega]))
    t = data["time"]
    mask = steady_window(t, w.period, s.simulation.steady_periods)
    # Exact answers are referred to the wave's own phase at the origin.
    wave_phase = np.exp(1j * math.radians(w.phase_deg))
    out = []
    for b in s.bodies:
        rao = fd.body_rao(b.name)[0] * amplitude * wave_phase
        for d in b.dofs:
            j = DOFS.index(d)
            y = data[f"bodies/{b.name}/displacement"][:, j]
            measured, _ = harmonic_fit(t[mask], y[mask], omega)
            out.append(Comparison(f"{b.name} {d}", "m" if j < 3 else "rad", measured, complex(rao[j])))
    for p in s.ptos:
        measured = window_mean(t, data[f"ptos/{p.name}/power"], mask)
        out.append(Comparison(f"{p.name} mean power", "W", measured, float(fd.pto_power[p.name][0] * amplitude**2)))
    return out


def format_summary(result: RunResult) -> str:
    lines = [f"results: {result.path}"]
    if result.comparisons:
        lines.append("steady state against the exact frequency-domain solution:")
        lines.append(f"  {'quantity':<24}{'co-simulation':>16}{'exact':>16}{'error':>10}{'phase err':>11}")
        for c in result.comparisons:
            phase = f"{c.phase_error_deg:+9.2f} deg" if not math.isnan(c.phase_error_deg) else ""
            lines.append(
                f"  {c.label:<24}{abs(c.measured):>13.5g} {c.unit:<2}{abs(c.exact):>13.5g} {c.unit:<2}"
                f"{100 * c.amplitude_error:>+9.3f}%{phase:>13}")
    lines.append(
        f"wall time {result.wall_time:.2f} s for {result.simulated_time:g} s simulated "
        f"({result.steps} macro steps): real-time factor {result.real_time_factor:.1f}")
    return "\n".join(lines)
