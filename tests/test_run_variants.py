"""`wec-cosim run` with an iterative master and the adaptive step: summary lines and results attributes."""

from __future__ import annotations

import json

import h5py
import numpy as np

from .conftest import SCENARIOS
from .test_cli import wec_cosim


def test_iterative_adaptive_run_reports_iterations_and_steps(tmp_path) -> None:
    text = (SCENARIOS / "two_floats.toml").read_text()
    text = text.replace("duration = 60.0", "duration = 12.0").replace("step = 0.1 ", "step = 0.05 ")
    text = text.replace('master = "jacobi"', 'master = "iqn_ils"')
    text = text.replace("[waves]", "[simulation.adaptive]\nenabled = true\nmax_step = 0.4\ntolerance = 0.02\n\n[waves]")
    text = text.replace("[hydro]", f'[hydro]\ncache_dir = "{SCENARIOS / "hydro_cache"}"')
    path = tmp_path / "adaptive.toml"
    path.write_text(text)
    out = tmp_path / "adaptive.h5"
    proc = wec_cosim("run", str(path), "--out", str(out), "--quiet")
    assert proc.returncode == 0, proc.stderr
    assert "iqn_ils:" in proc.stdout and "evaluations per step" in proc.stdout
    assert "adaptive step: 0.05 .." in proc.stdout
    with h5py.File(out) as f:
        stats = json.loads(f.attrs["statistics"])
        settings = json.loads(f.attrs["settings"])
        t = f["time"][()]
    assert settings["master"] == "iqn_ils" and settings["adaptive"]["enabled"] is True
    assert stats["macro_steps"] == len(t) - 1 and t[-1] == 12.0
    steps = np.diff(t)
    assert np.allclose(steps / 0.05, np.round(steps / 0.05), atol=1e-9) and steps.max() > 0.05
