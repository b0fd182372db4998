"""The runtime's radiation memory (native/src/hydro/radiation_convolution.c, state_space.c) against exact answers.

Convolution: the blocked sums against the trapezoidal rule written out as a plain sum over a record of every grid
velocity (those between communication points interpolated linearly), at every point, across block boundaries,
with steps of several grid steps, step changes inside a block, steps longer than the kernel, points evaluated
several times with other velocities (iterative masters), and after a state saved inside a block and loaded onto a
model that went on. State space: a realised kernel (a decaying exponential, a damped cosine) against the exact
solution of its equation for a velocity linear between the points (the first-order hold the runtime claims to
integrate exactly), at uneven steps.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

from .hydro_runtime_cases import direct_convolution, runtime

DT, M, N = 0.1, 40, 3
DOFS = [(0, 0), (0, 2), (0, 4)]


class Run:
    """A runtime convolution memory driven through communication points, with the record of grid velocities the
    direct sum needs."""

    def __init__(self, kernel: np.ndarray, seed: int = 5) -> None:
        self.kernel = kernel
        self.model = runtime(dofs=DOFS, dt=DT, radiation=1, radiation_kernel=kernel, radiation_block_points=8)
        self.history: dict[int, np.ndarray] = {}
        self.now, self.last, self.v_last = 0, None, np.zeros(N)
        self.rng = np.random.default_rng(seed)

    def expected(self, v: np.ndarray) -> np.ndarray:
        history = dict(self.history)
        if self.last is not None:
            for j in range(self.last + 1, self.now):
                history[j] = self.v_last + (j - self.last) / (self.now - self.last) * (v - self.v_last)
        history[self.now] = v
        return direct_convolution(self.kernel, DT, history, self.now)

    def mu(self, v: np.ndarray) -> np.ndarray:
        self.model.evaluate(self.now * DT, np.zeros(N), v)
        return -self.model.block[2]

    def point(self, q: int, trials: int = 1) -> None:
        """Evaluate the current point ``trials`` times with other velocities, then with its own, check each against
        the direct sum, commit it and step q grid steps."""
        scale = np.abs(self.kernel).sum() * DT
        for _ in range(trials):
            v = self.rng.normal(size=N)
            np.testing.assert_allclose(self.mu(v), self.expected(v), rtol=0, atol=1e-12 * scale)
        v = 0.3 * np.sin(0.37 * self.now * DT * np.arange(1, N + 1) + 0.2) + 0.05 * self.rng.normal(size=N)
        np.testing.assert_allclose(self.mu(v), self.expected(v), rtol=0, atol=1e-12 * scale)
        if self.last is not None:
            for j in range(self.last + 1, self.now):
                self.history[j] = self.v_last + (j - self.last) / (self.now - self.last) * (v - self.v_last)
        self.history[self.now] = v
        self.model.advance(self.now * DT, q * DT, v)
        self.last, self.v_last, self.now = self.now, v, self.now + q


def _kernel(m: int = M) -> np.ndarray:
    return np.random.default_rng(3).normal(size=(m, N, N))


@pytest.mark.parametrize("steps", [(1,), (3,), (1, 4, 2, 7, 1, 13), (2, 2, 2, 5, 5, 1, 1, 1), (50,)])
def test_convolution_is_the_direct_trapezoidal_sum(steps: tuple[int, ...]) -> None:
    """Communication every q grid steps (q cycling through ``steps``: constant, several grid steps, changes inside
    a block, a step longer than the kernel), every point evaluated with two other velocities before its own."""
    run = Run(_kernel())
    for k in range(60):
        run.point(steps[k % len(steps)], trials=2)


def test_kernel_shorter_than_a_block() -> None:
    """A kernel of 5 samples (fewer lags than block points): blocks shrink to what the kernel holds."""
    run = Run(_kernel(5))
    for k in range(30):
        run.point((1, 1, 2, 1, 3, 4, 5)[k % 7], trials=1)


@pytest.mark.parametrize("how", ["bytes", "clone", "deepcopy"])
def test_state_saved_inside_a_block_continues_bit_for_bit(how: str) -> None:
    """A state saved in the middle of a block and loaded after the model went on (with other velocities) into the
    next block, as FMU rollback and checkpoints do: the sums after the load equal the direct sum of the restored
    history, and those of a copy that never left that history, bit for bit."""
    run = Run(_kernel())
    for _ in range(8 + 3):  # inside the second block of 8 points
        run.point(1)
    saved_run = copy.deepcopy({k: v for k, v in vars(run).items() if k != "model"})
    twin = run.model.clone()  # goes on from the saved point without any restore
    saved = run.model.state() if how == "bytes" else run.model.clone() if how == "clone" else copy.deepcopy(run.model)
    for q in (1, 1, 2, 1, 1, 1, 1, 3, 1):  # on into the next block, with other velocities
        run.point(q, trials=1)
    if how == "bytes":
        run.model.load_state(saved)
    else:
        run.model.copy_state_from(saved)
    vars(run).update(copy.deepcopy(saved_run))
    run.rng = np.random.default_rng(11)
    for q in (1, 2, 1, 1, 4, 1, 1, 1, 1, 1, 1, 1):
        v = run.rng.normal(size=N)
        now = run.now * DT
        run.model.evaluate(now, np.zeros(N), v)
        restored = run.model.block[2].copy()
        twin.evaluate(now, np.zeros(N), v)
        np.testing.assert_array_equal(restored, twin.block[2])
        run.rng = np.random.default_rng(int(1000 * abs(v[0])))
        run.point(q, trials=1)
        twin.advance(now, q * DT, run.history[run.last])


def _foh_exact(lam: complex, h: float, z: complex, v0: float, v1: float) -> complex:
    """w(t + h) of w' = lam w + v for v linear from v0 to v1 over the step (exact integral)."""
    e = np.exp(lam * h)
    dv = v1 - v0
    return e * z + v1 * (e - 1) / lam - dv / h * (e * (lam * h - 1) + 1) / lam**2


@pytest.mark.parametrize("system", ["exponential", "damped cosine"])
def test_state_space_is_exact_for_a_velocity_linear_between_points(system: str) -> None:
    """K(t) = 2 e^(-0.3 t) (one state) or e^(-0.2 t) cos(1.3 t) (two states, a = [[-0.2, 1.3], [-1.3, -0.2]]): mu at
    each point equals the exact convolution with the piecewise-linear velocity through the point samples, at
    steps of 0.1, 0.37, 0.05 and 1.1 s in turn (any step: the discretisation is per step size)."""
    if system == "exponential":
        a, b, c, lam, gain = np.array([[-0.3]]), np.array([[2.0]]), np.array([[1.0]]), -0.3 + 0j, 2.0
    else:
        a, b, c = np.array([[-0.2, 1.3], [-1.3, -0.2]]), np.array([[1.0], [0.0]]), np.array([[1.0, 0.0]])
        lam, gain = -0.2 + 1.3j, 1.0
    model = runtime(dofs=[(0, 2)], dt=0.1, radiation=2, radiation_a=a, radiation_b=b, radiation_c=c)
    steps = [0.1, 0.37, 0.05, 1.1] * 12
    t, w, v_last = 0.0, 0j, 0.0
    for k, h in enumerate(steps):
        v = np.sin(0.8 * t) + 0.3 * np.cos(2.1 * t + 0.4)
        if k > 0:  # exact state at t from the previous point
            w = _foh_exact(lam, steps[k - 1], w, v_last, v)
        model.evaluate(t, np.zeros(1), np.array([v]))
        expected = gain * w.real
        assert abs(-model.block[2][0] - expected) <= 1e-12 * max(abs(expected), 1.0)
        model.advance(t, h, np.array([v]))
        t, v_last = t + h, v
