"""Radiation memory of the Cummins equation: impulse response function and convolution.

The radiation force beyond the infinite-frequency added mass (which the multibody side carries
in its mass matrix) is the memory integral

    F_rad(t) = - mu(t),   mu(t) = int_0^t K(t - tau) v(tau) dtau,

    K(t) = (2/pi) int_0^inf B(omega) cos(omega t) domega.

Impulse response: B(omega) is taken piecewise linear between the database frequencies (and
linear from B(0) = 0 to the first frequency, zero above the last one) and the cosine integral is
evaluated exactly on each segment (Filon-type). On a uniform grid this equals the trapezoidal
cosine sum times sinc^2(Delta omega t / 2): the periodic images of K that the trapezoidal sum
produces at t = 2 pi m / Delta omega are suppressed (to zero at those times), and for
t << pi / Delta omega the error is second order in Delta omega. Keep the kernel shorter than
about pi / Delta omega. Truncation at the highest database frequency shows as a ripple of period
2 pi / omega_max in K(t), decaying only as 1/t; :func:`damping_tail` continues B above the table by
a power law instead (:func:`kernel_table` is the table the kernel is computed from).

Convolution: trapezoidal rule on a uniform grid t_j = j * dt over the kernel length T_K
(``irf_duration``): second-order accurate in dt for a smooth velocity, no stability limit of its
own (it is an explicit sum over past velocities); the current velocity enters with weight
K(0) dt / 2, so the force depends directly on the current velocity input. Velocities before
t = 0 are zero (the device starts from rest). Communication steps may be any integer multiple q
of dt: the velocity between two communication points is interpolated linearly onto the grid
(still second order).

Diagnostics (:func:`irf_diagnostics`): the kernel is trusted only where the database allows it;
a warning is given when the kernel is longer than pi / d_omega (largest frequency step, the
first one from 0 included), when B has not decayed at the highest frequency (truncation ripple),
and when K has not decayed at the end of the kernel (memory cut off).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .transforms import fourier_integral

# Points that share one pass over the convolution weights (the runtime's radiation.block_points,
# native/src/hydro/radiation_convolution.c). Hinge barge in a co-simulation loop, measured with the numba pass the
# runtime replaced (same blocks): 21 us per point with B = 1, 11 us with B = 4 to 32 alike
# (benchmarks/results/hydro_block.txt); 8 keeps a block's first point short.
BLOCK_POINTS = 8
# Tail correction of :func:`kramers_kronig_tail`: hats at Omega r^j, j = 1..count, ridge weight.
TAIL_RATIO = 1.25
TAIL_COUNT = 3
TAIL_SMOOTHING = 1e-3


def impulse_response(omega: np.ndarray, damping: np.ndarray, t: np.ndarray) -> np.ndarray:
    """K(t) (len(t), n, n) from B(omega) (Nw, n, n) by exact integration of the linear interpolant.

    Args:
        omega: increasing frequencies (Nw,), rad/s, all positive.
        damping: radiation damping B at those frequencies (Nw, n, n).
        t: times (s), >= 0.
    """
    w = np.concatenate([[0.0], np.asarray(omega, dtype=float)])
    B = np.concatenate([np.zeros((1,) + damping.shape[1:]), damping], axis=0)
    return (2.0 / np.pi) * np.real(fourier_integral(w, B, t))


def damping_tail(omega: np.ndarray, damping: np.ndarray, exponent: float, *, ratio: float = 1.02,
                 reach: float = 100.0, correction: tuple[np.ndarray, np.ndarray] | None = None,
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The table continued above its last frequency Omega by B(omega) = B(Omega) (Omega / omega)^n.

    A BEM database stops at some Omega where B has not decayed; cutting B there (the default)
    leaves out of A(omega) the Kramers-Kronig share of the missing tail, about
    (2/pi) int_Omega^inf B(nu) / nu^2 (1 + omega^2 / nu^2 + ...) dnu: a constant, which the
    Ogilvie A_inf absorbs, plus a part rising as omega^2 that nothing else can absorb. The
    continuation is a model, chosen by the exponent n: 3 is the deep-water high-frequency
    law of a wall-sided body in surge (wave amplitude / stroke tends to a constant, so the
    radiated power per unit velocity squared falls as g^2 / omega^3); heave and pitch of a flat
    bottom decay faster. Tabulated on a geometric grid of ratio ``ratio`` (linear-interpolation
    error about n (n + 1) (ratio - 1)^2 / 8 of the tail) up to ``reach`` * Omega, where the tail
    is ``reach``^-n of B(Omega).

    ``correction``: (nodes (k,), values (k, ...)) of a piecewise-linear addition to the tail above Omega,
    zero at Omega and beyond its last node (:func:`kramers_kronig_tail`); the table then holds the union of
    both grids, on which the sum is exactly piecewise linear. With n = 0 and a correction, the tail is the
    correction alone.
    """
    omega = np.asarray(omega, dtype=float)
    if exponent <= 0 and correction is None:
        return omega, damping
    top = omega[-1]
    shape = (-1,) + (1,) * (damping.ndim - 1)
    if exponent > 0:
        nodes = top * ratio ** np.arange(1, int(np.ceil(np.log(reach) / np.log(ratio))) + 1)
        tail = damping[-1][None] * ((top / nodes) ** exponent).reshape(shape)
    else:
        nodes, tail = np.zeros(0), np.zeros((0,) + damping.shape[1:])
    if correction is not None:
        c_nodes, c_values = np.asarray(correction[0], dtype=float), np.asarray(correction[1])
        grid = np.union1d(nodes, c_nodes)
        if exponent > 0:
            law = damping[-1][None] * ((top / grid) ** exponent).reshape(shape)
        else:
            law = np.zeros((len(grid),) + damping.shape[1:])
        hats = _piecewise_linear(np.concatenate([[top], c_nodes]),
                                 np.concatenate([np.zeros((1,) + c_values.shape[1:]), c_values]), grid)
        nodes, tail = grid, law + hats
    return np.concatenate([omega, nodes]), np.concatenate([damping, tail], axis=0)


def _piecewise_linear(nodes: np.ndarray, values: np.ndarray, x: np.ndarray) -> np.ndarray:
    """The linear interpolant of ``values`` (k, ...) at ``nodes`` evaluated at ``x``, zero outside the nodes."""
    flat = values.reshape(len(nodes), -1)
    out = np.stack([np.interp(x, nodes, flat[:, j], left=0.0, right=0.0) for j in range(flat.shape[1])], axis=1)
    return out.reshape((len(x),) + values.shape[1:])


def kernel_table(omega: np.ndarray, damping: np.ndarray, *, d_omega: float = 0.0,
                 tail_exponent: float = 0.0, tail_correction: tuple[np.ndarray, np.ndarray] | None = None,
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The B(omega) table the impulse response is computed from: the database's, resampled
    (``d_omega`` > 0, :func:`resample_damping`) and continued above its last frequency
    (``tail_exponent`` > 0 and/or ``tail_correction``, :func:`damping_tail`)."""
    if d_omega > 0:
        omega, damping = resample_damping(omega, damping, d_omega)
    return damping_tail(omega, damping, tail_exponent, correction=tail_correction)


def resample_damping(omega: np.ndarray, damping: np.ndarray, d_omega: float) -> tuple[np.ndarray, np.ndarray]:
    """B on a uniform grid of step ``d_omega`` from d_omega up to the last frequency, by
    shape-preserving cubic (PCHIP) interpolation through (0, 0) and the database values.

    A finer grid than the database's makes the interpolant smoother (C1 instead of kinks at
    every node), which lengthens the time over which the transform is accurate; it adds no
    information beyond the database.
    """
    from scipy.interpolate import PchipInterpolator

    if not d_omega > 0:
        raise ValueError(f"IRF frequency step must be positive (got {d_omega})")
    w = np.concatenate([[0.0], omega])
    table = np.concatenate([np.zeros((1,) + damping.shape[1:]), damping], axis=0)
    grid = np.arange(1, int(np.floor(omega[-1] / d_omega + 1e-9)) + 1) * d_omega
    if grid[-1] < omega[-1] - 1e-9:
        grid = np.append(grid, omega[-1])
    return grid, PchipInterpolator(w, table, axis=0)(grid)


def irf_diagnostics(omega: np.ndarray, damping: np.ndarray, t: np.ndarray, kernel: np.ndarray,
                    labels: list[str], *, decay: float = 0.05, continued: bool = False) -> list[str]:
    """Warnings about the accuracy of K(t) computed from B(omega) (module docstring).

    Args:
        omega, damping: the table the kernel was computed from (Nw,), (Nw, n, n).
        t, kernel: the kernel's times and values (m,), (m, n, n).
        labels: a name for each degree of freedom, for the messages.
        decay: fraction of the peak that B at the last frequency, or K over the last tenth of
            the kernel, may keep without a warning.
        continued: B is continued above the table (:func:`damping_tail`), so it is not cut at the last
            frequency: no truncation warning.
    """
    out = []
    steps = np.diff(np.concatenate([[0.0], omega]))
    limit = np.pi / steps.max()
    if t[-1] > limit * (1 + 1e-9):
        out.append(
            f"radiation: the impulse response is {t[-1]:g} s long but the database's frequency step "
            f"{steps.max():g} rad/s resolves it only up to pi/d_omega = {limit:.3g} s: beyond that K(t) is "
            "unreliable; shorten hydro.irf_duration or compute the database on a finer frequency grid")
    diag_b = np.abs(np.einsum("wii->wi", damping))
    diag_k = np.abs(np.einsum("tii->ti", kernel))
    tail = t >= 0.9 * t[-1]
    for i, label in enumerate(labels):
        peak = diag_b[:, i].max()
        if not continued and peak > 0 and diag_b[-1, i] > decay * peak:
            out.append(
                f"radiation: {label}: B at the highest frequency {omega[-1]:g} rad/s is still "
                f"{diag_b[-1, i] / peak:.0%} of its peak; cutting it there ripples K(t) with period "
                f"{2 * np.pi / omega[-1]:.3g} s (extend the database's frequency range)")
        kpeak = diag_k[:, i].max()
        if kpeak > 0 and tail.any() and diag_k[tail, i].max() > decay * kpeak:
            out.append(
                f"radiation: {label}: K(t) is still {diag_k[tail, i].max() / kpeak:.0%} of its peak at the end of the "
                f"{t[-1]:g} s impulse response: memory beyond it is lost (lengthen hydro.irf_duration)")
    return out


class RadiationMemory:
    """Trapezoidal convolution of the impulse response with the velocity history.

    Args:
        kernel: K sampled at t_j = j dt, j = 0..m-1, shape (m, n, n).
        dt: sampling step (s).

    Use: at each communication point call :meth:`force` with the current velocity (as often as
    needed: the result depends only on the committed history and that velocity), then :meth:`step`
    (or :meth:`advance`) with that velocity and the step to the next communication point.

    Layout: the velocities at the last m grid points (lags m-1 .. 0, the current point and the points
    interpolated since the last commit included) are one contiguous (m, n) window of a double-length
    ring buffer (grid point s at rows s mod m and s mod m + m), and all the trapezoidal weights one
    (n, m n) matrix, so the force is a single matrix-vector product (about 11 us for n = 6,
    m = 1500 here) and committing a point writes no more than its own rows.

    This is the Python reference of the memory the hydro model steps in the compiled runtime
    (native/src/hydro/radiation_convolution.c, the same layout, the sums blocked over points):
    :meth:`hydro_fmu.model.HydroModel.reference_memory` makes one.
    """

    def __init__(self, kernel: np.ndarray, dt: float) -> None:
        m, n, _ = kernel.shape
        if m < 2:
            raise ValueError("the impulse response needs at least two samples")
        self.dt = float(dt)
        self.n = n
        self.m = m
        weights = np.full(m, dt)
        weights[0] = weights[-1] = dt / 2
        w = kernel * weights[:, None, None]
        self._k0 = w[0]  # weight of the current velocity
        self._weights = w  # (m, n, n): weight of the velocity j grid steps ago
        # Weights of lags m-1 .. 0 (oldest first) as one (n, m n) matrix for a single mat-vec.
        self._all = np.ascontiguousarray(np.transpose(w[::-1], (1, 0, 2)).reshape(n, m * n))
        self._ring = np.zeros((2 * m, n))  # grid point s at rows s % m and s % m + m
        self._last = np.zeros(n)  # velocity at the last committed grid point
        self.gap = 1  # grid steps from the last committed point to the current time
        self.steps = 0  # grid points committed so far

    @property
    def current(self) -> int:
        """Grid index of the current time."""
        return self.steps - 1 + self.gap

    def _write_pending(self, v_now: np.ndarray) -> None:
        """Velocities of the grid points after the last committed one, up to now: linear from the last
        committed velocity to ``v_now`` (only the last m of them are ever read)."""
        c, q, m = self.current, self.gap, self.m
        if q == 1:
            row = c % m
            self._ring[row] = v_now
            self._ring[row + m] = v_now
            return
        lags = np.arange(min(q, m) - 1, -1, -1)  # oldest first
        values = v_now + (lags / q)[:, None] * (self._last - v_now)
        rows = (c - lags) % m
        self._ring[rows] = values
        self._ring[rows + m] = values

    def window(self) -> np.ndarray:
        """Velocities at lags m-1 .. 0 (oldest first), (m, n), as last written."""
        start = (self.current + 1) % self.m
        return self._ring[start : start + self.m]

    def force(self, v_now: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """mu at the current time given the current velocity (N; the radiation force is -mu); written into
        ``out`` (n,) if given."""
        self._write_pending(v_now)
        m = self.m
        start = (self.steps + self.gap) % m  # (current + 1) % m, as window()
        return np.dot(self._all, self._ring[start : start + m].reshape(-1), out=out)

    def instantaneous_damping(self) -> np.ndarray:
        """d mu / d v_now (n, n), N s/m: the weight of the current velocity in :meth:`force`, the current
        point's own trapezoidal weight K(0) dt / 2 plus its share of the points interpolated since the
        last commit (for a step of q grid steps, sum over lags l < q of (1 - l/q) K(l dt) dt)."""
        q = self.gap
        d = self._k0.copy()
        for lag in range(1, min(q, self.m)):
            d += (1.0 - lag / q) * self._weights[lag]
        return d

    def step(self, v_now: np.ndarray, h: float) -> None:
        """Commit the current velocity and move ``h`` seconds on: a whole number of grid steps."""
        q = int(round(h / self.dt))
        if q < 1 or abs(h - q * self.dt) > 1e-9 * self.dt:
            raise ValueError(
                f"communication step {h:g} s is not a whole multiple of the radiation convolution step "
                f"{self.dt:g} s; set the hydro FMU parameter radiation.dt to the master's (smallest) macro step, "
                "or use the state-space radiation model, which takes any step")
        self.advance(v_now, q)

    def advance(self, v_now: np.ndarray, q: int = 1) -> None:
        """Commit the velocity of the current time (and the interpolated points since the last
        commit), then move ``q`` grid steps forward."""
        if q < 1:
            raise ValueError("a step must span at least one grid step")
        self._write_pending(v_now)
        self.steps += self.gap
        self._last[:] = v_now
        self.gap = q


def ogilvie_added_mass_inf(omega: np.ndarray, added_mass: np.ndarray, damping: np.ndarray, duration: float,
                           dt: float | None = None, *, d_omega: float = 0.0,
                           tail_exponent: float = 0.0) -> tuple[np.ndarray, float]:
    """A_inf consistent with a database's A(omega) and the impulse response of its B(omega).

    Ogilvie's relation (1964) holds at every frequency for a causal radiation force,

        A_inf = A(omega) + (1/omega) int_0^T K(t) sin(omega t) dt,

    with K the impulse response of B (:func:`impulse_response` of :func:`kernel_table` with the
    same ``d_omega`` and ``tail_exponent`` as the time-domain model, length ``duration``, trapezoidal rule at step
    ``dt``, default pi / (20 omega_max)). A time-domain model built from K and A_inf reproduces
    the database's A(omega) only if A_inf satisfies it; a BEM's separately computed
    infinite-frequency limit, and the truncation of B at the last frequency, can break that by a
    few percent. Returns the median of the right-hand side over the frequency range (each
    frequency weighted by its share of the range, so a locally refined grid does not pull the
    median towards the refined band; robust to the few frequencies where the BEM is least
    accurate), symmetrised, and its spread (largest weighted standard deviation over the range,
    relative to the largest |A_inf|).
    """
    omega = np.asarray(omega, dtype=float)
    estimates = _ogilvie_estimates(omega, added_mass, damping, duration, dt, d_omega=d_omega,
                                   tail_exponent=tail_exponent)
    share = _frequency_shares(omega)
    a_inf = _weighted_median(estimates, share)
    a_inf = 0.5 * (a_inf + a_inf.T)
    return a_inf, _spread(estimates - a_inf, share, a_inf)


def _ogilvie_estimates(omega: np.ndarray, added_mass: np.ndarray, damping: np.ndarray, duration: float,
                       dt: float | None, *, d_omega: float = 0.0, tail_exponent: float = 0.0,
                       tail_correction: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """A(omega) + (1/omega) int_0^T K(t) sin(omega t) dt at the database frequencies (Nw, ...): the A_inf each
    frequency implies for the kernel of the (resampled, continued) table (:func:`ogilvie_added_mass_inf`)."""
    dt = dt or np.pi / (20 * omega[-1])
    t = np.arange(int(np.ceil(duration / dt)) + 1) * dt
    k = impulse_response(*kernel_table(omega, damping, d_omega=d_omega, tail_exponent=tail_exponent,
                                       tail_correction=tail_correction), t)
    return added_mass + _sine_transform(omega, t, k) / omega.reshape((-1,) + (1,) * (k.ndim - 1))


def _sine_transform(omega: np.ndarray, t: np.ndarray, k: np.ndarray) -> np.ndarray:
    """int_0^T K(t) sin(omega t) dt by the trapezoidal rule on the uniform grid ``t`` (Nw, ...)."""
    dt = t[1] - t[0]
    weights = np.full(len(t), dt)
    weights[0] = weights[-1] = dt / 2
    return np.tensordot(np.sin(np.outer(omega, t)) * weights, k, axes=(1, 0))


def _spread(deviation: np.ndarray, share: np.ndarray, a_inf: np.ndarray) -> float:
    """Largest weighted standard deviation over frequency of ``deviation`` (Nw, n, n), relative to max |A_inf|."""
    std = np.sqrt(np.einsum("w,wij->ij", share, deviation ** 2) / share.sum())
    return float(np.max(std) / max(float(np.max(np.abs(a_inf))), 1e-300))


@dataclass(frozen=True)
class KramersKronigTail:
    """A_inf and the radiation damping above a database's last frequency, fitted to its A(omega).

    Attributes:
        added_mass_inf: (n, n), symmetric.
        nodes: (k + 1,) frequencies (rad/s) above Omega: the peaks of the k hat functions and the end of the last.
        values: (k + 1, n, n) the correction's B at the nodes (N s/m ...; 0 at the last): the continuation is the
            power law plus the piecewise-linear interpolant of (Omega, 0), (nodes, values), 0 beyond.
        spread: the residual A(omega) misfit, as :func:`ogilvie_added_mass_inf`'s spread.
        spread_without: the same with the power law alone and Ogilvie's A_inf (for the record).
        negative: the most negative (scaled) eigenvalue of the least-squares continuation at the nodes,
            relative to the largest, that was set to 0 (0: none).
    """

    added_mass_inf: np.ndarray
    nodes: np.ndarray
    values: np.ndarray
    spread: float
    spread_without: float
    negative: float

    @property
    def correction(self) -> tuple[np.ndarray, np.ndarray]:
        """(nodes, values) as :func:`damping_tail` takes them."""
        return self.nodes, self.values


def kramers_kronig_tail(omega: np.ndarray, added_mass: np.ndarray, damping: np.ndarray, duration: float,
                        dt: float | None = None, *, d_omega: float = 0.0, tail_exponent: float = 0.0,
                        ratio: float = TAIL_RATIO, count: int = TAIL_COUNT,
                        smoothing: float = TAIL_SMOOTHING) -> KramersKronigTail:
    """Fit A_inf and the damping above the database's last frequency Omega to the database's A(omega).

    A(omega) and B(omega) of a causal radiation force are one function, K^(omega) = B + i omega (A - A_inf)
    (Kramers-Kronig): A(omega) - A_inf = (2/pi) int_0^inf B(nu) / (nu^2 - omega^2) dnu. A database stops at
    Omega, so the B above it, which A(omega) inside the band still feels (strongly near Omega when B has
    resonances just above it, such as sloshing between bodies), is unknown; a kernel computed from the
    table and a power-law continuation (:func:`damping_tail`) then rebuilds B but misses A by an amount that
    rises with omega and that no constant A_inf (:func:`ogilvie_added_mass_inf`) can absorb. Here the
    database's own A(omega) determines the missing B: the continuation is the power law plus ``count``
    hat functions peaking at Omega ``ratio``^j, j = 1..count (each zero at its neighbours; the first
    rises from 0 at Omega, so B stays continuous), and, for each matrix entry, A_inf and the hats'
    heights minimise

        sum_w s_w |A(w) + (1/w) int_0^T K_0 sin(w t) dt - A_inf - sum_j c_j G_j(w)|^2 + smoothing sum_j |c_j g_j|^2,

    s_w the share of the range each frequency stands for, K_0 the kernel of the table with the power law
    (the same transform as :func:`ogilvie_added_mass_inf`: length ``duration``, trapezoidal rule at ``dt``),
    G_j(w) = -(1/w) int_0^T K_j sin(w t) dt the added mass hat j adds to the time-domain model, and g_j the
    weighted norm of G_j (a ridge term: the functions 1 / (nu^2 - w^2) of the far hats are nearly
    collinear inside the band, so the fit is ill posed without it; ``smoothing`` is relative to their
    size). Linear least squares, entry by entry, then symmetrised. The continued B (power law plus hats) at
    each node is then made positive semi-definite (negative eigenvalues of the matrix scaled by
    sqrt(max |B_ii|) set to 0; ``negative`` reports the largest removed), so the radiation force stays
    passive, and A_inf is refitted as the weighted mean of what the tail leaves: the result therefore
    depends on which degrees of freedom are passed together (pass the scene's). No iteration; cost a few
    impulse responses of a scalar table.

    Error: B inside the band is the table's (this only adds above Omega); A inside the band matches the
    database to the residual ``spread``, which is what a smooth function of omega (the hats' shares are
    smooth below Omega) cannot follow: BEM noise, asymmetry, and A's response to features of B between the
    database's frequencies that the interpolated table misses. On a closed-form pair with a resonance above
    the table, A's error falls 40-fold against Ogilvie's (tests/test_radiation.py). The continuation is a
    model fitted to A inside the band, not the true B above Omega, and A_inf alone is not identified (the far
    tail's share, (2/pi) int B / nu^2, is a constant too): only the pair reproduces A(omega).
    """
    omega = np.asarray(omega, dtype=float)
    top = omega[-1]
    nodes = top * ratio ** np.arange(1, count + 2)  # hats peak at nodes[:-1]; the last is the last hat's end
    share = _frequency_shares(omega)
    base = _ogilvie_estimates(omega, added_mass, damping, duration, dt, d_omega=d_omega, tail_exponent=tail_exponent)
    a_ogilvie = _weighted_median(base, share)
    spread_without = _spread(base - 0.5 * (a_ogilvie + a_ogilvie.T), share, a_ogilvie)
    dt = dt or np.pi / (20 * nodes[-1])
    t = np.arange(int(np.ceil(duration / dt)) + 1) * dt
    columns = []
    for j in range(count):
        heights = np.zeros(count + 1)
        heights[j] = 1.0
        k = impulse_response(*damping_tail(np.array([top]), np.zeros(1), 0.0,
                                           correction=(nodes, heights)), t)
        columns.append(-_sine_transform(omega, t, k) / omega)
    g = np.column_stack(columns)  # (Nw, count)
    root = np.sqrt(share)
    design = np.column_stack([np.ones(len(omega)), g]) * root[:, None]
    norms = np.linalg.norm(design[:, 1:], axis=0)
    ridge = np.sqrt(smoothing) * np.column_stack([np.zeros(count), np.diag(norms)])
    system = np.vstack([design, ridge])
    flat = base.reshape(len(omega), -1)
    rhs = np.vstack([flat * root[:, None], np.zeros((count, flat.shape[1]))])
    solution, *_ = np.linalg.lstsq(system, rhs, rcond=None)
    shape = base.shape[1:]
    values = solution[1:].reshape((count,) + shape)
    values = 0.5 * (values + np.swapaxes(values, 1, 2))
    law = damping[-1][None] * (((top / nodes[:-1]) ** tail_exponent) if tail_exponent > 0
                               else np.zeros(count))[:, None, None]
    peak = np.abs(np.einsum("wii->wi", damping)).max(axis=0)  # per-DOF scale of B inside the band
    scale = np.sqrt(np.maximum(peak, 1e-9 * peak.max() + 1e-300))
    total, negative = _positive_part(values + law, scale)
    values = total - law
    fitted = base - np.einsum("wj,jab->wab", g, values)
    a_inf = np.tensordot(share, fitted, axes=(0, 0)) / share.sum()  # the constant that fits what the tail left
    a_inf = 0.5 * (a_inf + a_inf.T)
    ends = np.concatenate([values, np.zeros((1,) + shape)])  # the last hat falls to 0 at the last node
    return KramersKronigTail(a_inf, nodes, ends, _spread(fitted - a_inf, share, a_inf), spread_without, negative)


def _positive_part(matrices: np.ndarray, scale: np.ndarray) -> tuple[np.ndarray, float]:
    """Each symmetric matrix of ``matrices`` (k, n, n) with its negative eigenvalues set to 0, in the metric of
    the per-DOF ``scale`` (n,) (X -> S P(S^-1 X S^-1) S, S = diag(scale)), and the most negative scaled
    eigenvalue removed, relative to the largest one."""
    inv = 1.0 / scale
    scaled = matrices * np.outer(inv, inv)[None]
    eig, vec = np.linalg.eigh(scaled)
    negative = float(max(0.0, -eig.min()) / max(float(np.abs(eig).max()), 1e-300))
    kept = np.einsum("kij,kj,klj->kil", vec, np.maximum(eig, 0.0), vec)
    return kept * np.outer(scale, scale)[None], negative


def _frequency_shares(omega: np.ndarray) -> np.ndarray:
    """Width of the range each frequency stands for (midpoint rule; the first from 0)."""
    edges = np.concatenate([[0.0], 0.5 * (omega[1:] + omega[:-1]), [omega[-1]]])
    return np.diff(edges)


def _weighted_median(values: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Median over axis 0 of ``values`` (Nw, ...) with ``weights`` (Nw,): the smallest value at which the
    cumulative weight reaches half the total."""
    order = np.argsort(values, axis=0)
    ranked = np.take_along_axis(values, order, axis=0)
    cumulative = np.cumsum(weights[order], axis=0)
    k = np.argmax(cumulative >= 0.5 * cumulative[-1], axis=0)
    return np.take_along_axis(ranked, k[None], axis=0)[0]
