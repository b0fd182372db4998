"""Compiled (numba) per-point pass of the hydro FMU: every output of a communication point in one call.

:func:`point_outputs` does, for a linear model whose excitation and elevation are the superposition of the sea's
components (:meth:`hydro_fmu.model.HydroModel.evaluate` is the reference it must equal to round-off):

* excitation and elevation: the real part of one product of the phasors exp(i omega_k t) (from the model's
  :class:`hydro_fmu.waves.PhasorClock`) with the combined table of complex force and elevation amplitudes, times
  the half-cosine ramp r(t);
* radiation memory, Cummins convolution mu(t_c) = sum_{j=0}^{m-1} w_j K(j dt) v(t_c - j dt) by the trapezoidal
  rule on the grid of step dt (second order in dt; w_j = dt except dt/2 at both ends; velocities between two
  communication points interpolated linearly onto the grid, still second order), as one matrix-vector
  product of the (n, m n) weights with the window of the ring buffer of
  :class:`hydro_fmu.radiation.RadiationMemory` (the velocities of the pending grid points written first, as
  ``RadiationMemory._write_pending``); or, for the state-space
  model, mu computed beforehand into the block's radiation row (exact for piecewise-linear velocity);
* hydrostatics -C x, viscous -b v - q |v| v, the total ((exc + rad) + hs) + visc;
* the force rows copied into the output variables, the power F_c . v of each component, and the work by the
  trapezoidal rule over the communication points (:mod:`hydro_fmu.work`).

Explicit evaluation of given data: no stability limit of its own. With numba missing or ``WEC_COSIM_NO_JIT`` set
the same functions run as plain Python (slow, but the same answers); :class:`hydro_fmu.model.HydroModel` then
keeps its numpy path (:data:`COMPILED`).
"""

from __future__ import annotations

import math

import numpy as np

from fmu_base._jit import AVAILABLE, njit

COMPILED = AVAILABLE  # the pass is machine code (else HydroModel keeps its numpy path)

# Radiation modes of point_outputs
RADIATION_NONE, RADIATION_CONVOLUTION, RADIATION_GIVEN = 0, 1, 2


@njit
def write_pending(ring: np.ndarray, last: np.ndarray, v: np.ndarray, current: int, gap: int) -> None:
    """Velocities of the grid points after the last committed one up to ``current`` (grid index): linear from
    ``last`` to ``v``, each at rows s % m and s % m + m of the (2 m, n) ring (only the last m are written)."""
    m = ring.shape[0] // 2
    n = ring.shape[1]
    if gap == 1:
        row = current % m
        for i in range(n):
            ring[row, i] = v[i]
            ring[row + m, i] = v[i]
        return
    for lag in range(min(gap, m) - 1, -1, -1):
        row = (current - lag) % m
        f = lag / gap
        for i in range(n):
            value = v[i] + f * (last[i] - v[i])
            ring[row, i] = value
            ring[row + m, i] = value


@njit(reassociate=True)
def memory(weights: np.ndarray, ring: np.ndarray, start: int, out: np.ndarray) -> None:
    """The convolution sum ``out`` (n,) = ``weights`` (n, m n) times the window ring[start : start + m] (m, n) of
    velocities at lags m-1 .. 0 (oldest first), flattened: one dot product per output, vectorised (the sums
    reassociated). A loop in this thread: BLAS splits a product this size over threads, whose wake-up costs
    more than the product when the process runs other work between points (the multibody FMU)."""
    m = ring.shape[0] // 2
    n = ring.shape[1]
    window = ring[start : start + m].reshape(m * n)
    for i in range(out.shape[0]):
        row = weights[i]
        s = 0.0
        for k in range(m * n):
            s += row[k] * window[k]
        out[i] = s


@njit
def point_outputs(t: float, phasor: np.ndarray, table: np.ndarray, ramp_duration: float, radiation: int,
                  ring: np.ndarray, last: np.ndarray, current: int, gap: int, weights: np.ndarray,
                  hydrostatics: bool, restoring: np.ndarray, viscous: bool,
                  linear: np.ndarray, quadratic: np.ndarray, x: np.ndarray, v: np.ndarray, block: np.ndarray,
                  rows: np.ndarray, outputs: np.ndarray, power: np.ndarray, committed: np.ndarray,
                  last_power: np.ndarray, last_time: float, has_last: bool, energy: np.ndarray) -> float:
    """Every output of the point at time ``t`` (s); returns the wave elevation at the origin (m).

    Args:
        phasor: exp(i omega_k t) (K,); table: (K, n + 1) complex force amplitudes and, last, elevation amplitude.
        ramp_duration: of the half-cosine ramp (s; <= 0: none).
        radiation: RADIATION_NONE, RADIATION_CONVOLUTION (ring (2 m, n), last (n,), current and gap grid
            indices, weights (n, m n)) or RADIATION_GIVEN (mu already in block[2]).
        restoring: -C (n, n); linear, quadratic: viscous coefficients (n,).
        block: (5, n) force rows (total, excitation, radiation, hydrostatic, viscous), written.
        rows, outputs: block rows copied into the rows of ``outputs``.
        power: (4,) written: the power F_c . v of each component (W), hydro_fmu.work.COMPONENTS order.
        committed, last_power, last_time, has_last: the work account's committed work (J), the power at its
            last committed point and that point's time (has_last False: none yet, the work is ``committed``).
        energy: (4,) written: the work at ``t``, W_c + (t - t_c) / 2 (P_c + P(t)) (trapezoidal rule).
    """
    n = block.shape[1]
    if ramp_duration <= 0.0 or t >= ramp_duration:
        r = 1.0
    else:
        r = 0.5 * (1.0 - math.cos(math.pi * max(t, 0.0) / ramp_duration))
    eta = 0.0
    for c in range(n + 1):
        s = 0.0
        for k in range(phasor.shape[0]):  # real part of the complex product
            s += phasor[k].real * table[k, c].real - phasor[k].imag * table[k, c].imag
        if c < n:
            block[1, c] = s * r
        else:
            eta = s * r
    if radiation == RADIATION_CONVOLUTION:
        write_pending(ring, last, v, current, gap)
        m = ring.shape[0] // 2
        memory(weights, ring, (current + 1) % m, block[2])
    if radiation != RADIATION_NONE:
        for i in range(n):
            block[2, i] = -block[2, i]
    else:
        block[2, :] = 0.0
    for i in range(n):
        h = 0.0
        if hydrostatics:
            for j in range(n):
                h += restoring[i, j] * x[j]
        block[3, i] = h
        block[4, i] = (-linear[i] * v[i] - quadratic[i] * abs(v[i]) * v[i]) if viscous else 0.0
        block[0, i] = ((block[1, i] + block[2, i]) + block[3, i]) + block[4, i]
    for k in range(rows.shape[0]):
        for i in range(n):
            outputs[k, i] = block[rows[k], i]
    for c in range(4):
        p = 0.0
        for i in range(n):
            p += block[c + 1, i] * v[i]
        power[c] = p
    for c in range(4):
        if has_last:
            energy[c] = (last_power[c] + power[c]) * (0.5 * (t - last_time)) + committed[c]
        else:
            energy[c] = committed[c]
    return eta
