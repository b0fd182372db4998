"""The runtime's waves and excitation (native/src/hydro/excitation.c, excitation_convolution.c, record.c, ramp.c,
phasor_clock.c) against exact answers: one component against the analytic cosine through the ramp and over many
points of the phasor clock (recurrences and refreshes), its exact rate; the excitation convolution against the
trapezoidal sum written out (synthetic sea: exact cosines; record: the interpolated record); the record's periodic
linear interpolation."""

from __future__ import annotations

import math

import numpy as np

from .hydro_runtime_cases import runtime

RAMP = 5.0


def ramp(t: float) -> float:
    return 1.0 if t >= RAMP else 0.5 * (1 - math.cos(math.pi * max(t, 0.0) / RAMP))


def ramp_rate(t: float) -> float:
    return 0.0 if t >= RAMP or t <= 0 else 0.5 * math.pi / RAMP * math.sin(math.pi * t / RAMP)


def test_one_component_is_the_analytic_cosine_with_its_exact_rate() -> None:
    """F = r(t) |c| cos(w t + arg c), eta = r(t) a cos(w t + phi) and dF/dt exact, at 0.1 s over 300 points (the
    phasor clock's products and refreshes) and at uneven times; F0 = F and F0_rate = dF/dt when nothing depends on
    the motion."""
    w, amp, coef = 0.83, 0.7 * np.exp(0.4j), 1.3e5 * np.exp(-1.1j)
    model = runtime(dofs=[(0, 2)], ramp=RAMP, excitation=1, omega=[w], amplitude=[amp],
                    excitation_coefficients=np.array([[[coef.real, coef.imag]]]))
    times = list(np.arange(300) * 0.1) + [31.7, 31.7, 2.25, 40.0001, 1e4 / 3]
    for t in times:
        eta = model.evaluate(t, np.zeros(1), np.zeros(1))
        force = ramp(t) * abs(coef) * math.cos(w * t + np.angle(coef))
        assert abs(model.block[1][0] - force) <= 1e-12 * abs(coef)
        assert abs(model.block[0][0] - force) <= 1e-12 * abs(coef)
        assert abs(eta - ramp(t) * abs(amp) * math.cos(w * t + np.angle(amp))) <= 1e-12 * abs(amp)
        f0, rate, _, _ = model.linearise(t, np.zeros(1), np.zeros(1))
        exact_rate = abs(coef) * (ramp_rate(t) * math.cos(w * t + np.angle(coef))
                                  - ramp(t) * w * math.sin(w * t + np.angle(coef)))
        assert abs(f0[0] - force) <= 1e-12 * abs(coef)
        assert abs(rate[0] - exact_rate) <= 1e-12 * abs(coef) * w


def _kernel_data(n: int = 2, half: int = 30, dt: float = 0.1) -> tuple[np.ndarray, np.ndarray]:
    tau = np.arange(-half, half + 1) * dt
    weights = np.full(len(tau), dt)
    weights[0] = weights[-1] = dt / 2
    kernel = np.stack([np.exp(-(tau / 1.5) ** 2) * (1 + 0.3 * k * tau) for k in range(n)], axis=1) * 1e4
    return tau, kernel * weights[:, None]


def test_excitation_convolution_of_components_is_the_trapezoidal_sum() -> None:
    """F(t) = r(t) sum_j W_j eta(t - tau_j) with eta the exact component sum (three components): the runtime's
    per-component transfer equals the sum over lags written out, and its rate the central difference of step
    1e-4 s of that sum."""
    omega = np.array([0.5, 0.9, 1.7])
    amp = np.array([0.5 * np.exp(0.3j), 0.2 * np.exp(-1.0j), 0.05 * np.exp(2.0j)])
    tau, weighted = _kernel_data()
    model = runtime(dofs=[(0, 0), (0, 2)], ramp=RAMP, excitation=2, omega=omega, amplitude=amp,
                    excitation_tau=tau, excitation_kernel=weighted)

    def direct(t: float) -> np.ndarray:
        eta = np.real(np.exp(1j * np.outer(t - tau, omega)) @ amp)
        return ramp(t) * (eta @ weighted)

    scale = np.abs(weighted).sum(axis=0) * np.abs(amp).sum()
    for t in (0.0, 1.3, 4.99, 7.0, 123.4):
        model.evaluate(t, np.zeros(2), np.zeros(2))
        np.testing.assert_allclose(model.block[1], direct(t), rtol=0, atol=1e-13 * scale.max())
        _, rate, _, _ = model.linearise(t, np.zeros(2), np.zeros(2))
        np.testing.assert_allclose(rate, (direct(t + 1e-4) - direct(t - 1e-4)) / 2e-4, rtol=0,
                                   atol=1e-13 * scale.max() / 1e-4)


def record_value(eta: np.ndarray, dt: float, t: np.ndarray | float) -> np.ndarray:
    """The record's periodic linear interpolation, written with numpy's interp on one period plus one sample."""
    period = len(eta) * dt
    grid = np.arange(len(eta) + 1) * dt
    return np.interp(np.mod(t, period), grid, np.append(eta, eta[0]))


def test_record_elevation_and_its_convolution() -> None:
    """An imported record (no components): the elevation is the record's periodic linear interpolation times the
    ramp, at times inside, before and after the record; the convolution sums the interpolated record."""
    dt_record = 0.25
    eta = np.sin(np.arange(37) * 0.9) + 0.2 * np.cos(np.arange(37) * 2.3)
    tau, weighted = _kernel_data(n=1, half=12, dt=0.1)
    model = runtime(dofs=[(0, 2)], ramp=RAMP, excitation=2, excitation_tau=tau, excitation_kernel=weighted,
                    record_dt=dt_record, record_eta=eta)
    for t in (0.0, 0.1, 3.3, 9.24999, 9.25, 17.1, 100.05, -2.6):
        elevation = model.elevation(t)
        assert abs(elevation - ramp(t) * record_value(eta, dt_record, t)) <= 1e-14
        model.evaluate(t, np.zeros(1), np.zeros(1))
        expected = ramp(t) * (record_value(eta, dt_record, t - tau) @ weighted)
        np.testing.assert_allclose(model.block[1], expected, rtol=0, atol=1e-13 * np.abs(weighted).sum())
