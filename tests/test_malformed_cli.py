"""Each class of malformed scenario file gives a one-paragraph error from the command line (exit
status 2, the file and the key path named), never a traceback.

Joints naming unknown bodies: the scenario has no joints yet (the multibody issue adds them); the
same reference check exists for PTOs naming unknown bodies and is covered here in its place."""

from __future__ import annotations

import pytest

from .conftest import SCENARIOS
from .test_cli import wec_cosim

BASE = (SCENARIOS / "cylinder_regular.toml").read_text()

CASES = {
    "wrong type": (BASE.replace("radius = 5.0", 'radius = "five"'), ["bodies[0].geometry.radius", "expected a number"]),
    "unknown key": (BASE.replace("g = 9.81", "gravity = 9.81"), ["unknown key 'environment.gravity'"]),
    "missing mesh file": (BASE.replace('shape = "vertical_cylinder"', 'shape = "mesh"\nmesh_file = "hull.stl"'),
                          ["mesh_file", "hull.stl does not exist"]),
    "missing database": (BASE.replace("[hydro]", '[hydro]\ndatabase = "nowhere.h5"'),
                         ["hydro.database", "nowhere.h5 does not exist"]),
    "negative mass": (BASE.replace('name = "float"\n', 'name = "float"\nmass = -1.0e5\n'),
                      ["bodies[0].mass must be positive"]),
    "non-finite number": (BASE.replace("damping = 2.0e5", "damping = nan"),
                          ["ptos[0].damping", "expected a finite number"]),
    "reference to an unknown body": (BASE.replace('body = "float"', 'body = "buoy"'),
                                     ["ptos[0]", "body 'buoy' is not defined"]),
    "wrong type in a master key": (BASE.replace("extrapolation = 2 ", 'extrapolation = "high" '),
                                   ["simulation.extrapolation: expected an integer"]),
}


# Every class through `run`; two through `export-ssp`, which shares the loader.
@pytest.mark.parametrize("case, command", [(c, "run") for c in CASES]
                         + [("unknown key", "export-ssp"), ("negative mass", "export-ssp")])
def test_malformed_scenario_is_one_paragraph(tmp_path, case, command) -> None:
    text, fragments = CASES[case]
    path = tmp_path / "bad.toml"
    path.write_text(text)
    args = ("run", str(path), "--quiet") if command == "run" else ("export-ssp", str(path), str(tmp_path / "x.ssp"))
    proc = wec_cosim(*args)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1, proc.stderr
    assert str(path) in proc.stderr
    for fragment in fragments:
        assert fragment in proc.stderr, proc.stderr
