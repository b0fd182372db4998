"""FMI plumbing: the scene's FMUs built, loaded and exported.

Modules: :mod:`.fmu_builder` (build the hydro and multibody FMUs with PythonFMU, cached by content),
:mod:`.pythonfmu_patch` (a fix of PythonFMU 0.7.0's Linux binary), :mod:`.components` (an FMU run through fmpy,
or the same slave in process, behind one interface), :mod:`.ssp` (SSP export for other FMI tools),
:mod:`.foreign_hosts` (running an SSP in fmpy, libcosim and C hosts), :mod:`.host_environment` (what a C host
needs to load our FMUs).

May import: :mod:`orchestrator.scene`, :mod:`orchestrator.errors`, :mod:`hydro_fmu` (BEMIO writer),
:mod:`fmu_base`. Knows nothing of masters.
"""
