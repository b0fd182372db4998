"""Our FMUs in other FMI hosts, as their users run them (issue: "right answer in any FMI host").

* a plain C host (tests/c_host/jacobi_host.c, compiled here with the system compiler against the
  FMI 2.0 headers fmpy ships): dlopen, fixed step, Jacobi order, zero-order hold, no iteration, no
  rollback; run in its own process with the environment of ``wec-cosim host-env``;
* fmpy's SSP runner and libcosim on the exported SSP (each in its own process): the same figures,
  no error in libcosim's model-description parser;
* ``fmpy.simulate_fmu(fmu)`` with defaults; honest model descriptions; a readable message when a
  package is missing; the PythonFMU binary fix (no crash at exit: every host process exits 0).

Expected values: the exact frequency-domain answer (cylinder: 2 % / 2 deg at the exported step
0.1 s, measured +0.13 % / -0.01 deg), the excitation force from the database, FMI 2.0's rules.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import fmpy
import fmpy.validation
import numpy as np
import pytest

from orchestrator import frequency_domain
from orchestrator.analysis import harmonic_fit, steady_window
from orchestrator.fmu_builder import build_scene_fmus
from orchestrator.foreign_hosts import c_host_plan
from orchestrator.host_environment import fmu_environment
from orchestrator.pythonfmu_patch import is_patched, patch_library
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import ROOT, SCENARIOS

C_SOURCE = ROOT / "tests" / "c_host" / "jacobi_host.c"
FMI_HEADERS = Path(fmpy.__file__).parent / "c-code"


@pytest.fixture(scope="session")
def c_host(tmp_path_factory) -> Path:
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("no system C compiler (gcc) on this machine")
    exe = tmp_path_factory.mktemp("c_host") / "jacobi_host"
    proc = subprocess.run([gcc, "-O2", "-std=c99", "-D_POSIX_C_SOURCE=200809L", "-Wall", "-Wextra", "-Werror",
                           "-I", str(FMI_HEADERS), str(C_SOURCE), "-o", str(exe), "-ldl"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    return exe


def _export(name: str, folder: Path) -> Path:
    out = folder / f"{name}.ssp"
    proc = subprocess.run([sys.executable, "-m", "orchestrator.cli", "export-ssp", str(SCENARIOS / f"{name}.toml"),
                           str(out)], capture_output=True, text=True, cwd=ROOT, env=os.environ.copy(), timeout=900)
    assert proc.returncode == 0, proc.stderr
    return out


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    s = load_scenario(SCENARIOS / "cylinder_regular.toml")
    return load_scene(s, log=None), _export("cylinder_regular", tmp_path_factory.mktemp("ssp"))


@pytest.fixture(scope="module")
def hinge(tmp_path_factory):
    s = load_scenario(SCENARIOS / "hinge_barge.toml")
    return load_scene(s, log=None), _export("hinge_barge", tmp_path_factory.mktemp("ssp"))


def run_host(host: str, archive: Path, steps: int, step: float, variables: list[str], tmp: Path,
             executable: Path | None = None) -> tuple[dict, subprocess.CompletedProcess]:
    """One foreign host in its own process; its exit status must be 0 (no crash, not even at exit)."""
    out = tmp / f"{host}.npz"
    extra = ["--executable", str(executable)] if executable else []
    proc = subprocess.run([sys.executable, "-m", "orchestrator.foreign_hosts", host, str(archive), "--steps",
                           str(steps), "--step", repr(step), "--out", str(out), *extra, *variables],
                          capture_output=True, text=True, cwd=ROOT, env=os.environ.copy(), timeout=3600)
    assert proc.returncode == 0, (proc.returncode, proc.stderr[-3000:])
    data = np.load(out)
    return {k: data[k] for k in data.files}, proc


def steady_errors(scene, time: np.ndarray, series: dict[str, np.ndarray]) -> dict[str, tuple[float, float]]:
    """(amplitude error, phase error in degrees) of each ``body.x[i]`` series against the exact answer."""
    s = scene.scenario
    omega = 2 * math.pi / s.waves.period
    fd = frequency_domain.solve(scene, np.array([omega]))
    mask = steady_window(time, s.waves.period, s.simulation.steady_periods)
    out = {}
    for name, y in series.items():
        body, rest = name.split(".", 1)
        dof = int(rest[2:-1]) - 1
        exact = complex(fd.body_rao(body)[0][dof] * s.waves.height / 2)
        measured, _ = harmonic_fit(time[mask], y[mask], omega)
        out[name] = (abs(measured) / abs(exact) - 1, math.degrees(np.angle(measured / exact)))
    return out


def test_c_host_runs_the_cylinder_right_at_the_exported_step(cylinder, c_host, tmp_path) -> None:
    """Acceptance: the plain C host equals fmpy's SSP runner to 1e-10 m and the steady heave is within
    2 % / 2 deg of the exact answer at the exported step (0.1 s); both processes exit 0."""
    scene, archive = cylinder
    steps, h = 2000, scene.scenario.simulation.step
    var = ["mbd.float.x[3]"]
    c, _ = run_host("c", archive, steps, h, var, tmp_path, c_host)
    ref, _ = run_host("fmpy", archive, steps, h, var, tmp_path)
    np.testing.assert_allclose(c["time"], ref["time"], rtol=1e-12)
    assert np.max(np.abs(c[var[0]] - ref[var[0]])) < 1e-10
    amplitude, phase = steady_errors(scene, c["time"], {"float.x[3]": c[var[0]]})["float.x[3]"]
    assert abs(amplitude) < 0.02 and abs(phase) < 2.0, (amplitude, phase)


def test_libcosim_runs_the_cylinder_as_fmpy_does_without_parser_errors(cylinder, tmp_path) -> None:
    scene, archive = cylinder
    steps, h = 2000, scene.scenario.simulation.step
    var = ["mbd.float.x[3]"]
    ours, proc = run_host("libcosim", archive, steps, h, var, tmp_path)
    ref, _ = run_host("fmpy", archive, steps, h, var, tmp_path)
    log = proc.stdout + proc.stderr
    assert "FMI2XML" in log  # libcosim's parser log is really captured
    assert "[error]" not in log and "[fatal]" not in log and "[warning]" not in log, log[-3000:]
    assert np.max(np.abs(ours[var[0]] - ref[var[0]])) < 1e-10
    errors = steady_errors(scene, ours["time"], {"float.x[3]": ours[var[0]]})
    assert abs(errors["float.x[3]"][0]) < 0.02 and abs(errors["float.x[3]"][1]) < 2.0, errors


HINGE_VARIABLES = [f"mbd.{b}.x[{i}]" for b in ("barge1", "barge2") for i in (1, 3, 5)]


def test_hinge_barge_runs_alike_in_the_c_host_fmpy_and_libcosim(hinge, c_host, tmp_path) -> None:
    """The exported hinge barge (nonlinear index-3 multibody FMU) in all three hosts over the first 3 s
    (the full 200 s against the exact answer is the slow test below): same figures, clean log, exit 0."""
    scene, archive = hinge
    steps, h = 150, scene.scenario.simulation.step
    runs = {host: run_host(host, archive, steps, h, HINGE_VARIABLES, tmp_path, c_host if host == "c" else None)
            for host in ("c", "fmpy", "libcosim")}
    log = runs["libcosim"][1].stdout + runs["libcosim"][1].stderr
    assert "[error]" not in log and "[fatal]" not in log, log[-3000:]
    ref = runs["fmpy"][0]
    assert np.max(np.abs(ref["mbd.barge1.x[3]"])) > 1e-4  # the barges move (wave height 0.02 m, ramp)
    for host in ("c", "libcosim"):
        for v in HINGE_VARIABLES:
            assert np.max(np.abs(runs[host][0][v] - ref[v])) < 1e-10, (host, v)


@pytest.mark.slow
def test_c_host_hinge_barge_is_stable_and_right_over_200_s(hinge, c_host, tmp_path) -> None:
    """Acceptance: 200 s of the exported hinge barge at its exported step (0.02 s) in the plain C host:
    equal to fmpy's run, stable (the last ten periods' amplitudes equal the ten before to 0.5 %) and every
    motion amplitude within 2 % / 2 deg of the exact frequency-domain answer."""
    scene, archive = hinge
    h = scene.scenario.simulation.step
    steps = int(round(200.0 / h))
    c, _ = run_host("c", archive, steps, h, HINGE_VARIABLES, tmp_path, c_host)
    ref, _ = run_host("fmpy", archive, steps, h, HINGE_VARIABLES, tmp_path)
    for v in HINGE_VARIABLES:
        assert np.max(np.abs(c[v] - ref[v])) < 1e-10, v
    series = {v.removeprefix("mbd."): c[v] for v in HINGE_VARIABLES}
    errors = steady_errors(scene, c["time"], series)
    for name, (amplitude, phase) in errors.items():
        assert abs(amplitude) < 0.02 and abs(phase) < 2.0, (name, amplitude, phase)
    period = scene.scenario.waves.period
    omega = 2 * math.pi / period
    t = c["time"]
    late, earlier = t > t[-1] - 10 * period, (t > t[-1] - 20 * period) & (t <= t[-1] - 10 * period)
    for v in HINGE_VARIABLES:
        a1 = abs(harmonic_fit(t[late], c[v][late], omega)[0])
        a0 = abs(harmonic_fit(t[earlier], c[v][earlier], omega)[0])
        assert abs(a1 / a0 - 1) < 5e-3, (v, a0, a1)


def _model_description(fmu: Path) -> ET.Element:
    with zipfile.ZipFile(fmu) as z:
        return ET.fromstring(z.read("modelDescription.xml"))


def test_model_descriptions_are_honest(cylinder) -> None:
    """Inputs carry no initial attribute (FMI 2.0: not allowed; libcosim rejected initial="exact"), a
    DefaultExperiment with the scenario's stop time and step, capability flags as the FMU behaves, A_inf
    start values that are the database's, the PythonFMU binary fixed; fmpy validate finds nothing."""
    scene, _ = cylinder
    fmus = build_scene_fmus(scene)
    sim = scene.scenario.simulation
    for kind, fmu in fmus.items():
        root = _model_description(fmu)
        for var in root.iter("ScalarVariable"):
            if var.get("causality") == "input":
                assert var.get("initial") is None, var.get("name")
                assert var.find("Real").get("start") is not None, var.get("name")
        experiment = root.find("DefaultExperiment")
        assert float(experiment.get("stopTime")) == sim.duration and float(experiment.get("stepSize")) == sim.step
        flags = root.find("CoSimulation")
        assert flags.get("canGetAndSetFMUstate") == "true" and flags.get("canSerializeFMUstate") == "true"
        # the convolution needs whole multiples of radiation.dt; the multibody FMU takes any step
        assert flags.get("canHandleVariableCommunicationStepSize") == ("false" if kind == "hydro" else "true")
        assert fmpy.validation.validate_fmu(str(fmu)) == [], kind
        with zipfile.ZipFile(fmu) as z:
            assert is_patched(z.read(f"binaries/linux64/{flags.get('modelIdentifier')}.so"))
    mbd = _model_description(fmus["mbd"])
    start = {v.get("name"): float(v.find("Real").get("start")) for v in mbd.iter("ScalarVariable")
             if v.get("name").startswith("A_inf")}
    np.testing.assert_allclose(start["A_inf[3,3]"], scene.hdb.added_mass_inf[2, 2], rtol=1e-12)
    assert start["A_inf[3,3]"] > 1e5  # not zero: right without a parameter file


def test_fmpy_simulate_fmu_with_defaults_runs_each_fmu_to_its_stop_time(cylinder) -> None:
    """Each FMU alone, ``fmpy.simulate_fmu(fmu)`` and nothing else: both reach the DefaultExperiment's stop
    time; the hydro FMU held at rest outputs the wave excitation force, whose amplitude is the database's
    excitation coefficient times the wave amplitude."""
    scene, _ = cylinder
    fmus = build_scene_fmus(scene)
    stop = scene.scenario.simulation.duration
    hydro = fmpy.simulate_fmu(str(fmus["hydro"]), output=["float.F[3]", "float.F0[3]"])
    assert math.isclose(hydro["time"][-1], stop)
    mbd = fmpy.simulate_fmu(str(fmus["mbd"]))
    assert math.isclose(mbd["time"][-1], stop)
    w = scene.scenario.waves
    omega = 2 * math.pi / w.period
    exact = abs(scene.hdb.excitation_at(np.array([omega]), math.radians(w.heading_deg))[0][2]) * w.height / 2
    t = hydro["time"]
    late = t > stop - 5 * w.period
    amplitude = abs(harmonic_fit(t[late], hydro["float.F[3]"][late], omega)[0])
    assert abs(amplitude / exact - 1) < 1e-6
    np.testing.assert_allclose(hydro["float.F0[3]"], hydro["float.F[3]"], rtol=1e-12)  # at rest: no memory


def test_missing_package_is_reported_by_the_fmu(cylinder, c_host, tmp_path) -> None:
    """The C host with an environment whose h5py cannot be imported: fmi2Instantiate fails (the host exits
    with its error status, no crash) and the FMU says which package is missing and what to do, although the
    host instantiates with logging off."""
    _, archive = cylinder
    shadow = tmp_path / "shadow" / "h5py"
    shadow.mkdir(parents=True)
    (shadow / "__init__.py").write_text('raise ImportError("No module named \'h5py\'", name="h5py")\n')
    folder = tmp_path / "unpacked"
    with zipfile.ZipFile(archive) as z:
        z.extractall(folder)
    plan = c_host_plan(archive, folder, 5, 0.1, ["mbd.float.x[3]"])
    env = {**os.environ, **fmu_environment()}
    env["PYTHONPATH"] = f"{shadow.parent}{os.pathsep}{env['PYTHONPATH']}"
    proc = subprocess.run([str(c_host), str(plan), str(tmp_path / "out.txt")], capture_output=True, text=True,
                          env=env, timeout=600)
    assert proc.returncode == 1, (proc.returncode, proc.stderr[-2000:])
    assert "hydro: fmi2Instantiate returned NULL" in proc.stderr
    assert "wec-cosim hydro FMU" in proc.stderr and "cannot import 'h5py'" in proc.stderr
    assert "wec-cosim host-env" in proc.stderr


def test_host_env_prints_and_sets_the_environment() -> None:
    proc = subprocess.run([sys.executable, "-m", "orchestrator.cli", "host-env", "--json"], capture_output=True,
                          text=True, cwd=ROOT, timeout=120)
    assert proc.returncode == 0, proc.stderr
    env = json.loads(proc.stdout)
    assert Path(env["LD_PRELOAD"].split()[0]).is_file() and "libpython" in env["LD_PRELOAD"]
    assert str(Path(np.__file__).resolve().parent.parent) in env["PYTHONPATH"].split(os.pathsep)
    proc = subprocess.run([sys.executable, "-m", "orchestrator.cli", "host-env", "--", sys.executable, "-c",
                           "import os; print(os.environ['LD_PRELOAD'])"], capture_output=True, text=True, cwd=ROOT,
                          timeout=120)
    assert proc.returncode == 0 and proc.stdout.strip() == env["LD_PRELOAD"], proc.stderr


def test_pythonfmu_patch_changes_two_instructions_of_the_known_binary_only() -> None:
    import pythonfmu

    original = (Path(pythonfmu.__file__).parent / "resources" / "binaries" / "linux64"
                / "libpythonfmu-export.so").read_bytes()
    patched, applied = patch_library(original)
    assert applied and len(patched) == len(original)
    changed = [i for i, (a, b) in enumerate(zip(original, patched, strict=True)) if a != b]
    assert changed == [0x16F34, 0x16F8B] and patched[0x16F34] == patched[0x16F8B] == 0xC3  # two "ret"
    assert is_patched(patched) and not is_patched(original)
    other = original[:-1] + bytes([original[-1] ^ 1])  # any other build
    assert patch_library(other) == (other, False)
