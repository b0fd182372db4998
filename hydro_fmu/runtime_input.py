"""The hydrodynamics runtime's input: the arrays the offline preparation hands to the compiled runtime.

:func:`runtime_arrays` reads them off a prepared :class:`hydro_fmu.model.HydroModel` (whose construction did the
preparation: database selection, wave components, excitation coefficients interpolated in frequency and heading,
impulse responses, the state-space fit, meshes, checks); :func:`runtime_input` writes them into the runtime's
container (:mod:`fmu_base.runtime_data`, kind ``hydro``). Names, shapes and meanings (docs/runtime.md):

============================  ==========  =======================================================================
name                          shape       content
============================  ==========  =======================================================================
model.dofs                    (n, 2)      body index and DOF (0 surge .. 5 yaw) of each selected DOF, body by body
model.bodies                  ()          number of hydrodynamic bodies
model.dt                      ()          radiation grid step (s); the unit of the step-time check
model.added_mass_inf          (n, n)      infinite-frequency added mass (published, not used at step time)
ramp.duration                 ()          half-cosine ramp (s; <= 0 none)
excitation.method             ()          0 none, 1 superposition, 2 impulse-response convolution
radiation.method              ()          0 none, 1 convolution, 2 state space
hydrostatics.method           ()          0 none, 1 linear, 2 nonlinear (wetted mesh)
froude_krylov.nonlinear       ()          1: the Froude-Krylov force over the wetted mesh (superposition: diffraction)
waves.omega, waves.amplitude  (K), (K,2)  components: rad/s, complex amplitude at the origin (re, im), m
waves.heading, .wavenumber    (K), (K)    heading (rad) and wavenumber (rad/m) of each component (nonlinear FK)
excitation.coefficients       (K, n, 2)   complex force per component (0 above the database's range)
excitation.tau, .kernel       (L), (L,n)  lags (s) and trapezoid-weighted excitation impulse response
record.dt, record.eta         (), (N)     imported elevation record at the origin (unramped)
radiation.kernel              (m, n, n)   K(j dt), j = 0 .. m-1 (the runtime applies the trapezoidal weights)
radiation.block_points        ()          points that share one pass over the convolution weights
radiation.a, .b, .c           (r,r) ...   state-space realisation of the memory
hydrostatics.stiffness        (n, n)      C (the force is -C x)
viscous.linear, .quadratic    (n), (n)    b and q of F = -b v - q |v| v
environment.rho, .g, .depth   ()          kg/m^3, m/s^2, m (inf: deep water)
bodies.cg                     (B, 3)      centre of gravity of each body at equilibrium (m)
mesh.corners, mesh.faces      (F,3,3),(B) hull triangles relative to the cg, faces per body (body by body)
============================  ==========  =======================================================================
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from fmu_base import runtime_data

from .excitation import ExcitationConvolution, ExcitationForce
from .radiation import BLOCK_POINTS
from .waves import wavenumber

if TYPE_CHECKING:
    from .model import HydroModel

KIND = "hydro"
EXCITATION_CODES = {type(None): 0, ExcitationForce: 1, ExcitationConvolution: 2}


def _complex(values: np.ndarray) -> np.ndarray:
    values = np.asarray(values, dtype=complex)
    return np.stack([values.real, values.imag], axis=-1)


def runtime_arrays(model: HydroModel) -> dict[str, np.ndarray]:
    """The runtime's input arrays of a prepared model (module docstring)."""
    n, sw, o = model.n, model.switches, model.options
    waves = model.waves
    omega = np.asarray(waves.omega, dtype=float)
    arrays: dict[str, object] = {
        "model.dofs": np.array([(b, d) for b, ds in enumerate(model.dofs) for d in ds], dtype=np.int64).reshape(-1, 2),
        "model.bodies": len(model.bodies),
        "model.dt": float(model.dt),
        "model.added_mass_inf": np.asarray(model.added_mass_inf, dtype=float),
        "ramp.duration": float(model.ramp.duration),
        "excitation.method": EXCITATION_CODES[type(model.excitation)],
        "radiation.method": 0 if model.radiation is None else 2 if o.radiation_method == "state_space" else 1,
        "hydrostatics.method": 0 if not sw.hydrostatics else 2 if o.nonlinear_hydrostatics else 1,
        "froude_krylov.nonlinear": int(bool(o.nonlinear_froude_krylov and sw.excitation)),
        "waves.omega": omega,
        "waves.amplitude": _complex(waves.complex_amplitude),
    }
    if arrays["froude_krylov.nonlinear"]:
        arrays["waves.heading"] = np.asarray(waves.headings, dtype=float)
        arrays["waves.wavenumber"] = wavenumber(omega, model.hdb.water_depth, model.hdb.g) if len(omega) else omega
    excitation = model.excitation
    if isinstance(excitation, ExcitationForce):
        table = np.zeros((len(omega), n), complex)
        if len(excitation.omega):
            keep = omega <= model.hdb.omega[-1]  # as ExcitationForce: components above the database are left out
            table[keep] = excitation.coefficients
        arrays["excitation.coefficients"] = _complex(table)
    elif isinstance(excitation, ExcitationConvolution):
        arrays["excitation.tau"] = excitation.tau
        arrays["excitation.kernel"] = excitation.weighted
    if model.record is not None:
        arrays["record.dt"] = float(model.record.dt)
        arrays["record.eta"] = np.asarray(model.record.eta, dtype=float)
    if arrays["radiation.method"] == 1:
        arrays["radiation.kernel"] = model.kernel
        arrays["radiation.block_points"] = BLOCK_POINTS
    elif arrays["radiation.method"] == 2:
        fit = model.state_space
        arrays["radiation.a"], arrays["radiation.b"], arrays["radiation.c"] = fit.a, fit.b, fit.c
    if arrays["hydrostatics.method"] == 1:
        arrays["hydrostatics.stiffness"] = model.hydrostatics.stiffness
    if model.viscous is not None:
        arrays["viscous.linear"] = model.viscous.linear
        arrays["viscous.quadratic"] = model.viscous.quadratic
    if model.pressure_models:
        models = [model.pressure_models[b] for b in range(len(model.bodies))]
        arrays["environment.rho"], arrays["environment.g"] = models[0].rho, models[0].g
        arrays["environment.depth"] = models[0].water_depth
        arrays["bodies.cg"] = np.array([m.cg for m in models], dtype=float).reshape(-1, 3)
        arrays["mesh.corners"] = np.concatenate([m.mesh.corners for m in models]).reshape(-1, 3, 3)
        arrays["mesh.faces"] = np.array([m.mesh.n_faces for m in models], dtype=np.int64)
    return arrays


def runtime_input(model: HydroModel) -> bytes:
    """The runtime's input container of a prepared model."""
    return runtime_data.write(KIND, runtime_arrays(model))
