"""``wec-cosim`` command line.

    wec-cosim run SCENARIO [--out FILE] [--set KEY=VALUE] time-domain co-simulation
    wec-cosim rao SCENARIO --out FILE                     linear frequency-domain response
    wec-cosim hydro SCENARIO [--refresh]                  build or refresh the hydrodynamic database
    wec-cosim build-fmus SCENARIO [--out DIR]             build the scene's two FMUs
    wec-cosim controller NAME --run RUN_ID                run an example external controller
    wec-cosim export-ssp SCENARIO OUT.ssp [--native]      SSP archive (FMUs, connections, parameters)
    wec-cosim resume RESULTS.h5                           continue a run from its last checkpoint
    wec-cosim plot FILE.h5... [--out DIR] [--joints J[k]...]  PNG figures of results, RAO, steady or sweep files
    wec-cosim sweep SCENARIO --out FILE [--scheduler A]   one run per case of [sweep] on Dask; power matrices

User mistakes (bad scenario, missing file, diverging run) print one paragraph and exit with
status 2; nothing already computed is lost.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import shutil
import sys
import typing
from pathlib import Path

from hydro_fmu.hdb import HydroDatabaseError
from orchestrator.errors import WecCosimError


def _scenario(path: str):
    from orchestrator.scenario import load_scenario

    return load_scenario(path)


def _override_duration(scenario, duration: float) -> None:  # noqa: ANN001 - Scenario
    """Set ``simulation.duration`` from ``--duration`` and check it as the scenario's own value."""
    from orchestrator.errors import ScenarioError
    from orchestrator.scenario import input_checks
    from orchestrator.scenario.checks import check_simulation

    scenario.simulation.duration = duration
    try:
        check_simulation(scenario)
        input_checks.check_limits(scenario)
    except ScenarioError as exc:
        raise ScenarioError(f"{exc} (simulation.duration was set by --duration {duration:g})") from None


def _out(value: str, kind: str = "hdf5") -> Path:
    from orchestrator.scenario.input_checks import check_output

    if not value:
        raise WecCosimError("--out: an empty path is not usable; give a file name")
    return check_output(Path(value), "--out", kind=kind)


def cmd_run(args: argparse.Namespace) -> int:
    from orchestrator.cosim.simulation import format_summary, run_scenario
    from orchestrator.scenario import apply_overrides

    scenario = apply_overrides(_scenario(args.scenario), args.set or [], what="--set")
    if args.duration is not None:
        _override_duration(scenario, args.duration)
    if args.out is not None:
        _out(args.out)
    result = run_scenario(scenario, args.out, in_process=args.in_process, progress=not args.quiet)
    print(format_summary(result))
    return 0


def cmd_rao(args: argparse.Namespace) -> int:
    from orchestrator.reference.response_files import write_rao_file
    from orchestrator.scenario import apply_overrides
    from orchestrator.scene import load_scene

    scenario = apply_overrides(_scenario(args.scenario), args.set or [])
    if args.form:
        scenario.rao.form = args.form
    out = _out(args.out)
    scene = load_scene(scenario, progress=True)
    responses = write_rao_file(scene, out)
    print(f"RAOs ({responses[0].form} form) at {len(responses[0].omega)} frequencies and {len(responses)} "
          f"heading(s) written to {out}")
    _plots(args, out)
    return 0


def cmd_steady(args: argparse.Namespace) -> int:
    from orchestrator.reference.response_files import write_steady_file
    from orchestrator.scenario import apply_overrides
    from orchestrator.scene import load_scene

    scenario = apply_overrides(_scenario(args.scenario), args.set or [])
    out = _out(args.out)
    scene = load_scene(scenario, progress=True)
    states = write_steady_file(scene, out, args.harmonics, args.form)
    bad = [st for st in states if not (math.isfinite(st.residual) and all(map(math.isfinite, st.pto_power.values())))]
    if bad:
        raise WecCosimError(f"{scenario.file}: the steady state at T = {bad[0].period:g} s is not finite (residual "
                            f"{bad[0].residual:g}): the scene's values (masses, stiffnesses, wave) are out of any "
                            f"physical range; check them (the file {out} holds the failed solve)")
    for st in states:
        powers = ", ".join(f"{name} {p:.5g} W" for name, p in st.pto_power.items())
        print(f"T = {st.period:g} s, {st.harmonics} harmonics ({st.form}): mean power {powers or 'no PTO'}")
    print(f"steady states written to {out}")
    _plots(args, out)
    return 0 if all(st.converged for st in states) else 1


def _plots(args: argparse.Namespace, out: Path) -> None:
    if getattr(args, "plot", False):
        from orchestrator.results.plotting import plot_file

        for png in plot_file(out):
            print(f"figure: {png}")


def cmd_hydro(args: argparse.Namespace) -> int:
    from orchestrator.scene import load_database

    scenario = _scenario(args.scenario)
    out = _out(args.export) if args.export is not None else None
    hdb, path = load_database(scenario, refresh=args.refresh, progress=True)
    print(f"{path}: {hdb.n_bodies} bodies, {len(hdb.omega)} frequencies "
          f"{hdb.omega[0]:g}..{hdb.omega[-1]:g} rad/s, {len(hdb.headings)} headings ({hdb.source})")
    if out is not None:
        from hydro_fmu.bemio import write_bemio

        write_bemio(hdb, out, wec_sim_groups=True)
        print(f"{out}: the scene's database as BEMIO HDF5 with the impulse responses and state space WEC-Sim reads")
    return 0


def cmd_build_fmus(args: argparse.Namespace) -> int:
    from orchestrator.fmi.fmu_builder import build_scene_fmus
    from orchestrator.scene import load_scene

    scenario = _scenario(args.scenario)
    out = _out(args.out, kind="dir")
    scene = load_scene(scenario, progress=True)
    fmus = build_scene_fmus(scene)
    out.mkdir(parents=True, exist_ok=True)
    for kind, path in fmus.items():
        target = out / f"{scene.scenario.name}_{kind}.fmu"
        shutil.copy(path, target)
        print(f"{kind}: {target}")
    if args.native:
        from hydro_fmu.native_fmu import NativeBuildError, build_native_hydro_fmu, sea_constants

        s = scene.scenario
        for version in (2, 3):
            target = out / f"{s.name}_hydro_native_fmi{version}.fmu"
            try:
                build_native_hydro_fmu(scene.hydro_model(), target, constants=sea_constants(scene.sea_spec()),
                                       name=f"{s.name}_hydro", fmi_version=version,
                                       experiment=(0.0, s.simulation.duration, s.simulation.step))
            except NativeBuildError as exc:
                print(f"wec-cosim build-fmus: {exc}", file=sys.stderr)
                return 2
            print(f"hydro (native, FMI {version}.0, no Python needed; sea fixed at build time): {target}")
    print("connect them as docs/fmu_variables.md says (the linearised force interface: x, v -> hydro; F0, F0_rate, "
          "dF_dx, dF_dv -> mbd); in a C/C++ host use the environment of `wec-cosim host-env` (docs/hosts/)")
    return 0


def cmd_controller(args: argparse.Namespace) -> int:
    from orchestrator.control.examples import run_example

    try:
        return run_example(args)
    except (TimeoutError, RuntimeError, FileNotFoundError, TypeError, ValueError) as exc:
        raise WecCosimError(f"controller {args.name!r}: {exc}") from None


def cmd_export_ssp(args: argparse.Namespace) -> int:
    from orchestrator.fmi.ssp import export_ssp
    from orchestrator.scene import load_scene

    scenario = _scenario(args.scenario)
    _out(args.out, kind="file")
    scene = load_scene(scenario, progress=True)
    path = export_ssp(scene, args.out, native=args.native)
    hydro = "hydro (native, FMI 2.0, no Python needed; sea fixed at build time)" if args.native else "hydro"
    print(f"SSP archive {path}: components {hydro}, mbd; {len(scene.linearised_connections())} connections "
          f"(linearised force interface); run it with fmpy.ssp.simulation.simulate_ssp, libcosimpy, OMSimulator "
          f"or a C host (docs/hosts/)")
    return 0


def cmd_host_env(args: argparse.Namespace) -> int:
    from orchestrator.fmi.host_environment import main_host_env

    command = list(args.command_line)
    if command and command[0] == "--":
        command = command[1:]
    return main_host_env(command, "json" if args.json else "shell")


def cmd_resume(args: argparse.Namespace) -> int:
    from orchestrator.cosim.simulation import format_summary, resume_run

    result = resume_run(args.results, progress=not args.quiet)
    print(format_summary(result))
    return 0


def cmd_plot(args: argparse.Namespace) -> int:
    from orchestrator.results.plotting import plot_file
    from orchestrator.results.response_plots import joints_file_name, plot_joint_raos

    from .sweeps.plotting import DRAWERS

    if args.joints:
        target = Path(args.out or Path(args.file[0]).parent) / joints_file_name(args.file, args.joints)
        print(plot_joint_raos(args.file, args.joints, target))
        return 0
    for file in args.file:
        for path in plot_file(file, args.out, DRAWERS):
            print(path)
    return 0


def cmd_sweep(args: argparse.Namespace) -> int:
    from .sweeps import SweepInterrupted, run_sweep
    from .sweeps.grid import parse_grid_option, set_grid
    from .sweeps.report import format_outcome

    scenario = _scenario(args.scenario)
    _out(args.out)
    sw = scenario.sweep
    sw.method = args.method or sw.method
    sw.seeds = args.seeds or sw.seeds
    sw.time_series = sw.time_series or args.time_series
    sw.transient = sw.transient if args.transient is None else args.transient
    for option in args.grid:
        set_grid(scenario, *parse_grid_option(option))
    try:
        outcome = run_sweep(scenario, args.out, scheduler=args.scheduler, workers=args.workers,
                            in_process=True if args.in_process else None, retry_failed=args.retry_failed,
                            progress=not args.quiet)
    except SweepInterrupted as exc:
        print(f"wec-cosim sweep: {exc}", file=sys.stderr)
        return 130
    print(format_outcome(outcome))
    return 0


def _positive_seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"{text} s: give a positive, finite duration in seconds")
    return value


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value}: give a whole number of at least 1")
    return value


class _Parser(argparse.ArgumentParser):
    """Option errors as one paragraph, like every other error (exit status 2)."""

    def error(self, message: str) -> typing.NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not (math.isfinite(value) and value >= 0):
        raise argparse.ArgumentTypeError(f"{text} s: give a finite duration of at least 0 s")
    return value


def _add_set(command: argparse.ArgumentParser) -> None:
    """The ``--set KEY=VALUE`` option, the same keys for run, rao and steady."""
    command.add_argument("--set", action="append", metavar="KEY=VALUE",
                         help="override a numeric or choice key, e.g. mooring_lines.model=quasi_static or "
                              "ptos.pto.damping=8e5, or a list as a TOML array, e.g. 'bodies.float.dofs=[\"heave\"]' "
                              "(repeatable; recorded in the output file)")


def parser() -> argparse.ArgumentParser:
    from . import version

    p = _Parser(prog="wec-cosim", description="Multibody wave-energy co-simulation.")
    p.add_argument("--version", action="version", version=f"wec-cosim {version()}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    r = sub.add_parser("run", help="run a time-domain co-simulation")
    r.add_argument("scenario")
    r.add_argument("--out", help="results file (default from the scenario)")
    r.add_argument("--duration", type=_positive_seconds, help="override simulation.duration (s)")
    _add_set(r)
    r.add_argument("--in-process", action="store_true", help="call the FMU slaves directly, without fmpy")
    r.add_argument("--quiet", action="store_true", help="no progress display")
    r.set_defaults(func=cmd_run)
    a = sub.add_parser("rao", help="linear frequency-domain response (RAOs, PTO power)")
    a.add_argument("scenario")
    a.add_argument("--out", required=True, help="output HDF5 file")
    a.add_argument("--form", choices=("dae", "ode"), help="override rao.form")
    _add_set(a)
    a.add_argument("--plot", action="store_true", help="also write PNG figures next to the file")
    a.set_defaults(func=cmd_rao)
    y = sub.add_parser("steady", help="pseudo-spectral periodic steady state in regular waves (nonlinear forces)")
    y.add_argument("scenario")
    y.add_argument("--out", required=True, help="output HDF5 file")
    y.add_argument("--harmonics", type=_positive_int, help="override steady.harmonics")
    y.add_argument("--form", choices=("dae", "ode"), help="override steady.form")
    _add_set(y)
    y.add_argument("--plot", action="store_true", help="also write PNG figures next to the file")
    y.set_defaults(func=cmd_steady)
    h = sub.add_parser("hydro", help="build or refresh the scenario's hydrodynamic database")
    h.add_argument("scenario")
    h.add_argument("--refresh", action="store_true", help="recompute even if cached")
    h.add_argument("--export", metavar="FILE.h5",
                   help="also write the scene's database (its bodies, about their cgs) as BEMIO HDF5 with the "
                        "radiation and excitation impulse responses and the state-space realisation WEC-Sim reads")
    h.set_defaults(func=cmd_hydro)
    b = sub.add_parser("build-fmus", help="build the scenario's hydrodynamics and multibody FMUs")
    b.add_argument("scenario")
    b.add_argument("--out", default="fmus", help="folder for the FMUs (default ./fmus)")
    b.add_argument("--native", action="store_true",
                   help="also write the native hydro FMUs (FMI 2.0 and 3.0, compiled C, no Python needed in the host; "
                        "the sea is fixed at build time: docs/hosts/native_fmus.md)")
    b.set_defaults(func=cmd_build_fmus)
    from orchestrator.control.examples import add_arguments

    c = add_arguments(sub.add_parser("controller", help="run an example external controller (zenoh)"))
    c.set_defaults(func=cmd_controller)
    e = sub.add_parser("export-ssp", help="write the scene as an SSP archive for other FMI tools")
    e.add_argument("scenario")
    e.add_argument("out", help="output .ssp file")
    e.add_argument("--native", action="store_true",
                   help="the hydro component is the native hydro FMU (FMI 2.0, compiled C, no Python needed for it; "
                        "the sea is fixed at build time); the multibody FMU stays the Python one "
                        "(docs/hosts/native_fmus.md). The SSD carries OSP's and OMSimulator's fixed-step annotations")
    e.set_defaults(func=cmd_export_ssp)
    v = sub.add_parser("host-env", help="print (or run a command with) the environment our FMUs need in a C/C++ "
                                        "host: LD_PRELOAD of libpython, PYTHONHOME, PYTHONPATH (docs/hosts/c.md)")
    v.add_argument("--json", action="store_true", help="print JSON instead of shell export lines")
    v.add_argument("command_line", nargs=argparse.REMAINDER, metavar="-- COMMAND ...",
                   help="run COMMAND with that environment instead of printing it")
    v.set_defaults(func=cmd_host_env)
    c = sub.add_parser("resume", help="continue a run from the last checkpoint next to its results file")
    c.add_argument("results")
    c.add_argument("--quiet", action="store_true", help="no progress display")
    c.set_defaults(func=cmd_resume)
    g = sub.add_parser("plot", help="PNG figures of results, RAO or steady-state files")
    g.add_argument("file", nargs="+")
    g.add_argument("--out", help="folder for the PNG files (default: next to the (first) file)")
    g.add_argument("--joints", nargs="+", metavar="NAME[k]",
                   help="RAO files: one figure of these joint coordinates' RAOs from all the files given (NAME: "
                        "every coordinate of the joint, NAME[k]: the k-th)")
    g.set_defaults(func=cmd_plot)
    w = sub.add_parser("sweep", help="power matrices, PTO studies, seed ensembles: one run per case on Dask")
    w.add_argument("scenario")
    w.add_argument("--out", required=True, help="sweep file (HDF5); an existing one of the same scene is continued")
    w.add_argument("--grid", action="append", default=[], metavar="KEY=V1,V2|START:STOP:N",
                   help="add or replace a swept key of [sweep.grid], e.g. waves.hs=1,2,3 or waves.tp=5:10:6")
    w.add_argument("--seeds", type=_positive_int, help="override sweep.seeds (irregular seas, time domain)")
    w.add_argument("--method", choices=("frequency_domain", "time_domain"), help="override sweep.method")
    w.add_argument("--transient", type=_seconds, help="override sweep.transient (s)")
    w.add_argument("--time-series", action="store_true", help="also store each case's time series")
    w.add_argument("--scheduler", metavar="ADDRESS", help="a running Dask scheduler, e.g. tcp://head:8786 "
                                                          "(default: a local cluster)")
    w.add_argument("--workers", type=_positive_int, help="local cluster: worker processes (default sweep.workers, "
                                                  "or one per core)")
    w.add_argument("--in-process", action="store_true",
                   help="run the cases one after another in this process, without Dask (default for the "
                        "frequency-domain method unless --workers or --scheduler is given)")
    w.add_argument("--retry-failed", action="store_true", help="run the cases recorded as failed again")
    w.add_argument("--quiet", action="store_true", help="no progress display")
    w.set_defaults(func=cmd_sweep)
    k = sub.add_parser("bench", help="speed against error, hard cases, scaling: write the bench report (Markdown, "
                                     "PNG, CSV) from the bundled scenarios")
    k.add_argument("--quick", action="store_true", help="shorter runs and fewer points (under 10 minutes)")
    k.add_argument("--out", default="bench_report", help="report folder (default ./bench_report)")
    k.add_argument("--quiet", action="store_true", help="no progress lines")
    k.set_defaults(func=cmd_bench)
    return p


def cmd_bench(args: argparse.Namespace) -> int:
    from .benchreport.report import build

    command = "wec-cosim bench" + (" --quick" if args.quick else "") + f" --out {args.out}"
    path = build(Path(args.out), args.quick, log=print if not args.quiet else (lambda _: None), command=command)
    print(f"report: {path}")
    return 0


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    hooks = sys.unraisablehook, sys.excepthook
    sys.unraisablehook, sys.excepthook = _quiet_hdf5_dealloc, _quiet_hdf5_traceback
    with _numerical_warnings() as failed:
        try:
            code = _run(args)
            if code != 0:
                failed.append(True)
        except BaseException:
            failed.append(True)
            raise
        finally:
            sys.unraisablehook, sys.excepthook = hooks
        return code


@contextlib.contextmanager
def _numerical_warnings() -> typing.Iterator[list]:
    """numpy's floating-point warnings ("overflow encountered in ...") of a command that then fails are the
    failure's symptoms, not news: they are dropped so that the error is the one paragraph the user reads; the
    warnings of a command that succeeds are shown as they were. Other warnings are always shown."""
    import warnings

    failed: list = []
    with warnings.catch_warnings(record=True) as caught:  # the filters in force stay as they are
        yield failed
    for w in caught:
        numerical = issubclass(w.category, RuntimeWarning) and (
            "encountered in" in str(w.message) or "/numpy/" in w.filename.replace("\\", "/"))
        if failed and numerical:
            continue
        warnings.showwarning(w.message, w.category, w.filename, w.lineno)


def _run(args: argparse.Namespace) -> int:
    try:
        return args.func(args)
    except (WecCosimError, HydroDatabaseError) as exc:
        print(f"wec-cosim {args.command}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except OSError as exc:  # the machine's limits: disk full, permissions, file-size limit
        print(f"wec-cosim {args.command}: error: {machine_limit(exc)}", file=sys.stderr)
        return 2
    except RuntimeError as exc:  # h5py reports some refused writes (closing a file on a full disk) this way
        if "file write failed" not in str(exc):
            raise
        print(f"wec-cosim {args.command}: error: {machine_limit(exc)}", file=sys.stderr)
        return 2
    except MemoryError:
        print(f"wec-cosim {args.command}: error: out of memory; reduce the scenario's sizes (duration/step, "
              "frequency grids, wave components)", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"wec-cosim {args.command}: interrupted (a results file keeps its rows, status 'interrupted')",
              file=sys.stderr)
        return 130


def machine_limit(exc: OSError | RuntimeError) -> str:
    """One paragraph for an error of the machine's limits: the operating system's reason (not HDF5's long report),
    the file, and the fix (a file-size limit is named as such, a temporary folder as TMPDIR)."""
    import errno
    import resource
    import tempfile

    from orchestrator.results.results_file import write_error

    if "file write failed" in str(exc) or "errno =" in str(exc):  # HDF5's report: errno and reason inside it
        exc = write_error(exc, getattr(exc, "filename", None) or _hdf5_file(str(exc)))
    reason = exc.strerror or " ".join(str(exc).split())
    limit = resource.getrlimit(resource.RLIMIT_FSIZE)[0]
    where = f" ({exc.filename})" if exc.filename else ""
    if limit != resource.RLIM_INFINITY and (exc.errno == errno.EFBIG or "No usable temporary directory" in reason
                                            or limit < 1 << 20):
        return (f"{reason}{where}: this process may write files of at most {limit} bytes (the shell's file-size "
                "limit, `ulimit -f`); raise it (`ulimit -f unlimited`) and run again (nothing computed before the "
                "error is lost)")
    if "No usable temporary directory" in reason or (exc.filename and str(exc.filename).startswith(
            tempfile.gettempdir())):
        return (f"{reason}{where}: the temporary folder {tempfile.gettempdir()} cannot take the files a run writes "
                "there (FMUs, the database they carry); free space there or set TMPDIR to a folder with room")
    return f"{reason}{where}; free space or choose another output path (nothing computed before the error is lost)"


def _hdf5_file(text: str) -> str:
    import re

    found = re.search(r"filename = '([^']*)'", text)
    return found.group(1) if found else ""


def _hdf5_release_failure(exc: BaseException | None) -> bool:
    return isinstance(exc, RuntimeError) and "decrement id ref count" in str(exc)


def _quiet_hdf5_dealloc(unraisable: sys.UnraisableHookArgs) -> None:
    """h5py reports each object it could not release after a failed write (a full disk) as a traceback and an
    "Exception ignored" block of several lines; the command reports the failure itself, once."""
    if _hdf5_release_failure(unraisable.exc_value):
        return
    sys.__unraisablehook__(unraisable)


def _quiet_hdf5_traceback(kind: type, value: BaseException, tb: object) -> None:
    """The traceback half of h5py's report of an object it could not release (printed through sys.excepthook)."""
    if _hdf5_release_failure(value):
        return
    sys.__excepthook__(kind, value, tb)


def console() -> None:
    """The ``wec-cosim`` console script: :func:`main`, then the process's exit.

    After a write failed on a full disk HDF5 may still hold objects of a file it could not close; its exit
    handler (``H5_term_library``) then closes them and crashes in ``H5D_close`` (a segmentation fault after
    the clean message; found with gdb, not PythonFMU). When HDF5 still holds any file, dataset, group or
    attribute at the end, the process ends without the exit handlers (output flushed first). A file-size limit
    is reported as a failed write, not as the signal that would end the process silently."""
    import signal

    sys.unraisablehook, sys.excepthook = _quiet_hdf5_dealloc, _quiet_hdf5_traceback
    # a file-size limit (`ulimit -f`) kills the process at the first write past it (SIGXFSZ) before it can say
    # why; ignored, the write fails with EFBIG and the limit is named (machine_limit)
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    try:
        code = main()
    except SystemExit as exc:  # argparse: --help, or an option error already printed
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    except BaseException:  # noqa: BLE001 - a bug: its traceback, then the same safe exit
        import traceback

        traceback.print_exc()
        code = 1
    h5py = sys.modules.get("h5py")
    if h5py is not None:
        f = h5py.h5f
        try:
            held = f.get_obj_count(f.OBJ_ALL, f.OBJ_FILE | f.OBJ_DATASET | f.OBJ_GROUP | f.OBJ_ATTR)
        except Exception:  # noqa: BLE001 - HDF5 in a state that cannot even count: do not run its exit handler
            held = 1
        if held:
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(code)
    sys.exit(code)


def _one_line(exc: BaseException) -> str:
    """One paragraph: messages that quote multi-line text keep it on one line."""
    return " ".join(str(exc).split("\n"))


if __name__ == "__main__":
    console()
