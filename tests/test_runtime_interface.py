"""The runtime's per-point interface (native/src/hydro/step.c, evaluate.c, linearised.c, work.c, viscous.c,
state.c): linearised outputs, viscous force, work account and model state against exact answers; calls refused
with a message."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from fmu_base import state_codec
from fmu_base.native import RuntimeCallError

from .hydro_runtime_cases import runtime

DT = 0.1
KERNEL = np.random.default_rng(7).normal(size=(12, 2, 2)) * 1e3
STIFFNESS = np.array([[3.0e5, 1.0e4], [1.0e4, 8.0e5]])
LINEAR, QUADRATIC = np.array([2.0e3, 0.0]), np.array([5.0e2, 3.0e3])


def linear_model(**kw: object):
    """Two DOFs: regular-wave excitation, convolution memory, linear hydrostatics, drag."""
    coef = np.array([[[1e4, 2e3], [-3e3, 5e3]]])
    return runtime(dofs=[(0, 2), (0, 4)], dt=DT, ramp=2.0, excitation=1, radiation=1, hydrostatics=1,
                   omega=[1.1], amplitude=[0.5 + 0.1j], excitation_coefficients=coef, radiation_kernel=KERNEL,
                   radiation_block_points=4, hydrostatics_stiffness=STIFFNESS, viscous_linear=LINEAR,
                   viscous_quadratic=QUADRATIC, **kw)


def test_linearised_outputs_are_the_exact_tangents() -> None:
    """dF_dx = -C; dF_dv = -(current velocity's weight in the memory) + viscous tangent: K(0) dt/2 after a step of
    one grid step, K(0) dt/2 + (2/3) K(dt) dt + (1/3) K(2 dt) dt after a step of three; F0 = F - dF_dx x - dF_dv v
    does not depend on the motion for the linear parts (two inputs, same F0); masked entries are 0 and their share
    stays in F0."""
    model = linear_model()
    x0, v0 = np.array([0.1, -0.02]), np.array([0.3, 0.05])
    for point, q in ((0.0, 1), (0.1, 3)):
        if q == 3:
            model.advance(0.0, 0.1, v0)  # t = 0.1, the next step spans three grid steps
            model.advance(0.1, 0.3, v0)
            point = 0.4
        x, v = np.array([0.2, 0.01]), np.array([-0.4, 0.02])
        f0, rate, dfdx, dfdv = model.linearise(point, x, v)
        damping = KERNEL[0] * DT / 2 if q == 1 else KERNEL[0] * DT / 2 + (2 / 3) * KERNEL[1] * DT + (
            1 / 3) * KERNEL[2] * DT
        np.testing.assert_allclose(dfdx, -STIFFNESS, rtol=1e-15)
        np.testing.assert_allclose(dfdv, -damping + np.diag(-LINEAR - 2 * QUADRATIC * np.abs(v)), rtol=1e-13,
                                   atol=1e-12 * np.abs(damping).max())
        model.evaluate(point, x, v)
        total = model.block[0].copy()
        np.testing.assert_allclose(f0, total - dfdx @ x - dfdv @ v, rtol=1e-13)
        # the linear parts: F0 is the same for other inputs (the drag's intercept -q|v|v + 2q|v|v = q|v|v aside)
        f0_other, _, _, dfdv_other = model.linearise(point, x0, v0)
        drag_intercept = QUADRATIC * np.abs(v) * v - QUADRATIC * np.abs(v0) * v0
        np.testing.assert_allclose(f0 - f0_other, drag_intercept, rtol=0, atol=1e-9 * np.abs(f0).max())
        mask = np.array([[True, False], [False, True]])
        f0_masked, _, dfdx_masked, _ = model.linearise(point, x, v, stiffness_mask=mask)
        assert dfdx_masked[0, 1] == dfdx_masked[1, 0] == 0.0
        np.testing.assert_allclose(f0_masked, total - dfdx_masked @ x - dfdv @ v, rtol=1e-13)


def test_memory_rate_is_the_backward_difference_between_points() -> None:
    """F0_rate's memory part: minus (mu - D v) at this point minus at the last point where the interface was
    evaluated, over their time difference; 0 at the first point; the same point read twice does not shift it."""
    kernel = KERNEL[:, :1, :1]
    model = runtime(dofs=[(0, 2)], dt=DT, radiation=1, radiation_kernel=kernel, radiation_block_points=8)
    known = []
    for k in range(5):
        t, v = k * DT, np.array([np.sin(0.7 * k)])
        _, rate, _, dfdv = model.linearise(t, np.zeros(1), v)
        _, rate_again, _, _ = model.linearise(t, np.zeros(1), v)
        model.evaluate(t, np.zeros(1), v)
        known.append(-model.block[2][0] + dfdv[0, 0] * v[0])  # mu - D v, D = -dfdv
        expected = 0.0 if k == 0 else -(known[-1] - known[-2]) / DT
        assert rate[0] == pytest.approx(expected, rel=1e-12, abs=1e-12 * abs(known[-1]))
        assert rate_again[0] == rate[0]
        model.advance(t, DT, v)


def test_viscous_force_and_work_account_are_exact() -> None:
    """Drag only: F = -b v - q |v| v; power F v; work by the trapezoidal rule over the committed points,
    W(t_k) = sum h/2 (P_j + P_j+1), the value at a point before its commit included."""
    model = runtime(dofs=[(0, 2), (0, 4)], dt=DT, viscous_linear=LINEAR, viscous_quadratic=QUADRATIC)
    out, power, work = np.zeros((5, 2)), np.zeros(4), np.zeros(4)
    rows = np.arange(5, dtype=np.int64)
    expected_work, last_power = 0.0, None
    for k in range(8):
        t = k * DT
        v = np.array([0.5 * np.cos(0.9 * t), -0.2 + 0.1 * k])
        model.outputs(t, np.zeros(2), v, rows, out, power, work)
        force = -LINEAR * v - QUADRATIC * np.abs(v) * v
        np.testing.assert_allclose(out[4], force, rtol=1e-15)
        np.testing.assert_allclose(out[0], force, rtol=1e-15)
        p = float(force @ v)
        assert power[3] == pytest.approx(p, rel=1e-15) and power[:3].tolist() == [0.0, 0.0, 0.0]
        if last_power is not None:
            expected_work += DT / 2 * (last_power + p)
        assert work[3] == pytest.approx(expected_work, rel=1e-14, abs=1e-300)
        model.do_step(t, DT, np.zeros(2), v)
        last_power = p


def _drive(model, start: int, count: int) -> list[np.ndarray]:
    """Points start .. start + count - 1 with a fixed input history: per point the force rows, work, elevation and
    linearised outputs, all bits."""
    out, power, work = np.zeros((5, 2)), np.zeros(4), np.zeros(4)
    rows = np.arange(5, dtype=np.int64)
    seen = []
    for k in range(start, start + count):
        t = k * DT
        x, v = np.array([0.1 * np.sin(0.3 * k), 0.02 * k % 0.1]), np.array([np.cos(0.4 * k), 0.1 * np.sin(k)])
        eta = model.outputs(t, x, v, rows, out, power, work)
        f0, rate, dfdx, dfdv = model.linearise(t, x, v)
        seen.append(np.concatenate([out.ravel(), power, work, [eta], f0, rate, dfdx.ravel(), dfdv.ravel()]))
        model.do_step(t, DT, x, v)
    return seen


@pytest.mark.parametrize("how", ["bytes", "clone", "deepcopy", "codec"])
def test_state_save_and_load_are_bit_identical(how: str) -> None:
    """Saved after 23 points and loaded after 17 more: the next 17 points repeat bit for bit (block sums,
    phasor clock, work account and memory rate included), by bytes, a clone, a deep copy and the data-only codec."""
    model = linear_model()
    _drive(model, 0, 23)
    if how == "bytes":
        saved = model.state()
    elif how == "codec":
        saved = state_codec.encode({"runtime": model})
    else:
        saved = model.clone() if how == "clone" else copy.deepcopy(model)
    first = _drive(model, 23, 17)
    if how == "bytes":
        model.load_state(saved)
    elif how == "codec":
        model = state_codec.decode(saved, {"runtime": model})["runtime"]
    else:
        model.copy_state_from(saved)
    again = _drive(model, 23, 17)
    for a, b in zip(first, again, strict=True):
        np.testing.assert_array_equal(a, b)


def test_a_foreign_or_corrupt_state_is_refused_and_changes_nothing() -> None:
    """A state of other data, a truncated state, one with a wrong byte in a count: refused with a message; the
    model goes on exactly as if nothing had happened."""
    model = linear_model()
    other_data = runtime(dofs=[(0, 2), (0, 4)], dt=DT)
    _drive(model, 0, 5)
    twin = model.clone()
    state = model.state()
    with pytest.raises(RuntimeCallError, match="other data"):
        model.load_state(other_data.state())
    with pytest.raises(RuntimeCallError, match="shorter"):
        model.load_state(state[:-3])
    with pytest.raises(RuntimeCallError, match="longer"):
        model.load_state(state + b"\0")
    header = 8 + 8 * 7 + 8 * 3 + 8 * 2 + 8  # magic, version .. r, times, clock t and delta, clock count
    corrupt = bytearray(state)
    corrupt[header - 1] = 0x7F  # the clock count's top byte: a huge count
    with pytest.raises(RuntimeCallError, match="phasor clock"):
        model.load_state(bytes(corrupt))
    with pytest.raises(RuntimeCallError, match="WECHSTAT"):
        model.load_state(b"not a state")
    for a, b in zip(_drive(model, 5, 10), _drive(twin, 5, 10), strict=True):
        np.testing.assert_array_equal(a, b)


def test_calls_with_wrong_sizes_or_times_are_refused_with_a_message() -> None:
    model = linear_model()
    with pytest.raises(ValueError, match=r"shape \(3,\), expected \(2,\)"):
        model.evaluate(0.0, np.zeros(3), np.zeros(3))
    with pytest.raises(RuntimeCallError, match="not finite"):
        model.evaluate(float("nan"), np.zeros(2), np.zeros(2))
    with pytest.raises(RuntimeCallError, match="row 7 does not exist"):
        model.outputs(0.0, np.zeros(2), np.zeros(2), np.array([0, 7]), np.zeros((2, 2)), np.zeros(4), np.zeros(4))
    with pytest.raises(RuntimeCallError, match="not a whole multiple of the radiation convolution step 0.1 s"):
        model.advance(0.0, 0.15, np.zeros(2))
    with pytest.raises(RuntimeCallError, match="step starts at t = 0.5 s but the radiation history is at t = 0 s"):
        model.do_step(0.5, 0.1, np.zeros(2), np.zeros(2))
    state_space = runtime(dofs=[(0, 2)], radiation=2, radiation_a=-np.eye(1), radiation_b=np.eye(1),
                          radiation_c=np.eye(1))
    with pytest.raises(RuntimeCallError, match="a step must be positive"):
        state_space.advance(0.0, 0.0, np.zeros(1))
    model.advance(0.0, 0.1, np.zeros(2))  # the refused calls changed nothing
