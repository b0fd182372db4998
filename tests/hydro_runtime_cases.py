"""Runtime input of small synthetic hydro models for the runtime's tests (no scene, no database): the arrays of
:mod:`hydro_fmu.runtime_input` written directly, so that each test switches on exactly the concept it checks; and
the reference formulas the tests share."""

from __future__ import annotations

import numpy as np

from fmu_base import runtime_data
from hydro_fmu.runtime import HydroRuntime


def arrays(dofs: list[tuple[int, int]] | None = None, *, dt: float = 0.1, ramp: float = 0.0, excitation: int = 0,
           radiation: int = 0, hydrostatics: int = 0, froude_krylov: int = 0, omega=(), amplitude=(),
           **extra: object) -> dict[str, object]:
    """The arrays of a model with the given DOFs ((body, dof) pairs; default one heave DOF), methods and waves
    (``amplitude``: complex amplitudes at the origin); ``extra``: more arrays by name (``_`` for ``.`` after the
    first word: ``radiation_kernel`` is ``radiation.kernel``)."""
    dofs = dofs or [(0, 2)]
    out: dict[str, object] = {
        "model.dofs": np.array(dofs, dtype=np.int64), "model.bodies": max(b for b, _ in dofs) + 1,
        "model.dt": dt, "ramp.duration": ramp, "excitation.method": excitation, "radiation.method": radiation,
        "hydrostatics.method": hydrostatics, "froude_krylov.nonlinear": froude_krylov,
        "waves.omega": np.asarray(omega, dtype=float),
        "waves.amplitude": np.stack([np.real(amplitude), np.imag(amplitude)], axis=-1).reshape(-1, 2),
    }
    for key, value in extra.items():
        out[key.replace("_", ".", 1)] = value
    return out


def data(**kwargs: object) -> bytes:
    return runtime_data.write("hydro", arrays(**kwargs))


def runtime(**kwargs: object) -> HydroRuntime:
    return HydroRuntime(data(**kwargs))


def direct_convolution(kernel: np.ndarray, dt: float, history: dict[int, np.ndarray], now: int) -> np.ndarray:
    """mu at grid point ``now``: sum_j w_j K(j dt) v(now - j), trapezoidal weights over the kernel's m samples,
    zero velocity before the start (grid velocities in ``history``): the convolution written out."""
    m, n, _ = kernel.shape
    mu = np.zeros(n)
    for j in range(m):
        if now - j < 0:
            break
        w = dt / 2 if j in (0, m - 1) else dt
        mu += w * kernel[j] @ history[now - j]
    return mu


def box_corners(length: float, width: float, height: float, centre=(0.0, 0.0, 0.0)) -> np.ndarray:
    """(12, 3, 3) triangles of a closed box with outward normals (right-hand rule), centred at ``centre``."""
    c = np.asarray(centre, dtype=float)
    half = np.array([length, width, height]) / 2
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * half + c
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = []
    for a, b, cc, d in quads:
        tris += [(a, b, cc), (a, cc, d)]
    corners = v[np.array(tris)]
    centroid = corners.mean(axis=1) - c
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    assert np.all(np.einsum("fi,fi->f", normal, centroid) > 0), "box faces must point out"
    return corners
