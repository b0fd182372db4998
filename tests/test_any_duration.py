"""Durations that are not whole numbers of steps, `rao --set`, and the still-water energy account's wording."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from orchestrator.scenario import apply_overrides, load_scenario

from .conftest import ROOT, SCENARIOS


def wec_cosim(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "wec_cosim.cli", *args], capture_output=True, text=True, cwd=ROOT,
                          env=os.environ.copy(), timeout=600)


@pytest.mark.parametrize("duration, steps", [(40.0, 2667), (100.0, 6667), (29.99, 1999), (0.02, 1)])
def test_duration_is_rounded_to_the_nearest_whole_step(duration: float, steps: int) -> None:
    """40 s and 100 s at 0.015 s (2666.67 and 6666.67 steps) load, rounded to 2667 and 6667 steps; a note says so."""
    s = apply_overrides(load_scenario(SCENARIOS / "disc_decay.toml"),
                        ["simulation.step=0.015", f"simulation.duration={duration}"])
    assert s.simulation.duration == pytest.approx(steps * 0.015, rel=1e-12)
    assert f"not a whole number of 0.015 s steps: the run covers {steps} steps" in s._duration_note
    whole = apply_overrides(load_scenario(SCENARIOS / "disc_decay.toml"), ["simulation.step=0.015",
                                                                           "simulation.duration=30"])
    assert whole.simulation.duration == 30.0 and whole._duration_note == ""


def test_forty_seconds_at_fifteen_milliseconds_runs(tmp_path) -> None:
    """The disc decay for 40 s at 0.015 s through the command line: 2667 steps, the last sample at 40.005 s, the
    summary says why."""
    out = tmp_path / "disc.h5"
    proc = wec_cosim("run", str(SCENARIOS / "disc_decay.toml"), "--quiet", "--out", str(out),
                     "--set", "simulation.step=0.015", "--duration", "40")
    assert proc.returncode == 0, proc.stderr
    assert "the run covers 2667 steps, 40.005 s (the duration rounded to the nearest whole step)" in proc.stdout
    with h5py.File(out, "r", swmr=True) as f:
        time = f["time"][()]
    assert time[-1] == pytest.approx(40.005, abs=1e-9) and len(time) == 2668


def _heave_rao(hdb, omega: np.ndarray, mass: float, damping: float) -> np.ndarray:
    """Single-DOF heave response per metre of amplitude from the database: X / (C - w^2 (m + A) + i w (B + c))."""
    A, B, X = hdb.interpolate(omega)
    c33 = hdb.hydrostatic_stiffness[0, 2, 2]
    return X[:, 2] / (c33 - omega ** 2 * (mass + A[:, 2, 2]) + 1j * omega * (B[:, 2, 2] + damping))


def test_rao_set_overrides_the_pto_damping_per_condition(tmp_path) -> None:
    """`wec-cosim rao --set ptos.pto.damping=...`: the heave RAO is the single-DOF response with that damping, the
    power 1/2 w^2 c |RAO|^2, and the file records the override."""
    from orchestrator.scene import load_scene

    scene = load_scene(load_scenario(SCENARIOS / "cylinder_regular.toml"), log=None)
    mass = scene.scenario.bodies[0].mass or scene.hdb.displaced_volume[0] * scene.hdb.rho
    for damping in (5.0e4, 8.0e5):
        out = tmp_path / f"rao_{damping:g}.h5"
        proc = wec_cosim("rao", str(SCENARIOS / "cylinder_regular.toml"), "--out", str(out),
                         "--set", f"ptos.pto.damping={damping:g}")
        assert proc.returncode == 0, proc.stderr
        with h5py.File(out) as f:
            omega, rao = f["omega"][()], f["bodies/float/rao"][:, 2]
            power = f["ptos/pto/mean_power"][()]
            assert f.attrs["overrides"] == f"ptos.pto.damping={damping:g}"
        np.testing.assert_allclose(rao, _heave_rao(scene.hdb, omega, mass, damping), rtol=1e-9)
        np.testing.assert_allclose(power, 0.5 * omega ** 2 * damping * np.abs(rao) ** 2, rtol=1e-12)
    proc = wec_cosim("rao", str(SCENARIOS / "cylinder_regular.toml"), "--out", str(tmp_path / "x.h5"),
                     "--set", "ptos.pto.dampnig=1")
    assert proc.returncode == 2 and "ptos.pto.dampnig" in proc.stderr and "Traceback" not in proc.stderr


def test_still_water_energy_account_has_no_share_of_zero_work() -> None:
    """A decay in still water: work in 0 J; the residual is given in joules and as a share of the largest term."""
    from orchestrator.cosim.simulation import RunResult, format_summary

    energy = {"work_in": 0.0, "pto": 0.0, "radiated": 1.2e4, "dissipated": 3.0e2, "stored": -1.25e4,
              "residual": -31.6}
    text = format_summary(RunResult(Path("r.h5"), 1.0, 30.0, 600, energy=energy))
    assert "residual -31.6 J (-0.253 % of the largest term (stored))" in text
    assert "of the work in" not in text
    driven = dict(energy, work_in=2.0e5, pto=1.5e5, radiated=4.0e4, stored=9.0e3, residual=12.0)
    assert "residual 12 J (0.006 % of the work in)" in format_summary(RunResult(Path("r.h5"), 1.0, 30.0, 600,
                                                                                energy=driven))
