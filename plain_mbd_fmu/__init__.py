"""A minimal third-party-style multibody FMU: rigid bodies and PTO dampers, no added mass.

It stands for a commercial multibody tool that cannot take the hydrodynamic infinite-frequency
added mass into its mass matrix (added-mass mode c, ``docs/masters.md``). It shares nothing with
:mod:`mbd_fmu` but the FMI base class: own equations, own integrator, own script module name.
"""
