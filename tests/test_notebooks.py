"""The notebooks in ``examples/`` run from top to bottom in a fresh Jupyter kernel (nbclient), as a user would run
them from that folder; their own cells assert what they show (the mean power against the exact answer, the hinge
angle equal to the relative pitch, the DAE and ODE forms equal, power as Hs squared, the controlled run equal to
the same spring-damper inside the model). Each takes 20-30 s here with warm caches."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted((ROOT / "examples").glob("*.ipynb"))


def test_the_five_examples_are_there() -> None:
    assert [p.stem for p in NOTEBOOKS] == ["01_first_run", "02_jointed_device", "03_frequency_domain",
                                           "04_sweep_power_matrix", "05_controller_zenoh"]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs(path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import nbformat
    from nbclient import NotebookClient

    monkeypatch.setenv("WEC_COSIM_RESULTS", str(tmp_path / "results"))
    monkeypatch.setenv("WEC_COSIM_ROOT", str(ROOT))
    notebook = nbformat.read(path, as_version=4)
    assert all(not cell.get("outputs") for cell in notebook.cells if cell.cell_type == "code")  # stored clean
    NotebookClient(notebook, timeout=900, kernel_name="python3",
                   resources={"metadata": {"path": str(path.parent)}}).execute(env=dict(os.environ))
    errors = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs
              if o.output_type == "error"]
    assert not errors
    assert any((tmp_path / "results").iterdir())
