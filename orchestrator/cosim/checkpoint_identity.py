"""What a checkpoint belongs to, checked before a resume restores it.

A checkpoint is refused (one message, the results file untouched) when it was written by another run: its
scenario fingerprint (the resolved parameters) differs from the results file's scenario, or its build key (the
FMU builds, or the physics sources of the monolithic mode) differs from what this version builds; and when it
does not fit its results file: the rows it keeps must end at its own time (the last kept row at most one output
interval before it, the next row after it).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.errors import WecCosimError
from orchestrator.results.checkpoints import checkpoint_path, scenario_fingerprint


def run_identity(plan) -> dict[str, str]:  # noqa: ANN001 - simulation.RunPlan
    """``{"scenario": fingerprint, "build": key}`` of a prepared run."""
    fmus = plan.settings.get("fmus")
    if fmus:
        build = ",".join(f"{kind}={Path(path).name}" for kind, path in sorted(fmus.items()))
    else:
        from orchestrator.fmi.fmu_builder import sources_key

        build = f"in-process={sources_key()}"
    return {"scenario": scenario_fingerprint(plan.scene.scenario), "build": build}


def check_checkpoint(results: Path, saved: dict, plan, times: np.ndarray) -> None:  # noqa: ANN001
    """Refuse ``saved`` (a read checkpoint) if it belongs to another run or does not fit the results file's
    ``times`` (module docstring)."""
    ckpt = checkpoint_path(results)
    here = run_identity(plan)
    theirs = saved.get("identity", {})
    if theirs.get("scenario") != here["scenario"]:
        raise WecCosimError(
            f"{ckpt} belongs to another run: its scenario parameters differ from those of {results} (a checkpoint "
            "of another run of the scene, e.g. another wave height, copied next to this file); resuming would mix "
            f"two runs in one file. {results} is unchanged; run the simulation again")
    if theirs.get("build") != here["build"]:
        raise WecCosimError(
            f"{ckpt} was written by another build ({theirs.get('build') or 'unknown'}; this version builds "
            f"{here['build']}): an FMU state is the private data of the build that wrote it; resume with the version "
            f"that started the run, or run the simulation again. {results} is unchanged")
    t, rows = float(saved["time"]), int(saved["rows"])
    sim = plan.scene.scenario.simulation
    interval = sim.output_every * (sim.adaptive.max_step if sim.adaptive.enabled else sim.step)
    eps = 1e-9 * max(1.0, abs(t))
    if not (1 <= rows <= len(times) and t - interval - eps <= times[rows - 1] <= t + eps
            and (rows == len(times) or times[rows] > t + eps)):
        last = f"{times[rows - 1]:g} s" if 1 <= rows <= len(times) else "none"
        raise WecCosimError(
            f"{ckpt} does not fit {results}: it keeps {rows} rows up to t = {t:g} s, but the file's row {rows} is at "
            f"{last} ({len(times)} rows in all); the checkpoint or the results file was changed or replaced. "
            f"{results} is unchanged; run the simulation again")
