"""Generated multibody model errors and silent nonsense: inputs that ran with wrong results, or failed with a bare
ValueError or a LAPACK line, before the model checks (``mbd_fmu/spec_checks.py``), the static-stability test
(``orchestrator/reference/stability.py``) and the divergence diagnosis (``orchestrator/cosim/divergence.py``).

Model errors, generated from the hinge barge (two bodies, one revolute joint): inertia tensors that no rigid body
has (not positive definite, or principal moments breaking ``I1 + I2 >= I3``), joint axes that are the zero
vector, universal joints whose axes are parallel or not at a right angle, distance joints of one point, a body
placed off its hinge (the assembly would move it beyond its stated tolerance), a driver on a coordinate that a
locked joint fixes. Silent nonsense: names that differ only in case, a repeat period that leaves the sea with no
component, a database whose hydrostatic stiffness pushes the body away (``rao``, ``steady`` and a diverging
``run``). Each is exit status 2 and one paragraph naming the file, the object and the fix.

Correct runs where the old code went wrong silently: a joint axis of any scale is its direction (the joint
coordinate recorded is the one of the unit axis: the scale of a direction vector has no physical meaning), and a
start pose corrected by the assembly within the tolerance is reported with the move.
"""

from __future__ import annotations

import copy

import h5py
import numpy as np
import pytest

from mbd_fmu.spec_checks import ASSEMBLY_TOLERANCE

from .hostile import Case, check
from .test_malformed_generated import _materialise, run_in_process
from .toml_text import bundled

RUN = ["run", "{dir}/s.toml", "--quiet", "--out", "{dir}/out.h5"]


def barge(duration: float = 0.5) -> dict:
    """The bundled hinge barge (its database is cached), ``duration`` s long."""
    data = bundled("hinge_barge")
    data["simulation"]["duration"] = duration
    return data


def _changed(change) -> dict:  # noqa: ANN001
    data = barge()
    change(data)
    return data


def _body(k: int, **values) -> callable:  # noqa: ANN003
    return lambda d: d["bodies"][k].update(values)


def _joint(**values) -> callable:  # noqa: ANN003
    return lambda d: d["joints"][0].update(values)


def model_error_cases() -> list[Case]:
    """Multibody model errors: several generated values per kind."""
    cases = []
    for ixy in (30.0, 26.5, -40.0):  # the moments of barge1 are 17.6, 34.9, 37.7 kg m^2: |Ixy| > 24.8 breaks it
        cases.append(Case(f"inertia with Ixy = {ixy} not positive definite",
                          RUN, {"s.toml": _changed(_body(0, inertia=[17.6, 34.9, 37.7, ixy, 0.0, 0.0]))},
                          ["{dir}/s.toml", "barge1", "not positive definite"]))
    for moments in ([1.0, 1.0, 37.7], [66.8, 4.53, 80.0], [1.0, 100.0, 2.0]):
        cases.append(Case(f"principal moments {moments}", RUN, {"s.toml": _changed(_body(1, inertia=moments))},
                          ["{dir}/s.toml", "barge2", "I1 + I2 >= I3"]))
    for key in ("axis", "axis2"):
        cases.append(Case(f"joint {key} the zero vector", RUN, {"s.toml": _changed(_joint(
            kind="universal", axis=[0.0, 0.0, 0.0] if key == "axis" else [0.0, 1.0, 0.0],
            axis2=[0.0, 0.0, 0.0] if key == "axis2" else [1.0, 0.0, 0.0]))}, ["{dir}/s.toml", "hinge", key]))
    for axis2 in ([0.0, 2.0, 0.0], [0.0, -1.0, 0.0], [0.0, 1e-200, 0.0], [0.0, 1e200, 0.0]):
        cases.append(Case(f"universal joint axis2 {axis2} parallel to axis", RUN, {"s.toml": _changed(_joint(
            kind="universal", axis=[0.0, 1.0, 0.0], axis2=axis2))}, ["{dir}/s.toml", "hinge", "parallel"]))
    for axis2 in ([1.0, 1.0, 0.0], [1.0, 0.01, 0.0]):
        cases.append(Case(f"universal joint axes {axis2} and y not at a right angle", RUN, {"s.toml": _changed(
            _joint(kind="universal", axis=[0.0, 1.0, 0.0], axis2=axis2))}, ["{dir}/s.toml", "hinge", "right angle"]))
    for gap in (0.0, 1e-12):
        cases.append(Case(f"distance joint of length {gap}", RUN, {"s.toml": _changed(_joint(
            kind="distance", position2=[0.78 + gap, 0.0, 0.0]))}, ["{dir}/s.toml", "hinge", "coincide"]))
    for dof, value in ((2, 0.5), (0, 0.2), (4, 0.3), (2, -0.05)):
        displacement = [0.0] * 6
        displacement[dof] = value
        cases.append(Case(f"barge2 placed off its hinge (initial displacement {displacement})", RUN,
                          {"s.toml": _changed(_body(1, initial_displacement=displacement))},
                          ["{dir}/s.toml", "barge2", "would move body", "the assembly may correct"]))
    for driver in ({"joint": "hinge"}, {"body": "barge2", "dof": "pitch"}):
        def lock_and_drive(d: dict, driver: dict = driver) -> None:
            d["joints"][0]["locked"] = True
            d["drivers"] = [{"name": "drv", "amplitude": 0.1, "period": 2.0, **driver}]
            d["bodies"][0]["dofs"] = ["surge", "heave"]  # barge1 cannot pitch: the locked hinge fixes barge2's too
        cases.append(Case(f"driver {driver} on a locked hinge", RUN, {"s.toml": _changed(lock_and_drive)},
                          ["{dir}/s.toml", "driver 'drv'", "already fix"]))
    return cases


def _rename(k: int, name: str) -> callable:
    """Body k renamed everywhere it is named."""
    def change(d: dict) -> None:
        old = d["bodies"][k]["name"]
        for section in ("bodies", "joints", "ptos", "forces"):
            for item in d.get(section, []):
                for key in ("name", "body", "body1", "body2"):
                    if item.get(key) == old and (section == "bodies" or key != "name"):
                        item[key] = name
    return change


def silent_nonsense_cases() -> list[Case]:
    cases = [Case(f"bodies barge1 and {name}", RUN, {"s.toml": _changed(_rename(1, name))},
                  ["{dir}/s.toml", "differ only in case", name]) for name in ("Barge1", "BARGE1", "bArGe1")]
    cases += [Case(f"pto named {name} beside pto", RUN, {"s.toml": _changed(lambda d, name=name: d["ptos"].append(
        {**d["ptos"][0], "name": name}))}, ["{dir}/s.toml", "differ only in case", name]) for name in ("PTO", "Pto")]
    irregular = bundled("cylinder_irregular")
    irregular["simulation"]["duration"] = 1.0
    for period in (0.001, 0.05, 0.5):  # Tp = 7 s: a component spacing of 2 pi / period leaves none in the spectrum
        data = copy.deepcopy(irregular)
        data["waves"]["repeat_period"] = period
        cases.append(Case(f"waves.repeat_period = {period} s", RUN, {"s.toml": data},
                          ["{dir}/s.toml", "waves.repeat_period", "equal_energy"]))
    return cases


MODEL_ERRORS = model_error_cases()
SILENT = silent_nonsense_cases()


@pytest.mark.parametrize("case", MODEL_ERRORS + SILENT, ids=[c.name for c in MODEL_ERRORS + SILENT])
def test_a_model_error_or_silent_nonsense_is_one_clean_error(tmp_path, case) -> None:
    code, stderr = run_in_process(_materialise(case, tmp_path))
    check(case, code, stderr, tmp_path)


def test_the_generated_sets_cover_each_kind() -> None:
    names = " ".join(c.name for c in MODEL_ERRORS + SILENT)
    for word in ("not positive definite", "principal moments", "zero vector", "parallel", "right angle",
                 "distance joint", "off its hinge", "driver", "Barge1", "PTO", "repeat_period"):
        assert word in names, word
    assert len(MODEL_ERRORS) >= 20 and len(SILENT) >= 8


def _joint_coordinate(folder, axis) -> np.ndarray:  # noqa: ANN001
    data = barge(duration=2.0)
    data["joints"][0]["axis"] = axis
    case = Case(f"axis {axis}", RUN, {"s.toml": data})
    folder.mkdir()
    code, stderr = run_in_process(_materialise(case, folder))
    assert code == 0, stderr
    with h5py.File(folder / "out.h5", "r") as f:
        return f["joints/hinge/coordinate"][:, 0]


@pytest.mark.parametrize("scale", [1e-200, 1e-3, 7.0, 1e200])
def test_a_joint_axis_of_any_scale_is_its_direction(tmp_path, scale) -> None:
    """A revolute axis ``scale * y`` is the y hinge: the recorded hinge angle equals the unit axis's (the hinge of
    the barge moves by some 1e-3 rad in these 2 s of waves), where ``[0, 1e200, 1e200]`` used to record 0."""
    unit = _joint_coordinate(tmp_path / "unit", [0.0, 1.0, 0.0])
    scaled = _joint_coordinate(tmp_path / "scaled", [0.0, scale, 0.0])
    assert np.max(np.abs(unit)) > 1e-5  # the hinge moves: a coordinate stuck at 0 would fail below
    np.testing.assert_allclose(scaled, unit, rtol=1e-9, atol=1e-15)


def test_a_start_pose_corrected_within_the_tolerance_is_reported(tmp_path) -> None:
    """barge2 lifted by a tenth of the assembly's tolerance: the run goes on and its summary names the move."""
    lift = 0.1 * ASSEMBLY_TOLERANCE * 2.26  # the scene's length scale is its largest cg coordinate, 2.26 m
    case = Case("barge2 lifted slightly", ["run", "{dir}/s.toml", "--out", "{dir}/out.h5"],
                {"s.toml": _changed(_body(1, initial_displacement=[0.0, 0.0, lift, 0.0, 0.0, 0.0]))})
    argv = _materialise(case, tmp_path)
    import contextlib
    import io

    from wec_cosim.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()) as err:
        code = main(argv)
    assert code == 0, err.getvalue()
    assert "assembly moved the start pose" in out.getvalue() and "barge2 by" in out.getvalue(), out.getvalue()


@pytest.fixture(scope="module")
def unstable_databases(tmp_path_factory) -> dict[str, object]:
    """The cylinder's database with its heave hydrostatic stiffness C33 made negative (scaled by -0.5 and -2): a
    floating body's C33 is rho g times its waterplane area, never negative."""
    from hydro_fmu.bemio import write_bemio
    from orchestrator.scenario import load_scenario
    from orchestrator.scene import load_database

    from .conftest import SCENARIOS

    folder = tmp_path_factory.mktemp("unstable")
    out = {}
    for factor in (-0.5, -2.0):
        hdb, _ = load_database(load_scenario(SCENARIOS / "cylinder_regular.toml"), log=None)
        hdb.hydrostatic_stiffness[0][2, 2] *= factor
        out[f"C33 x {factor}"] = write_bemio(hdb, folder / f"c33_{-factor:g}.h5")
    return out


@pytest.mark.parametrize("command", ["rao", "steady", "run"])
@pytest.mark.parametrize("label", ["C33 x -0.5", "C33 x -2.0"])
def test_a_statically_unstable_database_is_named_by_every_command(tmp_path, unstable_databases, command,
                                                                   label) -> None:
    """``rao`` and ``steady`` refuse it before solving; ``run`` diverges (exponentially, rate sqrt(|C33|/M)) and
    names the cause, not only the output that crossed the limit."""
    db = unstable_databases[label]
    data = bundled("cylinder_regular")
    data["hydro"]["database"] = str(db)
    data["simulation"]["duration"] = 60.0
    argv = ["run", "{dir}/s.toml", "--quiet", "--out", "{dir}/out.h5"] if command == "run" else [
        command, "{dir}/s.toml", "--out", "{dir}/out.h5"]
    case = Case(f"{command} on {label}", argv, {"s.toml": data},
                [str(db), "'float' heave is statically unstable", "C33 = -"])
    code, stderr = run_in_process(_materialise(case, tmp_path))
    check(case, code, stderr, tmp_path)
