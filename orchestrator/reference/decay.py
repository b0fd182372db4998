"""Free-decay tests: natural modes of a scene's linear model, and damped modes fitted to decay records.

**Natural modes (the frequency-domain answer).** About equilibrium the scene's linear constrained
equations of motion, with the radiation memory of its time-domain model,

    (M + A_inf) x'' + int_0^t K(t - tau) x'(tau) dtau + D x' + K_s x = 0,   C x = 0,

have on the constraint null space P the impedance (``frequency_domain.linear_model``, here at complex
frequency w, time factor exp(i w t))

    Z(w) = P^T [-w^2 (M + A_inf) + i w (D + K^(w)) + K_s] P,   K^(w) = int_0^T K(t) exp(-i w t) dt,

with K the impulse response of the database's B (continued by ``hydro.damping_tail``, cut at
``hydro.irf_duration``, sampled at the macro step: the kernel the time-domain model convolves) and
K_s the hydrostatics, springs and the geometric stiffness of gravity, buoyancy and the static
reactions. On the real axis Z is the frequency-domain impedance with the kernel's A(w) and B(w),
which reproduce the database's to the frequency error the run reports; K^ is entire (the kernel is
finite), so Z continues analytically and a free mode is a root w = w_d + i sigma of det Z = 0 with
sigma > 0: damped period 2 pi / w_d, damping ratio sigma / |w|, with the frequency dependence of A
and B in it exactly (nothing frozen). The continuation weighs the kernel's tail by exp(sigma t), so
the root is well conditioned when sigma T << 1 (``Mode.tail_weight`` = exp(sigma T) is reported):
lightly damped modes such as the F3OF's (sigma T <= 0.2) are; a heavily damped mode would instead see
the truncation. Roots are found by the secant method on det Z (scaled), started from the undamped
modes with A(w) frozen at each mode's own frequency, and each root found is divided out (deflation)
so that close modes (two coupled flaps) are found separately. ``database_modes`` gives the same roots
from the database's tabulated A and B continued to first order off the real axis,
Z(w_d + i sigma) ~ Z(w_d) + i sigma dZ/dw(w_d) (exact to first order in the damping): the two agree
to the kernel's rebuild error.

**Measured decay (the time-domain answer).** A record of one or more channels is fitted over a window
[t0, t1] by K damped modes with common complex frequencies plus a constant per channel,

    x_j(t) = c_j + sum_k exp(-sigma_k t) (a_jk cos w_k t + b_jk sin w_k t),

by nonlinear least squares in (w_k, sigma_k) with the amplitudes eliminated (variable projection:
for given frequencies they solve a linear least-squares problem), started from the matrix pencil
method (Hua and Sarkar 1990) on the same window. Period and damping ratio are read in the same
definitions as the roots'; the fit's RMS residual relative to the record's RMS is reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from orchestrator.scene import Scene

from .frequency_domain import _impedance, kernel_coefficients, mechanical_matrices, scene_kernel


@dataclass
class DecayMode:
    """A damped mode exp(-sigma t) cos(w t + phase) (w, sigma in rad/s and 1/s)."""

    omega: float
    sigma: float

    @property
    def period(self) -> float:
        """Damped period 2 pi / w (s)."""
        return 2 * math.pi / self.omega

    @property
    def damping_ratio(self) -> float:
        """sigma / sqrt(w^2 + sigma^2)."""
        return self.sigma / math.hypot(self.omega, self.sigma)


@dataclass
class DecayFit:
    """Damped modes fitted to a decay record over ``window`` (s); ``residual``: RMS of the misfit over the
    RMS of the record about its constants (all channels)."""

    modes: list[DecayMode]
    window: tuple[float, float]
    residual: float


def matrix_pencil(x: np.ndarray, dt: float, order: int) -> np.ndarray:
    """Complex frequencies w of exp(i w t) (Im w > 0 decays) of the ``order`` strongest components of
    the uniformly sampled record ``x`` ((N,) or (N, channels)), by the matrix pencil method."""
    x = np.asarray(x, dtype=float).reshape(len(x), -1)
    pencil = len(x) // 3
    hankel = np.concatenate([np.lib.stride_tricks.sliding_window_view(x[:, j], pencil + 1)
                             for j in range(x.shape[1])], axis=0)
    _, _, vh = np.linalg.svd(hankel, full_matrices=False)
    v = vh[:order].T
    z = np.linalg.eigvals(np.linalg.pinv(v[:-1]) @ v[1:])
    return np.log(z.astype(complex)) / (1j * dt)


def _basis(t: np.ndarray, params: np.ndarray) -> np.ndarray:
    cols = [np.ones_like(t)]
    for w, s in zip(params[0::2], params[1::2], strict=True):
        e = np.exp(-s * t)
        cols += [e * np.cos(w * t), e * np.sin(w * t)]
    return np.stack(cols, axis=1)


def fit_decay(t: np.ndarray, x: np.ndarray, n_modes: int, window: tuple[float, float]) -> DecayFit:
    """Fit ``n_modes`` damped modes plus a constant per channel to ``x`` ((N,) or (N, channels)) sampled
    uniformly at ``t``, over ``window`` (module docstring). Raises ValueError if the window holds fewer
    oscillating components than asked for."""
    from scipy.optimize import least_squares

    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float).reshape(len(t), -1)
    keep = (t >= window[0] - 1e-9) & (t <= window[1] + 1e-9)
    tw, xw = t[keep] - window[0], x[keep]
    start = matrix_pencil(xw - xw.mean(axis=0), float(np.median(np.diff(tw))), 2 * n_modes)
    start = sorted((w for w in start if w.real > 1e-9), key=lambda w: w.real)
    if len(start) < n_modes:
        raise ValueError(f"fit_decay: the record over {window} s shows fewer than {n_modes} oscillating modes")
    # keep the n_modes components of largest amplitude among the pencil's oscillating ones
    p0 = np.array([v for w in start[:n_modes] for v in (w.real, w.imag)])

    def misfit(p: np.ndarray) -> np.ndarray:
        a = _basis(tw, p)
        return (a @ np.linalg.lstsq(a, xw, rcond=None)[0] - xw).ravel()

    p = least_squares(misfit, p0, xtol=1e-15, ftol=1e-15, gtol=1e-15).x
    rms = float(np.sqrt(np.mean(misfit(p) ** 2)) / np.sqrt(np.mean((xw - xw.mean(axis=0)) ** 2)))
    modes = sorted((DecayMode(float(w), float(s)) for w, s in zip(p[0::2], p[1::2], strict=True)),
                   key=lambda m: m.omega)
    return DecayFit(modes, (float(window[0]), float(window[1])), rms)


class ModalImpedance:
    """Z(w) of a scene on its constraint null space at real or complex frequencies (module docstring)."""

    def __init__(self, scene: Scene, dt: float | None = None, radiation: str = "impulse_response") -> None:
        self.scene = scene
        self.dt = dt or scene.scenario.simulation.step
        self.mech = mechanical_matrices(scene)
        n = self.mech.mass.shape[0]
        self.basis = self.mech.basis if self.mech.basis is not None else np.eye(n)
        self.kernel = scene_kernel(scene, self.dt, scene.scenario.hydro.irf_duration)
        idx = scene.hydro_index()
        self.a_inf = scene.hdb.added_mass_inf[np.ix_(idx, idx)]
        self.fit = None  # radiation = "state_space": the scene's fit (None when it fell back: the kernel)
        if radiation == "state_space":
            self.fit = scene.hydro_model(dt=self.dt).state_space

    def _coefficients(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A, B at (complex) ``w`` of the kernel, or of the state-space fit (then A = A_inf and B = K^(w): only
        -w^2 A + i w B enters Z)."""
        if self.fit is None:
            return kernel_coefficients(*self.kernel, self.a_inf, w)
        k = self.fit.transfer(w) if self.fit.order else np.zeros((len(w), *self.a_inf.shape), complex)
        return np.broadcast_to(self.a_inf, k.shape).astype(complex), k

    def _reduced(self, w: np.ndarray, **kwargs) -> np.ndarray:
        m = self.mech
        z, _, _ = _impedance(self.scene, w, m.mass, m.damping, m.stiffness, m.rows, dt=self.dt, omega_cut=np.inf,
                             heading=self.scene.scenario.waves.heading_deg, **kwargs)
        return np.einsum("ai,wab,bj->wij", self.basis, z, self.basis)

    def __call__(self, omega: complex) -> np.ndarray:
        """Reduced Z (d, d) of the time-domain model's kernel at ``omega`` (rad/s, complex allowed)."""
        w = np.array([complex(omega)])
        return self._reduced(w, radiation="impulse_response", coefficients=self._coefficients(w))[0]

    def database(self, omega: complex, h: float = 1e-4) -> np.ndarray:
        """Reduced Z with the database's A, B, continued to first order off the real axis."""
        w = np.array([omega.real - h, omega.real, omega.real + h])
        z = self._reduced(w, radiation="database")
        return z[1] + 1j * omega.imag * (z[2] - z[0]) / (2 * h)

    def frozen_modes(self, iterations: int = 50) -> np.ndarray:
        """Undamped frequencies (rad/s) with A(w) frozen at each mode's own frequency (starting values)."""
        k_s = self._reduced(np.array([0.0]), radiation="database").real[0]
        out = []
        for k in range(k_s.shape[0]):
            w = 0.5
            for _ in range(iterations):
                m_eff = (k_s - self._reduced(np.array([w]), radiation="database")[0].real) / w**2
                ev = np.sort(np.real(np.linalg.eigvals(np.linalg.solve(m_eff, k_s))))
                new = math.sqrt(max(ev[k], 1e-12))
                if abs(new - w) < 1e-12 * new:
                    break
                w = new
            out.append(w)
        return np.array(out)


@dataclass
class Mode:
    """A free mode: complex frequency ``omega = w_d + i sigma`` of exp(i omega t); ``shape`` on the scene's
    multibody coordinates (largest entry 1); ``tail_weight`` = exp(sigma T_K) (conditioning, docstring)."""

    omega: complex
    shape: np.ndarray
    tail_weight: float = 1.0

    @property
    def period(self) -> float:
        """Damped period 2 pi / w_d (s)."""
        return 2 * math.pi / self.omega.real

    @property
    def damping_ratio(self) -> float:
        """sigma / |omega|."""
        return self.omega.imag / abs(self.omega)


def _roots(z, starts: np.ndarray, basis: np.ndarray, tolerance: float, max_iterations: int) -> list[Mode]:
    found: list[complex] = []
    modes = []
    for w0 in starts:
        scale = float(np.abs(np.diag(z(complex(w0)))).max()) or 1.0

        def f(w: complex, scale: float = scale) -> complex:
            value = np.linalg.det(z(w) / scale)
            for r in found:
                value /= (w - r)
            return value

        a, b = complex(w0, 1e-3 * w0), complex(1.001 * w0, 2e-3 * w0)
        fa, fb = f(a), f(b)
        for _ in range(max_iterations):
            if fb == fa or abs(b - a) < tolerance * abs(b):
                break
            a, fa, b = b, fb, b - fb * (b - a) / (fb - fa)
            fb = f(b)
        else:
            raise RuntimeError(f"natural_modes: no convergence near {w0:.4g} rad/s")
        found.append(b)
        _, _, vh = np.linalg.svd(z(b))
        shape = basis @ vh[-1].conj()
        modes.append(Mode(complex(b), shape / shape[np.argmax(np.abs(shape))]))
    return sorted(modes, key=lambda m: m.omega.real)


def natural_modes(scene: Scene, *, dt: float | None = None, tolerance: float = 1e-13,
                  max_iterations: int = 200, radiation: str = "impulse_response") -> list[Mode]:
    """Free modes of the scene's linear model with its time-domain kernel (module docstring), by damped
    frequency. ``dt``: the kernel's sampling step (default the macro step); ``radiation = "state_space"``: with the
    scene's state-space fit (and its blocks left to the convolution) in place of the kernel."""
    z = ModalImpedance(scene, dt, radiation)
    modes = _roots(z, z.frozen_modes(), z.basis, tolerance, max_iterations)
    for m in modes:
        m.tail_weight = math.exp(max(m.omega.imag, 0.0) * z.kernel[0][-1])
    return modes


def database_modes(scene: Scene, *, tolerance: float = 1e-13, max_iterations: int = 200) -> list[Mode]:
    """The same roots from the database's A(w), B(w) continued to first order off the real axis."""
    z = ModalImpedance(scene)
    return _roots(z.database, z.frozen_modes(), z.basis, tolerance, max_iterations)


def linear_decay(scene: Scene, t: np.ndarray, *, radiation: str = "database", d_omega: float = 1e-3,
                 omega_max: float = 60.0) -> tuple[list[tuple[str, int]], np.ndarray]:
    """Exact free decay of the scene's linear model from the scenario's initial displacements, at rest
    (``frequency_domain.free_decay``: inverse transform, no time stepping; resolves modes whose decay
    rate sigma is well above ``d_omega``). Returns the model's coordinates (body, DOF index) and the
    displacements (len(t), n) on them; constrained scenes start from the initial displacement projected
    on the null space of the linearised constraints (exact to first order in it)."""
    from .frequency_domain import free_decay, linear_model

    model = linear_model(scene, np.array([1.0]))
    coordinates = list(model.coordinates)
    initial = {b.name: b.initial_displacement for b in scene.scenario.bodies}
    x0 = np.array([initial[b][d] for b, d in coordinates])
    basis = model.basis if model.basis is not None else np.eye(len(coordinates))
    y = free_decay(scene, t, basis.T @ x0, radiation=radiation, d_omega=d_omega, omega_max=omega_max)
    return coordinates, y @ basis.T


def fit_forced(t: np.ndarray, x: np.ndarray, omega: float, n_modes: int, window: tuple[float, float]) -> tuple[
        np.ndarray, DecayFit]:
    """Steady harmonic at ``omega`` (rad/s) of a record that still carries free-mode transients: ``x``
    ((N,) or (N, channels)) over ``window`` is fitted by ``X_j exp(i omega t)`` plus ``n_modes`` damped
    modes common to all channels and a constant (the same variable projection as :func:`fit_decay`,
    the modes started from the matrix pencil of the record minus its plain harmonic fit). Returns the
    complex amplitudes X_j (exp(+i omega t) convention, phase at t = 0) and the fitted modes."""
    from scipy.optimize import least_squares

    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float).reshape(len(t), -1)
    keep = (t >= window[0] - 1e-9) & (t <= window[1] + 1e-9)
    tw, xw = t[keep], x[keep]
    forced = np.stack([np.cos(omega * tw), -np.sin(omega * tw)], axis=1)

    def basis(p: np.ndarray) -> np.ndarray:
        return np.concatenate([forced, _basis(tw - tw[0], p)], axis=1)

    plain = forced @ np.linalg.lstsq(forced, xw - xw.mean(axis=0), rcond=None)[0]
    start = matrix_pencil(xw - xw.mean(axis=0) - plain, float(np.median(np.diff(tw))), 2 * n_modes)
    start = sorted((w for w in start if w.real > 1e-9), key=lambda w: w.real)[:n_modes]
    p0 = np.array([v for w in start for v in (w.real, max(w.imag, 0.0))])

    def misfit(p: np.ndarray) -> np.ndarray:
        a = basis(p)
        return (a @ np.linalg.lstsq(a, xw, rcond=None)[0] - xw).ravel()

    p = least_squares(misfit, p0, xtol=1e-15, ftol=1e-15, gtol=1e-15).x if len(p0) else p0
    coef = np.linalg.lstsq(basis(p), xw, rcond=None)[0]
    amplitude = coef[0] + 1j * coef[1]
    rms = float(np.sqrt(np.mean(misfit(p) ** 2)) / np.sqrt(np.mean((xw - xw.mean(axis=0)) ** 2)))
    modes = [DecayMode(float(w), float(s)) for w, s in zip(p[0::2], p[1::2], strict=True)]
    return amplitude, DecayFit(sorted(modes, key=lambda m: m.omega), (float(window[0]), float(window[1])), rms)
