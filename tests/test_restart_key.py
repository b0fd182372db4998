"""`multibody.restart` reaches the generalised-alpha formulation, and both restarts give the same motion.

The two restarts differ only in how the algorithmic acceleration is reset when the held inputs change
(module docstring of mbd_fmu/formulations.py); both are second order (tests/test_multibody_mechanisms.py::
test_restart_at_input_jumps_keeps_second_order), so on the hinge barge in waves their difference must be
well below the time-stepping error itself (the default step's steady errors against the frequency-domain
answer are up to 0.04 % of the amplitude, benchmarks/results/speed.txt): bound 1e-4 of each series' range
(measured 1e-6 on the motions, 5e-5 on the PTO power).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mbd_fmu.spec import build_simulator
from orchestrator.cosim.simulation import run_scenario
from orchestrator.errors import ScenarioError
from orchestrator.results import read_results
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

SCENARIO = Path(__file__).resolve().parents[1] / "scenarios" / "hinge_barge.toml"


def test_restart_key_reaches_the_formulation() -> None:
    s = load_scenario(SCENARIO)
    s.multibody.restart = "increment"
    sim = build_simulator(load_scene(s, log=None).mbd_spec())
    assert sim.formulation.settings.restart == "increment"


def test_unknown_restart_is_a_scenario_error(tmp_path: Path) -> None:
    text = SCENARIO.read_text().replace('[multibody]', '[multibody]\nrestart = "sometimes"', 1)
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace('"data/', f'"{SCENARIO.parent}/data/').replace(
        '"hydro_cache', f'"{SCENARIO.parent}/hydro_cache'))
    with pytest.raises(ScenarioError, match="restart"):
        load_scenario(bad)


def test_increment_and_consistent_restarts_give_the_same_motion(tmp_path: Path) -> None:
    runs = {}
    for restart in ("consistent", "increment"):
        s = load_scenario(SCENARIO)
        s.simulation.duration = 20.0
        s.multibody.restart = restart
        run_scenario(s, tmp_path / f"{restart}.h5", progress=False, log=None, in_process=True)
        runs[restart] = read_results(tmp_path / f"{restart}.h5")
    a, b = runs["consistent"], runs["increment"]
    for name in ("bodies/barge1/displacement", "bodies/barge2/displacement", "joints/hinge/coordinate",
                 "ptos/pto/power"):
        scale = np.max(np.abs(a[name]), axis=0) + 1e-9
        assert np.all(np.max(np.abs(b[name] - a[name]), axis=0) < 1e-4 * scale), name
