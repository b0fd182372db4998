"""Shared FMI-side helpers for the toolkit's PythonFMU slaves (bundled into both FMUs): the vector slave base
(:mod:`.slave`), the state codec (:mod:`.state_codec`), in-memory rollback of a model (:mod:`.rollback`)."""
