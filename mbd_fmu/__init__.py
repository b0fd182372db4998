"""Multibody dynamics of wave-energy converters, importable without FMI.

* :mod:`mbd_fmu.bodies` - rigid bodies; :mod:`mbd_fmu.force_elements` - PTOs;
* :mod:`mbd_fmu.linear_system` - the small-motion multibody model and its exact integrator;
* :mod:`mbd_fmu.slave` - the thin FMU wrapper.
"""

from .bodies import DOF_NAMES, RigidBody
from .force_elements import LinearPTO
from .linear_system import LinearMultibodySystem

__all__ = ["DOF_NAMES", "LinearMultibodySystem", "LinearPTO", "RigidBody"]
