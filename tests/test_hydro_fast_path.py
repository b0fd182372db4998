"""The hydro FMU's one-pass evaluation (HydroModel.evaluate, the compiled pass HydroModel.outputs, the slave's
value store) against the reference path (HydroModel.forces, HydroModel.elevation, WorkAccount.powers/value) and
against a direct convolution sum.

Expected values come from the reference formulas evaluated independently: the trapezoidal convolution written
out as a plain sum over the recorded grid velocities, and the component-by-component force model; the fast path
must agree with them to round-off over whole runs (regular and irregular seas, convolution with communication
steps of several grid steps, state-space radiation).
"""

from __future__ import annotations

import copy
import dataclasses
import math

import numpy as np
import pytest

from fmu_base.slave import RealStore
from hydro_fmu import kernels
from hydro_fmu.model import FORCE_ROWS, HydroModel
from hydro_fmu.radiation import RadiationMemory
from hydro_fmu.work import COMPONENTS, WorkAccount
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS


def _velocity(t: float, n: int) -> np.ndarray:
    """A smooth, non-periodic test velocity per DOF (m/s, rad/s)."""
    k = np.arange(1, n + 1)
    return 0.3 * np.sin(0.7 * k * t + 0.2 * k) + 0.05 * np.cos(1.9 * t / k)


def direct_convolution(kernel: np.ndarray, dt: float, history: dict[int, np.ndarray], now: int) -> np.ndarray:
    """mu at grid point ``now``: sum_j w_j K(j dt) v(now - j), trapezoidal weights over the kernel's m samples,
    zero velocity before the start (grid velocities in ``history``)."""
    m, n, _ = kernel.shape
    mu = np.zeros(n)
    for j in range(m):
        if now - j < 0:
            break
        w = dt / 2 if j in (0, m - 1) else dt
        mu += w * kernel[j] @ history[now - j]
    return mu


@pytest.mark.parametrize("steps", [(1,), (3,), (1, 4, 2, 7, 1, 13)])
def test_radiation_memory_is_the_direct_trapezoidal_sum(steps: tuple[int, ...]) -> None:
    """Communication every q grid steps (q cycling through ``steps``, q up to longer than the kernel): the memory
    equals the plain sum over grid velocities, those between communication points interpolated linearly."""
    dt, m, n = 0.1, 9, 3
    rng = np.random.default_rng(3)
    kernel = rng.normal(size=(m, n, n))
    memory = RadiationMemory(kernel, dt)
    history: dict[int, np.ndarray] = {}
    now, last, v_last = 0, None, np.zeros(n)
    for k in range(40):
        q = steps[k % len(steps)]
        v = _velocity(now * dt, n)
        if last is not None:  # grid points since the last communication point: linear interpolation
            for j in range(last + 1, now):
                history[j] = v_last + (j - last) / (now - last) * (v - v_last)
        history[now] = v
        for _ in range(2):  # any number of reads at a point gives the same answer
            assert memory.force(v) == pytest.approx(direct_convolution(kernel, dt, history, now), rel=1e-12, abs=1e-13)
        memory.step(v, q * dt)
        last, v_last, now = now, v, now + q


def _drive(model: HydroModel, fast: bool | str, h: float, steps: int) -> list[tuple[np.ndarray, float, np.ndarray]]:
    """Run the model with a prescribed motion; per point (force block, elevation, work). ``fast``: False the
    reference path, True :meth:`HydroModel.evaluate`, "outputs" :meth:`HydroModel.outputs` (the compiled pass
    when the model is covered) writing into output rows in another order, as the FMU's variables may be."""
    n = model.n
    account = WorkAccount()
    out = []
    power = np.zeros(len(COMPONENTS))
    energy = np.zeros(len(COMPONENTS))
    rows = np.array([4, 0, 2, 1, 3], dtype=np.intp)
    outputs = np.full((len(rows), n), np.nan)
    for k in range(steps):
        t = k * h
        v = _velocity(t, n)
        x = 0.1 * np.cos(0.5 * t + np.arange(n))
        if fast == "outputs":
            for _ in range(2):  # reading a point twice gives the same answer
                eta = model.outputs(t, x, v, rows, outputs, power, account, energy)
            block = np.empty_like(outputs)
            block[rows] = outputs
            work = energy.copy()
        elif fast:
            eta = model.evaluate(t, x, v)
            block = model.block.copy()
            np.dot(model.block[1:], v, out=power)
            account.value(t, power, out=energy)
            work = energy.copy()
        else:
            f = model.forces(t, x, v)
            eta = model.elevation(t)
            block = np.array([getattr(f, name) for name in FORCE_ROWS])
            power = WorkAccount.powers(f.excitation, f.radiation, f.hydrostatic, f.viscous, v)
            work = account.value(t, power)
        out.append((block, eta, work))
        account.commit(t, power)
        model.advance(t, h, v)
    return out


def _compare(model: HydroModel, h: float, steps: int) -> list[str]:
    """Fast (evaluate) and the compiled pass (outputs) against reference over a run; the force components that
    are not zero."""
    reference = _drive(copy.deepcopy(model), False, h, steps)
    scale = max(np.abs(b).max() for b, _, _ in reference)
    work_scale = max(np.abs(w).max() for _, _, w in reference)
    eta_scale = max(abs(e) for _, e, _ in reference)
    assert scale > 0 and work_scale > 0
    for mode in (True, "outputs"):
        fast = _drive(copy.deepcopy(model), mode, h, steps)
        for (b0, e0, w0), (b1, e1, w1) in zip(reference, fast, strict=True):
            np.testing.assert_allclose(b1, b0, rtol=0, atol=1e-12 * scale)
            assert abs(e1 - e0) <= 1e-12 * max(eta_scale, 1e-300)
            np.testing.assert_allclose(w1, w0, rtol=0, atol=1e-12 * work_scale)
    nonzero = [name for i, name in enumerate(FORCE_ROWS) if np.abs(reference[-1][0][i]).max() > 0]
    return nonzero


def test_fast_path_equals_reference_hinge_barge_regular_sea_convolution() -> None:
    """Hinge barge (two bodies, regular sea, 30 s convolution kernel), one grid step per communication point."""
    scene = load_scene(load_scenario(SCENARIOS / "hinge_barge.toml"), log=None)
    model = scene.hydro_model()
    assert model.report.method == "convolution"
    assert model.compiled == kernels.COMPILED  # the compiled pass covers it (when numba is there)
    h = scene.scenario.simulation.step
    present = _compare(model, h, round(12.0 / h))
    assert {"excitation", "radiation", "hydrostatic"} <= set(present)


def test_fast_path_equals_reference_irregular_sea_gap_and_viscous() -> None:
    """Cylinder in an irregular sea (many components, some above the database's range) with linear and quadratic
    drag; communication every 3 radiation grid steps (interpolated memory points) and through the ramp."""
    scenario = load_scenario(SCENARIOS / "cylinder_irregular.toml")
    scene = load_scene(scenario, log=None)
    options = dataclasses.replace(scene.hydro_options(), radiation_method="convolution")
    from hydro_fmu.drag import ViscousCoefficients

    index = scene.hydro_index()
    dofs = [[int(k) % 6 for k in index if k // 6 == b] for b in range(len(scene.hydro_bodies))]
    n = len(index)
    options = dataclasses.replace(options, viscous=ViscousCoefficients(np.full(n, 2e3), np.full(n, 5e2)))
    sea = scene.sea()
    dt = 0.05
    model = HydroModel(scene.hdb, scene.hydro_bodies, dofs, sea.components, sea.ramp, dt, 20.0, scene.switches(),
                       options)
    assert len(sea.components.omega) > 50 and model.radiation.gap == 1
    assert model.compiled == kernels.COMPILED
    assert sea.components.omega.max() > scene.hdb.omega[-1]  # components the excitation leaves out
    present = _compare(model, 3 * dt, 400)
    assert set(present) == set(FORCE_ROWS)


def test_fast_path_equals_reference_state_space() -> None:
    """State-space radiation (the irregular cylinder scenario's own model), a step that is not a multiple of
    anything in particular."""
    scene = load_scene(load_scenario(SCENARIOS / "cylinder_irregular.toml"), log=None)
    model = scene.hydro_model()
    assert model.report.method == "state_space"
    assert model.compiled == kernels.COMPILED
    present = _compare(model, 0.07, 400)
    assert {"excitation", "radiation", "hydrostatic"} <= set(present)


def test_value_store_gathers_and_scatters_like_single_values() -> None:
    """The flat value store: views stay valid when new blocks are added, a list of references spanning blocks
    falls back to one value at a time, and every read equals the value written."""
    store = RealStore()
    arrays, where = [], []
    rng = np.random.default_rng(0)
    vr = 0
    for size in (1, 3, 900, 1, 5000, 2, 1000, 4):  # forces several blocks and one large block of its own
        view = store.allocate(rng.normal(size=size))
        for i in range(size):
            store.bind(vr, view, i)
            where.append((view, i))
            vr += 1
        arrays.append(view)
    for _ in range(20):
        vrs = [int(k) for k in rng.choice(vr, size=int(rng.integers(1, 30)), replace=False)]
        values = rng.normal(size=len(vrs)).tolist()
        store.scatter(vrs, values)
        assert store.gather(vrs) == values
        assert [where[k][0][where[k][1]] for k in vrs] == values  # written through to the views
    small = list(range(1, 4))  # one block: a cached plan
    assert store.gather(small) == [float(a) for a in arrays[1]]
    with pytest.raises(ValueError, match="2 value references but 1 values"):
        store.scatter([0, 1], [1.0])
    with pytest.raises(KeyError):
        store.gather([vr + 5])
    assert not math.isnan(sum(store.gather(list(range(vr)))))
