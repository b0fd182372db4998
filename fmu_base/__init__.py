"""Shared FMI-side helpers for the toolkit's PythonFMU slaves (bundled into both FMUs), and the compiled runtime's
Python side: :mod:`fmu_base.native` loads the library built from ``native/`` (``_wecrt.so`` here, beside the
sources), :mod:`fmu_base.runtime_data` writes its versioned input container. Imports no other toolkit package."""
