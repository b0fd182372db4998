"""Multibody dynamics of wave-energy converters, importable without FMI.

* :mod:`mbd_fmu.bodies` - rigid bodies and point masses; :mod:`mbd_fmu.force_elements`,
  :mod:`mbd_fmu.moorings` - PTOs, springs, dampers, ropes, friction, moorings;
* :mod:`mbd_fmu.linear_system` - the small-motion model and its exact integrator;
* :mod:`mbd_fmu.joints`, :mod:`mbd_fmu.constraints`, :mod:`mbd_fmu.coordinates`,
  :mod:`mbd_fmu.model` - the constrained nonlinear model; :mod:`mbd_fmu.formulations`,
  :mod:`mbd_fmu.integrators` - index-3, index-1 and null-space formulations and their integrators;
  :mod:`mbd_fmu.assembly` - mobility and initial assembly; :mod:`mbd_fmu.linearize` - linearisation;
  :mod:`mbd_fmu.simulator` - macro steps with held inputs and outputs;
* :mod:`mbd_fmu.slave` - the thin FMU wrapper.
"""

from .bodies import DOF_NAMES, RigidBody
from .force_elements import LinearPTO
from .linear_system import LinearMultibodySystem

__all__ = ["DOF_NAMES", "LinearMultibodySystem", "LinearPTO", "RigidBody"]
