"""A macro step that aliases a fast mode onto the waves is said in the run's first lines (cosim.step_checks).

The floating cylinder with a stiff PTO spring of natural period T_k: at h = T_k (the mode seen at zero frequency,
among the waves) the held force drives the spring at resonance and the steady heave is far off the exact answer;
at h = 1.5 T_k the mode appears at the Nyquist frequency, far from the waves, and the run is right. The warning must
come exactly where the run is wrong, and name the mode's period and a safe step.
"""

from __future__ import annotations

import math
import re

import pytest

from orchestrator.cosim.simulation import format_summary, run_scenario
from orchestrator.cosim.step_checks import aliasing_warnings, undamped_modes
from orchestrator.scenario import apply_overrides, load_scenario
from orchestrator.scene import Scene, load_scene

from .conftest import SCENARIOS

STEP = 0.1  # s


@pytest.fixture(scope="module")
def cylinder():
    scenario = load_scenario(SCENARIOS / "cylinder_regular.toml")
    return scenario, load_scene(scenario, log=None)


def with_spring(cylinder, ratio: float) -> Scene:
    """The cylinder with a PTO spring of natural period STEP / ratio (mass and A_inf of its heave)."""
    scenario, scene = cylinder
    mass = scene.body_mass(scenario.bodies[0])
    a_inf = float(scene.hdb.added_mass_inf[2, 2])
    k = (mass + a_inf) * (2 * math.pi * ratio / STEP) ** 2
    s = apply_overrides(scenario, [f"ptos.{scenario.ptos[0].name}.stiffness={k:.9g}", f"simulation.step={STEP}",
                                   "simulation.error_estimate=none"])
    return Scene(s, scene.hdb, scene.hdb_file)


def test_the_spring_mode_is_found(cylinder) -> None:
    scene = with_spring(cylinder, 1.0)
    modes = undamped_modes(scene)
    assert max(modes) == pytest.approx(2 * math.pi / STEP, rel=0.02)  # hydrostatics add 0.1 % to k here


@pytest.mark.parametrize("ratio, warned", [(1.0, True), (0.95, True), (3.0, True), (1.5, False), (0.3, False)])
def test_a_warning_where_the_step_aliases_the_spring_onto_the_waves(cylinder, ratio, warned) -> None:
    warnings = aliasing_warnings(with_spring(cylinder, ratio))
    assert bool(warnings) == warned, warnings
    if warned:
        period = float(re.search(r"\(period ([0-9.e+-]+) s", warnings[0]).group(1))
        safe = float(re.search(r"below half its period \(([0-9.e+-]+) s\)", warnings[0]).group(1))
        assert period == pytest.approx(STEP / ratio, rel=0.01) and safe == pytest.approx(period / 2, rel=0.01)


@pytest.mark.parametrize("ratio", [1.0, 1.5])
def test_the_warning_comes_where_the_run_is_wrong(cylinder, ratio, tmp_path) -> None:
    """h = T_k: the heave far off the exact answer, and the summary says why; h = 1.5 T_k: within 1 %, no
    warning."""
    scene = with_spring(cylinder, ratio)
    result = run_scenario(scene.scenario, tmp_path / "r.h5", in_process=True, log=None, progress=False, scene=scene)
    heave = next(c for c in result.comparisons if c.label == "float heave")
    error = abs(heave.measured - heave.exact) / abs(heave.exact)
    summary = format_summary(result)
    if ratio == 1.0:
        assert error > 0.3 and "drives it at resonance" in summary, (error, summary)
    else:
        assert error < 0.01 and "drives it at resonance" not in summary, (error, summary)
