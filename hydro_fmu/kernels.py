"""Compiled (numba) per-point pass of the hydro FMU: every output of a communication point in one call.

:func:`point_outputs` does, for a linear model whose excitation and elevation are the superposition of the sea's
components (:meth:`hydro_fmu.model.HydroModel.evaluate` is the reference it must equal to round-off):

* excitation and elevation: the real part of one product of the phasors exp(i omega_k t) (from the model's
  :class:`hydro_fmu.waves.PhasorClock`) with the combined table of complex force and elevation amplitudes, times
  the half-cosine ramp r(t);
* radiation memory, Cummins convolution mu(t_c) = sum_{j=0}^{m-1} w_j K(j dt) v(t_c - j dt) by the trapezoidal
  rule on the grid of step dt (second order in dt; w_j = dt except dt/2 at both ends; velocities between two
  communication points interpolated linearly onto the grid, still second order), the (n, m n) weights times
  the window of the ring buffer of :class:`hydro_fmu.radiation.RadiationMemory` (the velocities of the pending
  grid points written first, as ``RadiationMemory._write_pending``), blocked over the next points
  (:func:`blocked_memory`); or, for the state-space model, mu computed beforehand into the block's radiation row
  (exact for piecewise-linear velocity);
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


@njit(reassociate=True)
def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """sum_f a[f] b[f] over a's length (vectorised: the sum reassociated)."""
    s = 0.0
    for f in range(a.shape[0]):
        s += a[f] * b[f]
    return s


@njit(reassociate=True)
def _dot4(a: np.ndarray, b0: np.ndarray, b1: np.ndarray, b2: np.ndarray, b3: np.ndarray
          ) -> tuple[float, float, float, float]:
    """The four sums sum_f a[f] b_j[f] over a's length in one pass over ``a`` (five loads per four products
    instead of eight)."""
    s0 = s1 = s2 = s3 = 0.0
    for f in range(a.shape[0]):
        x = a[f]
        s0 += x * b0[f]
        s1 += x * b1[f]
        s2 += x * b2[f]
        s3 += x * b3[f]
    return s0, s1, s2, s3


@njit(reassociate=True)
def block_history(weights: np.ndarray, ring: np.ndarray, start: int, stride: int, count: int,
                  history: np.ndarray) -> None:
    """The history parts of a block of points (:func:`blocked_memory`): ``history[k]`` (n,), k < ``count``, is the
    part of the convolution sum at the point (k + 1) ``stride`` grid steps after the block start that reaches
    only into the velocities committed before it, read from the window ring[start : start + m] of the velocities
    at the m grid points before the block start (oldest first). For offset b: sum over lags j >= b of
    W_j v(s0 - 1 + b - j), i.e. the first (m - b) n weights of each row times the window shifted by b rows.
    Four offsets per pass over a row (their common range together, then the rest of each); ``count`` stride
    must be below m."""
    m = ring.shape[0] // 2
    n = ring.shape[1]
    size = m * n
    window = ring[start : start + m].reshape(size)
    step = stride * n
    for i in range(n):
        row = weights[i]
        k = 0
        while k + 4 <= count:
            first = (k + 1) * step
            common = size - first - 3 * step
            sums = _dot4(row[:common], window[first : first + common], window[first + step : first + step + common],
                         window[first + 2 * step : first + 2 * step + common], window[first + 3 * step :])
            for j in range(4):
                shift = first + j * step
                history[k + j, i] = sums[j] + _dot(row[common : size - shift], window[common + shift :])
            k += 4
        while k < count:
            shift = (k + 1) * step
            history[k, i] = _dot(row[: size - shift], window[shift:])
            k += 1


@njit(reassociate=True)
def blocked_memory(weights: np.ndarray, ring: np.ndarray, steps: int, gap: int, history: np.ndarray,
                   block: np.ndarray, out: np.ndarray) -> None:
    """The convolution sum of :func:`memory` at the current grid point c = ``steps`` - 1 + ``gap`` (pending
    velocities already written to the ring), blocked over points: the lags that reach into velocities committed
    before a block's start s0 do not depend on the velocities of the points to come, so one pass over the
    weights at the block's first point computes that "history" part for the block's next points
    (:func:`block_history`, into ``history`` (B, n)), and each point then adds only its own b most recent lags,
    b = c - s0 + 1 (the last b n weights of each row times the current window): the same products as the direct
    sum, summed in another order (equal to round-off); the weights stream from memory once per B points instead
    of at every point.

    ``block`` (int64): [valid, s0, stride, count]: the history holds the points at offsets b = stride,
    2 stride, ..., count stride after s0. A point outside it (past the block's end, an offset the block does not
    hold because the step size changed, or no valid block: the first point) starts a new block at its own
    s0 = ``steps`` with stride ``gap``. Valid as long as the velocities committed before s0 do not change, which
    holds in one memory (commits only append; a restored state brings back its own block with its ring). The
    window at a block's start holds grid points s0 - m .. s0 - 1; the pending points of the first point
    overwrite the oldest ``gap`` of them, which no offset >= ``gap`` reads.
    """
    m = ring.shape[0] // 2
    n = ring.shape[1]
    c = steps - 1 + gap
    k = -1
    if block[0] == 1 and steps >= block[1]:
        b = c - block[1] + 1
        if b % block[2] == 0 and b // block[2] <= block[3]:
            k = b // block[2] - 1
    if k < 0:
        count = min(history.shape[0], (m - 1) // gap)
        if count == 0:  # a step as long as the kernel: nothing to share
            block[0] = 0
            memory(weights, ring, (c + 1) % m, out)
            return
        block_history(weights, ring, steps % m, gap, count, history)
        block[0], block[1], block[2], block[3] = 1, steps, gap, count
        k = 0
    b = c - block[1] + 1
    start = (c + 1) % m
    window = ring[start : start + m].reshape(m * n)
    low = (m - b) * n
    for i in range(n):
        row = weights[i]
        s = 0.0
        for f in range(low, m * n):
            s += row[f] * window[f]
        out[i] = history[k, i] + s


@njit
def point_outputs(t: float, phasor: np.ndarray, table: np.ndarray, ramp_duration: float, radiation: int,
                  ring: np.ndarray, last: np.ndarray, steps: int, gap: int, weights: np.ndarray,
                  history: np.ndarray, block: np.ndarray,
                  hydrostatics: bool, restoring: np.ndarray, viscous: bool,
                  linear: np.ndarray, quadratic: np.ndarray, x: np.ndarray, v: np.ndarray, forces: np.ndarray,
                  rows: np.ndarray, outputs: np.ndarray, power: np.ndarray, committed: np.ndarray,
                  last_power: np.ndarray, last_time: float, has_last: bool, energy: np.ndarray) -> float:
    """Every output of the point at time ``t`` (s); returns the wave elevation at the origin (m).

    Args:
        phasor: exp(i omega_k t) (K,); table: (K, n + 1) complex force amplitudes and, last, elevation amplitude.
        ramp_duration: of the half-cosine ramp (s; <= 0: none).
        radiation: RADIATION_NONE, RADIATION_CONVOLUTION (ring (2 m, n), last (n,), the committed grid points
            ``steps`` and the ``gap`` to the current one, weights (n, m n), the block's history (B, n) and
            state (4,) of :func:`blocked_memory`) or RADIATION_GIVEN (mu already in forces[2]).
        restoring: -C (n, n); linear, quadratic: viscous coefficients (n,).
        forces: (5, n) force rows (total, excitation, radiation, hydrostatic, viscous), written.
        rows, outputs: force rows copied into the rows of ``outputs``.
        power: (4,) written: the power F_c . v of each component (W), hydro_fmu.work.COMPONENTS order.
        committed, last_power, last_time, has_last: the work account's committed work (J), the power at its
            last committed point and that point's time (has_last False: none yet, the work is ``committed``).
        energy: (4,) written: the work at ``t``, W_c + (t - t_c) / 2 (P_c + P(t)) (trapezoidal rule).
    """
    n = forces.shape[1]
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
            forces[1, c] = s * r
        else:
            eta = s * r
    if radiation == RADIATION_CONVOLUTION:
        write_pending(ring, last, v, steps - 1 + gap, gap)
        blocked_memory(weights, ring, steps, gap, history, block, forces[2])
    if radiation != RADIATION_NONE:
        for i in range(n):
            forces[2, i] = -forces[2, i]
    else:
        forces[2, :] = 0.0
    for i in range(n):
        h = 0.0
        if hydrostatics:
            for j in range(n):
                h += restoring[i, j] * x[j]
        forces[3, i] = h
        forces[4, i] = (-linear[i] * v[i] - quadratic[i] * abs(v[i]) * v[i]) if viscous else 0.0
        forces[0, i] = ((forces[1, i] + forces[2, i]) + forces[3, i]) + forces[4, i]
    for k in range(rows.shape[0]):
        for i in range(n):
            outputs[k, i] = forces[rows[k], i]
    for c in range(4):
        p = 0.0
        for i in range(n):
            p += forces[c + 1, i] * v[i]
        power[c] = p
    for c in range(4):
        if has_last:
            energy[c] = (last_power[c] + power[c]) * (0.5 * (t - last_time)) + committed[c]
        else:
            energy[c] = committed[c]
    return eta
