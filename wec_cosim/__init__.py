"""wec-cosim: open multibody wave-energy co-simulation.

The top of the project, above :mod:`orchestrator` (which it may import, with every package below it):
:mod:`wec_cosim.cli` (the ``wec-cosim`` command line), :mod:`wec_cosim.sweeps` (sweeps and power matrices on
Dask) and :mod:`wec_cosim.benchreport` (``wec-cosim bench``: speed against error).

Packages of the project, bottom to top: :mod:`fmu_base` (shared FMU slave base) -> :mod:`hydro_fmu`,
:mod:`mbd_fmu`, :mod:`plain_mbd_fmu` (the physics and their FMUs) -> :mod:`orchestrator` (scenario to
results, one subpackage per stage) -> :mod:`wec_cosim`.
"""
