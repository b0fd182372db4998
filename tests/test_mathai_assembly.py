"""Mathai's triple modular assembly (seed 001, section 3.4; ``scenarios/mathai_assembly.toml``,
docs/mathai_assembly.md): the breakover angles' shape in the frequency domain, and the time domain against it.

Expected values from the geometry of the waves: the relative pitch of two rafts is largest where the wave
puts a crest on one raft and a trough on the next, a wavelength (along the assembly) of twice the raft
spacing s = 80 + 2 ft; in quartering seas that wavelength is measured along the assembly, so the wave itself
is shorter by cos 45 deg, and its crests cross each 48 ft wide raft obliquely, which averages the pressure
over the width (factor sin(u)/u, u = k B sin 45 deg / 2): smaller peaks. In long waves the rafts follow the
wave's slope, and the breakover angle is the slope's change over one spacing, k^2 s per metre of amplitude.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hydro_fmu.waves import wavenumber
from orchestrator.cosim.simulation import run_scenario
from orchestrator.cosim.study import regular_wave
from orchestrator.reference import frequency_domain
from orchestrator.results import read_results
from orchestrator.results.analysis import steady_response
from orchestrator.scenario import load_scenario
from orchestrator.scene import load_scene

from .conftest import SCENARIOS

SCENARIO = SCENARIOS / "mathai_assembly.toml"
FOOT = 0.3048
SPACING = 82 * FOOT   # raft centre to raft centre
WIDTH = 48 * FOOT
DEPTH = 50 * FOOT
G = 9.81
OMEGA = np.round(np.arange(0.05, 1.8 + 1e-9, 0.01), 10)


@pytest.fixture(scope="module")
def scene():
    return load_scene(load_scenario(SCENARIO), log=None)


@pytest.fixture(scope="module")
def curves(scene):
    return {h: frequency_domain.solve(scene, OMEGA, heading_deg=h) for h in (0.0, 45.0)}


def frequency_of(k: float) -> float:
    return math.sqrt(G * k * math.tanh(k * DEPTH))


def breakover(fd, hinge: str) -> np.ndarray:
    return np.abs(fd.joint_rao[hinge][:, 0])


def test_breakover_peaks_where_the_wave_spans_two_rafts(curves) -> None:
    """Peak frequencies within 12 % of the wave whose (along-assembly) wavelength is twice the raft spacing:
    1.09 rad/s following, 1.31 rad/s quartering; the quartering peak is the later one."""
    k = 2 * math.pi / (2 * SPACING)
    expected = {0.0: frequency_of(k), 45.0: frequency_of(k / math.cos(math.radians(45)))}
    for heading, fd in curves.items():
        for hinge in ("hinge1", "hinge2"):
            peak = OMEGA[int(np.argmax(breakover(fd, hinge)))]
            assert peak == pytest.approx(expected[heading], rel=0.12), (heading, hinge, peak)
    assert OMEGA[np.argmax(breakover(curves[45.0], "hinge1"))] > OMEGA[np.argmax(breakover(curves[0.0], "hinge1"))]


def test_following_seas_break_the_assembly_more_than_quartering_seas(curves) -> None:
    """Each hinge's peak is lower in quartering seas, by about the averaging over the oblique crests'
    width (sin u / u = 0.87 at the quartering peak): between 0.75 and 0.97 of the following-seas peak."""
    k = 2 * math.pi / (2 * SPACING) / math.cos(math.radians(45))
    u = k * WIDTH * math.sin(math.radians(45)) / 2
    assert math.sin(u) / u == pytest.approx(0.87, abs=0.01)
    for hinge in ("hinge1", "hinge2"):
        ratio = breakover(curves[45.0], hinge).max() / breakover(curves[0.0], hinge).max()
        assert 0.75 < ratio < 0.97, (hinge, ratio)


def test_long_waves_bend_the_assembly_by_the_change_of_slope(curves) -> None:
    """At 0.05 rad/s (wavelength 1.5 km in 50 ft of water) the breakover angle is k^2 s per metre of amplitude
    within 30 %, in following seas; the curves rise monotonically to their peak."""
    k = wavenumber(0.05, DEPTH, G)
    for hinge in ("hinge1", "hinge2"):
        low = breakover(curves[0.0], hinge)
        assert low[0] == pytest.approx(k**2 * SPACING, rel=0.3), hinge
        rising = low[: int(np.argmax(low)) + 1]
        assert np.all(np.diff(rising) > 0), hinge


@pytest.mark.slow
@pytest.mark.parametrize("heading", [pytest.param(0.0, marks=pytest.mark.acceptance), 45.0])
def test_time_domain_against_the_frequency_domain_at_five_frequencies(scene, heading: float, tmp_path) -> None:
    """One foot of amplitude, macro step T/100, 15 periods (two FMUs through fmpy): both breakover angles within
    2 % of the exact linear answer at 0.4, 0.7, 1.0, 1.3 and 1.6 rad/s."""
    for omega in (0.4, 0.7, 1.0, 1.3, 1.6):
        s = regular_wave(scene.scenario, 2 * math.pi / omega, FOOT, heading)
        r = steady_response(s, read_results(run_scenario(s, tmp_path / "td.h5", progress=False, log=None).path))
        fd = frequency_domain.solve(scene, np.array([omega]), heading_deg=heading)
        for hinge in ("hinge1", "hinge2"):
            td, exact = r[f"{hinge} 0"], fd.joint_rao[hinge][0, 0]
            assert abs(abs(td) / abs(exact) - 1) < 0.02, (omega, hinge, td, exact)


def test_rao_file_and_heading_figure_carry_the_breakover_angles(scene, curves, tmp_path) -> None:
    """`wec-cosim rao` writes the joints' RAOs per heading and `wec-cosim plot` draws them, one column per heading."""
    import h5py
    from matplotlib.image import imread

    from orchestrator.reference.response_files import write_rao_file
    from orchestrator.results.plotting import plot_file

    path = tmp_path / "mathai.h5"
    write_rao_file(scene, path)
    with h5py.File(path) as f:
        omega = f["omega"][()]
        sweep = f["heading_sweep/joints/hinge1/rao"][()]
        assert list(f["heading_sweep/headings_deg"][()]) == [0.0, 45.0]
    k = int(np.argmin(np.abs(OMEGA - omega[10])))
    assert sweep[1, 10, 0] == pytest.approx(curves[45.0].joint_rao["hinge1"][k, 0], rel=1e-9)
    figures = plot_file(path, tmp_path / "png")
    assert [p.name for p in figures] == ["mathai_rao.png", "mathai_headings.png"]
    assert imread(figures[1]).shape[1] > imread(figures[1]).shape[0]  # two columns side by side
