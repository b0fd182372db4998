"""Orchestration of a wec-cosim run: from a scenario file to results, one subpackage per stage.

The pipeline of ``wec-cosim run``, bottom to top (each subpackage imports only those above it in this list,
and :mod:`hydro_fmu`, :mod:`mbd_fmu`, :mod:`fmu_base`; ``tests/test_layering.py`` holds the code to it):

* :mod:`orchestrator.errors`, :mod:`orchestrator.progress` - the errors a user sees, progress lines;
* :mod:`orchestrator.control` - external control over zenoh: wire protocol, master-side bridge, client;
* :mod:`orchestrator.scenario` - input: the TOML scenario's schema, sections, checks, ``--set`` keys;
* :mod:`orchestrator.scene` - a scenario resolved against its hydrodynamic database: FMU specifications,
  connections, physics objects, static equilibrium;
* :mod:`orchestrator.results` - results files (written as the run goes, read back), checkpoints, the energy
  account, time-series analysis and figures;
* :mod:`orchestrator.reference` - exact references: frequency-domain response, pseudo-spectral steady state,
  free-decay modes, RAO and steady-state files;
* :mod:`orchestrator.fmi` - FMI plumbing: building the FMUs, running them (fmpy or in process), SSP export and
  foreign hosts;
* :mod:`orchestrator.cosim` - co-simulation: step control, masters, added-mass coupling, the monolithic mode,
  the recorder, the control loop and the run itself (:func:`orchestrator.cosim.simulation.run_scenario`).

The command line, sweeps and the bench report sit above all of these, in :mod:`wec_cosim`.
"""
