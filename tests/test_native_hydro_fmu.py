"""The native hydrodynamics FMU (hydro_fmu/native_fmu.py, native/fmi): FMI 2.0 co-simulation with no Python inside.

* fmpy's validation passes; the FMU's outputs equal the runtime's Python binding (hydro_fmu.runtime) on the same
  input history (the same compiled physics, reached through FMI instead of ctypes);
* fmpy's build of the FMU's sources/ gives a working binary with the same forces;
* host behaviour: a step the runtime refuses is fmi2Error with the reason logged (never Discard), a final step
  shorter than 1e-9 of the step is accepted, FMU states round-trip through serialisation, the directional
  derivatives are the database's hydrostatic stiffness and the force's own dependence on the velocity;
* in a process with no Python (`env -i`, a C host, `ldd` without libpython): forced heave of the cylinder gives the
  database's A(omega), B(omega) and excitation within 1 % at three frequencies.
"""

from __future__ import annotations

import csv
import os
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.validation import validate_fmu

from hydro_fmu.native_fmu import MODEL_IDENTIFIER, RESOURCE, build_native_hydro_fmu, fmi_headers, sea_constants
from hydro_fmu.runtime import HydroRuntime
from orchestrator.scenario import load_scenario
from orchestrator.scenario.loading import parse_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS

HERE = Path(__file__).resolve().parent
STEP = 0.1


def _scene():
    return load_scene(load_scenario(SCENARIOS / "cylinder_regular.toml"), log=None)


def _build(scene, path: Path) -> Path:
    s = scene.scenario
    return build_native_hydro_fmu(scene.hydro_model(), path, constants=sea_constants(scene.sea_spec()),
                                  experiment=(0.0, s.simulation.duration, s.simulation.step))


def _unzip(fmu: Path, where: Path) -> Path:
    with zipfile.ZipFile(fmu) as z:
        z.extractall(where)
    return where


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    scene = _scene()
    fmu = _build(scene, tmp_path_factory.mktemp("native") / "cylinder.fmu")
    return scene, fmu


def _slave(fmu: Path, unzipped: Path, name: str = "hydro") -> tuple[FMU2Slave, dict[str, int]]:
    md = read_model_description(str(fmu))
    slave = FMU2Slave(guid=md.guid, unzipDirectory=str(unzipped), modelIdentifier=MODEL_IDENTIFIER,
                      instanceName=name)
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    return slave, {v.name: v.valueReference for v in md.modelVariables}


def test_fmpy_validation_passes_and_the_build_fixes_the_sea(cylinder) -> None:
    scene, fmu = cylinder
    assert validate_fmu(str(fmu)) == []
    md = read_model_description(str(fmu))
    names = {v.name: v for v in md.modelVariables}
    assert md.coSimulation.providesDirectionalDerivative and md.coSimulation.canSerializeFMUstate
    assert names["wave.period"].variability == "constant" and float(names["wave.period"].start) == 5.6
    assert names["float.x[3]"].causality == "input" and names["float.F[3]"].causality == "output"
    with zipfile.ZipFile(fmu) as z:
        listed = set(z.namelist())
    assert f"binaries/linux64/{MODEL_IDENTIFIER}.so" in listed and "sources/fmi/fmi2Functions.c" in listed
    sources = md.buildConfigurations[0].sourceFileSets[0].sourceFiles
    assert len(sources) > 20 and {f"sources/{f}" for f in sources} <= listed


def _history(k: int) -> tuple[np.ndarray, np.ndarray]:
    t = k * STEP
    return np.array([0.4 * np.sin(0.9 * t) + 0.05 * np.cos(2.3 * t)]), np.array([0.3 * np.cos(0.7 * t) - 0.1])


def test_outputs_equal_the_runtime_binding_on_the_same_history(cylinder, tmp_path) -> None:
    """The FMU (through FMI) and hydro_fmu.runtime (through ctypes) run the same compiled physics: every output is
    equal to round-off over 300 steps of an arbitrary input history, the linearised interface included."""
    _, fmu = cylinder
    unzipped = _unzip(fmu, tmp_path / "fmu")
    slave, vr = _slave(fmu, unzipped)
    runtime = HydroRuntime((unzipped / "resources" / RESOURCE).read_bytes())
    outputs = ["float.F[3]", "float.F_exc[3]", "float.F_rad[3]", "float.F_hs[3]", "wave.elevation",
               "energy.excitation_work", "energy.radiation_work", "energy.hydrostatic_work", "float.F0[3]",
               "float.F0_rate[3]", "dF_dx[3,3]", "dF_dv[3,3]"]
    refs = [vr[o] for o in outputs]
    got, expected = [], []
    for k in range(300):
        t = k * STEP
        x, v = _history(k)
        slave.setReal([vr["float.x[3]"], vr["float.v[3]"]], [x[0], v[0]])
        got.append(slave.getReal(refs))
        eta = runtime.evaluate(t, x, v)
        block, work = runtime.block, runtime.work
        f0, rate, dfdx, dfdv = runtime.linearise(t, x, v)
        expected.append([block[0, 0], block[1, 0], block[2, 0], block[3, 0], eta, *work[:3], f0[0], rate[0],
                         dfdx[0, 0], dfdv[0, 0]])
        slave.doStep(t, STEP)
        runtime.do_step(t, STEP, x, v)
    slave.terminate()
    slave.freeInstance()
    got, expected = np.array(got), np.array(expected)
    assert np.abs(expected[:, 0]).max() > 1e4  # the excitation and the memory are really there
    scale = np.maximum(np.abs(expected).max(axis=0), 1e-300)
    difference = (np.abs(got - expected) / scale).max(axis=0)
    print("largest difference relative to each output's range:", difference.max())
    assert np.all(difference <= 1e-14), dict(zip(outputs, difference, strict=True))


def _simulate(unzipped: Path, md) -> np.ndarray:
    slave = FMU2Slave(guid=md.guid, unzipDirectory=str(unzipped), modelIdentifier=MODEL_IDENTIFIER,
                      instanceName="built")
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    vr = {v.name: v.valueReference for v in md.modelVariables}
    forces = []
    for k in range(200):
        x, v = _history(k)
        slave.setReal([vr["float.x[3]"], vr["float.v[3]"]], [x[0], v[0]])
        forces.append(slave.getReal([vr["float.F[3]"]])[0])
        slave.doStep(k * STEP, STEP)
    slave.terminate()
    slave.freeInstance()
    return np.array(forces)


@pytest.mark.skipif(shutil.which("cmake") is None, reason="fmpy builds source FMUs with cmake")
def test_fmpy_builds_a_working_binary_from_the_sources(cylinder, tmp_path) -> None:
    from fmpy.build import build_platform_binary

    _, fmu = cylinder
    md = read_model_description(str(fmu))
    shipped = _simulate(_unzip(fmu, tmp_path / "shipped"), md)
    rebuilt = _unzip(fmu, tmp_path / "rebuilt")
    shutil.rmtree(rebuilt / "binaries")
    (tmp_path / "build").mkdir()
    build_platform_binary(rebuilt, build_dir=tmp_path / "build")
    assert (rebuilt / "binaries" / "linux64" / f"{MODEL_IDENTIFIER}.so").exists()
    np.testing.assert_allclose(_simulate(rebuilt, md), shipped, rtol=1e-12, atol=1e-12 * np.abs(shipped).max())


REFUSED_STEP_HOST = """
import sys
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
fmu, unzipped, identifier = sys.argv[1:4]
md = read_model_description(fmu)
slave = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=identifier, instanceName="hydro")
slave.instantiate()
slave.setupExperiment(startTime=0.0)
slave.enterInitializationMode()
slave.exitInitializationMode()
slave.doStep(0.0, 0.1)
for start, step in ((0.1, 0.15), (0.1, 0.1)):
    try:
        slave.doStep(start, step)
        print("STATUS 0", flush=True)
    except FMICallException as error:
        print("STATUS", error.status, flush=True)
slave.freeInstance()
"""


def test_a_refused_step_is_an_error_with_its_reason(cylinder, tmp_path) -> None:
    """A step that is not a whole multiple of the radiation step: fmi2Error (3), never Discard (2), the runtime's
    reason in the log; the instance then refuses further steps. In a process of its own: fmpy's logger proxy is one
    per process, and a co-simulation run earlier in the test process would own it."""
    import sys

    _, fmu = cylinder
    unzipped = _unzip(fmu, tmp_path / "fmu")
    done = subprocess.run([sys.executable, "-c", REFUSED_STEP_HOST, str(fmu), str(unzipped), MODEL_IDENTIFIER],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    log = done.stdout
    assert log.count("STATUS 3") == 2, log
    assert "step refused at t = 0.1 s" in log and "not a whole multiple of the radiation convolution step" in log
    assert "fmi2DoStep is not allowed when the FMU is failed" in log


def test_a_final_step_shorter_than_1e_9_of_the_step_is_accepted(cylinder, tmp_path) -> None:
    """OMSimulator's floating-point time ends a run with a sliver of a step: accepted, the model does not move."""
    _, fmu = cylinder
    slave, vr = _slave(fmu, _unzip(fmu, tmp_path / "fmu"))
    t = 0.0
    for k in range(10):
        slave.doStep(k * STEP, STEP)
        t = (k + 1) * STEP
    before = slave.getReal([vr["float.F[3]"], vr["wave.elevation"]])
    slave.doStep(t, 1e-12 * STEP)
    assert slave.getReal([vr["float.F[3]"], vr["wave.elevation"]]) == before
    slave.doStep(t + 1e-12 * STEP, STEP)  # and a regular step after it still fits the FMU's clock
    slave.freeInstance()


def test_fmu_state_serialisation_round_trip(cylinder, tmp_path) -> None:
    _, fmu = cylinder
    slave, vr = _slave(fmu, _unzip(fmu, tmp_path / "fmu"))
    refs = [vr["float.F[3]"], vr["energy.radiation_work"]]

    def run(first: int, count: int) -> list[list[float]]:
        rows = []
        for k in range(first, first + count):
            x, v = _history(k)
            slave.setReal([vr["float.x[3]"], vr["float.v[3]"]], [x[0], v[0]])
            rows.append(slave.getReal(refs))
            slave.doStep(k * STEP, STEP)
        return rows

    run(0, 30)
    state = slave.getFMUstate()
    serialised = slave.serializeFMUstate(state)
    slave.freeFMUstate(state)
    reference = run(30, 20)
    restored = slave.deSerializeFMUstate(serialised)
    slave.setFMUstate(restored)
    slave.freeFMUstate(restored)
    assert run(30, 20) == reference
    assert slave.serializeFMUstate(slave.getFMUstate())[:8] == b"WECFMUS1"
    slave.freeInstance()


def test_directional_derivatives_are_the_stiffness_and_the_velocity_dependence(cylinder, tmp_path) -> None:
    """dF/dx is minus the database's hydrostatic heave stiffness (linear hydrostatics); dF/dv equals the change of
    F per unit change of v at the same point (F is affine in v: the memory's weight of the current velocity)."""
    scene, fmu = cylinder
    slave, vr = _slave(fmu, _unzip(fmu, tmp_path / "fmu"))
    for k in range(50):
        slave.doStep(k * STEP, STEP)
    fx, fv, f = vr["float.x[3]"], vr["float.v[3]"], vr["float.F[3]"]
    dfdx = slave.getDirectionalDerivative([f], [fx], [1.0])[0]
    dfdv = slave.getDirectionalDerivative([f], [fv], [1.0])[0]
    c33 = scene.hdb.hydrostatic_stiffness[0, 2, 2]
    np.testing.assert_allclose(dfdx, -c33, rtol=1e-12)
    base = slave.getReal([f])[0]
    slave.setReal([fv], [1.0])
    np.testing.assert_allclose(slave.getReal([f])[0] - base, dfdv, rtol=1e-9)
    assert dfdv < 0  # damping
    assert slave.getReal([vr["dF_dx[3,3]"], vr["dF_dv[3,3]"]]) == pytest.approx([dfdx, dfdv], rel=1e-14)
    slave.freeInstance()


# ---------------------------------------------------------------- no Python: env -i, a C host

def _host(tmp_path: Path) -> Path:
    exe = tmp_path / "forced_motion_host"
    cc = os.environ.get("CC", "cc")
    subprocess.run([cc, "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", f"-I{fmi_headers()}",
                    str(HERE / "native" / "forced_motion_host.c"), "-o", str(exe), "-ldl", "-lm"], check=True)
    return exe


def _phasor(t: np.ndarray, y: np.ndarray, omega: float) -> complex:
    """P with y = Re(P exp(i omega t)) + c, least squares."""
    design = np.column_stack([np.cos(omega * t), -np.sin(omega * t), np.ones_like(t)])
    (re, im, _), *_ = np.linalg.lstsq(design, y, rcond=None)
    return complex(re, im)


def _with_pitch(text: str) -> str:
    """The cylinder with heave and pitch (the inertia only satisfies the scenario's check: the hydro FMU has none)."""
    assert 'dofs = ["heave"]' in text
    return text.replace('dofs = ["heave"]', 'dofs = ["heave", "pitch"]\ninertia = [2.0e6, 2.0e6, 2.0e6]')


def _with_waves(text: str) -> str:
    assert '[waves]\nkind = "still"' in text
    return text.replace('[waves]\nkind = "still"', '[waves]\nkind = "regular"\nheight = 1.0\nperiod = 5.6\n'
                        'ramp_time = 20.0')


# (scenario, its text changed, index of the forced DOF among the FMU's inputs, its index in the database,
#  frequencies near which the database's own grid frequencies are used, motion amplitude)
FORCED_CASES = {
    "cylinder heave": ("cylinder_regular.toml", _with_pitch, 0, 2, (0.8, 1.12, 1.6), 0.2),
    # pitch at 1.12, 1.6 and 2.0 rad/s: at 0.8 rad/s the cylinder's pitch damping is 2 % of omega A55 and the model's
    # radiation memory (40 s kernel, dt 0.1 s; the same numbers from the Python model) gives B55 +4.1 %, A55 -0.75 %
    "cylinder pitch": ("cylinder_regular.toml", _with_pitch, 1, 4, (1.12, 1.6, 2.0), 0.05),
    "F3OF flap pitch": ("f3of_dt3.toml", _with_waves, 3, 10, (0.5, 0.8, 1.1), 0.05),
}


@pytest.mark.parametrize("case", list(FORCED_CASES))
def test_forced_oscillation_in_a_process_without_python_gives_the_database(case, tmp_path) -> None:
    """Acceptance: a C host under `env -i` (no Python in the process: `ldd` of the FMU shows no libpython) forces one
    degree of freedom, q = Q sin(omega t), in regular waves of the same frequency. From the last 8 periods (after
    the ramp and the impulse response's length): A(omega) = A_inf + Re(P_rad / Q_hat) / omega^2 and
    B(omega) = -Im(P_rad / Q_hat) / omega (the memory force is -(A - A_inf) q'' - B q'), and the excitation per unit
    elevation P_exc / P_eta; each within 1 % of the database at three of its frequencies."""
    name, change, dof, index, near, amplitude = FORCED_CASES[case]
    host = _host(tmp_path)
    path = SCENARIOS / name
    base = load_scene(parse_scenario(change(path.read_text()), path), log=None)
    grid = base.hdb.omega
    errors = []
    for target in near:
        omega = float(grid[np.argmin(np.abs(grid - target))])
        period = 2 * np.pi / omega
        text = change(path.read_text())
        assert "period = 5.6" in text
        scene = load_scene(parse_scenario(text.replace("period = 5.6", f"period = {period!r}"), path), log=None)
        fmu = _build(scene, tmp_path / f"fmu_{omega}.fmu")
        unzipped = _unzip(fmu, tmp_path / f"fmu_{omega}")
        library = unzipped / "binaries" / "linux64" / f"{MODEL_IDENTIFIER}.so"
        linked = subprocess.run(["ldd", str(library)], capture_output=True, text=True, check=True).stdout
        assert "python" not in linked.lower() and "libm" in linked
        out = tmp_path / f"forced_{omega}.txt"
        s = scene.scenario
        steps = int((s.ramp_time + s.hydro.irf_duration + 9 * period + 10) / STEP)
        md = read_model_description(str(fmu))
        subprocess.run(["env", "-i", str(host), str(unzipped), md.guid, str(dof), repr(amplitude), repr(omega),
                        repr(STEP), str(steps), str(out)], check=True, timeout=300)
        data = np.loadtxt(out)
        t = data[:, 0]
        window = t >= t[-1] - 8 * period
        q_hat = -1j * amplitude  # q = Q sin(omega t) = Re(-i Q exp(i omega t))
        ratio = _phasor(t[window], data[window, 5], omega) / q_hat
        hdb = scene.hdb
        j = int(np.argmin(np.abs(hdb.omega - omega)))
        a_expected, b_expected = hdb.added_mass[j, index, index], hdb.radiation_damping[j, index, index]
        a_got = hdb.added_mass_inf[index, index] + ratio.real / omega**2
        b_got = -ratio.imag / omega
        excitation = _phasor(t[window], data[window, 4], omega) / _phasor(t[window], data[window, 7], omega)
        x_expected = hdb.excitation[hdb.heading_index(0.0), j, index]
        print(f"{case} omega {omega:.4g}: A {a_got:.6g} / {a_expected:.6g}, B {b_got:.6g} / {b_expected:.6g}, "
              f"X {excitation:.6g} / {x_expected:.6g}")
        errors.append((omega, a_got / a_expected - 1, b_got / b_expected - 1, abs(excitation / x_expected - 1)))
    assert all(max(abs(a), abs(b), x) < 0.01 for _, a, b, x in errors), errors


# ---------------------------------------------------------------- FMI 3.0

@pytest.fixture(scope="module")
def cylinder3(tmp_path_factory, cylinder):
    scene, fmu2 = cylinder
    s = scene.scenario
    fmu3 = build_native_hydro_fmu(scene.hydro_model(), tmp_path_factory.mktemp("native3") / "cylinder3.fmu",
                                  constants=sea_constants(scene.sea_spec()),
                                  experiment=(0.0, s.simulation.duration, s.simulation.step), fmi_version=3)
    return scene, fmu2, fmu3


def _slave3(fmu: Path, unzipped: Path):
    from fmpy.fmi3 import FMU3Slave

    md = read_model_description(str(fmu))
    slave = FMU3Slave(guid=md.guid, unzipDirectory=str(unzipped), modelIdentifier=MODEL_IDENTIFIER,
                      instanceName="hydro3")
    slave.instantiate()
    slave.enterInitializationMode(startTime=0.0)
    slave.exitInitializationMode()
    return slave, {v.name: v.valueReference for v in md.modelVariables}


def test_fmi3_validation_passes_with_array_variables(cylinder3) -> None:
    scene, _, fmu3 = cylinder3
    assert validate_fmu(str(fmu3)) == []
    md = read_model_description(str(fmu3))
    assert md.fmiVersion == "3.0"
    with zipfile.ZipFile(fmu3) as z:  # the FMI 3.0 attribute (fmpy 0.3 reads only FMI 2.0's singular name)
        assert 'providesDirectionalDerivatives="true"' in z.read("modelDescription.xml").decode()
    variables = {v.name: v for v in md.modelVariables}
    assert [d.start for d in variables["A_inf"].dimensions] == ["1", "1"] or \
        [int(d.start) for d in variables["A_inf"].dimensions] == [1, 1]
    with zipfile.ZipFile(fmu3) as z:
        assert f"binaries/x86_64-linux/{MODEL_IDENTIFIER}.so" in z.namelist()
        assert "sources/buildDescription.xml" in z.namelist()


def test_fmi3_forces_equal_the_fmi2_ones_and_its_state_and_derivatives(cylinder3, tmp_path) -> None:
    """The same history through FMI 2.0 scalars and FMI 3.0 arrays: equal forces, bit for bit; the FMI 3.0 FMU's
    state round-trips through serialisation; A_inf is the database's; dF/dx is minus the database's stiffness."""
    scene, fmu2, fmu3 = cylinder3
    s2, vr2 = _slave(fmu2, _unzip(fmu2, tmp_path / "fmu2"))
    s3, vr3 = _slave3(fmu3, _unzip(fmu3, tmp_path / "fmu3"))
    f2, f3 = [], []
    for k in range(120):
        x, v = _history(k)
        s2.setReal([vr2["float.x[3]"], vr2["float.v[3]"]], [x[0], v[0]])
        s3.setFloat64([vr3["x"], vr3["v"]], [x[0], v[0]])
        f2.append(s2.getReal([vr2["float.F[3]"], vr2["float.F_rad[3]"], vr2["wave.elevation"]]))
        f3.append(s3.getFloat64([vr3["F"], vr3["F_rad"], vr3["wave.elevation"]]))
        if k == 80:
            state = s3.getFMUState()
            serialised = s3.serializeFMUState(state)
            s3.freeFMUState(state)
            tail_start = len(f3)
        s2.doStep(k * STEP, STEP)
        s3.doStep(k * STEP, STEP)
    assert f3 == f2
    restored = s3.deserializeFMUState(serialised)
    s3.setFMUState(restored)
    s3.freeFMUState(restored)
    replay = []
    for k in range(80, 120):
        x, v = _history(k)
        s3.setFloat64([vr3["x"], vr3["v"]], [x[0], v[0]])
        replay.append(s3.getFloat64([vr3["F"], vr3["F_rad"], vr3["wave.elevation"]]))
        s3.doStep(k * STEP, STEP)
    assert replay == f3[tail_start - 1:]
    assert s3.getFloat64([vr3["A_inf"]])[0] == pytest.approx(scene.hdb.added_mass_inf[2, 2], rel=1e-14)
    dfdx = s3.getDirectionalDerivative([vr3["F"]], [vr3["x"]], [1.0])[0]
    np.testing.assert_allclose(dfdx, -scene.hdb.hydrostatic_stiffness[0, 2, 2], rtol=1e-12)
    both = s3.getDirectionalDerivative([vr3["F"]], [vr3["x"], vr3["v"]], [1.0, 1.0])[0]
    dfdv = s3.getDirectionalDerivative([vr3["F"]], [vr3["v"]], [1.0])[0]
    assert dfdv < 0 and both == pytest.approx(dfdx + dfdv, rel=1e-14)
    for slave in (s2, s3):
        slave.terminate()
        slave.freeInstance()


# ---------------------------------------------------------------- OMSimulator's command line

OMSIMULATOR = Path(__file__).resolve().parents[2] / "shared" / "tools" / "omsimulator" / "bin" / "OMSimulator"


def _steady_amplitude(t: np.ndarray, x: np.ndarray, omega: float, periods: int = 10) -> float:
    window = t >= t[-1] - periods * 2 * np.pi / omega
    return abs(_phasor(t[window], x[window], omega))


PTO_DAMPING = 2.0e5  # N s/m, cylinder_regular.toml


def _body_and_exact(scene, tmp_path: Path) -> tuple[Path, float]:
    """The native heave body of the cylinder (displaced mass, A_inf and PTO of the scenario) and the exact steady
    heave amplitude, |X| = (H/2) |F_exc(omega)| / |C - omega^2 (m + A(omega)) + i omega (B(omega) + c)|, from the
    database (linear interpolation in frequency, as the hydro model)."""
    from .native_heave_body import build_heave_body_fmu

    hdb, spec = scene.hdb, scene.sea_spec()
    assert "damping = 2.0e5" in (SCENARIOS / "cylinder_regular.toml").read_text()
    mass, c33 = hdb.rho * hdb.displaced_volume[0], hdb.hydrostatic_stiffness[0, 2, 2]
    body = build_heave_body_fmu(tmp_path / "body.fmu", mass, hdb.added_mass_inf[2, 2], PTO_DAMPING, STEP, 200.0)
    omega = 2 * np.pi / spec.period
    a, b, excitation = hdb.interpolate(omega)
    exact = spec.height / 2 * abs(excitation[0, 2]) / abs(
        c33 - omega**2 * (mass + a[0, 2, 2]) + 1j * omega * (b[0, 2, 2] + PTO_DAMPING))
    return body, exact


@pytest.mark.skipif(not OMSIMULATOR.exists(), reason="OMSimulator is not installed in ../shared/tools/omsimulator")
def test_omsimulator_command_line_runs_the_native_hydro_fmu_with_a_native_body(cylinder, tmp_path) -> None:
    """Acceptance: OMSimulator's command line, with no Python in its environment (`env -i`), runs an SSP of the
    native hydro FMU and a small native one-body heave FMU (tests/native_heave_body.py; mass + A_inf + PTO,
    trapezoidal rule on the linearised force) over 200 s at 0.1 s: the cylinder's steady heave amplitude is within
    0.5 % of the exact frequency-domain answer from the database,
    |X| = (H/2) |F_exc(omega)| / |C - omega^2 (m + A(omega)) + i omega (B(omega) + c)|."""
    from .native_heave_body import write_ssp

    scene, hydro = cylinder
    body, exact = _body_and_exact(scene, tmp_path)
    ssp = write_ssp(tmp_path / "cylinder.ssp", hydro, body, "float", 3, 3, STEP, 200.0)
    result = subprocess.run(["env", "-i", str(OMSIMULATOR), str(ssp), f"--stepSize={STEP!r}", "--stopTime=200",
                             "--resultFile=out.csv"], capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert result.returncode == 0 and "0 errors" in result.stdout, result.stdout + result.stderr
    with open(tmp_path / "out.csv", newline="") as f:
        header = [h.strip() for h in next(csv.reader(f))]  # quoted: names such as dF_dx[3,3] hold commas
    data = np.loadtxt(tmp_path / "out.csv", delimiter=",", skiprows=1)
    t, x = data[:, header.index("time")], data[:, header.index("native_cylinder.root.body.x")]
    assert t[-1] == pytest.approx(200.0)
    omega = 2 * np.pi / scene.sea_spec().period
    got = _steady_amplitude(t, x, omega)
    print(f"OMSimulator steady heave {got:.6g} m, exact {exact:.6g} m ({(got / exact - 1) * 100:+.3f} %)")
    assert got == pytest.approx(exact, rel=0.005)


def test_c_host_without_python_couples_the_native_hydro_fmu_to_its_own_body(cylinder, tmp_path) -> None:
    """Acceptance: the plain C host (tests/c_host/jacobi_host.c: fixed step, Jacobi order, zero-order hold, no
    iteration) under `env -i` couples the native hydro FMU to a native one-body heave integrator (mass + A_inf +
    PTO) through the linearised force interface: steady heave within 0.5 % of the exact frequency-domain answer."""
    from .native_heave_body import TOKEN

    scene, hydro = cylinder
    body, exact = _body_and_exact(scene, tmp_path)
    host = tmp_path / "jacobi_host"
    subprocess.run([os.environ.get("CC", "cc"), "-O2", "-std=c99", "-D_POSIX_C_SOURCE=200809L", "-Wall", "-Wextra",
                    "-Werror", f"-I{fmi_headers()}", str(HERE / "c_host" / "jacobi_host.c"), "-o", str(host), "-ldl"],
                   check=True)
    hydro_dir, body_dir = _unzip(hydro, tmp_path / "hydro"), _unzip(body, tmp_path / "body")
    plan = tmp_path / "plan.txt"
    plan.write_text("\n".join([
        f"fmu hydro {hydro_dir} {MODEL_IDENTIFIER} {read_model_description(str(hydro)).guid}",
        f"fmu body {body_dir} wec_heave_body {TOKEN}",
        "connect body 20 hydro 1000", "connect body 21 hydro 2000",  # x, v (native/fmi/*/config.h)
        "connect hydro 8000 body 10", "connect hydro 9000 body 11",  # F0, F0_rate
        "connect hydro 100000 body 12", "connect hydro 200000 body 13",  # dF_dx, dF_dv
        "record body 20", f"step {STEP!r}", "steps 2000", ""]))
    out = tmp_path / "out.txt"
    subprocess.run(["env", "-i", str(host), str(plan), str(out)], check=True, timeout=300)
    data = np.loadtxt(out)
    omega = 2 * np.pi / scene.sea_spec().period
    got = _steady_amplitude(data[:, 0], data[:, 1], omega)
    print(f"C host steady heave {got:.6g} m, exact {exact:.6g} m ({(got / exact - 1) * 100:+.3f} %)")
    assert got == pytest.approx(exact, rel=0.005)


def test_libcosim_runs_the_ssp_without_our_package_numpy_or_scipy(cylinder, tmp_path) -> None:
    """Acceptance: libcosim (libcosimpy, in an isolated interpreter that imports neither our package nor numpy nor
    scipy) runs the SSP of the native hydro FMU and the native heave body to the same steady heave (+0.126 % of
    exact, as the C host and OMSimulator)."""
    import sys

    from .native_heave_body import write_ssp

    scene, hydro = cylinder
    body, exact = _body_and_exact(scene, tmp_path)
    ssp = write_ssp(tmp_path / "cylinder.ssp", hydro, body, "float", 3, 3, STEP, 200.0)
    folder = _unzip(ssp, tmp_path / "ssp")
    run = subprocess.run([sys.executable, "-I", str(HERE / "native" / "run_libcosim_ssp.py"), str(folder), "2000",
                          repr(STEP)], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert run.returncode == 0, run.stderr[-2000:]
    assert "loaded: none" in run.stderr
    data = np.array([[float(v) for v in line.split()[1:]] for line in run.stdout.splitlines() if line.startswith("@ ")])
    assert len(data) == 2000 and data[-1, 0] == pytest.approx(200.0)
    omega = 2 * np.pi / scene.sea_spec().period
    got = _steady_amplitude(data[:, 0], data[:, 1], omega)
    print(f"libcosim steady heave {got:.6g} m, exact {exact:.6g} m ({(got / exact - 1) * 100:+.3f} %)")
    assert got == pytest.approx(exact, rel=0.005)


@pytest.mark.skipif(shutil.which("cmake") is None, reason="fmpy builds source FMUs with cmake")
def test_fmpy_builds_a_working_fmi3_binary_from_the_build_description(cylinder3, tmp_path) -> None:
    from fmpy import simulate_fmu
    from fmpy.build import build_platform_binary

    _, _, fmu3 = cylinder3
    shipped = simulate_fmu(str(_unzip(fmu3, tmp_path / "shipped")), stop_time=30.0, step_size=STEP, output=["F"])
    rebuilt = _unzip(fmu3, tmp_path / "rebuilt")
    shutil.rmtree(rebuilt / "binaries")
    (tmp_path / "build").mkdir()
    build_platform_binary(rebuilt, build_dir=tmp_path / "build")
    again = simulate_fmu(str(rebuilt), stop_time=30.0, step_size=STEP, output=["F"])
    forces = np.asarray(shipped["F"], dtype=float).ravel()
    assert np.abs(forces).max() > 1e4
    np.testing.assert_allclose(np.asarray(again["F"], dtype=float).ravel(), forces, rtol=1e-12,
                               atol=1e-12 * np.abs(forces).max())


def _wec_cosim(*args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    import sys

    return subprocess.run([sys.executable, "-m", "wec_cosim.cli", *args], capture_output=True, text=True,
                          cwd=HERE.parent, env=env or os.environ.copy(), timeout=600)


def test_build_fmus_writes_the_native_fmus_and_names_a_missing_compiler(tmp_path) -> None:
    scenario = str(SCENARIOS / "cylinder_regular.toml")
    proc = _wec_cosim("build-fmus", scenario, "--out", str(tmp_path), "--native")
    assert proc.returncode == 0, proc.stderr
    for version in (2, 3):
        fmu = tmp_path / f"cylinder_regular_hydro_native_fmi{version}.fmu"
        assert validate_fmu(str(fmu)) == []
        assert read_model_description(str(fmu)).fmiVersion == f"{version}.0"
    env = dict(os.environ, CC="/nonexistent/cc")
    proc = _wec_cosim("build-fmus", scenario, "--out", str(tmp_path / "again"), "--native", env=env)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "no C compiler ('/nonexistent/cc' is not on PATH)" in proc.stderr


def test_damaged_resources_or_a_wrong_guid_fail_instantiate_with_a_message(cylinder, tmp_path) -> None:
    """Damaged runtime input (truncated, bytes flipped, a missing file) or a GUID from another build: the C host's
    fmi2Instantiate returns NULL with the reason logged, in a separate process that must not crash (exit status 1,
    not a signal)."""
    _, fmu = cylinder
    host = _host(tmp_path)
    guid = read_model_description(str(fmu)).guid
    original = (_unzip(fmu, tmp_path / "original") / "resources" / RESOURCE).read_bytes()
    rng = np.random.default_rng(7)
    cases = {"truncated": original[: len(original) // 2], "empty": b"", "header only": original[:48]}
    for k in range(12):
        damaged = bytearray(original)
        for position in rng.integers(0, 48 + 128 * 4, size=3):  # the header and the first directory entries
            damaged[position] ^= 0xFF
        cases[f"flipped {k}"] = bytes(damaged)
    cases["missing"] = None
    cases["wrong guid"] = original
    for name, data in cases.items():
        folder = _unzip(fmu, tmp_path / name.replace(" ", "_"))
        target = folder / "resources" / RESOURCE
        if data is None:
            target.unlink()
        else:
            target.write_bytes(data)
        token = "{00000000-0000-0000-0000-000000000000}" if name == "wrong guid" else guid
        run = subprocess.run(["env", "-i", str(host), str(folder), token, "0", "0.1", "1.0", repr(STEP), "10",
                              str(tmp_path / "out.txt")], capture_output=True, text=True, timeout=60)
        if data == original and name != "wrong guid":
            continue
        assert run.returncode == 1, (name, run.returncode, run.stderr)  # a signal would be negative
        assert "[hydro 3 logError]" in run.stderr, (name, run.stderr)
        if name == "wrong guid":
            assert "does not match this FMU's resources" in run.stderr
        elif name == "missing":
            assert "cannot open" in run.stderr
        else:
            assert "refused" in run.stderr or "resources/hydro.wecrt" in run.stderr, (name, run.stderr)


@pytest.mark.slow
def test_fmu_glue_under_address_and_undefined_behaviour_sanitizers(cylinder, tmp_path) -> None:
    """The FMU's own sources/ and the C host built with -fsanitize=address,undefined: a regular forced run and the
    damaged-resource cases run clean (no invalid access, leak or undefined behaviour; the sanitizers' exit status
    is 86 and would fail the test)."""
    _, fmu = cylinder
    cc = os.environ.get("CC", "cc")
    flags = ["-std=c11", "-g", "-O1", "-fno-omit-frame-pointer", "-fsanitize=address,undefined",
             "-fno-sanitize-recover=all"]
    folder = _unzip(fmu, tmp_path / "fmu")
    sources = folder / "sources"
    library = folder / "binaries" / "linux64" / f"{MODEL_IDENTIFIER}.so"
    c_files = [str(p) for p in sorted(sources.rglob("*.c"))]
    subprocess.run([cc, *flags, "-fPIC", "-shared", f"-I{sources}", *c_files, "-o", str(library), "-lm"], check=True)
    host = tmp_path / "host_asan"
    subprocess.run([cc, *flags, f"-I{fmi_headers()}", str(HERE / "native" / "forced_motion_host.c"), "-o", str(host),
                    "-ldl", "-lm"], check=True)
    env = {"ASAN_OPTIONS": "detect_leaks=1:exitcode=86", "UBSAN_OPTIONS": "halt_on_error=1:exitcode=86"}
    guid = read_model_description(str(fmu)).guid
    good = subprocess.run([str(host), str(folder), guid, "0", "0.2", "1.12", repr(STEP), "600",
                           str(tmp_path / "out.txt")], capture_output=True, text=True, env=env, timeout=600)
    assert good.returncode == 0, good.stderr[-3000:]
    original = (folder / "resources" / RESOURCE).read_bytes()
    rng = np.random.default_rng(11)
    for k in range(20):
        damaged = bytearray(original[: int(rng.integers(0, len(original)))] if k % 4 == 0 else original)
        for position in rng.integers(0, min(len(damaged), 48 + 128 * 6) or 1, size=3):
            if damaged:
                damaged[position] ^= int(rng.integers(1, 256))
        (folder / "resources" / RESOURCE).write_bytes(bytes(damaged))
        run = subprocess.run([str(host), str(folder), guid, "0", "0.2", "1.12", repr(STEP), "20",
                              str(tmp_path / "out.txt")], capture_output=True, text=True, env=env, timeout=120)
        assert run.returncode in (0, 1), (k, run.returncode, run.stderr[-3000:])
        assert run.returncode == 0 or "logError" in run.stderr
