"""Hydrodynamics of wave-energy converters: database, waves, excitation, radiation, hydrostatics.

Plain Python physics (importable and testable without FMI) plus the thin FMU wrapper in
:mod:`hydro_fmu.slave`. Layering, from data to forces:

* :mod:`hydro_fmu.hdb` - the hydrodynamic database type; :mod:`hydro_fmu.bemio` - BEMIO HDF5;
  :mod:`hydro_fmu.bem` - Capytaine front end with an on-disk cache;
* :mod:`hydro_fmu.waves` - incident wave components and the ramp;
* :mod:`hydro_fmu.excitation`, :mod:`hydro_fmu.radiation`, :mod:`hydro_fmu.hydrostatics` - forces;
* :mod:`hydro_fmu.model` - the forces of one scene, as the FMU computes them: the preparation, then the compiled
  runtime (:mod:`hydro_fmu.runtime_input` its input, :mod:`hydro_fmu.runtime` its binding; ``native/``);
* :mod:`hydro_fmu.native_fmu` - the native FMI 2.0 / 3.0 hydro FMU of a prepared model (the runtime behind
  ``native/fmi``, no Python inside).
"""

from .hdb import DOF_NAMES, HydroDatabase, HydroDatabaseError

__all__ = ["DOF_NAMES", "HydroDatabase", "HydroDatabaseError"]
