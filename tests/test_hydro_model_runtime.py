"""The hydro model as the FMU, the monolithic mode and the bench report use it (HydroModel.outputs, evaluate, forces,
elevation, advance: the compiled runtime) against the Python reference of the same physics assembled from the
model's own component objects (ExcitationForce, the reference radiation memory, LinearHydrostatics, ViscousForce,
the wave components, WorkAccount), over whole runs of bundled scenes; the Python reference memory against the
trapezoidal sum written out; the FMU's value store.

Expected values come from the reference formulas evaluated independently: the Python component classes (tested
themselves against exact answers in test_radiation, test_excitation, test_state_space, test_drag_nonlinear) and the
trapezoidal convolution written out as a plain sum over the recorded grid velocities. The runtime must agree with
them to round-off over whole runs (regular and irregular seas, convolution with communication steps of several grid
steps, state-space radiation, drag, components above the database's range).
"""

from __future__ import annotations

import copy
import dataclasses
import math

import numpy as np
import pytest

from fmu_base.slave import RealStore
from hydro_fmu.model import FORCE_ROWS, HydroModel
from hydro_fmu.radiation import RadiationMemory
from hydro_fmu.work import COMPONENTS, WorkAccount
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS
from .hydro_runtime_cases import direct_convolution


def _velocity(t: float, n: int) -> np.ndarray:
    """A smooth, non-periodic test velocity per DOF (m/s, rad/s)."""
    k = np.arange(1, n + 1)
    return 0.3 * np.sin(0.7 * k * t + 0.2 * k) + 0.05 * np.cos(1.9 * t / k)


@pytest.mark.parametrize("steps", [(1,), (3,), (1, 4, 2, 7, 1, 13)])
def test_reference_memory_is_the_direct_trapezoidal_sum(steps: tuple[int, ...]) -> None:
    """The Python reference memory, communication every q grid steps (q cycling through ``steps``, q up to longer
    than the kernel): the plain sum over grid velocities, those between communication points interpolated
    linearly."""
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


def _reference(model: HydroModel, h: float, steps: int) -> list[tuple[np.ndarray, float, np.ndarray]]:
    """The run through the Python component objects: per point (force rows, elevation, work)."""
    n = model.n
    memory = model.reference_memory()
    account = WorkAccount()
    zero = np.zeros(n)
    out = []
    for k in range(steps):
        t = k * h
        v, x = _velocity(t, n), 0.1 * np.cos(0.5 * t + np.arange(n))
        exc = model.excitation(t) if model.excitation is not None else zero
        rad = -memory.force(v) if memory is not None else zero
        hs = model.hydrostatics(x) if model.switches.hydrostatics else zero
        visc = model.viscous(v) if model.viscous is not None else zero
        block = np.array([((exc + rad) + hs) + visc, exc, rad, hs, visc])
        eta = model.waves.elevation(t, model.ramp)
        power = WorkAccount.powers(exc, rad, hs, visc, v)
        out.append((block, eta, account.value(t, power)))
        account.commit(t, power)
        if memory is not None:
            memory.step(v, h)
    return out


def _drive(model: HydroModel, h: float, steps: int) -> list[tuple[np.ndarray, float, np.ndarray]]:
    """The run through HydroModel.outputs as the FMU calls it (rows in another order than FORCE_ROWS, each point read
    twice, work committed at the point, then the step)."""
    n = model.n
    out = []
    power, energy = np.zeros(len(COMPONENTS)), np.zeros(len(COMPONENTS))
    rows = np.array([4, 0, 2, 1, 3], dtype=np.intp)
    outputs = np.full((len(rows), n), np.nan)
    for k in range(steps):
        t = k * h
        v, x = _velocity(t, n), 0.1 * np.cos(0.5 * t + np.arange(n))
        for _ in range(2):
            eta = model.outputs(t, x, v, rows, outputs, power, energy)
        block = np.empty_like(outputs)
        block[rows] = outputs
        forces = model.forces(t, x, v)
        np.testing.assert_array_equal(np.array([getattr(forces, name) for name in FORCE_ROWS]), block)
        assert model.elevation(t) == eta
        out.append((block, eta, energy.copy()))
        model.commit_work(t, x, v)
        model.advance(t, h, v)
    return out


def _compare(model: HydroModel, h: float, steps: int) -> list[str]:
    """The model against the reference over a run; the force components that are not zero."""
    reference = _reference(model, h, steps)
    scale = max(np.abs(b).max() for b, _, _ in reference)
    work_scale = max(np.abs(w).max() for _, _, w in reference)
    eta_scale = max(abs(e) for _, e, _ in reference)
    assert scale > 0 and work_scale > 0
    for (b0, e0, w0), (b1, e1, w1) in zip(reference, _drive(copy.deepcopy(model), h, steps), strict=True):
        np.testing.assert_allclose(b1, b0, rtol=0, atol=1e-12 * scale)
        assert abs(e1 - e0) <= 1e-12 * max(eta_scale, 1e-300)
        np.testing.assert_allclose(w1, w0, rtol=0, atol=1e-12 * work_scale)
    return [name for i, name in enumerate(FORCE_ROWS) if np.abs(reference[-1][0][i]).max() > 0]


def test_model_equals_reference_hinge_barge_regular_sea_convolution() -> None:
    """Hinge barge (two bodies, regular sea, 30 s convolution kernel), one grid step per communication point."""
    scene = load_scene(load_scenario(SCENARIOS / "hinge_barge.toml"), log=None)
    model = scene.hydro_model()
    assert model.report.method == "convolution"
    h = scene.scenario.simulation.step
    present = _compare(model, h, round(12.0 / h))
    assert {"excitation", "radiation", "hydrostatic"} <= set(present)


def test_model_equals_reference_irregular_sea_gap_and_viscous() -> None:
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
    assert len(sea.components.omega) > 50
    assert sea.components.omega.max() > scene.hdb.omega[-1]  # components the excitation leaves out
    present = _compare(model, 3 * dt, 400)
    assert set(present) == set(FORCE_ROWS)


def test_model_equals_reference_state_space() -> None:
    """State-space radiation (the irregular cylinder scenario's own model), a step that is not a multiple of
    anything in particular."""
    scene = load_scene(load_scenario(SCENARIOS / "cylinder_irregular.toml"), log=None)
    model = scene.hydro_model()
    assert model.report.method == "state_space"
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
