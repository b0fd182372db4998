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

import copy
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

from orchestrator.cosim import study
from orchestrator.fmi.fmu_builder import build_scene_fmus
from orchestrator.fmi.foreign_hosts import c_host_plan
from orchestrator.fmi.host_environment import fmu_environment
from orchestrator.fmi.pythonfmu_patch import is_patched, patch_library
from orchestrator.reference import frequency_domain
from orchestrator.results.analysis import harmonic_fit, steady_window
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
    proc = subprocess.run([sys.executable, "-m", "wec_cosim.cli", "export-ssp", str(SCENARIOS / f"{name}.toml"),
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
    proc = subprocess.run([sys.executable, "-m", "orchestrator.fmi.foreign_hosts", host, str(archive), "--steps",
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


@pytest.fixture(scope="module")
def cylinder_fmpy(cylinder, tmp_path_factory) -> dict:
    """fmpy's simulate_ssp on the exported cylinder, 200 s at the exported step."""
    scene, archive = cylinder
    data, _ = run_host("fmpy", archive, 2000, scene.scenario.simulation.step, ["mbd.float.x[3]"],
                       tmp_path_factory.mktemp("fmpy"))
    return data


def test_c_host_runs_the_cylinder_right_at_the_exported_step(cylinder, cylinder_fmpy, c_host, tmp_path) -> None:
    """Acceptance: the plain C host equals fmpy's SSP runner to 1e-10 m and the steady heave is within
    2 % / 2 deg of the exact answer at the exported step (0.1 s); both processes exit 0."""
    scene, archive = cylinder
    steps, h = 2000, scene.scenario.simulation.step
    var = ["mbd.float.x[3]"]
    c, _ = run_host("c", archive, steps, h, var, tmp_path, c_host)
    ref = cylinder_fmpy
    np.testing.assert_allclose(c["time"], ref["time"], rtol=1e-12)
    assert np.max(np.abs(c[var[0]] - ref[var[0]])) < 1e-10
    amplitude, phase = steady_errors(scene, c["time"], {"float.x[3]": c[var[0]]})["float.x[3]"]
    assert abs(amplitude) < 0.02 and abs(phase) < 2.0, (amplitude, phase)


def test_libcosim_runs_the_cylinder_as_fmpy_does_without_parser_errors(cylinder, cylinder_fmpy, tmp_path) -> None:
    scene, archive = cylinder
    steps, h = 2000, scene.scenario.simulation.step
    var = ["mbd.float.x[3]"]
    ours, proc = run_host("libcosim", archive, steps, h, var, tmp_path)
    log = proc.stdout + proc.stderr
    assert "FMI2XML" in log  # libcosim's parser log is really captured
    assert "[error]" not in log and "[fatal]" not in log and "[warning]" not in log, log[-3000:]
    assert np.max(np.abs(ours[var[0]] - cylinder_fmpy[var[0]])) < 1e-10
    errors = steady_errors(scene, ours["time"], {"float.x[3]": ours[var[0]]})
    assert abs(errors["float.x[3]"][0]) < 0.02 and abs(errors["float.x[3]"][1]) < 2.0, errors


HINGE_VARIABLES = [f"mbd.{b}.x[{i}]" for b in ("barge1", "barge2") for i in (1, 3, 5)]


def plain_fmpy_run(scene, duration: float) -> study.Series:
    """The same plain host through fmpy in this process: our fixed-step Jacobi, outputs read right after each
    step (``resolve_feedthrough = false``), the linearised interface, the FMUs loaded by fmpy."""
    s = copy.deepcopy(scene.scenario)
    s.simulation.duration = duration
    h = s.simulation.step
    return study.run_series(study.variant(s, "jacobi", h, 0, interface="linearised", plain_host=True), scene=scene)


def test_hinge_barge_runs_alike_in_the_c_host_fmpy_and_libcosim(hinge, c_host, tmp_path) -> None:
    """The exported hinge barge (nonlinear index-3 multibody FMU) over its first 2 s (the full 200 s against the
    exact answer is the slow test below): the C host equals the same plain host through fmpy to 1e-10;
    fmpy's simulate_ssp and libcosim agree to 1e-9 (simulate_ssp starts its connectors at 0, not at the
    outputs after initialisation: a different first step); clean log; every process exits 0."""
    scene, archive = hinge
    steps, h = 100, scene.scenario.simulation.step
    runs = {host: run_host(host, archive, steps, h, HINGE_VARIABLES, tmp_path, c_host if host == "c" else None)
            for host in ("c", "fmpy", "libcosim")}
    log = runs["libcosim"][1].stdout + runs["libcosim"][1].stderr
    assert "[error]" not in log and "[fatal]" not in log, log[-3000:]
    c = runs["c"][0]
    assert np.max(np.abs(c["mbd.barge1.x[3]"])) > 1e-4  # the barges move (wave height 0.02 m, ramp)
    ours = plain_fmpy_run(scene, steps * h)
    for j, v in enumerate(HINGE_VARIABLES):
        assert np.max(np.abs(c[v] - ours.displacement[1:, j])) < 1e-10, v
        for host in ("fmpy", "libcosim"):
            assert np.max(np.abs(runs[host][0][v] - c[v])) < 1e-9, (host, v)


@pytest.mark.slow
@pytest.mark.acceptance
def test_c_host_hinge_barge_is_stable_and_right_over_200_s(hinge, c_host, tmp_path) -> None:
    """Acceptance: 200 s of the exported hinge barge at its exported step (0.02 s) in the plain C host: equal
    to the same plain host run through fmpy (our fixed-step Jacobi with outputs read right after each step,
    FMUs loaded by fmpy) to 1e-10, stable (the last ten periods' amplitudes equal the ten before to 0.5 %),
    every motion amplitude within 2 % / 2 deg of the exact frequency-domain answer. fmpy's simulate_ssp and
    libcosim agree to 1e-8 (a 5e-7 fraction of the motion): simulate_ssp starts every connector at 0 instead
    of at the outputs after initialisation (a different first step, by the hydrostatic tangent times a 1e-9
    rad settling motion), and the index-3 Newton iterations, which stop at 1e-10 of the coordinates, carry
    such differences on over 10 000 steps."""
    scene, archive = hinge
    h = scene.scenario.simulation.step
    steps = int(round(200.0 / h))
    c, _ = run_host("c", archive, steps, h, HINGE_VARIABLES, tmp_path, c_host)
    ours = plain_fmpy_run(scene, 200.0)
    np.testing.assert_allclose(ours.time[1:], c["time"], rtol=1e-12)
    for j, v in enumerate(HINGE_VARIABLES):
        assert np.max(np.abs(c[v] - ours.displacement[1:, j])) < 1e-10, v
    ref, _ = run_host("fmpy", archive, steps, h, HINGE_VARIABLES, tmp_path)
    cosim, proc = run_host("libcosim", archive, steps, h, HINGE_VARIABLES, tmp_path)
    log = proc.stdout + proc.stderr
    assert "[error]" not in log and "[fatal]" not in log, log[-3000:]
    for v in HINGE_VARIABLES:  # measured 2.7e-10 (fmpy) and 1.6e-9 (libcosim) rad at most
        assert np.max(np.abs(ref[v] - c[v])) < 1e-8 and np.max(np.abs(cosim[v] - c[v])) < 1e-8, v
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


@pytest.mark.parametrize("name", ["cylinder", pytest.param("hinge", marks=pytest.mark.slow)])
def test_fmpy_simulate_fmu_with_defaults_runs_each_fmu_to_its_stop_time(name, request) -> None:
    """Each FMU alone, ``fmpy.simulate_fmu(fmu)`` and nothing else: both reach the DefaultExperiment's stop
    time; the hydro FMU held at rest outputs the wave excitation force, whose amplitude is the database's
    excitation coefficient times the wave amplitude; the multibody FMU without force stays at rest."""
    scene, _ = request.getfixturevalue(name)
    fmus = build_scene_fmus(scene)
    stop = scene.scenario.simulation.duration
    b, dof = scene.hydro_coordinates[0 if name == "cylinder" else 1]  # heave of the first body
    force = f"{b}.F[{dof + 1}]"
    hydro = fmpy.simulate_fmu(str(fmus["hydro"]), output=[force, f"{b}.F0[{dof + 1}]"])
    assert math.isclose(hydro["time"][-1], stop)
    mbd = fmpy.simulate_fmu(str(fmus["mbd"]), output=[f"{b}.x[{dof + 1}]"])
    assert math.isclose(mbd["time"][-1], stop)
    assert np.max(np.abs(mbd[f"{b}.x[{dof + 1}]"])) < 1e-6
    w = scene.scenario.waves
    omega = 2 * math.pi / w.period
    k = scene.hydro_index()[0 if name == "cylinder" else 1]
    exact = abs(scene.hdb.excitation_at(np.array([omega]), math.radians(w.heading_deg))[0][k]) * w.height / 2
    t = hydro["time"]
    late = t > stop - 5 * w.period
    amplitude = abs(harmonic_fit(t[late], hydro[force][late], omega)[0])
    assert abs(amplitude / exact - 1) < 1e-6
    # x = v = 0: the constant term of the linearised force is the whole force
    np.testing.assert_allclose(hydro[f"{b}.F0[{dof + 1}]"], hydro[force], rtol=1e-12)


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
    proc = subprocess.run([sys.executable, "-m", "wec_cosim.cli", "host-env", "--json"], capture_output=True,
                          text=True, cwd=ROOT, timeout=120)
    assert proc.returncode == 0, proc.stderr
    env = json.loads(proc.stdout)
    assert Path(env["LD_PRELOAD"].split()[0]).is_file() and "libpython" in env["LD_PRELOAD"]
    assert str(Path(np.__file__).resolve().parent.parent) in env["PYTHONPATH"].split(os.pathsep)
    proc = subprocess.run([sys.executable, "-m", "wec_cosim.cli", "host-env", "--", sys.executable, "-c",
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
