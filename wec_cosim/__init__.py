"""wec-cosim: open multibody wave-energy co-simulation.

The Python API (:mod:`wec_cosim.api`, documented in ``docs/api.md``)::

    import wec_cosim as wc

    s = wc.load_scenario("scenarios/cylinder_regular.toml")
    s.waves.height = 1.5                      # checked when the run starts
    result = wc.run(s, "results/cylinder.h5")
    ds = result.dataset()                     # xarray: time, body, dof, pto, ...

The functions are imported when first used (a module-level ``__getattr__``), so ``import wec_cosim`` and the
``wec-cosim`` command line do not import xarray, pandas, matplotlib, Dask or Capytaine until something needs them.

The top of the project, above :mod:`orchestrator` (which it may import, with every package below it):
:mod:`wec_cosim.api` (the Python API), :mod:`wec_cosim.cli` (the ``wec-cosim`` command line),
:mod:`wec_cosim.sweeps` (sweeps and power matrices on Dask) and :mod:`wec_cosim.benchreport` (``wec-cosim bench``:
speed against error).

Packages of the project, bottom to top: :mod:`fmu_base` (shared FMU slave base) -> :mod:`hydro_fmu`,
:mod:`mbd_fmu`, :mod:`plain_mbd_fmu` (the physics and their FMUs) -> :mod:`orchestrator` (scenario to
results, one subpackage per stage) -> :mod:`wec_cosim`.
"""

from __future__ import annotations

API = ("ScenarioError", "WecCosimError", "apply_overrides", "check", "load_scenario", "open_dataset", "open_netcdf",
       "plot", "rao", "run", "steady", "summary", "sweep", "to_netcdf", "to_pandas", "write_results")

__all__ = ["__version__", *API]


def version() -> str:
    """The installed version of wec-cosim (``unknown`` when run from sources that were not installed)."""
    from importlib import metadata

    try:
        return metadata.version("wec-cosim")
    except metadata.PackageNotFoundError:
        return "unknown"


def __getattr__(name: str) -> object:
    if name == "__version__":
        return version()
    if name in API:
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module 'wec_cosim' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
