"""Shared FMI-side helpers for the toolkit's PythonFMU slaves (bundled into both FMUs)."""
