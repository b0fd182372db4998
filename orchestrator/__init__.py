"""Orchestration: scenarios, FMU building, master algorithms, frequency-domain reference, results, CLI.

Pipeline of ``wec-cosim run``: :mod:`~orchestrator.scenario` (TOML, validated) ->
:mod:`~orchestrator.scene` (database, FMU specs, connections) -> :mod:`~orchestrator.fmu_builder`
-> :mod:`~orchestrator.components` + :mod:`~orchestrator.masters` -> :mod:`~orchestrator.results`,
checked against :mod:`~orchestrator.frequency_domain`.
"""
