"""Seed 000's node/link-arm arrays, 4N3LA and 9N9LA (scenarios/array_*.toml, docs/arrays.md).

Expected values come from geometry (Table 2, the link-arm length), from counting (Grubler's
mobility of bodies and spherical joints), from statics (the pretensioned moorings balance through
the arms) and from the exact linear frequency-domain solution of the same scene; the energy
account closes by conservation. Databases: Capytaine 3.0, committed in scenarios/hydro_cache/.
"""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pytest

from orchestrator import frequency_domain
from orchestrator.analysis import harmonic_fit, steady_window, window_mean
from orchestrator.results import read_results
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene
from orchestrator.simulation import run_scenario

from .conftest import SCENARIOS

ARRAYS = ("array_4n3la", "array_9n9la")
TABLE_2 = {"S3": (0.0, 0.0), "C1": (0.7, -1.21), "S1": (0.0, -2.42), "S2": (2.1, -1.21)}


def generator():
    spec = importlib.util.spec_from_file_location("arrays_generate", SCENARIOS / "data" / "arrays" / "generate.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def scenes():
    return {name: load_scene(load_scenario(SCENARIOS / f"{name}.toml"), log=None) for name in ARRAYS}


def test_committed_scenarios_are_what_the_generator_writes(tmp_path, monkeypatch) -> None:
    gen = generator()
    monkeypatch.setattr(gen, "SCENARIOS", tmp_path)
    gen.main()
    for name in ARRAYS:
        assert (tmp_path / f"{name}.toml").read_text() == (SCENARIOS / f"{name}.toml").read_text(), (
            f"scenarios/{name}.toml differs from scenarios/data/arrays/generate.py's output: rerun the script")


def node_positions(name: str) -> dict[str, np.ndarray]:
    s = load_scenario(SCENARIOS / f"{name}.toml")
    return {b.name: np.array(b.cg) for b in s.hydro_bodies}


def test_4n3la_nodes_are_table_2_and_the_arms_are_1_4_m() -> None:
    """Node cgs within Table 2's rounding (1 cm) of it, every arm 1.4 m between its joints, joints and arm
    cgs at 0.4 m depth, arms 120 deg apart at C1."""
    s = load_scenario(SCENARIOS / "array_4n3la.toml")
    nodes = node_positions("array_4n3la")
    for name, (x, y) in TABLE_2.items():
        assert np.allclose(nodes[name], [x, y, -0.3], atol=0.005), name
    joints = {j.name: np.array(j.position) for j in s.joints}
    for arm in ("LA1", "LA2", "LA3"):
        ends = [p for n, p in joints.items() if n.startswith(arm + "_")]
        assert len(ends) == 2 and np.linalg.norm(ends[1] - ends[0]) == pytest.approx(1.4, abs=1e-9)
        assert all(p[2] == pytest.approx(-0.4) for p in ends)
        assert next(b for b in s.bodies if b.name == arm).cg[2] == pytest.approx(-0.4)
    directions = [nodes[n][:2] - nodes["C1"][:2] for n in ("S1", "S2", "S3")]
    assert np.allclose(np.sum([d / np.linalg.norm(d) for d in directions], axis=0), 0.0, atol=1e-9)


def test_9n9la_has_a_regular_hexagon_of_side_1_4_m_upstream_of_4n3la() -> None:
    """Six nodes 1.4 m from the hexagon's centre, 60 deg apart, alternating three-arm (C) and two-arm (D)
    nodes; C1 and S2 where 4N3LA has them; D1, D2 where 4N3LA has S3, S1; every arm 1.4 m."""
    nodes = node_positions("array_9n9la")
    four = node_positions("array_4n3la")
    ring = ["C1", "D1", "C2", "D3", "C3", "D2"]
    centre = np.mean([nodes[n] for n in ring], axis=0)
    angles = []
    for n in ring:
        r = nodes[n][:2] - centre[:2]
        assert np.linalg.norm(r) == pytest.approx(1.4, abs=1e-9)
        angles.append(math.degrees(math.atan2(r[1], r[0])))
    steps = np.diff(np.unwrap(np.radians(angles)))
    assert np.allclose(np.abs(np.degrees(steps)), 60.0, atol=1e-9)
    for a, b in (("C1", "C1"), ("S2", "S2"), ("D1", "S3"), ("D2", "S1")):
        assert np.allclose(nodes[a], four[b], atol=1e-12), (a, b)
    s = load_scenario(SCENARIOS / "array_9n9la.toml")
    degree = {n: 0 for n in nodes}
    for j in s.joints:
        degree[j.body2] += 1
        arm_ends = [np.array(k.position) for k in s.joints if k.body1 == j.body1]
        assert np.linalg.norm(arm_ends[1] - arm_ends[0]) == pytest.approx(1.4, abs=1e-9)
    assert {n: d for n, d in degree.items()} == {"C1": 3, "C2": 3, "C3": 3, "D1": 2, "D2": 2, "D3": 2,
                                                  "S1": 1, "S2": 1, "S3": 1}


@pytest.mark.parametrize("name, rigid, points, joints", [("array_4n3la", 7, 3, 6), ("array_9n9la", 18, 6, 18)])
def test_dof_count_and_redundant_rows(scenes, name, rigid, points, joints) -> None:
    """Grubler: 6 per rigid body + 3 per point mass - 3 per spherical joint; the analysis finds the
    constraint Jacobian of full rank (no redundant row) at the start and after a motion. A loop of
    spherical joints is not overconstrained: the hexagon's 36 equations are independent (its idle
    modes are the six arms' spins about their own axes)."""
    sim = scenes[name].multibody_simulator()
    expected = 6 * rigid + 3 * points - 3 * joints
    assert sim.report.dof == expected
    assert sim.report.redundant == []
    assert sim.report.rank == 3 * joints


@pytest.mark.parametrize("name", ARRAYS)
def test_reference_pose_is_a_static_equilibrium(scenes, name) -> None:
    """Mooring pretension, buoyancy, gravity and the arms' tensions balance at the reference pose."""
    from mbd_fmu.linearize import linearize

    scene = scenes[name]
    lin = linearize(scene.multibody_simulator().model)
    weight = scene.hdb.rho * scene.hdb.g * float(np.sum(scene.hdb.displaced_volume))
    assert lin.equilibrium_residual < 1e-9 * weight
