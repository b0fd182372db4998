"""``wec-cosim export-ssp --native``: the SSP whose hydro component is the native hydro FMU (FMI 2.0, compiled C)
and whose multibody component is the PythonFMU one, run in a real host.

* structure: the archive's hydro FMU is the native one (a binary, C sources, no Python script); every connection
  names an output of its start component and an input of its end component in the two FMUs' model descriptions, with
  the connector kinds of the SSD and the same unit at both ends; the parameter bindings name the multibody FMU's
  parameters; OSP's and OMSimulator's fixed-step annotations both give the scenario's step (also without
  ``--native``: OMSimulator's command line aborts on an SSD without its annotation);
* runs: libcosim (libcosimpy, its own process), OMSimulator's command line and the plain C host run the exported
  cylinder over 200 s at the exported step (0.1 s); the steady heave is compared with the exact frequency-domain
  answer of the scene.
"""

from __future__ import annotations

import csv
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description

from orchestrator.fmi.host_environment import fmu_environment
from orchestrator.fmi.ssp import NS, system_structure
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import ROOT, SCENARIOS
from .test_plain_hosts import c_host, run_host, steady_errors  # noqa: F401  (c_host: a fixture)

SSD = f"{{{NS['ssd']}}}"
OMSIMULATOR = ROOT.parent / "shared" / "tools" / "omsimulator" / "bin" / "OMSimulator"


def _export(name: str, out: Path, *options: str, env: dict | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "wec_cosim.cli", "export-ssp", str(SCENARIOS / f"{name}.toml"),
                           str(out), *options], capture_output=True, text=True, cwd=ROOT, env=env or os.environ.copy(),
                          timeout=900)


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    s = load_scenario(SCENARIOS / "cylinder_regular.toml")
    out = tmp_path_factory.mktemp("ssp_native") / "cylinder_regular.ssp"
    proc = _export("cylinder_regular", out, "--native")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "native" in proc.stdout
    return load_scene(s, log=None), out


def _annotation_steps(ssd: ET.Element) -> tuple[float, float]:
    """(OSP's baseStepSize, OMSimulator's FixedStepMaster stepSize) of an SSD."""
    osp = ssd.find(f"{SSD}DefaultExperiment//{{{NS['osp']}}}FixedStepAlgorithm")
    system = ssd.find(f"{SSD}System")
    note = system.find(f"{SSD}Annotations/{{{NS['ssc']}}}Annotation[@type='org.openmodelica']")
    oms = note.find(f".//{{{NS['oms']}}}FixedStepMaster")
    return float(osp.get("baseStepSize")), float(oms.get("stepSize"))


def test_every_export_carries_omsimulators_fixed_step_annotation(cylinder) -> None:
    """The Python-FMU export too (the SSD is the same document): OMSimulator's and OSP's annotations give the step."""
    scene, _ = cylinder
    ssd = ET.fromstring(system_structure(scene))
    assert _annotation_steps(ssd) == (scene.scenario.simulation.step, scene.scenario.simulation.step)


def _unit(md, variable) -> str | None:
    if variable.unit:
        return variable.unit
    if variable.declaredType is not None:
        return variable.declaredType.unit
    return None


def test_the_native_ssp_connects_existing_variables_of_both_fmus_with_their_units(cylinder, tmp_path) -> None:
    scene, archive = cylinder
    with zipfile.ZipFile(archive) as z:
        names = set(z.namelist())
        ssd = ET.fromstring(z.read("SystemStructure.ssd"))
        z.extractall(tmp_path)
    assert _annotation_steps(ssd) == (0.1, 0.1) == (scene.scenario.simulation.step,) * 2
    components = {c.get("name"): c for c in ssd.iter(f"{SSD}Component")}
    assert set(components) == {"hydro", "mbd"}
    md = {name: read_model_description(str(tmp_path / c.get("source"))) for name, c in components.items()}
    assert md["hydro"].fmiVersion == "2.0" and md["hydro"].coSimulation.modelIdentifier == "wec_hydro_native"
    hydro_files = zipfile.ZipFile(tmp_path / "resources" / "hydro.fmu").namelist()
    assert "binaries/linux64/wec_hydro_native.so" in hydro_files and "resources/hydro.wecrt" in hydro_files
    assert any(f.startswith("sources/") and f.endswith(".c") for f in hydro_files)
    assert not any(f.endswith(".py") for f in hydro_files)  # no Python inside the hydro component
    assert {"resources/hydro.fmu", "resources/mbd.fmu", "OspSystemStructure.xml", "resources/parameters.ssv"} <= names
    variables = {name: {v.name: v for v in d.modelVariables} for name, d in md.items()}
    kinds = {(c.get("name"), k.get("name")): k.get("kind") for c in components.values()
             for k in c.iter(f"{SSD}Connector")}
    connections = list(ssd.iter(f"{SSD}Connection"))
    assert len(connections) == len(scene.linearised_connections()) == 6  # x, v; F0, F0_rate, dF_dx, dF_dv (heave)
    both = 0
    for c in connections:
        a, b = c.get("startElement"), c.get("endElement")
        out, inp = variables[a][c.get("startConnector")], variables[b][c.get("endConnector")]
        assert (out.causality, inp.causality) == ("output", "input"), (a, out.name, b, inp.name)
        assert (kinds[a, out.name], kinds[b, inp.name]) == ("output", "input")
        assert out.type == inp.type == "Real"
        units = (_unit(md[a], out), _unit(md[b], inp))
        assert None in units or units[0] == units[1], (out.name, inp.name, units)
        both += None not in units
    assert both == len(connections)  # every connection's unit is declared at both ends, so the check above is real
    declared = {(a, n) for (a, n), k in kinds.items() if k != "parameter"}
    assert declared == {(c.get(e), c.get(n)) for c in connections
                        for e, n in (("startElement", "startConnector"), ("endElement", "endConnector"))}
    for (comp, name), kind in kinds.items():
        if kind == "parameter":
            assert comp == "mbd" and variables["mbd"][name].causality == "parameter", name


@pytest.fixture(scope="module")
def libcosim_run(cylinder, tmp_path_factory) -> tuple[dict, subprocess.CompletedProcess]:
    """libcosim (libcosimpy, in its own process) on the exported archive, 200 s at the exported step."""
    scene, archive = cylinder
    return run_host("libcosim", archive, 2000, scene.scenario.simulation.step, ["mbd.float.x[3]"],
                    tmp_path_factory.mktemp("libcosim"))


def test_libcosim_runs_the_native_ssp_to_the_exact_steady_heave(cylinder, libcosim_run) -> None:
    """Acceptance: libcosim (libcosimpy, in its own process) runs the exported SSP (native hydro FMU, Python
    multibody FMU) over 200 s at the exported step 0.1 s: the steady heave amplitude within 0.5 % and the phase
    within 1 deg of the exact frequency-domain answer, with no error or warning from libcosim's parser."""
    scene, _ = cylinder
    var = ["mbd.float.x[3]"]
    data, proc = libcosim_run
    log = proc.stdout + proc.stderr
    assert "FMI2XML" in log  # libcosim's parser log is really captured
    assert "[error]" not in log and "[fatal]" not in log and "[warning]" not in log, log[-3000:]
    amplitude, phase = steady_errors(scene, data["time"], {"float.x[3]": data[var[0]]})["float.x[3]"]
    print(f"libcosim, native hydro FMU: steady heave {amplitude * 100:+.3f} %, phase {phase:+.3f} deg")
    assert abs(amplitude) < 0.005 and abs(phase) < 1.0, (amplitude, phase)


def test_the_c_host_runs_the_native_ssp_as_libcosim_does(cylinder, c_host, libcosim_run, tmp_path) -> None:  # noqa: F811
    """The plain C host (tests/c_host/jacobi_host.c: fixed step, Jacobi, zero-order hold; the environment of
    ``wec-cosim host-env`` for the Python multibody FMU) on the same archive: the same exchange as libcosim, so the
    same heave to 1e-10 m, and the steady heave within 0.5 % / 1 deg of the exact answer."""
    scene, archive = cylinder
    var = ["mbd.float.x[3]"]
    h = scene.scenario.simulation.step
    c, _ = run_host("c", archive, 2000, h, var, tmp_path, c_host)
    ref, _ = libcosim_run
    assert max(abs(c[var[0]] - ref[var[0]])) < 1e-10
    amplitude, phase = steady_errors(scene, c["time"], {"float.x[3]": c[var[0]]})["float.x[3]"]
    print(f"C host, native hydro FMU: steady heave {amplitude * 100:+.3f} %, phase {phase:+.3f} deg")
    assert abs(amplitude) < 0.005 and abs(phase) < 1.0, (amplitude, phase)


@pytest.mark.skipif(not OMSIMULATOR.exists(), reason="OMSimulator is not installed in ../shared/tools/omsimulator")
def test_omsimulator_command_line_runs_the_exported_native_ssp(cylinder, libcosim_run, tmp_path) -> None:
    """Acceptance: OMSimulator's command line runs the archive exactly as ``export-ssp --native`` wrote it (its
    fixed-step master from the SSD's annotation; only the environment of ``wec-cosim host-env`` for the Python
    multibody FMU, nothing else inherited) over 200 s at 0.1 s: no error, the same heave as libcosim to 1e-10 m
    (both exchange values once per step, zero-order hold), and the steady heave within 0.5 % / 1 deg of the exact
    frequency-domain answer."""
    scene, archive = cylinder
    env = {"PATH": "/usr/bin:/bin", **fmu_environment({})}
    run = subprocess.run([str(OMSIMULATOR), str(archive), "--stepSize=0.1", "--stopTime=200", "--resultFile=out.csv"],
                         capture_output=True, text=True, cwd=tmp_path, env=env, timeout=900)
    assert run.returncode == 0 and "0 errors" in run.stdout, (run.stdout + run.stderr)[-3000:]
    with open(tmp_path / "out.csv", newline="") as f:
        header = [h.strip() for h in next(csv.reader(f))]  # quoted: names such as dF_dx[3,3] hold commas
    data = np.loadtxt(tmp_path / "out.csv", delimiter=",", skiprows=1)
    column = next(k for k, h in enumerate(header) if h.endswith(".mbd.float.x[3]"))
    t, x = data[:, 0], data[:, column]
    # OMSimulator writes two rows at each communication point (before and after the step's events): keep the last
    last = len(t) - 1 - np.unique(t[::-1], return_index=True)[1]
    t, x = t[last], x[last]
    assert len(t) == 2001 and t[-1] == pytest.approx(200.0)
    ref, _ = libcosim_run  # its rows are the points after each step: 0.1 ... 200 s
    np.testing.assert_allclose(t[1:], ref["time"], rtol=1e-9)
    assert np.max(np.abs(x[1:] - ref["mbd.float.x[3]"])) < 1e-10
    amplitude, phase = steady_errors(scene, t[1:], {"float.x[3]": x[1:]})["float.x[3]"]
    print(f"OMSimulator, native hydro FMU: steady heave {amplitude * 100:+.3f} %, phase {phase:+.3f} deg")
    assert abs(amplitude) < 0.005 and abs(phase) < 1.0, (amplitude, phase)


def test_the_native_archive_moves_the_body_as_the_python_one_does(cylinder, libcosim_run, tmp_path) -> None:
    """Both hydro FMUs call the same compiled runtime on the same prepared model: in libcosim the archive without
    ``--native`` (PythonFMU hydro FMU) gives the same heave to 1e-12 m over the 200 s."""
    scene, _ = cylinder
    archive = tmp_path / "python.ssp"
    proc = _export("cylinder_regular", archive)
    assert proc.returncode == 0, proc.stderr[-3000:]
    var = "mbd.float.x[3]"
    python, _ = run_host("libcosim", archive, 2000, scene.scenario.simulation.step, [var], tmp_path)
    native, _ = libcosim_run
    assert np.max(np.abs(python[var] - native[var])) < 1e-12


def test_a_missing_compiler_is_one_message_and_exit_status_2(tmp_path) -> None:
    """``CC`` names no compiler: the archive is not written, one message names the compiler and the fix."""
    out = tmp_path / "cylinder.ssp"
    proc = _export("cylinder_regular", out, "--native", env=dict(os.environ, CC="/nonexistent/cc"))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr[-3000:]
    assert "no C compiler ('/nonexistent/cc' is not on PATH)" in proc.stderr and "set CC" in proc.stderr
    assert not out.exists()
