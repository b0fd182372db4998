"""Reference solvers: the exact answers time-domain runs are measured against.

Modules: :mod:`.frequency_domain` (the exact linear constrained response: RAOs, power, reaction loads, free
decay roots), :mod:`.pseudo_spectral` (periodic steady state with nonlinear PTO laws, drag and moorings by
Fourier collocation), :mod:`.decay` (natural modes of a scene and damped modes fitted to decay records),
:mod:`.response_files` (``wec-cosim rao`` and ``wec-cosim steady`` files).

May import: :mod:`orchestrator.scene`, :mod:`orchestrator.scenario`, :mod:`orchestrator.errors`,
:mod:`hydro_fmu`, :mod:`mbd_fmu`. Independent of FMI and of the masters.
"""
