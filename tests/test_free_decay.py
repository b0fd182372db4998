"""The exact free-decay reference warns when its frequency grid cannot resolve the response."""

from __future__ import annotations

import numpy as np
import pytest

from orchestrator.reference import frequency_domain
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS


def test_coarse_frequency_step_is_flagged_and_fine_step_is_not() -> None:
    scenario = load_scenario(SCENARIOS / "cylinder_regular.toml")
    scenario.ptos[0].damping = 0.0  # radiation damping only: a sharp heave resonance
    scene = load_scene(scenario, log=None)
    t = np.linspace(0.0, 60.0, 121)
    with pytest.warns(UserWarning, match="does not resolve the response"):
        frequency_domain.free_decay(scene, t, np.array([0.5]), d_omega=0.05)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        x = frequency_domain.free_decay(scene, t, np.array([0.5]))
    assert x[0, 0] == pytest.approx(0.5, abs=1e-4)  # starts at the initial displacement
