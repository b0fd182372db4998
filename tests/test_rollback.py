"""In-memory FMU states of the multibody FMU (fmu_base.rollback and the linear model's rollback state): set back, the
model is what it was, object for object, and steps taken again repeat the first ones bit for bit.

An iterative master sets the multibody FMU back at every iteration; this state replaces a deep copy of the whole model
(and the rebuild of its compiled plan) by copies of what a step can change. Checked on the linear model, the compiled
index-3 path (hinge barge, F3OF with a fixed base), the Python paths of the null-space and index-1 formulations, and a
closed-loop array with redundant constraints; the full state (every attribute of every object, as the checkpoint codec
writes it) must equal the state before the steps, and the outputs of the repeated steps those of the first.
"""

from __future__ import annotations

import numpy as np
import pytest

from fmu_base import state_codec
from fmu_base.slave import RollbackState
from orchestrator.cosim.simulation import prepare_run
from orchestrator.scenario import apply_overrides, load_scenario

from .conftest import SCENARIOS

CASES = {
    "linear (two floats)": ("two_floats", []),
    "index-3, compiled (hinge barge)": ("hinge_barge", []),
    "index-3, fixed base (F3OF DT3)": ("f3of_dt3", []),
    "null space (hinge barge)": ("hinge_barge", ["multibody.formulation=nullspace"]),
    "index-1 (hinge barge)": ("hinge_barge", ["multibody.formulation=index1"]),
    "closed loops, redundant constraints (4N3LA)": ("array_4n3la", []),
}


def _steps(master, slave, h: float, n: int, rng) -> list[np.ndarray]:
    """n steps of the multibody slave with random force inputs (the same for a given generator state); its outputs
    after each."""
    comp = master.components["mbd"]
    port = master.wiring["mbd"].port
    out = []
    for _ in range(n):
        comp.set_reals(port, rng.normal(scale=1e3, size=len(port.vrs)))
        comp.do_step(master.time, h)
        out.append(comp.get_reals(master.output_ports["mbd"]))
    return out


@pytest.mark.parametrize("case", list(CASES))
def test_a_rolled_back_multibody_fmu_repeats_its_steps_bit_for_bit(case) -> None:
    name, overrides = CASES[case]
    s = apply_overrides(load_scenario(SCENARIOS / f"{name}.toml"), ["simulation.error_estimate=none", *overrides])
    plan = prepare_run(s, in_process=True, log=None)
    master = plan.master
    try:
        master.initialize(0.0, s.simulation.duration, plan.parameter_links)
        for _ in range(3):
            master.step(s.simulation.step)
        slave = master.components["mbd"].slave
        h = s.simulation.step
        for rounds in range(3):  # several states in a row: the walk of the graph is reused between them
            state = master.components["mbd"].get_state()
            assert isinstance(state["attributes"]["system"], RollbackState), "no rollback state: deep copies"
            before = state_codec.encode({"system": slave.system})
            first = _steps(master, slave, h, 4, np.random.default_rng(rounds))
            master.components["mbd"].set_state(state)
            if case != "linear (two floats)":  # its steppers are a shared cache keyed by their inputs
                assert state_codec.encode({"system": slave.system}) == before
            again = _steps(master, slave, h, 4, np.random.default_rng(rounds))
            for a, b in zip(first, again, strict=True):
                np.testing.assert_array_equal(a, b)
            master.components["mbd"].set_state(state)
            master.step(h)
    finally:
        master.terminate()


def test_a_rollback_state_serialises_as_the_model_it_saved() -> None:
    """An FMU state taken as a rollback state and serialised later (a checkpoint), after the model has moved on,
    holds the model as it was when taken: set from its bytes, the steps that follow are those that follow the state
    set in memory, bit for bit."""
    s = apply_overrides(load_scenario(SCENARIOS / "hinge_barge.toml"), ["simulation.error_estimate=none"])
    plan = prepare_run(s, in_process=True, log=None)
    master = plan.master
    h = s.simulation.step
    try:
        master.initialize(0.0, s.simulation.duration, plan.parameter_links)
        master.step(h)
        comp = master.components["mbd"]
        state = comp.get_state()
        _steps(master, comp.slave, h, 3, np.random.default_rng(0))
        data = comp.serialize_state(state)
        comp.set_state(comp.deserialize_state(data))
        from_bytes = _steps(master, comp.slave, h, 3, np.random.default_rng(1))
        comp.set_state(state)
        in_memory = _steps(master, comp.slave, h, 3, np.random.default_rng(1))
        for a, b in zip(from_bytes, in_memory, strict=True):
            np.testing.assert_array_equal(a, b)
    finally:
        master.terminate()
