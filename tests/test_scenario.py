"""Scenario files: loading, validation messages, documentation in sync with the schema."""

from __future__ import annotations

import pytest

from orchestrator.errors import ScenarioError
from orchestrator.scenario import load_scenario, reference_markdown

from .conftest import ROOT, SCENARIOS

BASE = (SCENARIOS / "cylinder_regular.toml").read_text()


def write(tmp_path, text: str):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    (tmp_path / "hydro_cache").mkdir(exist_ok=True)
    return path


def test_bundled_scenarios_load() -> None:
    for path in SCENARIOS.glob("*.toml"):
        s = load_scenario(path)
        assert s.name == path.stem and s.bodies


@pytest.mark.parametrize("edit, fragments", [
    (lambda t: t.replace("duration = 200.0", "duraton = 200.0"),
     ["unknown key 'simulation.duraton'", "Did you mean 'duration'"]),
    (lambda t: t.replace("step = 0.1 ", 'step = "fast" '), ["simulation.step", "expected a number", "'fast'"]),
    (lambda t: t.replace("damping = 2.0e5", "damping = -2.0e5"), ["ptos[0].damping must not be negative"]),
    (lambda t: t.replace("height = 1.0", "height = nan"), ["waves.height", "expected a finite number"]),
    (lambda t: t.replace('body = "float"', 'body = "floater"'), ["body 'floater' is not defined"]),
    (lambda t: t.replace('dof = "heave"', 'dof = "pitch"'), ["dof 'pitch' is not active"]),
    (lambda t: t.replace('dofs = ["heave"]', 'dofs = ["heave", "spin"]'),
     ["bodies[0].dofs[1]", "'spin' is not one of"]),
    (lambda t: t.replace('cg = [0.0, 0.0, -2.5]', 'cg = [0.0, -2.5]'), ["bodies[0].cg", "expected 3 values"]),
    (lambda t: t.replace('shape = "vertical_cylinder"', 'shape = "mesh"\nmesh_file = "nowhere.obj"'),
     ["mesh_file", "nowhere.obj does not exist"]),
    (lambda t: t.replace("[simulation]", "[simulation\n"), ["not valid TOML"]),
    (lambda t: t.replace('name = "float"\n', 'name = "float"\nmass = -3.0\n'), ["bodies[0].mass must be positive"]),
    (lambda t: t.replace("duration = 200.0", ""), ["missing required key 'simulation.duration'"]),
    (lambda t: t.replace('[[ptos]]\nname = "pto"', '[[ptos]]\nname = "float"'), ["name 'float' is used twice"]),
])
def test_invalid_scenarios_name_file_and_key(tmp_path, edit, fragments) -> None:
    assert_rejected(write(tmp_path, edit(BASE)), fragments)


def assert_rejected(path, fragments: list[str]) -> None:
    """Loading ``path`` raises a ScenarioError that names the file and contains every fragment."""
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    message = str(info.value)
    assert str(path) in message
    for fragment in fragments:
        assert fragment in message, message


def test_missing_scenario_file(tmp_path) -> None:
    with pytest.raises(ScenarioError, match="does not exist"):
        load_scenario(tmp_path / "absent.toml")


def test_reference_page_matches_schema() -> None:
    """docs/scenario.md is generated from the schema; regenerate with python -m orchestrator.scenario."""
    assert (ROOT / "docs" / "scenario.md").read_text() == reference_markdown()
