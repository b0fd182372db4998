"""The bench report's hard cases (wec_cosim/benchreport/hard_cases.py): physical expectations on small maps, the
figure."""

from __future__ import annotations

import dataclasses
import math

from wec_cosim.benchreport import hard_cases
from wec_cosim.benchreport.points import ROOT, Point, Variant


def test_explicit_added_mass_diverges_on_a_light_float_while_the_mass_matrix_stays_exact():
    """Partitioned coupling with the added mass as an explicit force is unstable once A_inf > M; with A_inf in the
    multibody mass matrix the same light float stays stable and within 2 % of the frequency-domain answer."""
    spec = dataclasses.replace(
        hard_cases.ADDED_MASS, series=hard_cases.ADDED_MASS.series[:2], quick_hardness_values=(0.5, 30.0),
        quick_steps=(0.2, 0.1))
    lines: list[str] = []
    m = hard_cases.run_map(spec, quick=True, log=lines.append)
    assert len(lines) == 8 and m.hardness_values == [0.5, 30.0] and m.steps == [0.2, 0.1]
    matrix, explicit = m.points["jacobi + mass_matrix"], m.points["jacobi + explicit_force"]
    for row in matrix:
        for p in row:
            assert p.status == "ok" and p.error < 0.02, (p.variant.command(), p.error)
    assert all(p.stable for p in explicit[0]), [p.message for p in explicit[0]]  # A_inf / M = 0.5
    for p in explicit[1]:  # A_inf / M = 30
        assert p.status == "diverged" and "exceeds" in p.message and p.simulated < 10.0
    assert m.stable_fraction("jacobi + explicit_force") == 0.5


def test_the_stiff_pto_spring_has_the_asked_period():
    """The stiffness set for h / T_k = r gives T_k = 2 pi sqrt((M + A_inf) / k) = h / r, with M and A_inf from the
    scene (the displaced mass and the database's infinite-frequency heave added mass)."""
    from orchestrator.scenario import load_scenario
    from orchestrator.scene import load_scene

    scene = load_scene(load_scenario(ROOT / "scenarios/cylinder_regular.toml"), log=None)
    (item,) = hard_cases._spring_for_ratio(scene, 0.5, 0.1)
    k = float(item.partition("=")[2])
    ((_, mass, a_inf),) = hard_cases._heave_bodies(scene)
    assert mass > 0 and a_inf > 0
    assert math.isclose(2 * math.pi * math.sqrt((mass + a_inf) / k), 0.1 / 0.5, rel_tol=1e-5)


def test_map_figure_writes_a_png_with_a_diverged_point(tmp_path):
    v = Variant("scenarios/light_float.toml")
    ok = [[Point(v, "ok", 0.1, 120.0, error=e) for e in row] for row in ((1e-3, 4e-4), (5e-3, 2e-3))]
    mixed = [[Point(v, "ok", 0.1, 120.0, error=0.05), Point(v, "ok", 0.1, 120.0)],
             [Point(v, "diverged", math.nan, 0.8, message="diverged"), Point(v, "failed", math.nan, 0.0)]]
    m = hard_cases.StabilityMap("demo", "A demo map", "A_inf / M (heave)", [1.0, 30.0], [0.2, 0.1], "an error",
                                {"mass_matrix": ok, "explicit_force": mixed})
    path = tmp_path / "maps" / "demo.png"
    hard_cases.map_figure(m, path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 10_000


def test_a_pto_spring_one_macro_step_long_resonates_with_the_held_input():
    """The force input is held or ramped over each macro step; its step rhythm (kinks every h) drives a spring mode
    whose period is exactly h at resonance: the steady response is then wrong by ~100 %, while at h / T_k = 1.5 it
    is within 1 % of the frequency-domain answer (a stable run either way)."""
    spec = dataclasses.replace(hard_cases.STIFF_PTO, series=hard_cases.STIFF_PTO.series[:1],
                               quick_hardness_values=(1.0, 1.5), quick_steps=(0.1,))
    m = hard_cases.run_map(spec, quick=True, log=lambda line: None)
    (resonant,), (off,) = m.points["jacobi"]
    assert resonant.stable and off.stable
    assert resonant.error > 0.5 and off.error < 0.01, (resonant.error, off.error)


def test_long_run_measures_hold_the_constraint_and_the_energy_balance():
    """A minute of the hinge barge in the long run's sea: the constraint residual stays at round-off and the
    wave-to-wire energy balance closes to 1 % of the work the waves did (physical invariants)."""
    from wec_cosim.benchreport.points import run_point

    variant = Variant("scenarios/hinge_barge.toml", (*hard_cases.LONG_SEA, "simulation.duration=60"))
    p = run_point(variant, measures=hard_cases._long_run_measures(20.0))
    assert p.status == "ok", p.message
    assert p.extra["max_violation"] < 1e-9
    assert p.extra["first_violation"] <= p.extra["max_violation"] and p.extra["last_violation"] <= p.extra[
        "max_violation"]
    assert p.extra["energy_residual"] <= p.extra["largest_energy_residual"] < 0.01
