"""Shared FMI-side helpers for the toolkit's PythonFMU slaves (bundled into both FMUs): the vector slave base
(:mod:`.slave`), the state codec (:mod:`.state_codec`), in-memory rollback of a model (:mod:`.rollback`); and the
compiled runtime's Python side: :mod:`fmu_base.native` loads the library built from ``native/`` (``_wecrt.so`` here,
beside the sources), :mod:`fmu_base.runtime_data` writes its versioned input container. Imports no other toolkit
package."""
