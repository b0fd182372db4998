"""Results stage: what a run leaves on disk and how it is read back.

Modules: :mod:`.results_file` (the HDF5 results file, written as the run goes; :func:`read_results`),
:mod:`.checkpoints` (checkpoint files for ``wec-cosim resume``), :mod:`.energy` (the wave-to-wire energy
account from the energy series), :mod:`.analysis` (steady windows, harmonic fits, mean powers of a time
series), :mod:`.datasets` (results, RAO and steady-state files as labelled xarray datasets, back to HDF5, NetCDF,
pandas), :mod:`.figures` (what every figure shares: units, titles, legends), :mod:`.plotting` (``wec-cosim
plot``: figures of results files, and the dispatch of every kind of file), :mod:`.response_plots` (figures of RAO
and steady-state files).

May import: :mod:`orchestrator.scenario`, :mod:`orchestrator.errors`, :mod:`fmu_base` (state codec). It
runs nothing: no FMU, no solver.
"""

from .energy import energy_account, energy_terms, wave_balance
from .results_file import ResultsWriter, read_results

__all__ = ["ResultsWriter", "energy_account", "energy_terms", "read_results", "wave_balance"]
