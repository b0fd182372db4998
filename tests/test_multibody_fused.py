"""One compiled call per macro step (MultibodySimulator._advance_fused, mbd_fmu.kernels.ga_macro_step) against
the substep-by-substep compiled path it replaces.

Both run the same compiled operations in the same order (restart, generalised-alpha substeps with the kept
factors, powers and trapezoidal energy sums, angle references, outputs), so the states agree to round-off: bit
for bit where the restart is computed once on both paths, to a few units of the last place where the step by
step path restarts twice in one macro step (new PTO commands, then new inputs: the ``increment`` restart then adds
two jumps of the acceleration instead of one). Compared over runs with inputs and PTO commands that change, for
each restart mode: pose, velocities, accelerations (consistent and algorithmic), multipliers, time, step count,
the energy account (dissipated, external work, PTO energy, balance), the PTO and joint outputs and the angle
references. Redundant constraints (rows re-selected along the motion) and a step the fused call cannot finish
hand over to the step by step path mid-step.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

from fmu_base import state_codec
from mbd_fmu.formulations import RESTARTS, ConvergenceError, Settings
from mbd_fmu.simulator import FusedBuffers, MultibodySimulator

from .mechanisms import bricard
from .test_multibody_fast import two_bodies

H, MAX_STEP = 0.02, 0.0075  # three substeps per macro step


def run(fused: bool, restart: str, steps: int = 60, each=None) -> MultibodySimulator:
    """The floating body with a rod on a revolute joint (mooring, nonlinear PTO, slide spring, rotary spring),
    wave-like inputs every macro step, the PTO's damping and force command changed every 7th and 11th step."""
    model, pose, v = two_bodies("revolute")
    pto = next(e for e in model.elements if e.name == "pto")
    sim = MultibodySimulator(model, Settings("index3", spectral_radius=0.8, restart=restart), MAX_STEP, [pto])
    sim.fused = fused
    sim.start(pose, v)
    forced = np.array([dof < 3 for _, dof in model.coordinates])
    for k in range(steps):
        damping = 40.0 + 20.0 * (k // 7 % 2)
        command = 5.0 * np.cos(0.3 * (k // 11))
        sim.set_pto_commands([300.0], [damping], [command], defer=True)
        sim.advance(H, 20.0 * forced * np.sin(3.0 * k * H + np.arange(model.n)))
        if each is not None:
            each(sim)
    return sim


def outputs(sim: MultibodySimulator) -> dict[str, np.ndarray]:
    """Everything the FMU reports, from the simulator's output methods."""
    f = sim.formulation
    joints = sim.joint_coordinates()
    return {"pose.r": f.pose.r, "pose.R": f.pose.R, "v": f.v, "vdot": f.vdot, "a": f.a, "lam": f.lam,
            "displacement": sim.displacement(), "pto": sim.pto_outputs(),
            "joints": np.concatenate([np.concatenate(q) for q in joints]),
            "reactions": np.concatenate([np.concatenate(r) for r in sim.reactions()]),
            "energy": np.array(list(sim.energy().values())), "powers": np.array(sim.powers()),
            "violation": np.array([sim.constraint_violation()]),
            "refs": np.array([c.reference for _, c in f.compiled.angles])}


@pytest.mark.parametrize("restart", RESTARTS)
def test_fused_macro_steps_give_the_states_and_outputs_of_the_step_by_step_path(restart) -> None:
    seen = []
    fused = run(True, restart, each=lambda sim: seen.append(sim.formulation.steps))
    plain = run(False, restart)
    a, b = fused.formulation, plain.formulation
    assert a.compiled is not None and b.compiled is not None
    assert seen == list(range(3, 3 * 61, 3))  # three substeps per macro step
    assert (a.steps, a.t) == (b.steps, b.t)
    assert a.newton_iterations == b.newton_iterations and a.stiff_restarts == b.stiff_restarts
    x, y = outputs(fused), outputs(plain)
    # "increment" restarts twice on the step by step path when both the commands and the inputs change
    exact = restart != "increment"
    for key in x:
        scale = max(1.0, float(np.max(np.abs(y[key]), initial=0.0)))
        if exact:
            assert np.array_equal(x[key], y[key]), key
        else:
            assert np.max(np.abs(x[key] - y[key]), initial=0.0) <= 1e-9 * scale, key
    # the energy account is the same on both (compared above) and closes: the restarts that keep second order
    # leave a balance of 0.1 % of the energy exchanged over this run ("none" keeps the algorithmic acceleration
    # across the input jumps: first order, 0.2 %)
    e = fused.energy()
    assert abs(e["balance"]) < (3e-3 if restart == "none" else 1e-3) * max(abs(e["external_work"]),
                                                                           abs(e["dissipated"]))
    assert e["pto"] > 0.0


def test_fused_macro_steps_match_the_step_by_step_path_with_rows_reselected() -> None:
    """Bricard's linkage (redundant constraints: the kept rows are re-chosen along the motion): the fused call
    stops after a substep whose rows need re-selection and the step by step path takes the rest."""
    def go(fused: bool) -> MultibodySimulator:
        model, pose = bricard()
        sim = MultibodySimulator(model, Settings("index3", spectral_radius=0.8), 1e-3)
        sim.fused = fused
        sim.start(pose, np.zeros(model.n))
        inputs = np.zeros(model.n)
        for k in range(150):
            inputs[:] = 0.3 * np.sin(0.1 * k + np.arange(model.n))
            sim.advance(4e-3, inputs)
        return sim

    fused, plain = go(True), go(False)
    a, b = fused.formulation, plain.formulation
    assert a.row_changes == b.row_changes > 0
    for x, y in ((a.pose.r, b.pose.r), (a.pose.R, b.pose.R), (a.v, b.v), (a.lam, b.lam)):
        assert np.array_equal(x, y)
    assert fused.energy() == plain.energy()


def test_a_macro_step_that_does_not_converge_fails_as_on_the_step_by_step_path() -> None:
    """A substep that does not converge in the fused call (two Newton iterations allowed) is retaken step by step,
    by the compiled step and then the Python iteration, which reports it: the same error, at the same time, with
    the state of the last completed macro step kept, as on the step by step path alone."""
    def go(fused: bool) -> tuple[str, MultibodySimulator, int]:
        model, pose, v = two_bodies("spherical")
        sim = MultibodySimulator(model, Settings("index3", spectral_radius=0.8, max_iterations=2), MAX_STEP)
        sim.fused = fused
        sim.start(pose, v)
        for k in range(50):
            try:
                sim.advance(H, np.full(model.n, 50.0 * np.sin(k)))
            except ConvergenceError as exc:
                return str(exc), sim, k
        raise AssertionError("every step converged")

    (message, fused, k), (expected, plain, j) = go(True), go(False)
    assert message == expected and k == j
    assert "did not converge" in message
    a, b = fused.formulation, plain.formulation
    assert (a.steps, a.t) == (b.steps, b.t)
    for x, y in ((a.pose.r, b.pose.r), (a.v, b.v), (a.lam, b.lam)):
        assert np.array_equal(x, y)


def test_a_saved_state_is_a_copy_that_later_steps_do_not_overwrite() -> None:
    """The fused path keeps its output buffers between macro steps and the formulation's state is views of them
    (:class:`~mbd_fmu.simulator.FusedBuffers`, rewritten every other step): a state saved between steps (the deep
    copy of the FMU's getFMUstate, the data-only encoding of serialised FMU states and checkpoints) must hold
    copies. Saved after 20 macro steps while the original runs 20 more: the saved states are unchanged, and each,
    restored (the encoded one onto the live simulator, as setFMUstate does), repeats those 20 steps bit for bit."""
    model, pose, v = two_bodies("revolute")
    pto = next(e for e in model.elements if e.name == "pto")
    sim = MultibodySimulator(model, Settings("index3", spectral_radius=0.8), MAX_STEP, [pto])
    sim.eager_outputs = True  # as in the FMU: the outputs are views of the kept buffers too
    sim.start(pose, v)
    forced = np.array([dof < 3 for _, dof in model.coordinates])

    def steps(s: MultibodySimulator, first: int) -> None:
        for k in range(first, first + 20):
            s.advance(H, 20.0 * forced * np.sin(3.0 * k * H + np.arange(model.n)))

    def state(s: MultibodySimulator) -> dict[str, np.ndarray]:
        f = s.formulation
        return {"r": f.pose.r.copy(), "R": f.pose.R.copy(), "v": f.v.copy(), "vdot": f.vdot.copy(), "a": f.a.copy(),
                "lam": f.lam.copy(), "outputs": s.output_values().copy(), "t": np.array([f.t, f.steps]),
                "energy": np.array(list(s.energy().values()))}

    steps(sim, 0)
    assert isinstance(sim._buffers, FusedBuffers)  # the kept buffers' path ran: the state is views of them
    assert any(sim.formulation.v is side[1][3] and sim.formulation.pose is side[1][2] for side in sim._buffers.sides)
    at_save = state(sim)
    copied, encoded = copy.deepcopy(sim), state_codec.encode(sim)
    steps(sim, 20)
    final = state(sim)
    assert not np.array_equal(final["r"], at_save["r"])
    for key, value in state(copied).items():
        assert np.array_equal(value, at_save[key]), key
    for restored in (copied, state_codec.decode(encoded, sim)):
        for key, value in state(restored).items():
            assert np.array_equal(value, at_save[key]), key
        steps(restored, 20)
        for key, value in state(restored).items():
            assert np.array_equal(value, final[key]), key


def test_pto_parameters_set_on_the_element_act_from_the_next_fused_step() -> None:
    """The compiled plan rewrites a spring's parameters only when they differ from those it last wrote
    (CompiledModel._refresh), but reads them from the Python element at every step: a PTO's stiffness, damping or
    force command assigned on the element itself (not through set_pto_commands), or set back to an earlier value,
    drives the next fused macro step. Checked on the PTO outputs by the element's own law (its nonlinear law of
    g = -k x - c v + u with the parameters of now)."""
    model, pose, v = two_bodies("revolute")
    pto = next(e for e in model.elements if e.name == "pto")
    sim = MultibodySimulator(model, Settings("index3", spectral_radius=0.8), MAX_STEP, [pto])
    sim.start(pose, v)
    forced = np.array([dof < 3 for _, dof in model.coordinates])
    for k, (stiffness, damping, command) in enumerate([(300.0, 40.0, 0.0), (300.0, 90.0, 0.0), (500.0, 90.0, 7.0),
                                                       (300.0, 40.0, 0.0), (300.0, 40.0, -3.0)]):
        pto.stiffness, pto.damping, pto.force_command = stiffness, damping, command
        for j in range(5):
            sim.advance(H, 20.0 * forced * np.sin(3.0 * (5 * k + j) * H + np.arange(model.n)))
        if sim.formulation.compiled is not None:  # (WEC_COSIM_NO_JIT: the Python path, the same law)
            assert sim._buffers is not None and sim._outputs is None  # the fused path ran (outputs when read)
        x, rate, force, _ = sim.pto_outputs()[0]
        expected = pto.law_force(x, rate)
        assert abs(force - expected) <= 1e-12 * max(abs(expected), 1.0)
