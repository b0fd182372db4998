"""Time-domain run of a scenario: database -> FMUs -> master -> results file -> summary."""

from __future__ import annotations

import json
import math
import os
import platform
import time
import typing
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from importlib import metadata
from pathlib import Path

import h5py
import numpy as np

from orchestrator.errors import MasterError, WecCosimError
from orchestrator.fmi.components import FmuComponent, InProcessComponent
from orchestrator.progress import ProgressBar
from orchestrator.reference import frequency_domain
from orchestrator.results import ResultsWriter, energy_account, read_results
from orchestrator.results.analysis import averaging_window, harmonic_fit, mean_pto_powers, window_mean
from orchestrator.results.checkpoints import checkpoint_path, read_checkpoint, write_checkpoint
from orchestrator.results.file_guard import ResultsFileLost, ResultsLock
from orchestrator.scenario import DOFS, Scenario, parse_scenario
from orchestrator.scenario.input_checks import check_output
from orchestrator.scene import HYDRO, Scene, load_scene

from . import error_estimate, step_choice
from .checkpoint_identity import check_checkpoint, run_identity
from .control_loop import ControlLoop, control_loop
from .coupling import bonds, scene_coupling
from .divergence import divergence_causes
from .interrupts import InterruptAtStep
from .master_factory import make_master
from .masters import Master, MasterSettings
from .monolithic import MonolithicMaster
from .recorder import Recorder  # noqa: F401 - (also imported from here)
from .step_checks import aliasing_warnings
from .step_control import EnergyStepController, FixedStepController, StepController


def versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for pkg in ("wec-cosim", "numpy", "scipy", "h5py", "fmpy", "pythonfmu", "capytaine", "eclipse-zenoh"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    return out


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
    statistics: dict = field(default_factory=dict)
    radiation: dict = field(default_factory=dict)
    mobility: dict | None = None
    energy: dict[str, float] | None = None
    notes: list[str] = field(default_factory=list)
    mean_power: dict[str, float] = field(default_factory=dict)  # W per PTO, over ``power_window``
    power_window: str = ""
    error_estimate: error_estimate.ErrorEstimate | None = None
    step_choice: step_choice.StepChoice | None = None  # simulation.error_tolerance's runs
    setup_time: float = math.nan  # s of wall time before the first step: scene, FMUs (build, compile), initialisation
    radiation_check: Callable[[], str] | None = None  # the impulse-response check's summary text, when printed

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per wall-clock second of stepping (``wall_time``; set-up not counted)."""
        return self.simulated_time / self.wall_time if self.wall_time > 0 else math.inf

    def dataset(self):  # noqa: ANN201 - xarray.Dataset (xarray is imported here, not with this module)
        """The results file as a labelled xarray dataset (:func:`orchestrator.results.datasets.results_dataset`)."""
        from orchestrator.results.datasets import results_dataset

        return results_dataset(self.path)

    def summary(self) -> str:
        """What ``wec-cosim run`` prints at the end (:func:`format_summary`)."""
        return format_summary(self)


def make_components(fmus: dict[str, Path], in_process: bool = False) -> dict:
    kind = InProcessComponent if in_process else FmuComponent
    return {name: kind(name, path) for name, path in fmus.items()}


@dataclass
class RunPlan:
    """Everything a run needs, built from the scenario: master, step controller, recorder."""

    scene: Scene
    master: Master | MonolithicMaster
    controller: StepController
    recorder: Recorder
    parameter_links: list
    settings: dict
    control: ControlLoop | None = None
    radiation: dict = field(default_factory=dict)
    mobility: dict | None = None
    warnings: list[str] = field(default_factory=list)  # said in the run's first lines and its summary
    started: float = field(default_factory=time.perf_counter)  # perf_counter when the run's set-up began

    @property
    def series(self) -> dict[str, tuple[int, ...]]:
        return self.recorder.series | (self.control.series if self.control else {})

    def attrs(self) -> dict:
        """Root attributes of the results file."""
        scenario = self.scene.scenario
        out = {"scenario": scenario.text, "scenario_file": str(Path(scenario.file).resolve()),
               "versions": versions(), "settings": self.settings, "hydro_database": str(self.scene.hdb_file)}
        if self.control:
            out["control_manifest"] = self.control.manifest.to_json()
        if self.mobility:
            out["mobility"] = self.mobility
        if scenario.multibody.static_equilibrium:
            out["static_equilibrium"] = self.scene.equilibrium().as_dict()
        return out


def master_settings(scenario: Scenario, scene: Scene | None = None) -> MasterSettings:
    sim = scenario.simulation
    return MasterSettings(extrapolation=sim.extrapolation, tolerance=sim.tolerance,
                          max_iterations=sim.max_iterations, relaxation=sim.relaxation, reuse=sim.iqn_reuse,
                          divergence_limit=sim.divergence_limit,
                          energy_scale=energy_scale(scene) if scene is not None else 1.0,
                          precision=multibody_precision(scenario))


def multibody_precision(scenario: Scenario) -> float:
    """Absolute accuracy of the multibody FMU's outputs (m, rad, m/s, rad/s): 10 times its Newton tolerance times
    its length scale (the larger of 1 m and the farthest centre of gravity, ``mbd_fmu.formulations``) for the
    constrained formulations; 0 for the linear model (exact steps) and the plain multibody FMU (explicit steps)."""
    if scenario.formulation == "linear" or scenario.simulation.added_mass == "interface":
        return 0.0
    length = max([1.0] + [float(np.max(np.abs(b.cg))) for b in scenario.bodies])
    return 10 * scenario.multibody.newton_tolerance * length


def energy_scale(scene: Scene) -> float:
    """The scene's energy scale (J): its bodies' weight and static loads times a metre (at least 1 J)."""
    spec = scene.mbd_spec()
    g = float(np.linalg.norm(spec.get("gravity", (0.0, 0.0, 0.0)))) or 9.81
    loads = sum(abs(float(b["mass"])) * g + float(np.linalg.norm(b.get("static_load", [0.0] * 6)[:3]))
                for b in spec["bodies"])
    return max(1.0, loads)


def prepare_run(scenario: Scenario, *, in_process: bool = False, log=print, scene: Scene | None = None,
                progress: bool = False) -> RunPlan:
    """Load the scene, build the FMUs for the scenario's added-mass mode, make the master (``progress``:
    show the progress of a BEM solve, if the database must be computed)."""
    # A scene given is reused for its database only (the scenario may be a variant of its own).
    scene = (Scene(scenario, scene.hdb, scene.hdb_file) if scene is not None
             else load_scene(scenario, log=log, progress=progress))
    if scenario.multibody.static_equilibrium and log is not None:
        from orchestrator.scene.equilibrium import equilibrium_report

        log(equilibrium_report(scene.equilibrium()))
    sim = scenario.simulation
    observe = Recorder.observed(scene)
    settings = {"master": sim.master, "step": sim.step, "duration": sim.duration,
                "extrapolation": sim.extrapolation, "added_mass": sim.added_mass, "interface": sim.interface,
                "output_every": sim.output_every, "adaptive": asdict(sim.adaptive),
                "fmi": "none" if sim.master == "monolithic" else ("in-process" if in_process else "fmpy"),
                "overrides": list(scenario._overrides)}
    notice = compile_notice(scene)
    if notice and log is not None:
        log(notice)
    if sim.master == "monolithic":
        master: Master | MonolithicMaster = MonolithicMaster(scene, observe)
        links: list = []
    else:
        coupling = scene_coupling(scene, sim.added_mass, interface=sim.interface)
        if not sim.resolve_feedthrough and sim.interface == "force" and log is not None:
            log("warning: resolve_feedthrough = false with the force interface is what a plain FMI host does with "
                "the force connected: first order, and unstable for light bodies (docs/hosts/README.md); "
                "simulation.interface = 'linearised' is second order under the same host")
        components = make_components(coupling.fmus, in_process)
        kind = "simple_jacobi" if not sim.resolve_feedthrough else sim.master
        master = make_master(kind, components, coupling.connections, master_settings(scenario, scene),
                             observe, coupling.added_mass, coupling.parameters)
        links = coupling.parameter_links
        settings["fmus"] = {k: str(v) for k, v in coupling.fmus.items()}
    if sim.adaptive.enabled:
        a = sim.adaptive
        controller: StepController = EnergyStepController(
            sim.step, 0.0, a.max_step, a.tolerance, bonds(scene), order=1 if sim.extrapolation == 0 else 2,
            safety=a.safety, max_growth=a.max_growth)
    else:
        controller = FixedStepController(sim.step, 0.0)
    control = control_loop(scene, master) if scenario.control.mode != "off" else None
    report = mobility(scene)
    if report and log is not None:
        log(f"multibody: {report['summary']}")
    plan = RunPlan(scene, master, controller, Recorder(scene, master), links, settings, control, mobility=report)
    plan.warnings = aliasing_warnings(scene)
    for message in plan.warnings if log is not None else []:
        log(f"warning: {message}")
    return plan


# CPU seconds that compiling each kernel module costs on first use, measured on a 2-core machine: the multibody
# kernels in benchmarks/results/first_run.txt (146-164 s), the null-space ones in
# benchmarks/results/first_run_notice.txt (a cold null-space hinge-barge run 195 s in all). The hydrodynamics needs
# none: it runs on the compiled runtime built at install (docs/runtime.md), so a linear scene compiles nothing at its
# first run.
COMPILE_SECONDS = {("mbd_fmu", "kernels"): 155.0, ("mbd_fmu", "nullspace_kernels"): 35.0}


def compile_notice(scene: Scene) -> str | None:
    """A line to show before the FMUs start when their compiled kernels are not in the cache yet (the first run
    of this version of the sources): which, how long it takes, and where the result is kept; None when warm or when
    the scene needs no kernel (the linear model: the hydrodynamics is compiled at install)."""
    import mbd_fmu
    from fmu_base._jit import cache_root

    needed = []
    formulation = scene.scenario.formulation
    if formulation != "linear":
        needed.append(("mbd_fmu", "kernels"))
    if formulation == "nullspace":
        needed.append(("mbd_fmu", "nullspace_kernels"))
    folder = Path(mbd_fmu.__file__).parent
    missing = [(pkg, mod) for pkg, mod in needed if not is_compiled(folder / f"{mod}.py")]
    if not missing:
        return None
    seconds = sum(COMPILE_SECONDS[m] for m in missing)
    what = " and ".join("multibody" + (" null-space" if "null" in mod else "") for _, mod in missing)
    span = f"about {seconds / 60:.1g} minutes" if seconds >= 90 else f"about {seconds:.0f} s"
    return (f"compiling the {what} kernels for this version of wec-cosim: {span} of CPU on a 2-core machine, longer "
            f"under load; once: later runs load them from {cache_root()} ...")


def is_compiled(py_file: Path) -> bool:
    """Whether the machine code of the kernel module at ``py_file`` (its current sources) is in numba's cache
    (:mod:`fmu_base._jit`), so that its first use loads it instead of compiling it; true when nothing is compiled
    (numba absent, ``WEC_COSIM_NO_JIT``)."""
    from fmu_base._jit import AVAILABLE, cache_root, source_stamp

    if not AVAILABLE:
        return True
    try:
        folder = cache_root() / f"{py_file.parent.name}.{py_file.stem}-{source_stamp(py_file)}"
        return folder.is_dir() and any(folder.glob("*.nbi"))
    except OSError:
        return True


def mobility(scene: Scene) -> dict | None:
    """DOF count and redundant constraint rows of a constrained scene at its start pose (the multibody
    FMU's own analysis, ``mbd_fmu.assembly.analyse``, run in-process), or None for the linear model."""
    r = scene.mobility()
    if r is None:
        return None
    return {"coordinates": r.coordinates, "constraints": r.constraints, "rank": r.rank, "dof": r.dof,
            "redundant": list(r.redundant), "summary": r.summary() + (f"; {r.note}" if r.note else "")}


@dataclass
class _Progress:
    """Row and checkpoint bookkeeping of a running simulation."""

    steps: int = 0
    next_checkpoint: float = math.inf


def run_scenario(
    scenario: Scenario,
    output: str | Path | None = None,
    *,
    in_process: bool = False,
    log=print,
    progress: bool = True,
    scene: Scene | None = None,
) -> RunResult:
    """Run the scenario's co-simulation, write the results file, compare with the exact answer.

    ``scene``: a loaded scene whose database is reused (the scenario may be a variant of its own).
    """
    sim = scenario.simulation
    started = time.perf_counter()
    key = "--out" if output else ("simulation.output" if sim.output else f"the default results file (scenario name "
                                                                        f"{scenario.name!r})")
    path = check_output(Path(output or sim.output or Path("results") / f"{scenario.name}.h5"), key)
    if sim.error_tolerance:  # runs at chosen steps (orchestrator.cosim.step_choice), each taking the file's lock
        return step_choice.run_to_tolerance(
            scenario, path, lambda s, out: run_scenario(s, out, in_process=in_process, log=log, progress=progress,
                                                         scene=scene), log)
    lock = ResultsLock(path)  # one writer per results file: a second run on it refuses here
    try:
        plan = prepare_run(scenario, in_process=in_process, log=log, progress=progress, scene=scene)
        plan.started = started
    except BaseException:
        lock.release()
        raise
    try:
        writer = ResultsWriter(path, plan.series, plan.attrs(), flush_seconds=sim.flush_seconds, lock=lock)
    except BaseException:
        lock.release()
        plan.master.terminate()
        raise
    state = _Progress(next_checkpoint=sim.checkpoint_every if sim.checkpoint_every > 0 else math.inf)
    try:
        if plan.control:
            c = scenario.control
            if log is not None:
                log(f"waiting up to {c.connect_timeout:g} s (control.connect_timeout) for a controller on run "
                    f"{plan.control.settings.run_id!r} ...")
            plan.control.start()
        plan.master.initialize(0.0, sim.duration, plan.parameter_links)
        plan.radiation = radiation_report(plan)
        for message in plan.radiation.get("warnings", []) if log is not None else []:
            log(f"warning: {message}")
    except BaseException as exc:
        plan.master.terminate()
        extra = {"control_statistics": plan.control.close("failed")} if plan.control else None
        writer.close(status=f"failed: initialisation: {exc}", attrs=extra)
        raise
    return _execute(plan, writer, state, progress, observe_start=True)


def resume_run(results: str | Path, *, log=print, progress: bool = True) -> RunResult:
    """Continue a run from the last checkpoint next to its results file (``wec-cosim resume``).

    The scenario and settings are those stored in the results file; rows after the checkpoint
    are dropped and computed again, so the finished file equals an uninterrupted run's.
    """
    results = Path(results)
    if not results.is_file():
        raise WecCosimError(f"results file {results} does not exist")
    lock = ResultsLock(results, "resume")  # not while a run (or another resume) writes the file
    try:
        return _resume(results, lock, log, progress)
    except BaseException:
        lock.release()
        raise


def _resume(results: Path, lock: ResultsLock, log, progress: bool) -> RunResult:  # noqa: ANN001
    try:
        with h5py.File(results, "r", swmr=True) as f:
            text = f.attrs["scenario"]
            scenario_file = Path(f.attrs["scenario_file"])
            stored = json.loads(f.attrs["settings"])
    except (OSError, KeyError, ValueError) as exc:
        raise WecCosimError(f"{results} is not a wec-cosim results file that can be resumed ({exc})") from None
    saved = read_checkpoint(checkpoint_path(results))
    from orchestrator.scenario import apply_overrides

    scenario = apply_overrides(parse_scenario(text, scenario_file), stored.get("overrides", []), what="--set")
    scenario.simulation.duration = stored.get("duration", scenario.simulation.duration)  # `run --duration`
    if scenario.control.mode != "off":
        raise WecCosimError(f"{results}: a run driven by an external controller cannot be resumed (the "
                            "controller's own state is not in the checkpoint); run it again")
    started = time.perf_counter()
    plan = prepare_run(scenario, in_process=stored.get("fmi") == "in-process", log=log, progress=progress)
    plan.started = started
    sim = scenario.simulation
    old = read_results(results)
    rows = saved["rows"]
    missing = [name for name in plan.recorder.series if name not in old or len(old[name]) < rows]
    if missing:
        plan.master.terminate()
        raise WecCosimError(f"{results} does not hold the {rows} rows its checkpoint needs ({missing[0]!r}); "
                            "run the simulation again")
    _check_same_build(results, stored.get("fmus", {}), plan)
    try:
        check_checkpoint(results, saved, plan, np.asarray(old["time"]))
    except WecCosimError:
        plan.master.terminate()
        raise
    # Restore first: a checkpoint that cannot be used leaves the results file as it was.
    try:
        plan.master.initialize(0.0, sim.duration, plan.parameter_links)
        plan.radiation = radiation_report(plan)
        plan.master.restore(saved["checkpoint"])
        plan.controller.set_state(saved["controller"])
    except BaseException as exc:
        plan.master.terminate()
        if isinstance(exc, (MasterError, WecCosimError)):
            raise WecCosimError(f"{checkpoint_path(results)}: the checkpoint could not be restored: {exc}; "
                                f"{results} is unchanged") from None
        raise
    writer = ResultsWriter(results.with_name(results.name + ".resume.part"), plan.recorder.series, {
        k: v for k, v in old["attrs"].items() if k not in ("status", "wall_time")}, flush_seconds=sim.flush_seconds,
        lock=lock)
    writer.append_block({name: old[name][:rows] for name in plan.recorder.series})
    writer.flush()
    os.replace(writer.path, results)
    writer.path = results
    writer.watch.moved_to(results)
    every = sim.checkpoint_every
    state = _Progress(steps=saved["steps"], next_checkpoint=saved["time"] + every if every > 0 else math.inf)
    return _execute(plan, writer, state, progress, observe_start=False)


def _check_same_build(results: Path, built: dict[str, str], plan: RunPlan) -> None:
    """Refuse a checkpoint whose FMUs were built from other sources than this version builds for the same
    scenario (the FMU file name carries the build key: sources, PythonFMU, specification, data): an FMU
    state is the private data of the build that wrote it and need not fit another one."""
    now = plan.settings.get("fmus", {})
    for kind, path in now.items():
        if kind in built and Path(built[kind]).name != Path(path).name:
            plan.master.terminate()
            raise WecCosimError(
                f"{checkpoint_path(results)}: the run was started by another build of the {kind} FMU "
                f"({Path(built[kind]).name}; this version builds {Path(path).name}: the sources or PythonFMU "
                f"changed since), and an FMU state need not fit another build; resume with the version that "
                f"started the run, or run the simulation again. {results} is unchanged")


def _execute(plan: RunPlan, writer: ResultsWriter, state: _Progress, progress: bool,
             observe_start: bool) -> RunResult:
    """Step to the end, writing rows and checkpoints; close the file with the run's status."""
    scenario = plan.scene.scenario
    sim = scenario.simulation
    master, recorder = plan.master, plan.recorder
    bar = ProgressBar(0.0, sim.duration, enabled=progress)
    ckpt = checkpoint_path(writer.path)
    identity = run_identity(plan) if sim.checkpoint_every > 0 else {}
    end_tick = int(round(sim.duration / sim.step))

    control = plan.control

    interrupt = InterruptAtStep()

    def observe(t: float, outputs: dict[str, np.ndarray]) -> None:
        interrupt.check()  # Ctrl-C: stop here, between steps (not inside an FMU's step)
        k = state.steps
        if control:
            control.on_point(t, outputs)
        if k % sim.output_every == 0 or plan.controller.ticks >= end_tick:
            recorder.values(t, outputs, out=writer.next_line())
            writer.commit_line(recorder.width, control.row() if control else None)
        state.steps = k + 1
        if t >= state.next_checkpoint - 1e-9 * sim.step:
            writer.flush()
            write_checkpoint(ckpt, master.checkpoint(), plan.controller.state(), time=t, rows=writer.written,
                             steps=state.steps, identity=identity)
            state.next_checkpoint += sim.checkpoint_every
        bar.update(t)

    start = time.perf_counter()
    setup = start - plan.started
    try:
        with interrupt:
            master.run(sim.duration, sim.step, observe, controller=plan.controller, observe_start=observe_start)
    except ResultsFileLost:  # the writer copied the rows and said where: nothing to close
        raise
    except MasterError as exc:
        writer.close(status=f"failed: {exc}", wall_time=time.perf_counter() - start, attrs=_final_attrs(plan, "failed"))
        raise MasterError(f"{exc}{divergence_causes(plan)} (results up to t = {master.time:g} s are in "
                          f"{writer.path})") from None
    except KeyboardInterrupt:
        writer.close(status="interrupted", wall_time=time.perf_counter() - start,
                     attrs=_final_attrs(plan, "failed"))
        raise
    except OSError as exc:  # the results or checkpoint file could not be written (disk full, file-size limit)
        _write_failure(plan, writer, exc, start)
    except BaseException:
        writer.release()
        raise
    finally:
        master.terminate()
        bar.close()
    wall = time.perf_counter() - start
    attrs = _final_attrs(plan, "finished")
    try:
        writer.close(status="completed", wall_time=wall, attrs=attrs)
    except OSError as exc:  # the last rows could not be flushed
        _write_failure(plan, writer, exc, start)
    result = RunResult(writer.path, wall, sim.duration, plan.controller.steps, statistics=attrs["statistics"],
                       radiation=plan.radiation, mobility=plan.mobility, setup_time=setup,
                       notes=[f"warning: {w}" for w in plan.warnings])
    if plan.radiation.get("method") == "convolution" and "frequency_error" in plan.radiation:
        scene, reported = plan.scene, plan.radiation["frequency_error"]
        # computed when the summary is printed (0.3-8 s on constrained scenes): sweeps and benchmarks skip it
        result.radiation_check = lambda: scene.radiation_check().text(reported)
    data = read_results(writer.path) if plan.recorder.wave_balance else None
    if data is not None:
        result.energy = energy_account(data)
    if scenario.waves.kind == "regular" and not control:  # an external law has no frequency-domain answer
        needed = scenario.ramp_time + sim.steady_periods * scenario.waves.period
        if sim.duration >= needed:
            result.comparisons = compare_with_frequency_domain(plan.scene, data or read_results(writer.path))
        else:
            result.notes.append(
                f"no comparison with the exact steady state: the run ({sim.duration:g} s) is shorter than the ramp "
                f"and simulation.steady_periods = {sim.steady_periods:g} wave periods ({needed:g} s)")
    if scenario.ptos:  # also beside the comparison: the Python API reads it (the summary prints it once)
        with h5py.File(writer.path, "r", swmr=True) as f:
            result.mean_power, result.power_window = mean_pto_powers(scenario, f)
    if control:
        result.notes += control_notes(attrs.get("control_statistics"), scenario.control.fallback)
    result.error_estimate = error_estimate.for_run(plan.scene, writer.path, _quiet_run, data)
    if scenario._duration_note:
        result.notes.append(scenario._duration_note)
    if scenario.waves.kind == "elevation":
        record = plan.scene.sea().record
        result.notes.append(f"waves: elevation record {record.source} read as {record.form} "
                            f"({len(record.eta)} samples every {record.dt:g} s)")
    return result


def _quiet_run(scenario: Scenario, output: Path, scene: Scene) -> RunResult:
    """A run of ``scenario`` into ``output`` with its slaves in process and nothing printed (the coarse shadow of
    :mod:`.error_estimate`)."""
    return run_scenario(scenario, output, in_process=True, log=None, progress=False, scene=scene)


def control_notes(stats: dict | None, fallback: str) -> list[str]:
    """Summary lines for the controller's faults, fallbacks and refused controllers."""
    if not stats:
        return []
    faults = {k: v for k, v in stats.get("faults", {}).items() if v}
    periods, fell = stats.get("periods", 0), stats.get("fallback_periods", 0)
    out = [f"controller: {periods - fell} of {periods} control periods commanded by the controller"
           + (f", {fell} on the fallback {fallback!r}" if fell else "")
           + (" (faults: " + ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in faults.items()) + ")" if faults
              else "")]
    dropped = {k: v for k, v in stats.get("dropped_frames", {}).items() if v}
    if dropped:
        out.append(f"controller: {sum(dropped.values())} frames dropped without acting on them ("
                   + ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in dropped.items()) + ")")
    if stats.get("refused_controllers"):
        out.append(f"controller: {stats['refused_controllers']} other controller(s) refused on this run id "
                   f"({stats.get('refused_commands', 0)} of their commands ignored)")
    return out


def _write_failure(plan: RunPlan, writer: ResultsWriter, exc: OSError, start: float) -> typing.NoReturn:
    """Record ``failed`` if the file system still allows it and raise one clear error (rows on disk kept)."""
    attrs = {"statistics": _run_statistics(plan), "radiation_model": plan.radiation}
    if plan.control and plan.control.bridge.session is not None:
        attrs["control_statistics"] = plan.control.close("failed")
    recorded = writer.fail(f"failed: writing the results: {exc.strerror or exc}",
                           wall_time=time.perf_counter() - start, attrs=attrs)
    kept = (f"the {writer.written} rows written before are kept"
            + ("" if recorded else " (the status attribute could not be recorded)") if writer.path.is_file()
            else f"the results file no longer exists: its {writer.written} rows are lost")
    raise WecCosimError(
        f"writing {writer.path} failed at t = {plan.master.time:g} s: {exc.strerror or exc}; {kept}: free "
        "space (or raise the file-size limit) and resume with `wec-cosim resume` if a checkpoint exists, or run "
        "again") from None


def _final_attrs(plan: RunPlan, state: str) -> dict:
    """Attributes written when a run ends: run statistics, and the control statistics (which also
    tells the external controller that the run is over)."""
    out = {"statistics": _run_statistics(plan), "radiation_model": plan.radiation}
    if plan.control:
        out["control_statistics"] = plan.control.close(state)
    return out


def radiation_report(plan: RunPlan) -> dict:
    """The radiation model's report (method, state-space order and errors, and the hydro model's warnings: state-space
    blocks left to the convolution, impulse-response accuracy): from the hydro FMU, or from the in-process model of
    the monolithic mode."""
    method = plan.scene.scenario.hydro.radiation_method
    hydro = getattr(plan.master, "hydro", None)
    if hydro is not None:  # monolithic: the physics object itself
        r = hydro.report
        return {"method": method, "order": r.order, "fit_error": r.kernel_error, "frequency_error": r.frequency_error,
                "warnings": list(r.warnings)}
    comp = plan.master.components.get(HYDRO) if hasattr(plan.master, "components") else None
    names = ["radiation.order", "radiation.fit_error", "radiation.frequency_error"]
    if comp is None or any(n not in comp.variables for n in names):
        return {}
    order, fit_error, frequency_error = (float(v) for v in comp.get_reals(comp.port(names)))
    warnings = [w for w in comp.warnings() if w.startswith("radiation")] if hasattr(comp, "warnings") else []
    return {"method": method, "order": int(order), "fit_error": fit_error, "frequency_error": frequency_error,
            "warnings": warnings}


def _run_statistics(plan: RunPlan) -> dict:
    sizes = plan.controller.sizes
    out = {"macro_steps": plan.controller.steps, "master": plan.master.name,
           "mooring_lines": plan.scene.scenario.mooring_lines.model}
    if sizes:
        out.update(smallest_step=min(sizes), largest_step=max(sizes), mean_step=float(np.mean(sizes)))
    its = getattr(plan.master, "iterations", [])
    if its:
        out.update(mean_iterations=float(np.mean(its)), max_iterations=int(np.max(its)))
    return out


def compare_with_frequency_domain(scene: Scene, data: dict) -> list[Comparison]:
    """Steady-state amplitude and phase of every active DOF and mean PTO power, against the FD solution."""
    s = scene.scenario
    w = s.waves
    omega = 2 * math.pi / w.period
    amplitude = w.height / 2
    fd = frequency_domain.solve(scene, np.array([omega]))
    t = data["time"]
    mask, _ = averaging_window(s, t)  # the window of the figures' mean power too
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
    from mbd_fmu.joints import JOINT_COORDINATE_UNITS

    for j in s.joints:
        if f"joints/{j.name}/coordinate" not in data:
            continue
        series = np.asarray(data[f"joints/{j.name}/coordinate"]).reshape(len(t), -1)
        for i, (name, (unit, _)) in enumerate(zip(fd.joint_coordinates[j.name], JOINT_COORDINATE_UNITS[j.kind],
                                                  strict=True)):
            measured, _ = harmonic_fit(t[mask], series[mask, i], omega)
            exact = complex(fd.joint_rao[j.name][0, i] * amplitude * wave_phase)
            out.append(Comparison(f"{j.name} {name}", unit, measured, exact))
    for p in s.ptos:
        measured = window_mean(t, data[f"ptos/{p.name}/power"], mask)
        out.append(Comparison(f"{p.name} mean power", "W", measured, float(fd.pto_power[p.name][0] * amplitude**2)))
    return out


def _powers_text(powers: dict[str, float], many: int = 6) -> str:
    """Each PTO's mean power, or for more than ``many`` PTOs their total and the three largest (W or kW)."""
    scale, unit = (1e3, "kW") if max(abs(p) for p in powers.values()) * len(powers) >= 1e3 else (1.0, "W")
    if len(powers) <= many:
        return ", ".join(f"{name} {p / scale:.4g} {unit}" for name, p in powers.items())
    largest = sorted(powers.items(), key=lambda item: -item[1])[:3]
    return (f"total {sum(powers.values()) / scale:.4g} {unit} of {len(powers)} PTOs; largest "
            + ", ".join(f"{name} {p / scale:.4g} {unit}" for name, p in largest))


def _residual_share(e: dict) -> str:
    """The residual as a share of the account's largest term: the work in when waves drive the bodies, the stored
    energy released in a decay in still water (where the work in is zero and a share of it means nothing)."""
    terms = {k: abs(e[k]) for k in ("work_in", "pto", "radiated", "dissipated", "stored")}
    key = "work_in" if terms["work_in"] >= 0.5 * max(terms.values()) else max(terms, key=terms.get)
    if not terms[key] > 0:
        return ""
    what = "the work in" if key == "work_in" else f"the largest term ({key.replace('_', ' ')})"
    return f" ({100 * e['residual'] / terms[key]:.3g} % of {what})"


def format_summary(result: RunResult) -> str:
    lines = [f"results: {result.path}"]
    if result.comparisons:
        lines.append("steady state against the exact frequency-domain solution"
                     + (" (mooring lines linearised quasi-statically: MoorDyn's line dynamics are not in it):"
                        if result.statistics.get("mooring_lines") == "moordyn" else ":"))
        lines.append(f"  {'quantity':<24}{'co-simulation':>16}{'exact':>16}{'error':>10}{'phase err':>11}")
        for c in result.comparisons:
            phase = f"{c.phase_error_deg:+9.2f} deg" if not math.isnan(c.phase_error_deg) else ""
            lines.append(
                f"  {c.label:<24}{abs(c.measured):>13.5g} {c.unit:<2}{abs(c.exact):>13.5g} {c.unit:<2}"
                f"{100 * c.amplitude_error:>+9.3f}%{phase:>13}")
    e = result.energy
    if e:
        lines.append("energy account (J): " + ", ".join(
            f"{k.replace('_', ' ')} {e[k]:.6g}" for k in ("work_in", "pto", "radiated", "dissipated", "stored"))
            + f"; residual {e['residual']:.3g} J" + _residual_share(e))
        if result.statistics.get("mooring_lines") == "moordyn":
            lines.append("  (the MoorDyn lines' work on the bodies is not a term of this account: the residual "
                         "includes it)")
    st = result.statistics
    if "mean_iterations" in st:
        lines.append(f"{st['master']}: {st['mean_iterations']:.2f} evaluations per step on average, "
                     f"at most {st['max_iterations']}")
    if st.get("smallest_step") is not None and st["smallest_step"] != st["largest_step"]:
        lines.append(f"adaptive step: {st['smallest_step']:g} .. {st['largest_step']:g} s, "
                     f"mean {st['mean_step']:.4g} s")
    r = result.radiation
    if r.get("method") == "state_space":
        lines.append(f"radiation: state space of order {r['order']}, impulse-response fit error {r['fit_error']:.3g}, "
                     f"A and B against the database {r['frequency_error']:.3g}")
    elif r.get("method") == "convolution" and result.radiation_check is not None:
        lines += ["radiation: convolution", result.radiation_check()]
    elif r:
        lines.append(f"radiation: convolution, A and B of the truncated impulse response against the database "
                     f"{r['frequency_error']:.3g} (relative 2-norm, no unit)")
    lines += [f"warning: {w}" for w in r.get("warnings", [])]
    if result.mean_power and not result.comparisons:  # (compared with the exact answer: in the table above)
        lines.append(f"mean PTO power ({result.power_window}): " + _powers_text(result.mean_power))
    lines += result.notes
    if result.error_estimate is not None:
        lines.append(result.error_estimate.text())
    if result.step_choice is not None:
        lines.append(result.step_choice.text())
    setup = f"set-up {result.setup_time:.2f} s (scene, FMUs, initialisation), " if math.isfinite(
        result.setup_time) else ""
    lines.append(
        f"wall time: {setup}stepping {result.wall_time:.2f} s for {result.simulated_time:g} s simulated "
        f"({result.steps} macro steps): real-time factor {result.real_time_factor:.1f}")
    return "\n".join(lines)
