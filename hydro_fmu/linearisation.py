"""The hydrodynamic force as an affine model over the next communication step (implicit coupling).

A plain FMI host (fixed step, Jacobi order, zero-order hold, no iteration) hands the multibody
FMU a force computed from the motion of an earlier communication point and holds it over the
step. The hydrostatic stiffness then acts with a delay of about 1.5 steps, which works as
negative damping (k * delay): the floating cylinder's heave comes out +93 % at 0.1 s and the
error falls only first order; the light hinge barge is unstable. Instead, the hydro FMU also
publishes, at every communication point t_n,

    F(t, x, v) ~= F0 + F0_rate (t - t_n) + dF_dx x + dF_dv v,       t in [t_n, t_n + h],

on the hydrodynamic degrees of freedom, where

* ``dF_dx`` is the derivative of the force with respect to the displacement x: -C for linear
  hydrostatics (exact), the tangent of the nonlinear hydrostatic and Froude-Krylov forces
  (central differences) otherwise;
* ``dF_dv`` is the derivative with respect to the *current* velocity: minus the instantaneous part
  of the radiation memory (the current velocity's weight in the convolution, K(0) dt / 2 for a step
  of one grid step; C G1 of the state space; both exact derivatives of the discrete memory) and
  the tangent of the viscous force, -(b + 2 q |v|);
* ``F0 = F(t_n, x_n, v_n) - dF_dx x_n - dF_dv v_n``: what does not depend on the motion, i.e.
  the excitation plus the memory of the velocities committed before (for linear parts exactly
  independent of the inputs x_n, v_n: which earlier point a host sampled them at does not
  matter), plus the intercept of the tangents of nonlinear parts;
* ``F0_rate``: the rate of F0 over the coming step: the exact time derivative of the excitation
  (the hydro FMU knows the wave ahead of time) plus the backward difference of the memory part
  between the last two communication points.

The multibody FMU integrates the affine force implicitly inside its own step (the linear
multibody model exactly, by the matrix exponential of the system with dF_dx, dF_dv added; the
nonlinear formulations through a force element with that tangent in their Newton matrix).

Order. With the multibody side exact for the affine force, the only errors are in the force:
the excitation's linear Taylor model over the step (E'' s^2 / 2), the memory's linear
extrapolation (O(h^2) for a smooth velocity history), and the trapezoidal convolution itself
(O(dt^2)); the motion-dependent parts are exact for linear hydrostatics and radiation. A force
error of O(h^2) everywhere gives a global error O(h^2) in x and v for a stable system: the
coupled scheme is second order (``tests/test_linearised_coupling.py`` measures the order). A held
force without the rate would lag by h/2 and be first order; without the tangents the delayed
stiffness makes it first order and, for light bodies, unstable.

Stability. The stiff parts (hydrostatic stiffness, instantaneous radiation damping, drag) are
integrated implicitly, so they impose no step limit (the multibody step is the exact solution of
a stable linear system for the linear model, A-stable generalised-alpha or the user's
formulation otherwise). What stays explicit is the memory of past velocities, a delayed feedback
of strength about h |K(t)| / (M + A_inf) per step, and the nonlinear remainders: stable for steps
that resolve the kernel (measured: cylinder up to 0.2 s, hinge barge at its exported 0.02 s over
200 s; docs/masters.md).

Which entries exist (:func:`coupling_pattern`): only those that can be non-zero (hydrostatic
coupling within a body, radiation coupling between any degrees of freedom whose damping is
not negligible, drag on the diagonal). An entry left out is not lost: its force stays in F0,
treated explicitly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .hdb import HydroDatabase


@dataclass(frozen=True)
class CouplingPattern:
    """Entries (row, column) of dF_dx and dF_dv that are published, 0-based positions in the
    selected-DOF vector (row: force, column: displacement or velocity)."""

    stiffness: tuple[tuple[int, int], ...]
    damping: tuple[tuple[int, int], ...]

    def to_json(self) -> dict:
        return {"stiffness": [list(p) for p in self.stiffness], "damping": [list(p) for p in self.damping]}

    @classmethod
    def from_json(cls, d: dict) -> CouplingPattern:
        return cls(tuple(tuple(p) for p in d["stiffness"]), tuple(tuple(p) for p in d["damping"]))

    def mask(self, n: int, which: str) -> np.ndarray:
        """(n, n) boolean mask of the published entries of ``stiffness`` or ``damping``."""
        out = np.zeros((n, n), dtype=bool)
        for i, j in getattr(self, which):
            out[i, j] = True
        return out


def coupling_pattern(hdb: HydroDatabase, index: np.ndarray, body_of: np.ndarray, *, hydrostatics: bool,
                     nonlinear_position: bool, radiation: bool, viscous: np.ndarray | None,
                     tolerance: float = 1e-6) -> CouplingPattern:
    """The entries of dF_dx and dF_dv that can be non-zero.

    Args:
        hdb: database (the scene's bodies).
        index: selected DOFs in the database's 6N numbering.
        body_of: body index of each selected DOF.
        hydrostatics: linear hydrostatics on (entries where the stiffness is not negligible).
        nonlinear_position: a force depends nonlinearly on x (nonlinear hydrostatics or Froude-Krylov):
            every pair of DOFs of one body.
        radiation: radiation memory on (pairs whose damping B(omega) is not negligible).
        viscous: per selected DOF, True where a viscous force acts (None: none).
        tolerance: an entry is negligible below ``tolerance`` times the geometric mean of its two
            diagonal entries' largest values (BEM noise on symmetric bodies is about 1e-8 of them).
    """
    n = len(index)
    same_body = body_of[:, None] == body_of[None, :]
    stiffness = np.zeros((n, n), dtype=bool)
    if hydrostatics:
        from scipy.linalg import block_diag

        c = np.abs(block_diag(*hdb.hydrostatic_stiffness)[np.ix_(index, index)])
        stiffness |= _significant(c, tolerance)
    if nonlinear_position:
        stiffness |= same_body
    damping = np.zeros((n, n), dtype=bool)
    if radiation:
        b = np.abs(hdb.radiation_damping[:, index][:, :, index]).max(axis=0)
        damping |= _significant(b, tolerance)
    if viscous is not None:
        damping |= np.diag(np.asarray(viscous, dtype=bool))
    def pairs(mask: np.ndarray) -> tuple[tuple[int, int], ...]:
        return tuple((int(i), int(j)) for i, j in zip(*np.nonzero(mask), strict=True))

    return CouplingPattern(pairs(stiffness), pairs(damping))


def _significant(m: np.ndarray, tolerance: float) -> np.ndarray:
    d = np.sqrt(np.abs(np.diag(m)))
    return (m > tolerance * np.outer(d, d)) & (m > 0)


@dataclass
class AffineForce:
    """F(t, x, v) ~= constant + rate (t - t_n) + dfdx x + dfdv v on the selected DOFs (module docstring).

    Attributes:
        constant: F0 (n,), N or N m.
        rate: F0_rate (n,), N/s or N m/s.
        dfdx: (n, n), published entries only (others zero), N/m, N/rad, N m/m, N m/rad.
        dfdv: (n, n), published entries only, N s/m ...
    """

    constant: np.ndarray
    rate: np.ndarray
    dfdx: np.ndarray
    dfdv: np.ndarray
