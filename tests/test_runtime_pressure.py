"""The runtime's pressure forces over the wetted mesh (native/src/hydro/pressure.c, mesh_clip.c, incident_wave.c,
spreading.c): a box against exact hydrostatics (heave force of a wall-sided body, the restoring stiffness of the
waterplane), and the Froude-Krylov force in a spread sea at finite depth against the Python reference
(hydro_fmu.nonlinear_hydrostatics.BodyPressureModel) at large motions."""

from __future__ import annotations

import math

import numpy as np

from hydro_fmu.meshes import from_corners
from hydro_fmu.nonlinear_hydrostatics import BodyPressureModel
from hydro_fmu.waves import Ramp, WaveComponents, wavenumber

from .hydro_runtime_cases import box_corners, runtime

RHO, G = 1025.0, 9.81
LENGTH, WIDTH, HEIGHT = 4.0, 2.0, 3.0
CG = np.array([0.3, -0.2, -0.5])  # the box's centre; draft 2 m, freeboard 1 m
DOFS = [(0, 0), (0, 2), (0, 3), (0, 4)]


def box_arrays(**kw: object) -> dict[str, object]:
    return {"environment_rho": RHO, "environment_g": G, "environment_depth": kw.pop("depth", math.inf),
            "bodies_cg": CG[None], "mesh_corners": box_corners(LENGTH, WIDTH, HEIGHT), "mesh_faces": np.array([12]),
            **kw}


def test_box_heave_force_and_restoring_stiffness_are_exact() -> None:
    """Heave by x3 (bottom wet, deck dry): F3 = -rho g L B x3 exactly, no other force or moment; at equilibrium the
    tangent is -C with C33 = rho g L B, C44 = rho g (L B^3 / 12 + V (z_b - z_g)), C55 = rho g (B L^3 / 12 + V (z_b -
    z_g)) (central differences of step 1e-6: their round-off bounds the agreement)."""
    model = runtime(dofs=DOFS, hydrostatics=2, **box_arrays())
    for heave in (-0.7, 0.4, 0.95):
        x = np.array([0.0, heave, 0.0, 0.0])
        model.evaluate(0.0, x, np.zeros(4))
        expected = -RHO * G * LENGTH * WIDTH * heave
        np.testing.assert_allclose(model.block[3], [0.0, expected, 0.0, 0.0], rtol=0, atol=1e-12 * abs(expected))
    _, _, dfdx, _ = model.linearise(0.0, np.zeros(4), np.zeros(4))
    volume, zb = LENGTH * WIDTH * 2.0, -1.0
    c33 = RHO * G * LENGTH * WIDTH
    c44 = RHO * G * (LENGTH * WIDTH**3 / 12 + volume * (zb - CG[2]))
    c55 = RHO * G * (WIDTH * LENGTH**3 / 12 + volume * (zb - CG[2]))
    np.testing.assert_allclose(np.diag(dfdx), [0.0, -c33, -c44, -c55], rtol=1e-6, atol=1e-6 * c33)
    off = dfdx - np.diag(np.diag(dfdx))
    assert np.abs(off).max() <= 1e-6 * c33


def test_froude_krylov_in_a_spread_sea_at_finite_depth_matches_the_python_model() -> None:
    """Two components at headings 0 and 0.6 rad, depth 12 m, ramp: the box heaved, rolled and pitched by large
    amounts; hydrostatic (cut at the wave surface) and Froude-Krylov forces equal BodyPressureModel's."""
    omega = np.array([0.9, 1.4])
    amp = np.array([0.6 * np.exp(0.5j), 0.25 * np.exp(-2.0j)])
    heading = np.array([0.0, 0.6])
    depth = 12.0
    k = wavenumber(omega, depth, G)
    coefficients = np.zeros((2, 4, 2))  # the diffraction part: none here
    model = runtime(dofs=DOFS, hydrostatics=2, froude_krylov=1, excitation=1, ramp=4.0, omega=omega,
                    amplitude=amp, waves_heading=heading, waves_wavenumber=k,
                    excitation_coefficients=coefficients, **box_arrays(depth=depth))
    waves = WaveComponents(omega, np.abs(amp), np.angle(amp), heading)
    reference = BodyPressureModel(from_corners(box_corners(LENGTH, WIDTH, HEIGHT)), CG, RHO, G, depth)
    for t, x in ((0.0, [0.0, 0.0, 0.0, 0.0]), (2.1, [0.4, -0.5, 0.2, -0.3]), (7.7, [-1.0, 0.6, -0.25, 0.15])):
        x = np.array(x)
        model.evaluate(t, x, np.zeros(4))
        pose = np.zeros(6)
        pose[[0, 2, 3, 4]] = x
        hs, fk = reference.forces(pose, t, waves, Ramp(4.0), hydrostatics=True, froude_krylov=True)
        scale = RHO * G * LENGTH * WIDTH * HEIGHT
        np.testing.assert_allclose(model.block[3], hs[[0, 2, 3, 4]], rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(model.block[1], fk[[0, 2, 3, 4]], rtol=0, atol=1e-12 * scale)
