"""`wec-cosim resume` continues bit for bit: for every master (jacobi, gauss_seidel, aitken, iqn_ils,
monolithic, adaptive step) and every multibody formulation (linear, index3, index1, nullspace), a
run resumed from a checkpoint ends with exactly the datasets of an uninterrupted run
(``np.array_equal``, no tolerance), through fmpy and in-process.

The reference is the uninterrupted run of the same code: the property tested is that stopping and
restarting changes nothing, which only exact equality can show (a missing piece of solver memory,
e.g. a cached extrapolation weight or a modified-Newton matrix, shows up as a 1e-16 difference that
grows)."""

from __future__ import annotations

import numpy as np
import pytest

from orchestrator.results import read_results
from orchestrator.results.checkpoints import checkpoint_path, read_checkpoint
from wec_cosim.cli import main

from .toml_text import bundled, write

CASES = {
    # name: (bundled scenario, [simulation] overrides, [multibody] overrides, duration, checkpoint_every)
    "jacobi": ("two_floats", {}, {}, 3.0, 1.1),
    "gauss_seidel": ("two_floats", {"master": "gauss_seidel"}, {}, 3.0, 1.1),
    "aitken": ("two_floats", {"master": "aitken"}, {}, 2.0, 0.7),
    "iqn_ils": ("two_floats", {"master": "iqn_ils"}, {}, 2.0, 0.7),
    "adaptive": ("two_floats", {"adaptive": {"enabled": True, "max_step": 0.4}}, {}, 4.0, 1.5),
    "monolithic": ("cylinder_regular", {"master": "monolithic"}, {}, 3.0, 1.1),
    "state_space": ("cylinder_regular", {}, {}, 3.0, 1.1),
    "index3 hinge barge": ("hinge_barge", {}, {}, 1.2, 0.5),
    "index1 hinge barge": ("hinge_barge", {}, {"formulation": "index1"}, 1.2, 0.5),
    "nullspace hinge barge": ("hinge_barge", {}, {"formulation": "nullspace"}, 1.2, 0.5),
    "irregular": ("cylinder_irregular", {}, {}, 3.0, 1.1),
}


def scenario(tmp_path, case: str):
    name, sim, mbd, duration, every = CASES[case]
    data = bundled(name)
    data["simulation"].update(sim, duration=duration, checkpoint_every=every)
    if mbd:
        data["multibody"].update(mbd)
    if case == "state_space":
        data["hydro"].update(radiation_method="state_space", state_space_tolerance=0.02)
    return write(tmp_path / f"{name}.toml", data)


# The default suite runs three representative cases (index-3 hinge barge, IQN-ILS's solver memory, the
# monolithic Newton matrices); the slow suite runs every master and formulation, through fmpy and in-process.
# The acceptance run (`pytest -m acceptance`) adds the other formulations, state space and the adaptive step.
DEFAULT = {("index3 hinge barge", "fmpy"), ("iqn_ils", "fmpy"), ("monolithic", "fmpy")}
ACCEPTANCE = {("index1 hinge barge", "fmpy"), ("nullspace hinge barge", "in-process"), ("state_space", "fmpy"),
              ("adaptive", "in-process"), ("aitken", "fmpy")}
PARAMS = [pytest.param(case, fmi, marks=() if (case, fmi) in DEFAULT else
                       (pytest.mark.slow, pytest.mark.acceptance) if (case, fmi) in ACCEPTANCE else pytest.mark.slow)
          for case in CASES for fmi in ("fmpy", "in-process")
          if not (fmi == "in-process" and case == "monolithic")]  # no FMI in the monolithic mode


@pytest.mark.parametrize("case, fmi", PARAMS)
def test_resume_is_bit_identical(tmp_path, case, fmi, capsys) -> None:
    path = scenario(tmp_path, case)
    out = tmp_path / "run.h5"
    extra = ["--in-process"] if fmi == "in-process" else []
    assert main(["run", str(path), "--out", str(out), "--quiet", *extra]) == 0
    whole = read_results(out)
    saved = read_checkpoint(checkpoint_path(out))
    n = len(whole["time"])
    assert 0 < saved["rows"] < n - 5, "the last checkpoint must leave steps to recompute"
    assert main(["resume", str(out), "--quiet"]) == 0
    resumed = read_results(out)
    assert resumed["attrs"]["status"] == "completed"
    series = [k for k in whole if k != "attrs"]
    assert len(series) >= 5
    different = [k for k in series if not np.array_equal(whole[k], resumed[k])]
    assert different == [], f"{len(different)} of {len(series)} datasets differ after resuming: {different}"
    capsys.readouterr()


def test_a_checkpoint_of_another_fmu_build_is_refused_with_the_file_unchanged(tmp_path, capsys) -> None:
    """The results file records the FMUs' build keys (their file names); a resume whose version builds other
    FMUs for the same scenario (sources or PythonFMU changed since the run started) is refused before any
    state is restored: one clear message, exit 2, the results file as it was."""
    import hashlib
    import json

    import h5py

    out = tmp_path / "run.h5"
    assert main(["run", str(scenario(tmp_path, "jacobi")), "--out", str(out), "--quiet"]) == 0
    with h5py.File(out, "r+") as f:  # as a run started by a version whose hydro FMU had another build key
        settings = json.loads(f.attrs["settings"])
        built = settings["fmus"]["hydro"]
        settings["fmus"]["hydro"] = built.replace(built.rsplit("-", 1)[-1], "0123456789abcdef.fmu")
        f.attrs["settings"] = json.dumps(settings)
    before = hashlib.sha256(out.read_bytes()).hexdigest()
    capsys.readouterr()
    assert main(["resume", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "another build of the hydro FMU" in err and "0123456789abcdef" in err and "Traceback" not in err, err
    assert hashlib.sha256(out.read_bytes()).hexdigest() == before
