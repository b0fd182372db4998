"""The Python API of wec-cosim: load a scenario, change it, run it (time domain, frequency domain, steady state,
sweep), read the results as labelled xarray datasets. ``import wec_cosim as wc`` gives every function here as
``wc.<name>`` (imported when first used: ``import wec_cosim`` itself stays cheap). The page ``docs/api.md``
walks through it.

Each function takes a :class:`~orchestrator.scenario.Scenario` (from :func:`load_scenario`) or the path of a
scenario file. Values changed in Python (``s.waves.height = 1.5``) are checked when a run, solve or sweep starts,
with the checks of the file's keys; a refused value raises :class:`ScenarioError` naming the attribute and the
value set. Errors a user can fix are :class:`WecCosimError` (of which :class:`ScenarioError` is one).
"""

from __future__ import annotations

import copy
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from orchestrator.errors import ScenarioError, WecCosimError

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
    import xarray as xr

    from orchestrator.cosim.simulation import RunResult
    from orchestrator.scenario import Scenario

__all__ = ["ScenarioError", "WecCosimError", "apply_overrides", "check", "load_scenario", "open_dataset",
           "open_netcdf", "plot", "rao", "run", "steady", "summary", "sweep", "to_netcdf", "to_pandas",
           "write_results"]


def load_scenario(path: str | Path) -> Scenario:
    """Read and check a scenario file (TOML; every key in ``docs/scenario.md``).

    The sections are attributes (``s.waves.height``, ``s.simulation.step``, ``s.bodies[0].mass``,
    ``s.ptos[0].damping``); change them in Python and the next :func:`run` (or :func:`check`) checks them.
    Raises :class:`ScenarioError` naming the file and key of a bad value.
    """
    from orchestrator.scenario import load_scenario as load

    return load(path)


def _scenario(scenario: Scenario | str | Path) -> Scenario:
    return load_scenario(scenario) if isinstance(scenario, (str, Path)) else scenario


def apply_overrides(scenario: Scenario | str | Path, overrides: Mapping[str, Any] | Iterable[str]) -> Scenario:
    """A checked copy of ``scenario`` with keys set by name, as ``wec-cosim run --set`` does.

    ``overrides``: ``{"waves.height": 2.0, "ptos.pto.damping": 8e5, "bodies.float.dofs": ["heave"]}`` (key paths as
    in the scenario file; items of lists by name), or ``"KEY=VALUE"`` strings with the value in TOML. The changes
    are recorded in the results files of the runs of the copy.
    """
    from orchestrator.scenario import apply_overrides as apply

    return apply(_scenario(scenario), overrides)


def check(scenario: Scenario) -> Scenario:
    """Check the values changed in Python since loading (each as the file's key would be checked, then the checks
    across keys) and record them for the results files; returns the scenario. :func:`run`, :func:`rao`,
    :func:`steady` and :func:`sweep` call it first.

    Raises :class:`ScenarioError`, e.g. ``waves.height = -3.0, set in Python: must not be negative (got -3.0)``.
    """
    from orchestrator.scenario.changes import check_python_changes

    return check_python_changes(scenario)


def _output(out: str | Path | None, default: Path, kind: str = "hdf5") -> Path:
    from orchestrator.scenario.input_checks import check_output

    if out is not None and not str(out):
        raise WecCosimError("out: an empty path is not usable; give a file name")
    return check_output(Path(out) if out is not None else default, "out" if out is not None else
                        f"the default output file {default}", kind=kind)


def run(scenario: Scenario | str | Path, out: str | Path | None = None, *, progress: bool = True,
        in_process: bool = False, log: Any = print) -> RunResult:
    """Run the scenario's time-domain co-simulation (``wec-cosim run``): build (or load from the cache) the FMUs,
    step the master, write the results file, compare with the exact frequency-domain answer in regular waves.

    Args:
        scenario: a scenario or the path of its file.
        out: results file (default ``simulation.output``, else ``results/<name>.h5``).
        progress: show progress (a bar on a terminal, a line every 5 % elsewhere, e.g. in a notebook or a log).
        in_process: call the FMU slaves directly instead of through fmpy (same results, less overhead).
        log: where set-up messages go (``None``: nowhere).

    Returns:
        The :class:`~orchestrator.cosim.simulation.RunResult`: ``path``, ``setup_time`` and ``wall_time`` (s,
        set-up and stepping), ``comparisons`` against the exact answer, ``mean_power`` (W per PTO) and
        ``energy``; ``result.dataset()`` opens the results file as an xarray dataset, ``print(result.summary())``
        prints what ``wec-cosim run`` prints.
    """
    from orchestrator.cosim.simulation import run_scenario

    s = check(_scenario(scenario))
    return run_scenario(s, out, in_process=in_process, log=log, progress=progress)


def rao(scenario: Scenario | str | Path, out: str | Path | None = None, *, form: str | None = None,
        progress: bool = True, log: Any = print) -> xr.Dataset:
    """The linear frequency-domain response (``wec-cosim rao``): body, joint and reaction RAOs, PTO power and
    capture width over ``[rao] omega`` (default the database's frequencies), written to ``out`` (default
    ``results/<name>_rao.h5``) and returned as an xarray dataset (:func:`open_dataset`).

    ``form``: ``"dae"`` or ``"ode"`` (default ``rao.form``). Values are per metre of wave amplitude, complex
    amplitudes in the ``exp(+i omega t)`` convention.
    """
    from orchestrator.reference.response_files import write_rao_file
    from orchestrator.scene import load_scene

    s = check(_scenario(scenario))
    if form is not None:
        s = apply_overrides(s, {"rao.form": form})
    path = _output(out, Path("results") / f"{s.name}_rao.h5")
    write_rao_file(load_scene(s, log=log, progress=progress), path)
    return open_dataset(path)


def steady(scenario: Scenario | str | Path, out: str | Path | None = None, *, harmonics: int | None = None,
           form: str | None = None, progress: bool = True, log: Any = print) -> xr.Dataset:
    """The periodic steady state in regular waves by the pseudo-spectral method (``wec-cosim steady``), with
    quadratic drag, nonlinear PTO laws and moorings; written to ``out`` (default ``results/<name>_steady.h5``) and
    returned as an xarray dataset (dimension ``period``; check its ``converged``)."""
    from orchestrator.reference.response_files import write_steady_file
    from orchestrator.scene import load_scene

    s = check(_scenario(scenario))
    path = _output(out, Path("results") / f"{s.name}_steady.h5")
    write_steady_file(load_scene(s, log=log, progress=progress), path, harmonics, form, log=log)
    return open_dataset(path)


def sweep(scenario: Scenario | str | Path, out: str | Path, *, grid: Mapping[str, Iterable[Any]] | None = None,
          method: str | None = None, seeds: int | None = None, workers: int | None = None,
          in_process: bool | None = None, progress: bool = True, log: Any = print) -> xr.Dataset:
    """One run per case of a grid of scenario keys (``wec-cosim sweep``): power matrices, PTO studies, seed
    ensembles, on Dask (a local cluster) or in this process; returns the matrices as an xarray dataset with one
    dimension per swept key (:func:`open_dataset` of the sweep file).

    Args:
        scenario: a scenario or the path of its file; its ``[sweep]`` table is the default plan.
        out: the sweep file (an existing one of the same scene is continued: finished cases are kept).
        grid: swept keys and their values, e.g. ``{"waves.hs": [1, 2, 3], "waves.tp": [6, 8, 10]}`` (added to or
            replacing ``[sweep.grid]``).
        method: ``"frequency_domain"`` (exact linear, milliseconds per case) or ``"time_domain"``.
        seeds: irregular-sea realisations per cell (time domain).
        workers: local Dask worker processes (default ``sweep.workers``, or one per core).
        in_process: run the cases one after another here, without Dask (default for the frequency domain).
    """
    from .sweeps import run_sweep
    from .sweeps.grid import set_grid

    s = copy.deepcopy(check(_scenario(scenario)))
    if method is not None:
        s = apply_overrides(s, {"sweep.method": method})
    if seeds is not None:
        s = apply_overrides(s, {"sweep.seeds": seeds})
    for key, values in (grid or {}).items():
        set_grid(s, key, list(values))
    path = _output(out, Path(str(out)))
    run_sweep(s, path, workers=workers, in_process=in_process, progress=progress, log=log)
    return open_dataset(path)


def open_dataset(path: str | Path) -> xr.Dataset:
    """Any file wec-cosim writes as an xarray dataset: a results file (dimensions ``time``, ``body``, ``dof``,
    ``pto``, ``joint``, ``coordinate``...), a RAO file (``omega``), a steady-state file (``period``), a sweep file
    (one dimension per swept key) or a NetCDF export (:func:`to_netcdf`). Units and long names are attributes of
    every variable; the file's attributes (scenario text, settings, status) are the dataset's."""
    from orchestrator.results.datasets import READERS, file_kind

    kind = file_kind(path)
    if kind == "sweep":
        from .sweeps.datasets import sweep_dataset

        return sweep_dataset(path)
    if kind == "netcdf":
        return open_netcdf(path)
    return READERS[kind](path)


def write_results(ds: xr.Dataset, path: str | Path) -> Path:
    """Write a results dataset (of :func:`open_dataset` on a results file) as a results file that ``wec-cosim
    plot`` and :func:`open_dataset` read: the same datasets and attributes as the file it came from."""
    from orchestrator.results.datasets import write_results as write

    return write(ds, path)


def to_netcdf(ds: xr.Dataset, path: str | Path) -> Path:
    """Write any dataset of :func:`open_dataset` as NetCDF-4 for other tools (``xarray.open_dataset(path)`` reads
    it with the same values, units and names; complex variables as ``<name>_real`` and ``<name>_imag``)."""
    from orchestrator.results.datasets import to_netcdf as write

    return write(ds, path)


def open_netcdf(path: str | Path) -> xr.Dataset:
    """A NetCDF file of :func:`to_netcdf` read back, complex variables joined again."""
    from orchestrator.results.datasets import open_netcdf as read

    return read(path)


def to_pandas(data: xr.Dataset | str | Path, index: str | None = None) -> pd.DataFrame:
    """A pandas table of a dataset (or of the file at a path): indexed by ``time`` (results), ``omega`` (RAOs) or
    ``period`` (steady states), one column per labelled series (``displacement[float,heave]``, ``pto_power[pto]``,
    ``wave_elevation``); ``DataFrame.attrs["units"]`` maps each column to its unit. MHKiT's wave and power
    functions take these columns as they are."""
    from orchestrator.results.datasets import to_pandas as table

    return table(open_dataset(data) if isinstance(data, (str, Path)) else data, index)


def plot(path: str | Path, out: str | Path | None = None) -> list[Path]:
    """The figures of a results, RAO, steady-state or sweep file as PNG files in ``out`` (default next to the
    file), as ``wec-cosim plot`` draws them; returns their paths."""
    from orchestrator.results.plotting import plot_file

    from .sweeps.plotting import DRAWERS

    return plot_file(path, out, DRAWERS)


def summary(result: RunResult) -> str:
    """The summary ``wec-cosim run`` prints for a run's result."""
    from orchestrator.cosim.simulation import format_summary

    return format_summary(result)
