"""Co-simulation: the master algorithm and the run.

Modules, bottom to top: :mod:`.step_control` (fixed and energy-based adaptive macro steps),
:mod:`.masters` (the master base and the explicit Jacobi and Gauss-Seidel masters), :mod:`.iterative_master`
(iterations with rollback: Aitken, interface quasi-Newton), :mod:`.master_factory` (a master by its scenario
name), :mod:`.coupling` (how the FMUs are wired for each added-mass mode), :mod:`.monolithic` (the same physics
in one process, without FMI), :mod:`.recorder` (the master's outputs as rows of the results file),
:mod:`.control_loop` (the external controller in the step loop), :mod:`.interrupts` (Ctrl-C at a step),
:mod:`.step_checks` (macro steps that alias a fast mode onto the waves), :mod:`.error_estimate` (every run's error
estimate: Richardson against a coarse shadow plus the radiation model's share), :mod:`.step_choice` (the macro
step chosen for ``simulation.error_tolerance``), :mod:`.simulation` (``wec-cosim run`` and ``resume``: scenario ->
scene -> FMUs -> master -> results file -> summary against the exact answer and the error estimate),
:mod:`.study` (accuracy studies over steps and masters).

May import every other stage of :mod:`orchestrator`, and :mod:`hydro_fmu`, :mod:`mbd_fmu`, :mod:`fmu_base`.
"""
