"""Scenario files: loading, validation messages, documentation in sync with the schema."""

from __future__ import annotations

import numpy as np
import pytest

from orchestrator.errors import ScenarioError
from orchestrator.scenario import load_scenario
from orchestrator.scenario.reference_doc import reference_markdown

from .conftest import ROOT, SCENARIOS

BASE = (SCENARIOS / "cylinder_regular.toml").read_text()
REFINE = "irf_duration = 40.0\nomega_refine = "


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
    (lambda t: t.replace('kind = "regular"', 'kind = "irregular"'), ["kind = 'irregular' needs a positive hs"]),
    (lambda t: t.replace('kind = "regular"', 'kind = "irregular"\nhs = 2.0'),
     ["spectrum = 'jonswap' needs a positive tp"]),
    (lambda t: t.replace('kind = "regular"', 'kind = "irregular"\nhs = 2.0\ntp = 8.0\nspectrum = "ochi"'),
     ["waves.spectrum", "'ochi' is not one of"]),
    (lambda t: t.replace('kind = "regular"', 'kind = "elevation"\nelevation_file = "sea.csv"'),
     ["waves.elevation_file", "sea.csv does not exist"]),
    (lambda t: t.replace('kind = "regular"', 'kind = "irregular"\nhs = 2.0\ntp = 8.0\nspreading_s = 4.0').replace(
        "irf_duration = 40.0", 'irf_duration = 40.0\nexcitation_method = "convolution"'),
     ["needs a unidirectional sea"]),
    (lambda t: t.replace('dofs = ["heave"]', 'dofs = ["heave"]\ndrag_coefficient = [0, 0, 1, 0, 0, 0]'),
     ["drag_coefficient and drag_area go together"]),
    (lambda t: t.replace('dofs = ["heave"]', 'dofs = ["heave"]\nlinear_damping = [0, 0, 1, 0, 0]'),
     ["bodies[0].linear_damping needs 6 values"]),
    (lambda t: t.replace("irf_duration = 40.0", "irf_duration = 40.0\nstate_space_tolerance = 1.5"),
     ["hydro.state_space_tolerance must be between 0 and 1"]),
    (lambda t: t.replace("irf_duration = 40.0", 'irf_duration = 40.0\nradiation_method = "ss"'),
     ["hydro.radiation_method", "'ss' is not one of"]),
    (lambda t: t.replace("panel_size = 0.6", "panel_size = 0.6\nrotation_deg = [0, 90]"),
     ["geometry.rotation_deg", "expected 3 values"]),
    (lambda t: t.replace("irf_duration = 40.0", 'irf_duration = 40.0\nbem_symmetry = "D1"'),
     ["hydro.bem_symmetry", "unknown BEM symmetry 'D1'"]),
    (lambda t: t.replace('shape = "vertical_cylinder"', 'shape = "regular_prism"\nsides = 2'),
     ["geometry shape 'regular_prism' needs sides >= 3"]),
    (lambda t: t + '\n[multibody]\nformulation = "linear"\nstatic_equilibrium = true\n',
     ["multibody.static_equilibrium needs a nonlinear formulation"]),
    (lambda t: t + '\n[control]\nmode = "lockstep"\nperiod = 0.15\n',
     ["control.period", "whole number of macro steps"]),
    (lambda t: t + '\n[control]\nmode = "lockstep"\nptos = ["pump"]\n', ["PTO 'pump' is not defined"]),
    (lambda t: t + '\n[control]\nmode = "lockstep"\nrun_id = "a/b"\n', ["control.run_id", "letters, digits"]),
    (lambda t: t + '\n[control]\nmode = "manual"\n', ["control.mode", "'manual' is not one of"]),
    (lambda t: t + '\n[control]\nmode = "lockstep"\ndamping_limits = [5.0, 1.0]\n', ["control.damping_limits"]),
    # [simulation] keys of the masters
    (lambda t: t.replace("extrapolation = 2 ", 'master = "newton"\nextrapolation = 2 '),
     ["simulation.master", "'newton' is not one of", "'iqn_ils'"]),
    (lambda t: t.replace("extrapolation = 2 ", 'added_mass = "none"\nextrapolation = 2 '),
     ["simulation.added_mass", "'none' is not one of"]),
    (lambda t: t.replace("extrapolation = 2 ", 'added_mass = "interface"\nextrapolation = 2 '),
     ["needs an iterative master", "'iqn_ils'"]),
    (lambda t: t.replace("extrapolation = 2 ", 'master = "monolithic"\nadded_mass = "explicit_force"\n'),
     ["simulation.master = 'monolithic'"]),
    (lambda t: t.replace("extrapolation = 2 ", 'master = "monolithic"\nextrapolation = 2 ')
     + '\n[multibody]\nformulation = "index3"\n', ["'monolithic' steps only the linear multibody model"]),
    (lambda t: t.replace("extrapolation = 2 ", "extrapolation = 3 "), ["simulation.extrapolation must be 0, 1 or 2"]),
    (lambda t: t + '\n[mooring_lines]\ncoupled_bodies = ["float"]\n',
     ["mooring_lines.coupled_bodies is set but mooring_lines.moordyn_file is not"]),
    (lambda t: t + '\n[mooring_lines]\nmoordyn_file = "no_such_lines.txt"\ncoupled_bodies = ["float"]\n',
     ["mooring_lines.moordyn_file", "no_such_lines.txt does not exist"]),
    (lambda t: t.replace("extrapolation = 2 ", "extrapolation = 2.0 "),
     ["simulation.extrapolation: expected an integer"]),
    (lambda t: t.replace("extrapolation = 2 ", "tolerance = -1e-9\n"), ["simulation.tolerance must be positive"]),
    (lambda t: t.replace("extrapolation = 2 ", "max_iterations = 0\n"), ["simulation.max_iterations must be positive"]),
    (lambda t: t.replace("extrapolation = 2 ", "checkpoint_every = inf\n"),
     ["simulation.checkpoint_every: expected a finite number"]),
    (lambda t: t.replace("extrapolation = 2 ", "resolve_feedthrough = false\n"),
     ["resolve_feedthrough = false", "extrapolation = 0"]),
    (lambda t: t.replace("extrapolation = 2 ", 'interface = "linearised"\nextrapolation = 2 '),
     ["simulation.interface = 'linearised'", "extrapolation = 0"]),
    (lambda t: t.replace("extrapolation = 2 ", 'interface = "linear"\n'), ["simulation.interface"]),
    (lambda t: t.replace("[environment]", "[simulation.adaptive]\nenabled = true\nmax_step = 0.05\n\n[environment]"),
     ["simulation.adaptive.max_step (0.05 s) is smaller than simulation.step"]),
    (lambda t: t.replace("[environment]", "[simulation.adaptive]\nenabeld = true\n\n[environment]"),
     ["unknown key 'simulation.adaptive.enabeld'", "Did you mean 'enabled'"]),
    (lambda t: t.replace("[environment]", "[simulation.adaptive]\nsafety = 1.5\n\n[environment]"),
     ["safety < 1"]),
    (lambda t: t + "\n[sweep]\nseeds = 0\n", ["sweep.seeds must be positive"]),
    (lambda t: t + "\n[sweep]\ngrid = [1.0]\n", ["sweep.grid: expected a table"]),
    (lambda t: t + "\n[sweep]\nparameter = 'waves.height'\nvalues = [1.0, 2.0]\nperiods = [5.0]\n",
     ["[sweep.grid]", "waves.height = [1.0, 2.0]; waves.period = [5.0]"]),
    (lambda t: t.replace("irf_duration = 40.0", REFINE + "[{ start = 1.0, stop = 0.9, step = 0.01 }]"),
     ["hydro.omega_refine[0]: stop must be larger than start"]),
    (lambda t: t.replace("irf_duration = 40.0", REFINE + "[{ start = 1.0, stop = 1.2 }]"),
     ["missing required key 'hydro.omega_refine[0].step'"]),
    (lambda t: t.replace("irf_duration = 40.0", "irf_duration = 40.0\ndamping_tail = -3"),
     ["hydro.damping_tail must not be negative"]),
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


def test_refined_frequency_grids_are_merged_into_the_bem_grid(tmp_path) -> None:
    """hydro.omega_refine adds its frequencies to hydro.omega (shared ones once, sorted); without it the grid,
    and so the database's cache key, is hydro.omega's alone."""
    from hydro_fmu.bem import frequency_grid
    from orchestrator.scene.database import bem_inputs

    plain = load_scenario(write(tmp_path, BASE))
    g = plain.hydro.omega
    assert bem_inputs(plain)[1].omega == frequency_grid(g.start, g.stop, g.step)
    refined = load_scenario(write(tmp_path, BASE.replace(
        "irf_duration = 40.0", REFINE + "[{ start = 1.0, stop = 1.2, step = 0.01 }]")))
    omega = refined.hydro.omega
    grid = bem_inputs(refined)[1].omega
    extra = frequency_grid(1.0, 1.2, 0.01)
    assert set(frequency_grid(omega.start, omega.stop, omega.step)) <= set(grid) and set(extra) <= set(grid)
    assert list(grid) == sorted(set(grid)) and np.min(np.diff(grid)) > 1e-9
