"""The iterative masters' convergence test (orchestrator.cosim.masters, IterativeMaster): stated, and checked here
from the outside on F3OF DT3, whose fixed base's surge sits on the interface with round-off values (1e-20 m/s).

Stated test: for every interface variable i, |r_i| <= max(tolerance S_i, precision), S_i the largest magnitude
reached so far (at any communication point or in the last evaluation) by the interface variables of i's kind (same
FMU, same unit), precision the multibody FMU's own accuracy (10 x its Newton tolerance x the scene's length scale).
Measured against each variable's own running maximum (the test before), the base's round-off could never converge
and the runs stopped within the first steps; with it, IQN-ILS converges in two or three evaluations per step.
"""

from __future__ import annotations

import numpy as np
import pytest

from orchestrator.cosim.simulation import multibody_precision, prepare_run
from orchestrator.scenario import apply_overrides, load_scenario

from .conftest import SCENARIOS

STEPS = 25


@pytest.mark.parametrize("solver", ["iqn_ils", "aitken"])
def test_the_convergence_test_holds_at_every_exit_and_a_fixed_body_does_not_stall_it(solver) -> None:
    s = apply_overrides(load_scenario(SCENARIOS / "f3of_dt3.toml"),
                        [f"simulation.master={solver}", "simulation.step=0.2", "simulation.error_estimate=none"])
    plan = prepare_run(s, in_process=True, log=None)
    m = plan.master
    exits: list[tuple[np.ndarray, np.ndarray]] = []  # (residual, outputs) where the master said converged
    converged = m._converged

    def recording(r: np.ndarray, y: np.ndarray) -> bool:
        ok = converged(r, y)
        if ok:
            exits.append((r.copy(), y.copy()))
        return ok

    m._converged = recording
    try:
        m.initialize(0.0, s.simulation.duration, plan.parameter_links)
        names = [v for c in m.integrators for v in m.output_names[c][: m.n_connected[c]]]
        units = [m.components[c].variables[v].unit for c in m.integrators
                 for v in m.output_names[c][: m.n_connected[c]]]
        history = [m._pack(m.outputs)]  # the interface values at every communication point
        for _ in range(STEPS):
            m.step(s.simulation.step)
            history.append(m._pack(m.outputs))
    finally:
        m.terminate()
    assert len(exits) == STEPS
    base = [i for i, n in enumerate(names) if n.startswith("base.")]
    assert base and np.max(np.abs(np.array(history)[:, base])) < 1e-12  # the fixed base: round-off only
    tolerance, precision = s.simulation.tolerance, multibody_precision(s)
    assert precision == pytest.approx(10 * 1e-10 * 12.5)  # the flaps' cg at 12.5 m
    for k, (r, y) in enumerate(exits):
        seen = np.max(np.abs(np.array(history[: k + 1])), axis=0)  # points before this step's end
        running = np.maximum(seen, np.abs(y))
        scale = np.array([max(running[j] for j in range(len(units)) if units[j] == u) for u in units])
        assert np.all(np.abs(r) <= np.maximum(tolerance * scale, precision)), (k, r, scale)
    evaluations = np.mean(m.iterations)
    print(f"\n{solver}: {evaluations:.2f} evaluations per step, at most {max(m.iterations)}")
    assert evaluations <= (3.5 if solver == "iqn_ils" else 8.0)
