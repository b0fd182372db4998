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
from typing import Any

import numpy as np
from scipy.linalg import expm

DEFAULT_TOLERANCE = 0.002
DEFAULT_MAX_ORDER = 100
HANKEL_ROWS = 300  # scalar rows of the ERA's block Hankel matrix (_hankel)
MAX_SAMPLES = 4000  # kernel samples of a fit at most (sampling_step)


class StateSpaceFitError(ValueError):
    """No realisation within the order limit meets the tolerance (``best``: (error, order) of the best one tried)."""

    def __init__(self, message: str, *, best: tuple[float, int] | None = None,
                 history: list[tuple[int, float]] | None = None) -> None:
        super().__init__(message)
        self.best = best
        self.history = history or []


@dataclass
class ConvolutionBlock:
    """A block of the kernel left to the convolution: no realisation up to the order limit reached the tolerance.

    Attributes:
        rows, columns: DOF indices (forces on ``rows`` from the velocities of ``columns``).
        error: the best scaled error reached (at ``order``).
        order: the order of that best fit.
    """

    rows: np.ndarray
    columns: np.ndarray
    error: float
    order: int


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
        convolution_blocks: blocks no order up to the limit fitted (``fallback``), left to the convolution.
    """

    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    order: int
    kernel_error: float
    tolerance: float
    frequency_error: float = float("nan")
    history: list[tuple[int, float]] = field(default_factory=list)
    convolution_blocks: list[ConvolutionBlock] = field(default_factory=list)

    def impulse_response(self, t: np.ndarray) -> np.ndarray:
        """C exp(A t) B at the times ``t`` (len(t), n, n)."""
        lam, vec = np.linalg.eig(self.a)
        left = self.c @ vec
        right = np.linalg.solve(vec, self.b)
        out = np.einsum("ir,tr,rj->tij", left, np.exp(np.outer(t, lam)), right)
        return np.real(out)

    def transfer(self, omega: np.ndarray) -> np.ndarray:
        """K^(omega) = C (i omega I - A)^-1 B (len(omega), n, n), from the eigen-decomposition of A (block by block:
        the fit's A is block-diagonal)."""
        out = np.zeros((len(omega), self.c.shape[0], self.b.shape[1]), complex)
        for part in _diagonal_blocks(self.a):
            lam, vec = np.linalg.eig(self.a[part, part])
            left = self.c[:, part] @ vec
            right = np.linalg.solve(vec, self.b[part])
            out += np.einsum("ir,wr,rj->wij", left, 1.0 / (1j * np.asarray(omega)[:, None] - lam[None, :]), right)
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


def dof_kind_floors(scales: np.ndarray, kinds: np.ndarray | None, fraction: float = 1e-3) -> np.ndarray | None:
    """Floors of the DOF scales: ``fraction`` of the largest scale among the DOFs of the same kind (``kinds``: a
    label per DOF, e.g. translation or rotation); None without kinds."""
    if kinds is None:
        return None
    kinds = np.asarray(kinds)
    floors = np.zeros_like(scales)
    for k in np.unique(kinds):
        floors[kinds == k] = fraction * scales[kinds == k].max()
    return floors


def fit_state_space(
    t: np.ndarray,
    kernel: np.ndarray,
    omega_max: float,
    tolerance: float = DEFAULT_TOLERANCE,
    max_order: int = DEFAULT_MAX_ORDER,
    kernel_function=None,
    floors: np.ndarray | None = None,
    groups: list[np.ndarray] | None = None,
    *,
    kinds: np.ndarray | None = None,
    still: np.ndarray | None = None,
    fallback: bool = False,
    sampling: float | None = None,
) -> StateSpaceFit:
    """Fit the lowest order whose kernel error is within ``tolerance`` (module docstring).

    The error is measured on the fit's own samples K(k D) (D = ``sampling``, by default pi / (2 omega_max): four
    samples per period of the highest frequency of the database), so that the fit, its order and whether it meets
    the tolerance do not depend on the grid ``t`` the kernel is given on (the simulation's step). A kernel with
    content above omega_max (B continued above the database) needs a finer D (:func:`sampling_step`).

    Args:
        t, kernel: the impulse response on a uniform grid from 0 (m,), (m, n, n).
        omega_max: highest frequency in the kernel's data (rad/s), sets the default sampling D = pi / (2 omega_max).
        tolerance: largest acceptable scaled kernel error.
        max_order: order limit (per block with ``groups``); :class:`StateSpaceFitError` if no order up to it
            fits (unless ``fallback``).
        kernel_function: K(times) -> (len, n, n), used to sample the kernel at D (default: every
            k-th sample of ``kernel``, k dt the largest multiple of its step not above D).
        floors: lower bounds of the DOF scales of the error measure (:func:`dof_scales`), or
        kinds: a label per DOF (translation, rotation): floors of 1e-3 of the largest scale of the same kind,
            measured on the fit's samples.
        groups: DOF indices of each body (several bodies): one realisation per ordered pair of bodies
            (K_ab: velocity of b to force on a), assembled block-diagonally, so that the order grows with the
            couplings that matter, not with the square of the body count; a pair whose coupling is already
            within the tolerance of zero (distant bodies) gets none. The error measure is the same
            entry-wise maximum, so the assembled fit meets the tolerance when every block does.
        still: DOFs whose velocity is always zero (a fixed body, a locked joint): their columns carry no
            memory, the fit leaves them out (no states; their error is not measured).
        fallback: a block that no order up to ``max_order`` fits is left to the convolution
            (:attr:`StateSpaceFit.convolution_blocks`) instead of raising.
        sampling: the sample step D (s), e.g. from :func:`sampling_step`.
    """
    if not tolerance > 0:
        raise ValueError(f"state-space tolerance must be positive (got {tolerance})")
    n = kernel.shape[1]
    d = min(sampling or np.pi / (2 * omega_max), t[-1] / 8)
    if kernel_function is not None:
        samples_t = np.arange(0.0, t[-1] + 1e-9 * d, d)
        samples = kernel_function(samples_t)
    else:  # every k-th sample of the given grid, k dt closest to d from below
        k = max(1, int(np.floor(d / (t[1] - t[0]) + 1e-9)))
        d = k * (t[1] - t[0])
        samples = kernel[::k]
        samples_t = t[::k]
    norms = dof_scales(samples)
    norms = np.maximum(norms, dof_kind_floors(norms, kinds)) if kinds is not None else dof_scales(samples, floors)
    moving = np.ones(n, dtype=bool) if still is None else ~np.asarray(still, dtype=bool)
    groups = [np.arange(n)] if not groups else [np.asarray(g, dtype=int) for g in groups]
    parts, worst, history, left = [], 0.0, [], []
    for ga in groups:
        for gb in groups:
            gb = gb[moving[gb]]
            if not len(gb):
                continue  # no memory of a DOF that cannot move
            block = samples[:, ga][:, :, gb]
            zero = scaled_error(block, np.zeros_like(block), norms[ga], norms[gb])
            if zero <= tolerance:  # coupling within the tolerance of zero: no states
                worst = max(worst, zero)
                continue
            label = "" if len(groups) == 1 and len(gb) == n else \
                f" (block of DOFs {list(map(int, ga))} x {list(map(int, gb))})"
            try:
                a, b, c, order, err, hist = _fit_block(samples_t, block, d, norms[ga], norms[gb], tolerance,
                                                      max_order, label)
            except StateSpaceFitError as exc:
                if not fallback or exc.best is None:
                    raise
                left.append(ConvolutionBlock(ga, gb, exc.best[0], exc.best[1]))
                history += exc.history
                continue
            parts.append((ga, gb, a, b, c))
            worst = max(worst, err)
            history += hist
    r = sum(part[2].shape[0] for part in parts)
    a, b, c = np.zeros((r, r)), np.zeros((r, n)), np.zeros((n, r))
    k = 0
    for ga, gb, ab, bb, cb in parts:
        o = ab.shape[0]
        a[k:k + o, k:k + o] = ab
        b[k:k + o, gb] = bb
        c[ga, k:k + o] = cb
        k += o
    return StateSpaceFit(a, b, c, r, worst, tolerance, history=history, convolution_blocks=left)


_FITS: dict[str, StateSpaceFit] = {}  # fits made in this process, by their inputs (fit_cached)


def fit_cached(table: tuple[np.ndarray, np.ndarray], kernel_time: np.ndarray, kernel: np.ndarray, **kwargs: Any
               ) -> StateSpaceFit:
    """:func:`fit_state_space` of the kernel of ``table`` (omega, B) (``kernel_function`` its impulse response), kept
    in this process for the same inputs: the fit does not depend on the grid the kernel is given on, and a run's
    error estimate makes the same fit three times (the run's hydro FMU, its coarse shadow's, the frequency domain's
    model of the run's radiation)."""
    import hashlib

    from .radiation import impulse_response

    digest = hashlib.sha256()
    for array in (*table, kernel_time[-1:]):
        value = np.ascontiguousarray(array)
        digest.update(f"{value.dtype.str}{value.shape}".encode())
        digest.update(value.tobytes())
    for key in sorted(kwargs):
        value = kwargs[key]
        if isinstance(value, list):  # groups
            value = [np.asarray(g).tolist() for g in value]
        elif isinstance(value, np.ndarray):
            value = value.tolist()
        digest.update(f"{key}={value!r};".encode())
    key = digest.hexdigest()
    if key not in _FITS:
        if len(_FITS) >= 8:
            _FITS.pop(next(iter(_FITS)))
        _FITS[key] = fit_state_space(kernel_time, kernel, kernel_function=lambda t: impulse_response(*table, t),
                                     **kwargs)
    fit = _FITS[key]
    return StateSpaceFit(fit.a.copy(), fit.b.copy(), fit.c.copy(), fit.order, fit.kernel_error, fit.tolerance,
                         fit.frequency_error, list(fit.history), list(fit.convolution_blocks))


def _fit_block(ts: np.ndarray, samples: np.ndarray, d: float, rows: np.ndarray, cols: np.ndarray,
               tolerance: float, max_order: int, label: str) -> tuple:
    """ERA fit of one (m, p, q) block of kernel samples at ``ts`` (step ``d``) with row and column scales:
    (a, b, c, order, error, history); the error is measured on the same samples."""
    p = samples.shape[1]
    scale_r = np.where(rows > 0, 1.0 / np.sqrt(np.where(rows > 0, rows, 1.0)), 1.0)
    scale_c = np.where(cols > 0, 1.0 / np.sqrt(np.where(cols > 0, cols, 1.0)), 1.0)
    scaled = samples * scale_r[None, :, None] * scale_c[None, None, :]
    h0, h1 = _hankel(scaled)
    if h0.shape[1] > 2 * h0.shape[0]:  # wide: the SVD of the triangular factor of H0^T (half the cost)
        q, r = np.linalg.qr(h0.T)
        u, s, wt = np.linalg.svd(r.T)
        vt = wt @ q.T
    else:
        u, s, vt = np.linalg.svd(h0, full_matrices=False)
    history = []
    best = None
    limit = min(max_order, int(np.sum(s > s[0] * 1e-12))) if s.size and s[0] > 0 else 0
    projected = u[:, :limit].T @ h1 @ vt[:limit].T  # U_r^T H1 V_r of every order r: its leading r x r block
    for order in range(1, limit + 1):
        fit = _realise(u, s, projected, order, p, d, scaled)
        if fit is None:
            continue
        a, b, c, response = fit
        c = c / scale_r[:, None]
        b = b / scale_c[None, :]
        err = scaled_error(samples, response / scale_r[None, :, None] / scale_c[None, None, :], rows, cols)
        history.append((order, err))
        if best is None or err < best[3]:
            best = (a, b, c, err, order)
        if err <= tolerance:
            return a, b, c, order, err, history
    if best is None:
        raise StateSpaceFitError(f"no stable state-space realisation could be formed from the impulse response{label}",
                                 history=history)
    raise StateSpaceFitError(
        f"no state-space realisation up to order {max_order} reaches the tolerance {tolerance:g}{label} "
        f"(best: order {best[4]}, error {best[3]:.3g}); raise hydro.state_space_max_order or the tolerance",
        best=(best[3], best[4]), history=history)


def _diagonal_blocks(a: np.ndarray) -> list[slice]:
    """The consecutive diagonal blocks of a block-diagonal ``a`` (slices)."""
    r = a.shape[0]
    out, start = [], 0
    for k in range(1, r + 1):
        if k == r or (not np.any(a[start:k, k:]) and not np.any(a[k:, start:k])):
            out.append(slice(start, k))
            start = k
    return out


def _hankel(samples: np.ndarray, max_rows: int = HANKEL_ROWS) -> tuple[np.ndarray, np.ndarray]:
    """Block Hankel matrices H0 = [K_{i+j}] and H1 = [K_{i+j+1}]: every sample in the columns, as many block rows
    as the samples allow up to ``max_rows`` scalar rows (square for short kernels, wide for long ones: the SVD's
    cost grows with the square of the rows)."""
    m, n, q = samples.shape
    r = max(1, min((m - 1) // 2, max_rows // max(n, 1)))
    c = m - r
    h0 = np.empty((r * n, c * q))
    h1 = np.empty((r * n, c * q))
    for i in range(r):
        h0[i * n:(i + 1) * n] = np.transpose(samples[i:i + c], (1, 0, 2)).reshape(n, c * q)
        h1[i * n:(i + 1) * n] = np.transpose(samples[i + 1:i + 1 + c], (1, 0, 2)).reshape(n, c * q)
    return h0, h1


def sampling_step(omega: np.ndarray, damping: np.ndarray, omega_max: float, tolerance: float, duration: float,
                  max_samples: int = MAX_SAMPLES) -> float:
    """The fit's sample step D = pi / (2 omega_e): four samples per period of the frequency omega_e above which the
    damping table (B on a grid up to its continuation's end) holds at most (tolerance / 4)^2 of the energy
    int B_ii^2 d omega of any diagonal entry (by Parseval, the kernel's L2 norm beyond what samples at D resolve
    is then at most a quarter of the tolerance), at least omega_max; coarser if the kernel's ``duration`` would need
    more than ``max_samples`` samples."""
    diag = np.einsum("wii->wi", np.asarray(damping, dtype=float)) ** 2
    w = np.asarray(omega, dtype=float)
    cum = np.concatenate([np.zeros((1, diag.shape[1])),
                          np.cumsum(0.5 * (diag[1:] + diag[:-1]) * np.diff(w)[:, None], axis=0)])
    total = cum[-1]
    above = 1.0 - cum / np.where(total > 0, total, 1.0)
    ok = np.all(above <= (tolerance / 4) ** 2, axis=1)
    omega_e = max(float(w[int(np.argmax(ok))]) if ok.any() else float(w[-1]), float(omega_max))
    return max(np.pi / (2 * omega_e), duration / max_samples)


def _realise(u: np.ndarray, s: np.ndarray, projected: np.ndarray, order: int, n: int, d: float,
             samples: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """ERA realisation of ``order`` with stable poles, continuous A, refitted B (scaled units) and its impulse
    response at the samples; ``projected``: U^T H1 V of a larger order (its leading block is this order's)."""
    root = np.sqrt(s[:order])
    phi = projected[:order, :order] / np.outer(root, root)
    c = u[:n, :order] * root
    lam, vec = np.linalg.eig(phi)
    unstable = np.abs(lam) >= 1.0
    lam = np.where(unstable, lam / np.abs(lam) ** 2 * (1 - 1e-9), lam)
    if np.any(np.abs(lam) < 1e-12) or np.any((np.abs(lam.imag) < 1e-12) & (lam.real < 0)):
        return None  # a pole at the Nyquist frequency or at zero has no continuous counterpart
    try:
        inverse = np.linalg.inv(vec)
    except np.linalg.LinAlgError:
        return None
    log_lam = np.log(lam.astype(complex)) / d
    a = np.real(vec @ np.diag(log_lam) @ inverse)
    if not np.all(np.isfinite(a)):
        return None
    # C exp(A k D) = (C V) diag(lambda^k) V^-1: the least-squares design of B (A and C fixed), row block k
    m = samples.shape[0]
    powers = np.exp(np.outer(np.arange(m), np.log(lam.astype(complex))))  # (m, r)
    design = np.real(((c @ vec)[None, :, :] * powers[:, None, :]).reshape(m * n, order) @ inverse)
    b, *_ = np.linalg.lstsq(design, samples.reshape(m * n, -1), rcond=None)
    return a, b, c, (design @ b).reshape(samples.shape)


def _response(a: np.ndarray, b: np.ndarray, c: np.ndarray, t: np.ndarray) -> np.ndarray:
    lam, vec = np.linalg.eig(a)
    left = c @ vec
    right = np.linalg.solve(vec, b)
    return np.real(np.einsum("ir,tr,rj->tij", left, np.exp(np.outer(t, lam)), right))


def frequency_error(fit: StateSpaceFit, omega: np.ndarray, added_mass: np.ndarray, damping: np.ndarray,
                    added_mass_inf: np.ndarray, floors: np.ndarray | None = None,
                    columns: np.ndarray | None = None) -> float:
    """Scaled error of the fit's A(omega) and B(omega) against the database (module docstring); ``columns``: the
    DOFs whose columns count (those that can move: the fit gives the others no memory)."""
    k = fit.transfer(omega)
    b_fit = k.real
    a_fit = added_mass_inf[None] + k.imag / omega[:, None, None]
    # Compare omega (A - A_inf) and B on one scale: both are parts of K^(omega).
    ref = np.concatenate([damping, omega[:, None, None] * (added_mass - added_mass_inf[None])], axis=0)
    approx = np.concatenate([b_fit, omega[:, None, None] * (a_fit - added_mass_inf[None])], axis=0)
    scales = dof_scales(ref, floors)
    if columns is None:
        return scaled_error(ref, approx, scales)
    return scaled_error(ref[:, :, columns], approx[:, :, columns], scales, scales[columns])


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

