"""A body twenty times lighter than its infinite-frequency added mass (scenarios/light_float.toml):
mode (b) diverges and stops with an explanation; modes (a) and (c) are stable and agree with the
exact frequency-domain answer within 1 %. Mode (c) couples the hydro FMU to a separate
third-party-style multibody FMU (plain_mbd_fmu) that has no added-mass parameters."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from fmpy import read_model_description

from orchestrator.cosim.simulation import run_scenario
from orchestrator.errors import MasterError, ScenarioError
from orchestrator.fmi.fmu_builder import PLAIN_MBD, build_fmu, cache_dir
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import ROOT, SCENARIOS

PATH = SCENARIOS / "light_float.toml"


def scenario(master: str, added_mass: str):
    s = load_scenario(PATH)
    s.simulation.master = master
    s.simulation.added_mass = added_mass
    return s


def test_the_body_is_twenty_times_lighter_than_its_added_mass() -> None:
    s = load_scenario(PATH)
    scene = load_scene(s, log=None)
    assert scene.hdb.added_mass_inf[2, 2] / s.bodies[0].mass == pytest.approx(20.0, rel=1e-5)


@pytest.mark.parametrize("master, mode", [("jacobi", "mass_matrix"), ("iqn_ils", "interface")])
def test_stable_modes_match_the_frequency_domain(tmp_path, master, mode) -> None:
    result = run_scenario(scenario(master, mode), tmp_path / "run.h5", progress=False, log=None)
    heave, power = result.comparisons
    assert abs(heave.amplitude_error) < 0.01, heave
    assert abs(heave.phase_error_deg) < 1.0, heave
    assert abs(power.amplitude_error) < 0.01, power


def test_interface_mode_uses_a_multibody_fmu_without_added_mass(tmp_path) -> None:
    scene = load_scene(load_scenario(PATH), log=None)
    fmu = build_fmu(PLAIN_MBD, scene.mbd_spec(), {}, cache_dir())
    md = read_model_description(str(fmu))
    names = {v.name for v in md.modelVariables}
    assert "float.F[3]" in names and "float.v[3]" in names
    assert not any(n.startswith("A_inf") for n in names)
    assert md.coSimulation.modelIdentifier == "WecPlainMultibody"


def test_explicit_added_mass_force_diverges_with_an_explanation(tmp_path) -> None:
    with pytest.raises(MasterError) as info:
        run_scenario(scenario("jacobi", "explicit_force"), tmp_path / "b.h5", progress=False, log=None)
    message = str(info.value)
    for fragment in ("diverged", "explicit_force", "previous step's acceleration", "20 times the mass",
                     "added_mass = 'mass_matrix'", "'interface'", str(tmp_path / "b.h5")):
        assert fragment in message, message


def test_divergence_is_one_paragraph_from_the_cli(tmp_path) -> None:
    text = PATH.read_text().replace('added_mass = "mass_matrix"', 'added_mass = "explicit_force"')
    path = tmp_path / "light.toml"
    path.write_text(text.replace("[hydro]", f'[hydro]\ncache_dir = "{SCENARIOS / "hydro_cache"}"'))
    proc = subprocess.run([sys.executable, "-m", "wec_cosim.cli", "run", str(path), "--out",
                           str(tmp_path / "b.h5"), "--quiet"], capture_output=True, text=True, cwd=ROOT,
                          env=os.environ.copy(), timeout=300)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1
    assert "unstable" in proc.stderr and "mass_matrix" in proc.stderr


def test_interface_mode_needs_an_iterative_master(tmp_path) -> None:
    text = PATH.read_text().replace('added_mass = "mass_matrix"', 'added_mass = "interface"')
    path = tmp_path / "light.toml"
    path.write_text(text)
    with pytest.raises(ScenarioError, match="needs an iterative master"):
        load_scenario(path)
