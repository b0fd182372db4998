"""Masters on the two-body scene (two interacting floats, FMUs through fmpy): co-simulation error
against the monolithic reference, measured convergence orders, iterative = monolithic, adaptive step.

Reference: the monolithic run (the same physics in one process, strongly coupled, no FMI) at
h = 0.0125 s and 0.00625 s, Richardson-extrapolated (its own error is below 1e-8 relative here,
four orders under the smallest co-simulation error measured)."""

from __future__ import annotations

import numpy as np
import pytest

from orchestrator.cosim import study
from orchestrator.cosim.masters import step_average_weights
from orchestrator.cosim.simulation import prepare_run
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS

STEPS = [0.1, 0.05, 0.025]
DURATION = 20.0


@pytest.fixture(scope="module")
def two_floats():
    s = load_scenario(SCENARIOS / "two_floats.toml")
    s.simulation.duration = DURATION
    scene = load_scene(s, log=None)
    return s, scene, study.reference(s, 0.0125, scene)


def test_reference_is_converged(two_floats) -> None:
    """The monolithic scheme is second order and the Richardson reference is far below every error."""
    s, scene, ref = two_floats
    errors = [study.error(study.run_series(study.variant(s, "monolithic", h), scene=scene), ref) for h in STEPS]
    assert np.all(np.abs(study.orders(STEPS, errors) - 2.0) < 0.05), errors
    finer = study.reference(s, 0.00625, scene)
    assert study.error(ref, finer) < 1e-4 * errors[-1]


# Expected orders: a zero-order hold lags by h/2 (order 1); any p >= 1 makes the step average right to
# O(h^2) or better, but the input stays constant within the step, which leaves O(h^2) (docs/masters.md).
@pytest.mark.parametrize("master", ["jacobi", "gauss_seidel", "aitken", "iqn_ils"])
@pytest.mark.parametrize("extrapolation, order", [(0, 1.0), (1, 2.0), (2, 2.0)])
def test_convergence_order_against_monolithic(two_floats, master, extrapolation, order) -> None:
    s, scene, ref = two_floats
    errors = [study.error(study.run_series(study.variant(s, master, h, extrapolation), scene=scene), ref)
              for h in STEPS]
    observed = study.orders(STEPS, errors)
    assert np.all(np.abs(observed - order) < 0.25), (errors, observed)
    assert errors[-1] < (0.1 if extrapolation == 0 else 2e-3), errors


def test_linearised_interface_is_second_order_in_a_plain_host(two_floats) -> None:
    """The plain fixed-step host (outputs read right after each step, zero-order hold, no iteration) with the
    linearised force interface (hydro_fmu.linearisation): order 2, and more accurate than our best explicit
    master with the force interface (Jacobi, p = 2) at every step (measured 2.2e-3 against 3.4e-3 at 0.1 s);
    the same host with the force interface is first order (test_convergence_order_against_monolithic, p = 0)."""
    s, scene, ref = two_floats
    plain = [study.error(study.run_series(study.variant(s, "jacobi", h, 0, interface="linearised", plain_host=True),
                                          scene=scene), ref) for h in STEPS]
    observed = study.orders(STEPS, plain)
    assert np.all(np.abs(observed - 2.0) < 0.1), (plain, observed)
    best = [study.error(study.run_series(study.variant(s, "jacobi", h, 2), scene=scene), ref) for h in STEPS[:1]]
    assert plain[0] < best[0], (plain, best)


def test_converged_iterative_step_is_the_monolithic_scheme(two_floats) -> None:
    """With linear interpolation (p = 1) the converged iteration is the trapezoidal force average of the
    monolithic mode: two independent implementations (FMUs + rollback vs. one process) agree to the
    iteration tolerance."""
    s, scene, _ = two_floats
    mono = study.run_series(study.variant(s, "monolithic", 0.05), scene=scene)
    for solver in ("iqn_ils", "aitken"):
        it = study.run_series(study.variant(s, solver, 0.05, 1), scene=scene)
        assert study.error(it, mono) < 1e-8


def test_iqn_ils_needs_fewer_evaluations_than_aitken(two_floats) -> None:
    s, scene, _ = two_floats
    aitken = study.run_series(study.variant(s, "aitken", 0.05), scene=scene)
    iqn = study.run_series(study.variant(s, "iqn_ils", 0.05), scene=scene)
    assert iqn.evaluations < aitken.evaluations


def adaptive_run(s, scene, tolerance):
    v = study.variant(s, "jacobi", 0.025)
    v.simulation.adaptive.enabled = True
    v.simulation.adaptive.max_step = 0.4
    v.simulation.adaptive.tolerance = tolerance
    plan = prepare_run(v, log=None, scene=scene)
    names = plan.master.output_names["mbd"]
    cols = [names.index("fore.x[3]"), names.index("aft.x[3]")]
    times, rows = [], []
    plan.master.initialize(0.0, DURATION, plan.parameter_links)
    plan.master.run(DURATION, 0.025, lambda t, o: (times.append(t), rows.append(o["mbd"][cols].copy())),
                    controller=plan.controller)
    plan.master.terminate()
    return plan.controller, np.array(times), np.array(rows)


def test_energy_based_adaptive_step(two_floats) -> None:
    """Steps are whole multiples of the radiation grid and end exactly at the stop time; a tighter
    tolerance on the bonds' energy mismatch gives smaller steps and a smaller error."""
    s, scene, ref = two_floats
    results = []
    for tol in (0.03, 0.003):
        controller, t, x = adaptive_run(s, scene, tol)
        ticks = np.array(controller.sizes) / 0.025
        assert np.allclose(ticks, np.round(ticks), atol=1e-9) and ticks.min() >= 1 and ticks.max() <= 16
        assert t[-1] == pytest.approx(DURATION, abs=1e-12) and np.all(np.diff(t) > 0)
        assert len(set(np.round(ticks))) > 2  # the step really changes
        exact = np.column_stack([np.interp(t, ref.time, ref.displacement[:, j]) for j in range(2)])
        results.append((np.mean(controller.sizes), np.max(np.abs(x - exact)) / np.max(np.abs(ref.displacement))))
    (h_loose, e_loose), (h_tight, e_tight) = results
    assert h_tight < h_loose and e_tight < 0.3 * e_loose


def test_step_average_weights_of_an_interpolation() -> None:
    """Through u_{n+1}, u_n, u_{n-1}: the step average of the quadratic is (5 u_{n+1} + 8 u_n - u_{n-1}) / 12."""
    np.testing.assert_allclose(step_average_weights([1.0, 0.0, -1.0], 1.0), [5 / 12, 8 / 12, -1 / 12])


def test_monolithic_mode_converges_to_the_exact_time_domain_answer(tmp_path) -> None:
    """Physics check of the reference itself: the cylinder's steady heave in the monolithic mode against the
    exact frequency-domain answer of the time-domain model (radiation from the sampled impulse response),
    error falling at order 2."""
    import math

    from orchestrator.reference import frequency_domain
    from orchestrator.results.analysis import harmonic_fit, steady_window

    period = 6.0
    errors = []
    for n in (50, 100):
        s = load_scenario(SCENARIOS / "cylinder_regular.toml")
        s.waves.period, s.waves.ramp_time = period, 3 * period
        s.simulation.master, s.simulation.step, s.simulation.duration = "monolithic", period / n, 30 * period
        scene = load_scene(s, log=None)
        exact = frequency_domain.solve(scene, np.array([2 * math.pi / period]), radiation="impulse_response",
                                       dt=0.002).rao[0, 0] * s.waves.height / 2
        run = study.run_series(s, scene=scene)
        mask = steady_window(run.time, period, 10)
        amp, _ = harmonic_fit(run.time[mask], run.displacement[mask, 0], 2 * math.pi / period)
        errors.append(abs(amp - exact) / abs(exact))
    assert errors[0] < 1e-2 and 1.8 < math.log2(errors[0] / errors[1]) < 2.3, errors
