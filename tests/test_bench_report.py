"""The bench report's parts (wec_cosim/benchreport/): points rerun as the commands they print, list overrides, the error
measures against independent answers, run classification and the report files. The whole `wec-cosim bench
--quick` runs in the slow suite (under 10 minutes)."""

from __future__ import annotations

import csv
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from orchestrator.errors import ScenarioError
from orchestrator.results import read_results
from orchestrator.scenario import apply_overrides, load_scenario
from orchestrator.scene import load_scene
from wec_cosim.benchreport import errors
from wec_cosim.benchreport.points import ROOT, Point, Variant, run_point
from wec_cosim.sweeps.grid import apply_params

CYLINDER = Variant("scenarios/cylinder_regular.toml", ("simulation.duration=100", "simulation.step=0.2"))
IRREGULAR = Variant("scenarios/two_floats.toml", ("waves.kind=irregular", "waves.spectrum=jonswap", "waves.hs=1.0",
                                                  "waves.tp=6.0", "waves.seed=7", "simulation.duration=150"))


def test_a_variant_reruns_as_the_command_it_prints(tmp_path: Path) -> None:
    """The report's promise: the printed command reproduces the point. Same steady response from run_point and
    from `wec-cosim run` with the printed arguments (the runs are deterministic)."""
    point = run_point(CYLINDER, errors.regular_wave_error)
    assert point.stable and np.isfinite(point.error)
    args = shlex.split(CYLINDER.command())[2:]  # after "wec-cosim run"
    out = tmp_path / "rerun.h5"
    run = subprocess.run([sys.executable, "-m", "wec_cosim.cli", "run", *args, "--out", str(out), "--quiet"],
                         cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    scene = load_scene(apply_overrides(load_scenario(ROOT / CYLINDER.scenario), list(CYLINDER.overrides)), log=None)
    from orchestrator.cosim.simulation import compare_with_frequency_domain

    class Result:  # the comparisons of the rerun, as run_scenario makes them
        comparisons = compare_with_frequency_domain(scene, read_results(out))

    assert errors.regular_wave_error(scene, {}, Result) == pytest.approx(point.error, rel=1e-9, abs=1e-15)


def test_with_replaces_a_key() -> None:
    v = Variant("s.toml", ("simulation.step=0.1", "waves.hs=1")).with_("simulation.step=0.05", "simulation.master=x")
    assert v.overrides == ("waves.hs=1", "simulation.step=0.05", "simulation.master=x")
    assert v.command() == ("wec-cosim run s.toml --set waves.hs=1 --set simulation.step=0.05 "
                           "--set simulation.master=x")
    listed = Variant("s.toml", ('bodies.b.dofs=["surge", "heave"]',))
    assert shlex.split(listed.command())[-1] == 'bodies.b.dofs=["surge", "heave"]'  # quoted for the shell


def test_set_takes_a_list_as_a_toml_array_and_checks_it() -> None:
    s = load_scenario(ROOT / "scenarios" / "two_floats.toml")
    s2 = apply_overrides(s, ['bodies.fore.dofs=["surge", "heave"]'])
    assert s2.bodies[0].dofs == ["surge", "heave"] and s.bodies[0].dofs == ["heave"]
    s3 = apply_overrides(s, ["bodies.fore.drag_coefficient=[0, 0, 1.2, 0, 0, 0]",  # optional lists
                             "bodies.fore.drag_area=[0, 0, 28.3, 0, 0, 0]"])
    assert s3.bodies[0].drag_coefficient == [0, 0, 1.2, 0, 0, 0]
    with pytest.raises(ScenarioError, match=r"dofs\[0\]: 'bogus' is not one of"):
        apply_overrides(s, ['bodies.fore.dofs=["bogus"]'])
    with pytest.raises(ScenarioError, match="expected an array"):
        apply_overrides(s, ["bodies.fore.dofs=3"])
    with pytest.raises(ScenarioError, match="or a list of them and cannot be set"):
        apply_overrides(s, ["bodies.fore.geometry=3"])
    with pytest.raises(ScenarioError, match="is not a single number, string or boolean and cannot be set"):
        apply_params(s, (("bodies.fore.drag_coefficient", [0.0] * 6),))  # sweep grids keep their rule


def test_settings_a_scene_refuses_are_an_unavailable_point() -> None:
    p = run_point(Variant("scenarios/hinge_barge.toml", ("simulation.master=monolithic",)))
    assert p.status == "unavailable" and "monolithic" in p.message and not p.stable


def test_irregular_error_converges_to_the_exact_linear_response() -> None:
    """Two floats in a JONSWAP sea against the superposition of frequency-domain RAOs over the realised
    components: small at the scenario's step, and smaller at half the step (the co-simulation converges to the
    linear answer; an error measure with a wrong reference, phase convention or sea would not shrink)."""
    e = [run_point(IRREGULAR.with_(f"simulation.step={h}"), errors.irregular_error).error for h in (0.2, 0.1)]
    assert e[0] < 0.05 and e[1] < 0.6 * e[0], e


def test_exact_response_of_a_one_component_sea_is_the_regular_wave_answer() -> None:
    """The superposition with one component (a regular wave of phase 40 deg) has the first harmonic that the
    regular-wave comparison takes as exact: the RAO times the amplitude times exp(i phase) (same convention)."""
    from orchestrator.results.analysis import harmonic_fit

    v = Variant("scenarios/two_floats.toml", ("waves.phase_deg=40",))
    scene = load_scene(apply_overrides(load_scenario(ROOT / v.scenario), list(v.overrides)), log=None)
    w = scene.scenario.waves
    omega = 2 * np.pi / w.period
    t = np.linspace(0.0, 4 * w.period, 401)
    coords, x = errors.linear_irregular_response(scene, t)
    from orchestrator.reference import frequency_domain

    fd = frequency_domain.solve(scene, np.array([omega]))
    for j, (body, dof) in enumerate(coords):
        exact = fd.body_rao(body)[0, dof] * w.height / 2 * np.exp(1j * np.radians(40.0))
        assert harmonic_fit(t, x[:, j], omega)[0] == pytest.approx(exact, rel=1e-9)


def test_report_files_hold_every_point_with_its_command(tmp_path: Path) -> None:
    from wec_cosim.benchreport.report import Report, write

    rep = Report(quick=True)
    good = Point(CYLINDER, "ok", 0.5, 60.0, error=0.001)  # RTF 120
    bad = Point(CYLINDER.with_("simulation.step=5"), "diverged", float("nan"), 12.0, message="output x is not finite")
    rep.record("work_precision", good, case="cylinder", factor="master", option="jacobi", step=0.2)
    rep.record("work_precision", bad, case="cylinder", factor="master", option="jacobi", step=5)
    rep.first_screen = ["## Recommended settings"]
    path = write(rep, tmp_path)
    text = path.read_text()
    assert text.index("## Recommended settings") < 1500 and "points.csv" in text
    rows = list(csv.DictReader(open(tmp_path / "points.csv")))
    assert [r["status"] for r in rows] == ["ok", "diverged"]
    assert rows[0]["rtf"] == "120" and rows[1]["rtf"] == "" and rows[1]["command"].endswith("simulation.step=5")


def test_a_failing_part_leaves_the_others_and_an_interrupt_keeps_the_parts_done(tmp_path: Path) -> None:
    from wec_cosim.benchreport.report import Report, run_parts

    def broken() -> str:
        raise ValueError("no database")

    def interrupted() -> str:
        raise KeyboardInterrupt

    rep = Report(quick=True)
    rep.record("a", Point(CYLINDER, "ok", 0.5, 60.0, error=0.001))
    run_parts(rep, (("first", lambda: "## first"), ("second", broken), ("third", lambda: "## third")), tmp_path,
              lambda _: None)
    assert rep.sections[0] == "## first" and "no database" in rep.sections[1] and rep.sections[2] == "## third"
    with pytest.raises(KeyboardInterrupt):
        run_parts(rep, (("fourth", lambda: "## fourth"), ("fifth", interrupted)), tmp_path, lambda _: None)
    text = (tmp_path / "README.md").read_text()
    assert "## fourth" in text and "**Interrupted**" in text and (tmp_path / "points.csv").exists()


@pytest.mark.slow
def test_bench_quick_writes_the_report_in_under_ten_minutes(tmp_path: Path) -> None:
    import time

    start = time.time()
    run = subprocess.run([sys.executable, "-m", "wec_cosim.cli", "bench", "--quick", "--out", str(tmp_path),
                          "--quiet"], cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-3000:]
    text = (tmp_path / "README.md").read_text()
    assert "## Recommended settings" in text and "## Hard cases" in text and "## Scaling" in text
    rows = list(csv.DictReader(open(tmp_path / "points.csv")))
    assert rows and all(r["command"].startswith("wec-cosim run scenarios/") for r in rows)
    for png in ("work_precision_hinge_barge.png", "scaling.png"):
        assert (tmp_path / "figures" / png).stat().st_size > 10_000
    print(f"wec-cosim bench --quick: {time.time() - start:.0f} s")
