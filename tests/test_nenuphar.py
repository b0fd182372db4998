"""Seed 001's Nenuphar (``scenarios/nenuphar.toml``, docs/nenuphar.md): the device's symmetry in the frequency and
time domains, the static equilibrium before waves start, and the time domain against the exact linear
frequency domain (slow).

Lateral body k lies at 60 (k - 1) deg and hangs on hinge k. The mirror y -> -y maps body k to body 8 - k (2 <-> 6,
3 <-> 5) and a wave at 0 deg to itself; the mirror about the 30 deg line maps body 1 <-> 2, 3 <-> 6, 4 <-> 5 and a
wave at 30 deg to itself; the rotation by 60 deg maps body k to k + 1 and a wave at 0 deg to 60 deg. Hinge axes
follow the bodies (positive: the outer end up), so mirror-image hinges have equal angles and the rotation
relabels them. These are exact properties of the model: the database is solved with the same symmetry
(``hydro.bem_symmetry = "D6"``), so they must hold to round-off in the frequency domain (issue 14: 1e-6) and to
the time stepping's own precision in the time domain (1 %).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from mbd_fmu.moorings import catenary_tensions
from orchestrator.cosim.simulation import run_scenario
from orchestrator.cosim.study import regular_wave
from orchestrator.reference import frequency_domain
from orchestrator.results import read_results
from orchestrator.results.analysis import steady_response
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS

SCENARIO = SCENARIOS / "nenuphar.toml"
OMEGA = np.round(np.arange(0.3, 3.31, 0.1), 10)
MIRROR_0 = [(2, 6), (3, 5)]
MIRROR_30 = [(1, 2), (3, 6), (4, 5)]


@pytest.fixture(scope="module")
def scene():
    return load_scene(load_scenario(SCENARIO), log=None)


@pytest.fixture(scope="module")
def responses(scene):
    return {h: frequency_domain.solve(scene, OMEGA, heading_deg=h) for h in (0.0, 15.0, 30.0, 60.0)}


def hinge(fd, k: int) -> np.ndarray:
    return fd.joint_rao[f"hinge{k}"][:, 0]


def largest_hinge(fd) -> float:
    return max(float(np.max(np.abs(hinge(fd, k)))) for k in range(1, 7))


def test_mirror_image_hinges_respond_equally_in_the_frequency_domain(responses) -> None:
    """At 0 and 30 deg the mirror-image hinges' complex RAOs and PTO powers agree to 1e-6 of the largest; at
    15 deg, which no mirror of the device maps to itself, the same pairs differ (the check can fail)."""
    for heading, pairs in ((0.0, MIRROR_0), (30.0, MIRROR_30)):
        fd = responses[heading]
        scale, power = largest_hinge(fd), max(float(np.max(p)) for p in fd.pto_power.values())
        for a, b in pairs:
            assert np.max(np.abs(hinge(fd, a) - hinge(fd, b))) < 1e-6 * scale, (heading, a, b)
            assert np.max(np.abs(fd.pto_power[f"pto{a}"] - fd.pto_power[f"pto{b}"])) < 1e-6 * power, (heading, a, b)
    fd = responses[15.0]
    assert np.max(np.abs(hinge(fd, 2) - hinge(fd, 6))) > 0.05 * largest_hinge(fd)
    assert np.max(np.abs(hinge(fd, 1) - hinge(fd, 4))) > 0.05 * largest_hinge(fd)


def test_heading_60_is_heading_0_with_the_hinges_relabelled(responses) -> None:
    """Hinge k + 1 at 60 deg is hinge k at 0 deg (1e-6 of the largest RAO); the central heave and the heave PTO's
    power do not depend on which of the six equivalent headings the wave comes from."""
    at0, at60 = responses[0.0], responses[60.0]
    scale = largest_hinge(at0)
    for k in range(1, 7):
        assert np.max(np.abs(hinge(at60, k % 6 + 1) - hinge(at0, k))) < 1e-6 * scale, k
        p0, p60 = at0.pto_power[f"pto{k}"], at60.pto_power[f"pto{k % 6 + 1}"]
        assert np.max(np.abs(p60 - p0)) < 1e-6 * np.max(p0), k
    heave0, heave60 = at0.body_rao("central")[:, 2], at60.body_rao("central")[:, 2]
    assert np.max(np.abs(heave60 - heave0)) < 1e-6 * np.max(np.abs(heave0))
    np.testing.assert_allclose(at60.pto_power["heave_pto"], at0.pto_power["heave_pto"], rtol=1e-6)
    assert np.max(np.abs(hinge(at0, 1) - hinge(at0, 4))) > 0.05 * scale  # the wave does tell 1 from 4


def test_static_equilibrium_balances_weight_buoyancy_lines_and_tether(scene) -> None:
    """The equilibrium found before the waves: the six lines pull equally with the tensions of the elastic
    catenary at their fairleads (evaluated here from the fairlead's position, not by the model), the six hinges
    bend equally, and the whole device's vertical forces balance: buoyancy and hydrostatic restoring up, weights,
    lines and tether down, to 1e-6 of the weight."""
    found = scene.equilibrium()
    s = scene.scenario
    eq = found.equilibrium
    x = eq.displacement
    assert eq.residual < 1e-6 * 9.81 * sum(b["mass"] for b in found.bodies)
    forces = {e.name: e for e in s.forces}
    central = [b.name for b in s.bodies].index("central")
    rot = eq.pose.R[central]
    lines = [e for e in found.elements if e["name"].startswith("line")]
    assert len(lines) == 6
    vertical = 0.0
    for e in lines:
        spec = forces[e["name"]]
        fairlead = eq.pose.r[central] + rot @ (np.asarray(spec.fairlead) - np.asarray(s.bodies[central].cg))
        d = fairlead - np.asarray(spec.anchor)
        h, v = catenary_tensions(math.hypot(d[0], d[1]), d[2], spec.length, spec.weight, spec.ea)
        assert e["horizontal"] == pytest.approx(h, rel=1e-9) and e["vertical"] == pytest.approx(v, rel=1e-9)
        vertical -= v
    tether = forces["tether"]
    keel = eq.pose.r[central] + rot @ (np.asarray(tether.point2) - np.asarray(s.bodies[central].cg))
    tension = tether.stiffness * (np.linalg.norm(keel - np.asarray(tether.point1)) - tether.free_length)
    assert next(e for e in found.elements if e["name"] == "tether")["force"] == pytest.approx(tension, rel=1e-9)
    vertical -= tension * (keel - np.asarray(tether.point1))[2] / np.linalg.norm(keel - np.asarray(tether.point1))
    idx = scene.hydro_index()
    for i, b in enumerate(found.bodies):
        restoring = -(scene.hdb.hydrostatic_stiffness[i] @ x[i])[2]  # -C x, heave row, about the reference pose
        vertical += b["buoyancy"] - b["weight"] + restoring
    del idx
    assert abs(vertical) < 1e-6 * sum(b["weight"] for b in found.bodies)
    angles = [j["coordinates"][0] for j in found.joints]
    np.testing.assert_allclose(angles, angles[0], rtol=0, atol=1e-12)
    assert abs(angles[0]) > 0  # the hub sinks under the lines' pull: the rafts hang off it
    assert x[central, 2] != 0
    assert found.bodies[central]["buoyancy"] > found.bodies[central]["weight"] + 6 * lines[0]["vertical"]


def test_time_domain_mirror_image_hinges_and_the_equilibrium_report(tmp_path: Path) -> None:
    """Two FMUs through fmpy at 0 deg (T = 4.8 s, 0.5 m): the static equilibrium is reported before the run and
    written to the results file, the run starts from it at rest, and the mirror-image hinges 2 and 6, 3 and 5
    move alike within 1 % of their amplitude over the whole run."""
    s = regular_wave(load_scenario(SCENARIO), 4.8, 0.5, 0.0, periods=8)
    messages: list[str] = []
    result = run_scenario(s, tmp_path / "mirror.h5", progress=False, log=messages.append)
    report = "\n".join(messages)
    assert "static equilibrium" in report and "line6: fairlead tension" in report and "tether" in report
    data = read_results(result.path)
    stored = data["attrs"]["static_equilibrium"]
    assert len(stored["elements"]) == 7 + 7  # six lines, the tether, six hinge PTOs and the heave PTO
    offsets = np.array([b["offset"] for b in stored["bodies"]])
    np.testing.assert_allclose(data["bodies/central/displacement"][0], offsets[0], rtol=0, atol=1e-9)
    for a, b in MIRROR_0:
        ya, yb = data[f"joints/hinge{a}/coordinate"][:, 0], data[f"joints/hinge{b}/coordinate"][:, 0]
        swing = ya - ya[0]
        assert np.max(np.abs(ya - yb)) < 0.01 * np.max(np.abs(swing)), (a, b)
    first = data["joints/hinge1/coordinate"][:, 0]
    assert np.max(np.abs(first - data["joints/hinge4/coordinate"][:, 0])) > 0.05 * np.max(np.abs(first - first[0]))


@pytest.mark.slow
def test_time_domain_mirror_symmetry_at_30_deg(tmp_path: Path) -> None:
    s = regular_wave(load_scenario(SCENARIO), 4.8, 0.5, 30.0, periods=8)
    data = read_results(run_scenario(s, tmp_path / "mirror30.h5", progress=False, log=None).path)
    for a, b in MIRROR_30:
        ya, yb = data[f"joints/hinge{a}/coordinate"][:, 0], data[f"joints/hinge{b}/coordinate"][:, 0]
        assert np.max(np.abs(ya - yb)) < 0.01 * np.max(np.abs(ya - ya[0])), (a, b)


@pytest.mark.slow
@pytest.mark.parametrize("period", [3.5, pytest.param(4.8, marks=pytest.mark.acceptance), 6.5])
def test_time_domain_against_the_frequency_domain_at_half_a_metre(scene, period: float, tmp_path: Path) -> None:
    """0.5 m waves at 0 deg, macro step T/100, 15 periods: the six hinge angles and the central heave within 1 % and
    2 deg of the exact linear answer, the seven PTOs' mean powers within 2 % (power goes as the square)."""
    s = regular_wave(scene.scenario, period, 0.5, 0.0)
    r = steady_response(s, read_results(run_scenario(s, tmp_path / "td.h5", progress=False, log=None).path))
    fd = frequency_domain.solve(scene, np.array([2 * math.pi / period]), heading_deg=0.0)
    for k in range(1, 7):
        td, exact = r[f"hinge{k} 0"], hinge(fd, k)[0]
        assert abs(abs(td) / abs(exact) - 1) < 0.01, (k, td, exact)
        assert abs(math.degrees(np.angle(td / exact))) < 2.0, (k, td, exact)
    td, exact = r["central heave"], fd.body_rao("central")[0, 2]
    assert abs(abs(td) / abs(exact) - 1) < 0.01 and abs(math.degrees(np.angle(td / exact))) < 2.0
    for name, p in fd.pto_power.items():
        assert r[f"{name} power"] == pytest.approx(p[0], rel=0.02), name
