"""The radiation convolution blocked over points (hydro_fmu.kernels.blocked_memory, the compiled pass's sum)
against the plain trapezoidal sum written out over the grid velocities.

Expected values: :func:`tests.test_hydro_fast_path.direct_convolution`, the sum sum_j w_j K(j dt) v(now - j) over
a record of every grid velocity (those between communication points interpolated linearly), evaluated
independently of the ring buffer and of the blocks. The blocked sum must equal it to round-off at the first
point, across block boundaries, with steps of several grid steps and step-size changes inside a block, when a
point is evaluated several times with different velocities (iterative masters, hosts that set inputs again
before a step), and after a state restored in the middle of a block (deep copy and the data-only codec), even
onto a memory whose own block belongs to another history.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

from fmu_base import state_codec
from hydro_fmu import kernels
from hydro_fmu.radiation import RadiationMemory

from .test_hydro_fast_path import direct_convolution

DT, M, N = 0.1, 40, 3


def blocked_force(memory: RadiationMemory, v: np.ndarray) -> np.ndarray:
    """mu at the memory's current point for velocity ``v`` through the compiled pass's two kernels (pending
    velocities written, then the blocked sum), as :func:`hydro_fmu.kernels.point_outputs` runs them."""
    out = np.zeros(memory.n)
    kernels.write_pending(memory._ring, memory._last, v, memory.current, memory.gap)
    kernels.blocked_memory(memory._all, memory._ring, memory.steps, memory.gap, memory._history, memory._block, out)
    return out


class Run:
    """A memory driven through communication points, with the record of grid velocities the direct sum needs."""

    def __init__(self, kernel: np.ndarray, seed: int = 5) -> None:
        self.kernel = kernel
        self.memory = RadiationMemory(kernel, DT)
        self.history: dict[int, np.ndarray] = {}
        self.now, self.last, self.v_last = 0, None, np.zeros(N)
        self.rng = np.random.default_rng(seed)
        self.block_starts: set[int] = set()

    def expected(self, v: np.ndarray) -> np.ndarray:
        history = dict(self.history)
        if self.last is not None:
            for j in range(self.last + 1, self.now):
                history[j] = self.v_last + (j - self.last) / (self.now - self.last) * (v - self.v_last)
        history[self.now] = v
        return direct_convolution(self.kernel, DT, history, self.now)

    def point(self, q: int, trials: int = 1) -> None:
        """Evaluate the current point ``trials`` times with other velocities, then with its own, check each against
        the direct sum, commit it and step q grid steps."""
        scale = np.abs(self.kernel).sum() * DT
        for _ in range(trials):
            v = self.rng.normal(size=N)
            np.testing.assert_allclose(blocked_force(self.memory, v), self.expected(v), rtol=0, atol=1e-12 * scale)
        v = 0.3 * np.sin(0.37 * self.now * DT * np.arange(1, N + 1) + 0.2) + 0.05 * self.rng.normal(size=N)
        np.testing.assert_allclose(blocked_force(self.memory, v), self.expected(v), rtol=0, atol=1e-12 * scale)
        if self.memory._block[0]:
            self.block_starts.add(int(self.memory._block[1]))
        if self.last is not None:
            for j in range(self.last + 1, self.now):
                self.history[j] = self.v_last + (j - self.last) / (self.now - self.last) * (v - self.v_last)
        self.history[self.now] = v
        self.memory.step(v, q * DT)
        self.last, self.v_last, self.now = self.now, v, self.now + q


def _kernel(m: int = M) -> np.ndarray:
    return np.random.default_rng(3).normal(size=(m, N, N))


@pytest.mark.parametrize("steps", [(1,), (3,), (1, 4, 2, 7, 1, 13), (2, 2, 2, 5, 5, 1, 1, 1), (50,)])
def test_blocked_sum_is_the_direct_trapezoidal_sum(steps: tuple[int, ...]) -> None:
    """Communication every q grid steps (q cycling through ``steps``: constant, several grid steps, changes inside
    a block, a step longer than the kernel), every point evaluated with two other velocities before its own: the
    blocked sum equals the direct sum at every point from the first one on."""
    run = Run(_kernel())
    points = 60
    for k in range(points):
        run.point(steps[k % len(steps)], trials=2)
    if max(steps) < M:  # blocks were used and shared: fewer block starts than points
        assert 0 < len(run.block_starts) < (points if len(steps) > 1 else points // 2)
    else:  # a step as long as the kernel: nothing to share after the first point (whose gap is 1), the direct sum
        assert run.block_starts == {0}


def test_blocks_of_one_constant_step_start_every_block_points() -> None:
    """With one grid step per point, a new block (one pass over the weights) starts every block_points points."""
    run = Run(_kernel())
    for _ in range(3 * RadiationMemory.block_points + 1):
        run.point(1)
    b = RadiationMemory.block_points
    assert run.block_starts == {0, b, 2 * b, 3 * b}


@pytest.mark.parametrize("codec", [False, True])
def test_state_restored_inside_a_block(codec: bool) -> None:
    """A state saved in the middle of a block and restored after the memory went on (with other velocities) into
    the next block, as FMU rollback and checkpoints do: the state carries the block it was saved with (it belongs to
    the saved ring and step count), so the restored memory continues with it, also when the state is decoded onto
    the live memory whose own block belongs to the history it went on with; the sums after the restore equal the
    direct sum of the restored history, and the same as the memory that never left that history, bit for bit."""
    run = Run(_kernel())
    b = RadiationMemory.block_points
    for _ in range(b + 3):  # inside the second block
        run.point(1)
    assert run.memory._block[0] == 1 and run.memory._block[1] == b
    saved_run = copy.deepcopy({k: v for k, v in vars(run).items() if k != "memory"})
    twin = copy.deepcopy(run.memory)  # goes on from the saved point without any restore
    if codec:
        data = state_codec.encode(run.memory)
    else:
        saved = copy.deepcopy(run.memory)
    saved_block = run.memory._block.copy()
    for q in (1, 1, 2, 1, 1, 1, 1, 3, 1):  # on into the next block, with other velocities
        run.point(q, trials=1)
    assert run.memory._block[0] == 1 and run.memory._block[1] > b
    memory = state_codec.decode(data, run.memory) if codec else saved
    np.testing.assert_array_equal(memory._block, saved_block)
    vars(run).update(copy.deepcopy(saved_run))
    run.memory = memory
    run.rng = np.random.default_rng(11)  # other velocities than the first time
    for q in (1, 2, 1, 1, 4, 1, 1, 1, 1, 1, 1, 1):
        v = run.rng.normal(size=N)
        restored, direct = blocked_force(run.memory, v), blocked_force(twin, v)
        np.testing.assert_array_equal(restored, direct)
        run.rng = np.random.default_rng(int(1000 * abs(v[0])))
        run.point(q, trials=1)
        twin.step(run.history[run.last], q * DT)


def test_kernel_shorter_than_a_block() -> None:
    """A kernel of 5 samples (fewer lags than block points): blocks shrink to what the kernel holds."""
    run = Run(_kernel(5))
    for k in range(30):
        run.point((1, 1, 2, 1, 3, 4, 5)[k % 7], trials=1)
    assert run.block_starts


def test_model_outputs_with_a_memory_restored_from_a_state_without_blocks() -> None:
    """A RadiationMemory decoded from a state saved before the blocks existed has no block arrays (the codec
    removes attributes the saved object did not have): the compiled pass makes new ones and the forces stay those of
    the reference path."""
    from hydro_fmu.work import COMPONENTS, WorkAccount
    from orchestrator.scenario import load_scenario
    from orchestrator.scene import load_scene

    from .conftest import SCENARIOS

    scene = load_scene(load_scenario(SCENARIOS / "hinge_barge.toml"), log=None)
    model = scene.hydro_model()
    reference = copy.deepcopy(model)
    h, n = scene.scenario.simulation.step, model.n
    rows = np.arange(5, dtype=np.intp)
    out, power, energy = np.zeros((5, n)), np.zeros(len(COMPONENTS)), np.zeros(len(COMPONENTS))
    account = WorkAccount()
    for k in range(30):
        t = k * h
        v, x = 0.2 * np.sin(0.9 * t + np.arange(n)), 0.1 * np.cos(0.5 * t + np.arange(n))
        if k == 13:  # inside the second block
            del model.radiation._history, model.radiation._block
        model.outputs(t, x, v, rows, out, power, account, energy)
        f = reference.forces(t, x, v)
        scale = max(np.abs(f.total).max(), 1.0)
        np.testing.assert_allclose(out[2], f.radiation, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(out[0], f.total, rtol=0, atol=1e-12 * scale)
        account.commit(t, power)
        model.advance(t, h, v)
        reference.advance(t, h, v)
