"""MoorDyn input files used as they are (scenarios/data/moordyn/, scenarios/data/rm3/rm3_moordyn.txt; README.md in
scenarios/data/moordyn says how they were written): what is read, what is refused, statics against exact sums of
weights, and RM3 moored by a file of six lines and three buoys."""

from __future__ import annotations

import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from mbd_fmu.moordyn_files import MoorDynFileError, read_moordyn_file, run_text, static_solve
from orchestrator.errors import ScenarioError
from orchestrator.scenario import apply_overrides, load_scenario

from .conftest import SCENARIOS

FILES = SCENARIOS / "data" / "moordyn"
RM3_FILE = SCENARIOS / "data" / "rm3" / "rm3_moordyn.txt"
RHO, G = 1025.0, 9.81


def submerged_weight(mass_per_length: float, diameter: float) -> float:
    """Weight in water per metre (N/m) of a line of that mass per length (kg/m) and volume-equivalent diameter."""
    return (mass_per_length - RHO * math.pi * diameter ** 2 / 4) * G


def test_rm3_file_is_read() -> None:
    f = read_moordyn_file(RM3_FILE)
    assert [pid for pid, _ in f.coupled] == [1, 2, 3]
    np.testing.assert_allclose(f.coupled[0][1], [3.0, 0.0, -21.0])
    assert f.line_ids == [1, 2, 3, 4, 5, 6] and f.kinds["free"] == 3 and f.kinds["fixed"] == 3
    assert f.time_step == 0.002 and f.depth == 70.0
    text = run_text(f, 1000.0, 9.81)
    assert "1 disableOutput" in text and "0 writeLog" in text and text.count("WtrDnsty") == 1


REFUSED = [
    ("coupled body", lambda t: t.replace("---------------------- POINTS", "---------------------- BODIES ---\n"
                                         "ID Attachment X0 Y0 Z0 r0 p0 y0 Mass CG* I* Volume CdA* Ca*\n"
                                         "(#) (-) (m) (m) (m) (deg) (deg) (deg) (kg) (m) (kg-m^2) (m^3) (m^2) (-)\n"
                                         "1 Coupled 0 0 0 0 0 0 0 0 0 0 0 0\n---------------------- POINTS", 1),
     r"rm3.txt:11: body 1 is Coupled: a 6-DOF coupled MoorDyn body is not supported; attach the lines to Coupled "
     r"points"),
    ("no coupled point", lambda t: t.replace("Coupled ", "Fixed   "), r"rm3.txt: no Coupled point"),
    ("no depth", lambda t: t.replace("70.0       WtrDpth\n", ""), r"sets no WtrDpth .* add a line '70.0  WtrDpth'"),
    ("unknown attachment", lambda t: t.replace("4   Free ", "4   Floating "),
     r"rm3.txt:14: unknown point attachment 'Floating'"),
    ("not MoorDyn", lambda t: "just some text\n1 2 3\n", r"no POINTS or no LINES section"),
]


@pytest.mark.parametrize("name, change, fragment", REFUSED, ids=[r[0] for r in REFUSED])
def test_refused_files_name_the_line_and_the_fix(tmp_path, name: str, change, fragment: str) -> None:
    path = tmp_path / "rm3.txt"
    path.write_text(change(RM3_FILE.read_text()))
    with pytest.raises(MoorDynFileError, match=fragment):
        read_moordyn_file(path)


def test_everything_hanging_from_one_point_weighs_on_it() -> None:
    """A chain, a free rod, a clump weight, a buoy and three lines joined at the clump (line-to-line), all hanging
    from one coupled point: MoorDyn's static force on the point is their total weight in water (exact)."""
    f = read_moordyn_file(FILES / "hanging_features.txt")
    assert f.kinds["rods"] == 1 and f.kinds["free"] == 2 and len(f.line_ids) == 4
    solution = static_solve(run_text(f), np.array([[0.0, 0.0, -5.0]]))
    chain = submerged_weight(60.0, 0.1) * (10.0 + 11.0 + 26.0 + 10.0)
    rod = submerged_weight(400.0, 0.5) * 4.0  # 4 m of 0.5 m pipe, 400 kg/m
    clump = 800.0 * G
    buoy = 100.0 * G - RHO * G * 0.5  # 100 kg, 0.5 m^3: floats
    expected = -(chain + rod + clump + buoy)
    assert solution.forces[0, 2] == pytest.approx(expected, rel=1e-3)
    assert abs(solution.forces[0, 0]) < 1e-3 * abs(expected)
    assert solution.free_points[3][2] > solution.free_points[2][2]  # the buoy above the clump it is tied to


def test_slack_line_on_the_sea_bed_carries_only_its_hanging_part() -> None:
    """A slack chain (100 m between an anchor 30 m away and a point 40 m above the bed) lies on the bed and hangs
    vertically: force w h (h = 40 m) to within one segment's weight (the lumped masses place the touchdown to a
    segment), and almost no horizontal force; without the bed it would carry its whole length."""
    f = read_moordyn_file(FILES / "slack_on_seabed.txt")
    solution = static_solve(run_text(f), np.array([[0.0, 0.0, -10.0]]))
    w = submerged_weight(60.0, 0.1)
    assert abs(solution.forces[0, 2] + w * 40.0) < w * 100.0 / 40
    assert abs(solution.forces[0, 0]) < 0.01 * w * 40.0


def _rm3(tmp_path: Path, extra: str = "", **replace: str) -> Path:
    text = (SCENARIOS / "rm3_moordyn_decay.toml").read_text().replace(
        'moordyn_file = "data/rm3/rm3_moordyn.txt"', f'moordyn_file = "{RM3_FILE.as_posix()}"').replace(
        'database = "data/rm3/rm3.h5"', f'database = "{(SCENARIOS / "data/rm3/rm3.h5").as_posix()}"')
    for old, new in replace.items():
        text = text.replace(old, new)
    path = tmp_path / "rm3.toml"
    path.write_text(text + extra)
    return path


@pytest.mark.parametrize("replace, fragment", [
    ({'coupled_bodies = ["spar", "spar", "spar"]': 'coupled_bodies = ["spar", "spar"]'},
     r"coupled_bodies names 2 bodies but .*rm3_moordyn.txt has 3 Coupled points \(1 at \(3, 0, -21\)"),
    ({'coupled_bodies = ["spar", "spar", "spar"]': 'coupled_bodies = ["spar", "spar", "bouy"]'},
     r"no body 'bouy' for Coupled point 3"),
    ({"rho = 1000.0": "rho = 1025.0"}, r"sets wtrdnsty = 1000.0 but environment.rho = 1025; make them equal"),
])
def test_scenario_names_what_to_fix(tmp_path, replace: dict, fragment: str) -> None:
    with pytest.raises(ScenarioError, match=fragment):
        load_scenario(_rm3(tmp_path, **replace))


def test_rm3_static_tensions_are_moordyns_static_solve(tmp_path) -> None:
    """Acceptance: RM3 at rest on the file's six lines and three buoys for 20 s. The tension at both ends of every
    line stays within 1 % of MoorDyn's own static solve of the same file (the file's lines carry the spar's
    designed pretension, so the bodies stay put), and every line end and coupled point is recorded."""
    from orchestrator.cosim.simulation import run_scenario

    zero = "[0.0, 0.0, 0.0, 0.0, 0.0, 0.0]"
    s = apply_overrides(load_scenario(_rm3(tmp_path)), [f"bodies.float.initial_displacement={zero}",
                                                        f"bodies.spar.initial_displacement={zero}",
                                                        "simulation.duration=20"])
    run_scenario(s, tmp_path / "rest.h5", in_process=True, progress=False, log=None)
    f = read_moordyn_file(RM3_FILE)
    static = static_solve(run_text(f, 1000.0, 9.81), np.array([p for _, p in f.coupled]))
    with h5py.File(tmp_path / "rest.h5", "r", swmr=True) as out:
        tensions = np.stack([out[f"mooring/line{i}/tension"][()] for i in f.line_ids], axis=1)  # (N, 6, 2)
        forces = np.stack([out[f"mooring/point{i}/force"][()] for i, _ in f.coupled], axis=1)
        spar = out["bodies/spar/displacement"][()]
    assert np.abs(tensions / static.end_tensions[None] - 1).max() < 0.01
    assert np.abs(forces[-1] - static.forces).max() < 0.01 * np.abs(static.forces).max()
    assert np.abs(spar).max() < 0.01  # m, rad


def _surge_zero_crossing_period_and_decrement(t: np.ndarray, x: np.ndarray) -> tuple[float, float]:
    """Mean period between zero up-crossings (linear interpolation) and mean logarithmic decrement of the positive
    peaks of a decay record."""
    i = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    up = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    j = np.flatnonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:])) + 1
    p = x[j][x[j] > 0]
    return float(np.mean(np.diff(up))), float(np.mean(np.log(p[:-1] / p[1:])))


def _linearised_surge_period(scene) -> float:  # noqa: ANN001
    """Undamped period of the slowest mode of the scene linearised at rest (surge on the soft buoyed legs): where
    det Re Z(omega) changes sign first, scanned from 0.01 rad/s."""
    from orchestrator.reference.frequency_domain import linear_model

    omega = np.arange(0.01, 0.2, 1e-4)
    det = np.array([np.linalg.det(z.real) for z in linear_model(scene, omega).impedance])
    i = int(np.flatnonzero(np.sign(det[:-1]) != np.sign(det[1:]))[0])
    return 2 * math.pi / (omega[i] - det[i] * (omega[i + 1] - omega[i]) / (det[i + 1] - det[i]))


@pytest.mark.slow
@pytest.mark.acceptance
def test_rm3_decay_with_moordyn_against_the_quasi_static_lines(tmp_path) -> None:
    """Acceptance: the bundled surge decay from 5 m (600 s), once with MoorDyn's line dynamics and once with the
    same file's lines as their linearised quasi-static stiffness. The quasi-static run's period is the linearised
    scene's undamped surge period within 1 % (radiation damps it little); MoorDyn's is within 3 % of it (the lines'
    dynamics and the catenary's stiffening at 5 m are what the quasi-static model leaves out), and it decays faster:
    the drag on the chains dissipates energy that the quasi-static lines cannot."""
    from orchestrator.cosim.simulation import run_scenario
    from orchestrator.scene import load_scene

    measured = {}
    for model in ("quasi_static", "moordyn"):
        s = apply_overrides(load_scenario(_rm3(tmp_path)), [f"mooring_lines.model={model}"])
        run_scenario(s, tmp_path / f"{model}.h5", in_process=True, progress=False, log=None)
        with h5py.File(tmp_path / f"{model}.h5", "r", swmr=True) as out:
            t, x = out["time"][()], out["bodies/spar/displacement"][:, 0]
        assert t[-1] == pytest.approx(600.0) and np.all(np.isfinite(x))
        measured[model] = _surge_zero_crossing_period_and_decrement(t, x)
    linear = _linearised_surge_period(load_scene(apply_overrides(load_scenario(_rm3(tmp_path)),
                                                                 ["mooring_lines.model=quasi_static"]), log=None))
    (qs_period, qs_decrement), (md_period, md_decrement) = measured["quasi_static"], measured["moordyn"]
    assert qs_period == pytest.approx(linear, rel=0.01)
    assert md_period == pytest.approx(qs_period, rel=0.03)
    assert md_decrement > 2 * max(qs_decrement, 0.0)


@pytest.mark.slow
@pytest.mark.acceptance
def test_rm3_irregular_sea_at_the_bundled_step(tmp_path) -> None:
    """Acceptance: the bundled irregular sea (Pierson-Moskowitz Hs 2.5 m, Tp 8 s) at the bundled 0.1 s step with the
    MoorDyn file's lines, 300 s: every line end stays in tension, and the bodies' heave follows the exact linear
    response of the same realised sea (the scene with the lines' linearised stiffness, which barely enters heave)
    to within 10 % RMS of the response, after the ramp and the radiation memory (measured over 600 s: float 0.6 %,
    spar 2.6 %; surge and pitch carry the free oscillation of the slow modes that the start excites, which the
    steady-state linear answer does not have, with the quasi-static lines as much: docs/benchmark_devices.md)."""
    from orchestrator.cosim.simulation import run_scenario
    from orchestrator.scene import load_scene
    from wec_cosim.benchreport.errors import linear_irregular_response

    irregular = (SCENARIOS / "rm3_moordyn_irregular.toml").read_text().replace(
        'moordyn_file = "data/rm3/rm3_moordyn.txt"', f'moordyn_file = "{RM3_FILE.as_posix()}"').replace(
        'database = "data/rm3/rm3.h5"', f'database = "{(SCENARIOS / "data/rm3/rm3.h5").as_posix()}"')
    (tmp_path / "irregular.toml").write_text(irregular)
    s = apply_overrides(load_scenario(tmp_path / "irregular.toml"), ["simulation.duration=300"])
    assert s.simulation.step == 0.1
    run_scenario(s, tmp_path / "irregular.h5", in_process=True, progress=False, log=None)
    f = read_moordyn_file(RM3_FILE)
    with h5py.File(tmp_path / "irregular.h5", "r", swmr=True) as out:
        t = out["time"][()]
        tensions = np.stack([out[f"mooring/line{i}/tension"][()] for i in f.line_ids], axis=1)
        heave = {b: out[f"bodies/{b}/displacement"][:, 2] for b in ("float", "spar")}
    assert t[-1] == pytest.approx(300.0) and np.all(np.isfinite(tensions)) and tensions.min() > 0
    linear = load_scene(apply_overrides(load_scenario(tmp_path / "irregular.toml"),
                                        ["simulation.duration=300", "mooring_lines.model=quasi_static"]), log=None)
    mask = t >= s.ramp_time + s.hydro.irf_duration
    coordinates, exact = linear_irregular_response(linear, t[mask])
    for body, x in heave.items():
        j = next(k for k, (b, d) in enumerate(coordinates) if b == body and d == 2)
        deviation = np.sqrt(np.mean((x[mask] - exact[:, j]) ** 2)) / np.sqrt(np.mean(exact[:, j] ** 2))
        assert deviation < 0.10, (body, deviation)
