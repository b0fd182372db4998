"""State-space realisation of the radiation memory, fitted to the impulse response.

The memory force mu(t) = int_0^t K(t - tau) v(tau) dtau is replaced by the output of

    z' = A z + B v,   mu = C z,

whose impulse response C exp(A t) B approximates K(t) (n x n for the n selected DOFs, one
multi-input multi-output system; no feedthrough, K(0) = C B).

Fit (:func:`fit_state_space`): the eigensystem realisation algorithm (ERA, Kung's Hankel-SVD
method) on samples K_k = K(k D) with D = pi / (2 omega_max) (four samples per period of the
highest database frequency), after scaling K by the sizes of its diagonal entries so that
translations and rotations weigh alike. For an order r the SVD of the block Hankel matrix of the
samples gives the discrete realisation (Phi, B_d, C); poles outside the unit circle are
reflected inside (|z| -> 1/|z|, stable poles enforced), the continuous matrix is
A = log(Phi) / D (exact for samples of a continuous system), and B is refitted by linear least
squares to the samples with A and C fixed. The order grows one by one until the fitted
kernel's error on the kernel's own time grid is at most the tolerance:

    error = max_ij ||K_ij - K^_ij||_2 / sqrt(s_i s_j),   s_i = max(||K_ii||_2, floor_i),

where the floor (set by the model: 1e-3 of the largest s of the same kind, translation or rotation)
keeps DOFs that carry only numerical noise (the yaw of an axisymmetric body) from setting the order.

The fitted model's error against the database is reported too: with K^(omega) =
C (i omega I - A)^-1 B, B_fit = Re K^ and A_fit = A_inf + Im K^ / omega (``frequency_error``,
the same scaled maximum over entries, over the database frequencies).

Integration (:class:`StateSpaceMemory`): exact over each step for a velocity that is linear
between two communication points (first-order hold): z_{n+1} = Phi(h) z_n + G0(h) v_n +
G1(h) (v_{n+1} - v_n), with Phi, G0, G1 from one matrix exponential of an augmented matrix per
distinct step h. Any step size, no stability limit (the poles are stable); the force at a
communication point uses the current velocity through the G1 term (direct feedthrough), like
the trapezoidal convolution.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import expm

DEFAULT_TOLERANCE = 0.002
DEFAULT_MAX_ORDER = 100


class StateSpaceFitError(ValueError):
    """No realisation within the order limit meets the tolerance."""


@dataclass
class StateSpaceFit:
    """A fitted realisation and its errors.

    Attributes:
        a, b, c: continuous-time matrices (r, r), (r, n), (n, r).
        order: r.
        kernel_error: scaled error against the impulse response (module docstring).
        frequency_error: scaled error of B and A against the database (nan if not evaluated).
        tolerance: the requested kernel error.
        history: (order, kernel_error) of every order tried.
    """

    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    order: int
    kernel_error: float
    tolerance: float
    frequency_error: float = float("nan")
    history: list[tuple[int, float]] = field(default_factory=list)

    def impulse_response(self, t: np.ndarray) -> np.ndarray:
        """C exp(A t) B at the times ``t`` (len(t), n, n)."""
        lam, vec = np.linalg.eig(self.a)
        left = self.c @ vec
        right = np.linalg.solve(vec, self.b)
        out = np.einsum("ir,tr,rj->tij", left, np.exp(np.outer(t, lam)), right)
        return np.real(out)

    def transfer(self, omega: np.ndarray) -> np.ndarray:
        """K^(omega) = C (i omega I - A)^-1 B (len(omega), n, n)."""
        r = self.order
        out = np.empty((len(omega), self.c.shape[0], self.b.shape[1]), complex)
        for k, w in enumerate(omega):
            out[k] = self.c @ np.linalg.solve(1j * w * np.eye(r) - self.a, self.b)
        return out

    @property
    def max_real_pole(self) -> float:
        """Largest real part of the poles (1/s); negative for a stable fit."""
        return float(np.max(np.linalg.eigvals(self.a).real)) if self.order else -np.inf


def dof_scales(reference: np.ndarray, floors: np.ndarray | None = None) -> np.ndarray:
    """s_i = ||R_ii||_2 over the first axis, raised to ``floors`` (so that a DOF with only numerical
    noise, e.g. the yaw of an axisymmetric body, is measured against its physical neighbours)."""
    s = np.sqrt(np.sum(np.abs(np.einsum("tii->ti", reference)) ** 2, axis=0))
    return s if floors is None else np.maximum(s, floors)


def scaled_error(reference: np.ndarray, approximation: np.ndarray, scales: np.ndarray | None = None,
                 column_scales: np.ndarray | None = None) -> float:
    """max_ij ||R_ij - X_ij||_2 / sqrt(s_i s_j) over the first axis (s from :func:`dof_scales`; for a block of
    rows i and columns j of a larger kernel, ``scales`` are the rows' and ``column_scales`` the columns')."""
    s = dof_scales(reference) if scales is None else np.asarray(scales, dtype=float)
    sc = s if column_scales is None else np.asarray(column_scales, dtype=float)
    err = np.sqrt(np.sum(np.abs(reference - approximation) ** 2, axis=0))
    active, active_c = s > 0, sc > 0
    pair = np.sqrt(np.outer(np.where(active, s, 1.0), np.where(active_c, sc, 1.0)))
    rel = np.where(active[:, None] & active_c[None, :], err / pair, 0.0)
    return float(rel.max()) if rel.size else 0.0


def fit_state_space(
    t: np.ndarray,
    kernel: np.ndarray,
    omega_max: float,
    tolerance: float = DEFAULT_TOLERANCE,
    max_order: int = DEFAULT_MAX_ORDER,
    kernel_function=None,
    floors: np.ndarray | None = None,
    groups: list[np.ndarray] | None = None,
) -> StateSpaceFit:
    """Fit the lowest order whose kernel error is within ``tolerance`` (module docstring).

    Args:
        t, kernel: the impulse response on a uniform grid from 0 (m,), (m, n, n).
        omega_max: highest frequency in the kernel (rad/s), sets the sampling D = pi / (2 omega_max).
        tolerance: largest acceptable scaled kernel error.
        max_order: order limit (per block with ``groups``); :class:`StateSpaceFitError` if no order up to it
            fits.
        kernel_function: K(times) -> (len, n, n), used to sample the kernel at D (default: every
            k-th sample of ``kernel``, k dt the largest multiple of its step not above D).
        floors: lower bounds of the DOF scales of the error measure (:func:`dof_scales`).
        groups: DOF indices of each body (several bodies): one realisation per ordered pair of bodies
            (K_ab: velocity of b to force on a), assembled block-diagonally, so that the order grows with the
            couplings that matter, not with the square of the body count; a pair whose coupling is already
            within the tolerance of zero (distant bodies) gets none. The error measure is the same
            entry-wise maximum, so the assembled fit meets the tolerance when every block does.
    """
    if not tolerance > 0:
        raise ValueError(f"state-space tolerance must be positive (got {tolerance})")
    norms = dof_scales(kernel, floors)
    d = min(np.pi / (2 * omega_max), t[-1] / 8)
    if kernel_function is not None:
        samples_t = np.arange(0.0, t[-1] + 1e-9 * d, d)
        samples = kernel_function(samples_t)
    else:  # every k-th sample of the given grid, k dt closest to d from below
        k = max(1, int(np.floor(d / (t[1] - t[0]) + 1e-9)))
        d = k * (t[1] - t[0])
        samples = kernel[::k]
    if groups is None or len(groups) <= 1:
        a, b, c, order, err, history = _fit_block(t, kernel, samples, d, norms, norms, tolerance, max_order, "")
        return StateSpaceFit(a, b, c, order, err, tolerance, history=history)
    n = kernel.shape[1]
    parts, worst, history = [], 0.0, []
    for ga in groups:
        for gb in groups:
            block = kernel[:, ga][:, :, gb]
            zero = scaled_error(block, np.zeros_like(block), norms[ga], norms[gb])
            if zero <= tolerance:  # coupling within the tolerance of zero: no states
                worst = max(worst, zero)
                continue
            label = f" (block of DOFs {list(map(int, ga))} x {list(map(int, gb))})"
            a, b, c, order, err, hist = _fit_block(t, block, samples[:, ga][:, :, gb], d, norms[ga], norms[gb],
                                                  tolerance, max_order, label)
            parts.append((ga, gb, a, b, c))
            worst = max(worst, err)
            history += hist
    r = sum(p[2].shape[0] for p in parts)
    a, b, c = np.zeros((r, r)), np.zeros((r, n)), np.zeros((n, r))
    k = 0
    for ga, gb, ab, bb, cb in parts:
        o = ab.shape[0]
        a[k:k + o, k:k + o] = ab
        b[k:k + o, gb] = bb
        c[ga, k:k + o] = cb
        k += o
    return StateSpaceFit(a, b, c, r, worst, tolerance, history=history)


def _fit_block(t: np.ndarray, kernel: np.ndarray, samples: np.ndarray, d: float, rows: np.ndarray,
               cols: np.ndarray, tolerance: float, max_order: int, label: str) -> tuple:
    """ERA fit of one (m, p, q) kernel block with row and column scales: (a, b, c, order, error, history)."""
    p = kernel.shape[1]
    scale_r = np.where(rows > 0, 1.0 / np.sqrt(np.where(rows > 0, rows, 1.0)), 1.0)
    scale_c = np.where(cols > 0, 1.0 / np.sqrt(np.where(cols > 0, cols, 1.0)), 1.0)
    scaled = samples * scale_r[None, :, None] * scale_c[None, None, :]
    h0, h1 = _hankel(scaled)
    u, s, vt = np.linalg.svd(h0, full_matrices=False)
    history = []
    best = None
    limit = min(max_order, int(np.sum(s > s[0] * 1e-12))) if s.size and s[0] > 0 else 0
    for order in range(1, limit + 1):
        fit = _realise(u, s, vt, h1, order, p, d, scaled)
        if fit is None:
            continue
        a, b, c = fit
        c = c / scale_r[:, None]
        b = b / scale_c[None, :]
        err = scaled_error(kernel, _response(a, b, c, t), rows, cols)
        history.append((order, err))
        if best is None or err < best[3]:
            best = (a, b, c, err, order)
        if err <= tolerance:
            return a, b, c, order, err, history
    if best is None:
        raise StateSpaceFitError(f"no stable state-space realisation could be formed from the impulse response{label}")
    raise StateSpaceFitError(
        f"no state-space realisation up to order {max_order} reaches the tolerance {tolerance:g}{label} "
        f"(best: order {best[4]}, error {best[3]:.3g}); raise hydro.state_space_max_order or the tolerance")


def _hankel(samples: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Block Hankel matrices H0 = [K_{i+j}] and H1 = [K_{i+j+1}] (square, as large as the samples allow)."""
    m, n, _ = samples.shape
    p = (m - 1) // 2
    rows = [np.concatenate(list(samples[i : i + p]), axis=1) for i in range(p)]
    h0 = np.concatenate(rows, axis=0)
    rows1 = [np.concatenate(list(samples[i + 1 : i + 1 + p]), axis=1) for i in range(p)]
    h1 = np.concatenate(rows1, axis=0)
    return h0, h1


def _realise(u: np.ndarray, s: np.ndarray, vt: np.ndarray, h1: np.ndarray, order: int, n: int, d: float,
             samples: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """ERA realisation of ``order`` with stable poles, continuous A, refitted B (scaled units)."""
    root = np.sqrt(s[:order])
    ur, vr = u[:, :order], vt[:order].T
    phi = (ur.T @ h1 @ vr) / np.outer(root, root)
    c = ur[:n] * root
    lam, vec = np.linalg.eig(phi)
    unstable = np.abs(lam) >= 1.0
    lam = np.where(unstable, lam / np.abs(lam) ** 2 * (1 - 1e-9), lam)
    if np.any(np.abs(lam) < 1e-12) or np.any((np.abs(lam.imag) < 1e-12) & (lam.real < 0)):
        return None  # a pole at the Nyquist frequency or at zero has no continuous counterpart
    log_lam = np.log(lam.astype(complex)) / d
    a = np.real(vec @ np.diag(log_lam) @ np.linalg.inv(vec))
    if not np.all(np.isfinite(a)):
        return None
    b = _refit_input(a, c, samples, d)
    return a, b, c


def _refit_input(a: np.ndarray, c: np.ndarray, samples: np.ndarray, d: float) -> np.ndarray:
    """B minimising sum_k ||C exp(A k D) B - K_k||^2 (linear least squares, A and C fixed)."""
    m, p, q = samples.shape
    step = expm(a * d)
    rows = []
    power = np.eye(a.shape[0])
    for _ in range(m):
        rows.append(c @ power)
        power = power @ step
    design = np.concatenate(rows, axis=0)  # (m p, r)
    target = samples.reshape(m * p, q)
    b, *_ = np.linalg.lstsq(design, target, rcond=None)
    return b


def _response(a: np.ndarray, b: np.ndarray, c: np.ndarray, t: np.ndarray) -> np.ndarray:
    lam, vec = np.linalg.eig(a)
    left = c @ vec
    right = np.linalg.solve(vec, b)
    return np.real(np.einsum("ir,tr,rj->tij", left, np.exp(np.outer(t, lam)), right))


def frequency_error(fit: StateSpaceFit, omega: np.ndarray, added_mass: np.ndarray, damping: np.ndarray,
                    added_mass_inf: np.ndarray, floors: np.ndarray | None = None) -> float:
    """Scaled error of the fit's A(omega) and B(omega) against the database (module docstring)."""
    k = fit.transfer(omega)
    b_fit = k.real
    a_fit = added_mass_inf[None] + k.imag / omega[:, None, None]
    # Compare omega (A - A_inf) and B on one scale: both are parts of K^(omega).
    ref = np.concatenate([damping, omega[:, None, None] * (added_mass - added_mass_inf[None])], axis=0)
    approx = np.concatenate([b_fit, omega[:, None, None] * (a_fit - added_mass_inf[None])], axis=0)
    return scaled_error(ref, approx, dof_scales(ref, floors))


class StateSpaceMemory:
    """Radiation memory mu(t) by the fitted state space, exact for piecewise-linear velocity.

    Same use as :class:`hydro_fmu.radiation.RadiationMemory`: :meth:`force` with the current
    velocity at a communication point, then :meth:`step` with that velocity and the step size.
    The update is one matrix-vector product with [Phi, G0 - G1, G1] (r x (r + 2n)) acting on
    w = (z, v_last, v_now), and the force one with C times that matrix, both cached per step size.
    """

    def __init__(self, fit: StateSpaceFit) -> None:
        self.a, self.b, self.c = fit.a, fit.b, fit.c
        self.r = fit.order
        self.n = fit.b.shape[1]
        # w = (state at the last committed point, velocity there, current velocity)
        self.w = np.zeros(self.r + 2 * self.n)
        self.pending = 0.0  # seconds from the last committed point to the current time
        self._cache: dict[float, tuple[np.ndarray, np.ndarray]] = {}

    @property
    def z(self) -> np.ndarray:
        """State at the last committed point."""
        return self.w[: self.r]

    def matrices(self, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Phi(h), G0(h), G1(h) from exp of [[A h, B h, 0], [0, 0, I], [0, 0, 0]]."""
        r, n = self.r, self.n
        aug = np.zeros((r + 2 * n, r + 2 * n))
        aug[:r, :r] = self.a * h
        aug[:r, r : r + n] = self.b * h
        aug[r : r + n, r + n :] = np.eye(n)
        e = expm(aug)
        return e[:r, :r], e[:r, r : r + n], e[:r, r + n :]

    def _update(self, h: float) -> tuple[np.ndarray, np.ndarray]:
        """(M, C M) with M = [Phi, G0 - G1, G1] for the step h (identity on z for h = 0)."""
        if h not in self._cache:
            r, n = self.r, self.n
            if h == 0.0:
                m = np.zeros((r, r + 2 * n))
                m[:, :r] = np.eye(r)
            else:
                phi, g0, g1 = self.matrices(h)
                m = np.concatenate([phi, g0 - g1, g1], axis=1)
            if len(self._cache) > 16:
                self._cache.clear()
            self._cache[h] = (m, self.c @ m)
        return self._cache[h]

    def force(self, v_now: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """mu at the current time given the current velocity (N; the radiation force is -mu); written into
        ``out`` (n,) if given."""
        self.w[self.r + self.n :] = v_now
        return np.dot(self._update(self.pending)[1], self.w, out=out)

    def instantaneous_damping(self) -> np.ndarray:
        """d mu / d v_now (n, n), N s/m: C G1 of the step since the last commit (about K(0) h / 2)."""
        return self._update(self.pending)[1][:, self.r + self.n :].copy()

    def step(self, v_now: np.ndarray, h: float) -> None:
        """Commit the current velocity and move ``h`` seconds on (any h > 0)."""
        if not h > 0:
            raise ValueError(f"a step must be positive (got {h})")
        r, n = self.r, self.n
        self.w[r + n :] = v_now
        self.w[:r] = self._update(self.pending)[0] @ self.w
        self.w[r : r + n] = v_now
        self.pending = float(h)
