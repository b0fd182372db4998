"""Sweeps: power matrices, PTO studies and seed ensembles, one full run per case on Dask.

``wec-cosim sweep SCENARIO --out F.h5`` plans the cases of the scenario's ``[sweep]`` table
(:mod:`sweeps.grid`), runs the missing ones on a local Dask cluster or a running one
(:mod:`sweeps.scheduler`, :mod:`sweeps.case`), records each in one HDF5 file
(:mod:`sweeps.store`) and assembles the matrices (:mod:`sweeps.matrices`), which ``wec-cosim plot``
draws (:mod:`sweeps.plotting`). See docs/sweeps.md.
"""

from .runner import SweepInterrupted, SweepOutcome, run_sweep

__all__ = ["SweepInterrupted", "SweepOutcome", "run_sweep"]
