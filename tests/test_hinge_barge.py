"""Seed 003's two-body hinge-barge in regular waves: multibody FMU (joints, point-to-point PTO,
mooring) co-simulated with the hydrodynamics FMU; DAE and reduced-ODE forms; exact linear answer.

Database: Capytaine 3.0 multibody BEM of the two barges, cached in scenarios/hydro_cache/.
"""

from __future__ import annotations

import numpy as np
import pytest

from orchestrator.cosim.simulation import run_scenario
from orchestrator.reference import frequency_domain
from orchestrator.results import read_results
from orchestrator.results.analysis import harmonic_fit, steady_window
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS

SCENARIO = SCENARIOS / "hinge_barge.toml"


def scenario(formulation: str = "index3", duration: float | None = None, max_step: float | None = None):
    s = load_scenario(SCENARIO)
    s.multibody.formulation = formulation
    if duration is not None:
        s.simulation.duration = duration
    if max_step is not None:
        s.multibody.max_step = max_step
    return s


def test_mobility_of_the_planar_hinge_barge() -> None:
    """Two planar bodies (surge, heave, pitch) and a hinge: 4 DOF; the hinge's three out-of-plane
    equations (y coincidence, rows 1-3 being x, y, z, and the two axis alignments, rows 4-5) are
    redundant: both bodies already move in the x-z plane."""
    sim = load_scene(scenario(), log=None).multibody_simulator()
    assert sim.report.dof == 4
    assert sorted(sim.report.redundant) == ["hinge[2]", "hinge[4]", "hinge[5]"]


@pytest.mark.parametrize("name", ["hinge_barge", "f3of_dt3"])
def test_the_run_reports_the_mobility_the_started_simulator_finds(name: str) -> None:
    """The mobility written into results files (assembly analysis only, no integrator start) is the report of the
    started multibody simulator, redundant rows included (F3OF: 16 equations of rank 5)."""
    from orchestrator.cosim.simulation import mobility

    scene = load_scene(load_scenario(SCENARIOS / f"{name}.toml"), log=None)
    report = scene.multibody_simulator().report
    found = mobility(scene)
    assert (found["dof"], found["rank"], found["constraints"], found["redundant"], found["summary"]) == (
        report.dof, report.rank, report.constraints, list(report.redundant), report.summary())


def test_linearised_hinge_barge_is_in_equilibrium_and_stable() -> None:
    from mbd_fmu.linearize import linearize

    scene = load_scene(scenario(), log=None)
    lin = linearize(scene.multibody_simulator().model)
    assert lin.equilibrium_residual < 1e-9 * scene.hdb.rho * scene.hdb.g
    assert lin.null_space.shape == (6, 4)


def motion(tmp_path, formulation: str, duration: float, max_step: float, name: str) -> np.ndarray:
    s = scenario(formulation, duration, max_step)
    run_scenario(s, tmp_path / f"{name}.h5", in_process=True, progress=False, log=None)
    data = read_results(tmp_path / f"{name}.h5")
    return np.hstack([data["bodies/barge1/displacement"], data["bodies/barge2/displacement"]])


def test_dae_and_reduced_ode_forms_give_the_same_motion(tmp_path) -> None:
    """Index-1 DAE (Lagrange multipliers, RK4 + projection) and the null-space reduced ODE (RK4)
    co-simulated with the same hydrodynamics agree to 1e-6 of the motion amplitude over 4 s; the
    index-3 DAE (generalised-alpha) converges to the same motion at second order."""
    dae = motion(tmp_path, "index1", 4.0, 0.01, "dae")
    ode = motion(tmp_path, "nullspace", 4.0, 0.01, "ode")
    scale = np.max(np.abs(ode), axis=0)
    scale[scale == 0] = 1.0
    assert np.max(np.abs(dae - ode) / scale) < 1e-6
    errors = [np.max(np.abs(motion(tmp_path, "index3", 4.0, h, f"i3_{k}") - ode) / scale)
              for k, h in enumerate((0.01, 0.005))]
    assert np.log2(errors[0] / errors[1]) == pytest.approx(2.0, abs=0.3), errors


def test_cosimulated_hinge_barge_matches_the_exact_frequency_domain_answer(tmp_path) -> None:
    """FMUs through fmpy, 40 s of 2 cm waves at T = 2 s: steady heave and pitch of both barges and the
    PTO's mean power against the constrained frequency-domain solution of the linearised system."""
    result = run_scenario(scenario(), tmp_path / "run.h5", progress=False, log=None)
    by_label = {c.label: c for c in result.comparisons}
    for label in ("barge1 heave", "barge1 pitch", "barge2 heave", "barge2 pitch"):
        c = by_label[label]
        assert abs(c.amplitude_error) < 0.02, c
        assert abs(c.phase_error_deg) < 2.0, c
    assert abs(by_label["pto mean power"].amplitude_error) < 0.03
    # The results file holds the hinge's angle and reaction: against the constrained frequency-domain answer
    # (DAE form: the reaction from the dynamic Lagrange multipliers), and the energy account closes.
    s = scenario()
    data = read_results(tmp_path / "run.h5")
    fd = frequency_domain.solve(load_scene(s, log=None), np.array([2 * np.pi / s.waves.period]), form="dae")
    angle = hinge_errors(s, data, fd)[0]
    assert abs(angle[0]) < 0.01 and abs(angle[1]) < 1.0
    # The reaction is algebraic in the hydrodynamic force, which the master holds over each macro step:
    # its error is first order in the step (about omega h / 2 = 3 % at h = T/100) and halves with the step.
    coarse = hinge_errors(s, data, fd)[1:]
    s.simulation.step = s.multibody.max_step = 0.01
    run_scenario(s, tmp_path / "fine.h5", in_process=True, progress=False, log=None)
    fine = hinge_errors(s, read_results(tmp_path / "fine.h5"), fd)[1:]
    for (a2, p2), (a1, p1) in zip(coarse, fine, strict=True):
        assert abs(a2) < 0.05 and abs(p2) < 5.0
        assert abs(a2) / abs(a1) > 1.6 and abs(p2) / max(abs(p1), 1e-3) > 1.6
    energy = {k: data[f"energy/{k}"] for k in ("dissipated", "external_work", "balance")}
    assert np.max(np.abs(energy["balance"])) < 0.01 * np.max(np.abs(energy["external_work"]))
    # The PTO is the only damper: its energy is the dissipation, and the integral of its recorded power
    # (a pure dash-pot: no stored part); the wave-to-wire account closes (docs/results.md).
    pto = data["energy/pto"]
    np.testing.assert_allclose(pto, energy["dissipated"], rtol=1e-12, atol=1e-12)
    power_integral = np.trapezoid(data["ptos/pto/power"], data["time"])
    assert pto[-1] == pytest.approx(power_integral, rel=1e-3)
    assert abs(data["energy/wave_balance"][-1]) < 0.01 * data["energy/excitation_work"][-1]


def hinge_errors(s, data: dict, fd) -> list[tuple[float, float]]:
    """(relative amplitude error, phase error in degrees) of the hinge angle and of the x and z reaction
    force over the steady window, against the frequency-domain answer ``fd`` (one frequency)."""
    omega, amplitude = 2 * np.pi / s.waves.period, s.waves.height / 2
    mask = steady_window(data["time"], s.waves.period, s.simulation.steady_periods)
    t = data["time"][mask]
    pairs = [(data["joints/hinge/coordinate"][mask, 0], fd.joint_rao["hinge"][0, 0])]
    pairs += [(data["joints/hinge/force"][mask, k], fd.reaction_rao["hinge"][0, k]) for k in (0, 2)]
    out = []
    for series, exact in pairs:
        measured, _ = harmonic_fit(t, series, omega)
        out.append((abs(measured) / (amplitude * abs(exact)) - 1, float(np.degrees(np.angle(measured / exact)))))
    return out
