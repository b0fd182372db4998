"""Sweeps: power matrices, PTO studies and seed ensembles, one full run per case on Dask.

``wec-cosim sweep SCENARIO --out F.h5`` plans the cases of the scenario's ``[sweep]`` table
(:mod:`wec_cosim.sweeps.grid`), runs the missing ones on a local Dask cluster or a running one
(:mod:`wec_cosim.sweeps.scheduler`, :mod:`wec_cosim.sweeps.case`), records each in one HDF5 file
(:mod:`wec_cosim.sweeps.store`) and assembles the matrices (:mod:`wec_cosim.sweeps.matrices`), which ``wec-cosim plot``
draws (:mod:`wec_cosim.sweeps.plotting`). See docs/sweeps.md.
"""

from .runner import SweepInterrupted, SweepOutcome, run_sweep

__all__ = ["SweepInterrupted", "SweepOutcome", "run_sweep"]
