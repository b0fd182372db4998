"""Elevation records in the forms users bring (scenarios/data/elevation/, README.md there): each reads to the known
elevation it was written from, and the run's summary names the form found."""

from __future__ import annotations

import numpy as np
import pytest

from hydro_fmu.wave_records import WaveDataError, read_elevation

from .conftest import SCENARIOS

FOLDER = SCENARIOS / "data" / "elevation"


def known(t: np.ndarray) -> np.ndarray:
    """The elevation the files were made from (make_files.py)."""
    return 0.5 * np.cos(2 * np.pi * t / 8) + 0.2 * np.sin(2 * np.pi * t / 5 + 0.3)


@pytest.mark.parametrize("name, form", [
    ("eta_percent_comments.txt", "two columns, whitespace-separated, 2 comment lines"),
    ("eta_header_units.dat", "two columns, whitespace-separated, header 'Time [s]    Eta [m]', 1 comment line"),
    ("eta_plain.csv", "two columns, comma-separated"),
    ("etaData.mat", "WEC-Sim elevation file (MATLAB 5 .mat, array etaData, 400 rows)"),
    ("etaData_v73.mat", "WEC-Sim elevation file (MATLAB 7.3 .mat, array etaData, 400 rows)"),
])
def test_each_form_reads_the_known_elevation(name: str, form: str) -> None:
    record = read_elevation(FOLDER / name)
    assert record.form == form
    assert record.dt == pytest.approx(0.1, rel=1e-12) and len(record.eta) == 400
    exact = name.endswith(".mat")  # binary forms carry every digit; the text forms 6 decimals
    np.testing.assert_allclose(record.eta, known(record.times()), rtol=0, atol=1e-12 if exact else 5.1e-7)


@pytest.mark.parametrize("text, form", [
    ("t;eta\n0;1\n0,5;2\n", None),  # decimal commas are not read as numbers: refused below
    ("time (s); elevation (m)\n0;1\n0.5;2\n1;3\n1.5;4\n", "two columns, semicolon-separated"),
    ("# made by hand\nt, x, eta\n0, 9, 1\n0.5, 9, 2\n1, 9, 3\n1.5, 9, 4\n", "3 columns, comma-separated"),
    ("0 1 % first sample\n0.5 2\n1 3\n1.5 4\n", "two columns, whitespace-separated"),
])
def test_separators_headers_and_inline_comments(tmp_path, text: str, form: str | None) -> None:
    path = tmp_path / "eta.txt"
    path.write_text(text)
    if form is None:
        with pytest.raises(WaveDataError, match=r"eta.txt:3: not a number in '0,5;2'"):
            read_elevation(path)
        return
    record = read_elevation(path)
    assert record.form.startswith(form)
    np.testing.assert_array_equal(record.eta, [1.0, 2.0, 3.0, 4.0])
    assert record.dt == 0.5


def test_mat_file_without_a_two_column_array_is_named(tmp_path) -> None:
    from scipy.io import savemat

    path = tmp_path / "eta.mat"
    savemat(path, {"waves": np.zeros((3, 3))})
    with pytest.raises(WaveDataError, match=r"eta.mat: a WEC-Sim elevation file holds one N x 2 array .*waves "
                                            r"\(3, 3\)"):
        read_elevation(path)


def test_run_summary_names_the_form(tmp_path) -> None:
    """A 12 s run of the floating cylinder driven by WEC-Sim's etaData.mat names the form in its summary."""
    from orchestrator.cosim.simulation import format_summary, run_scenario
    from orchestrator.scenario import load_scenario

    text = (SCENARIOS / "cylinder_regular.toml").read_text()
    start, end = text.index("[waves]"), text.index("[hydro]")
    text = (text[:start] + f'[waves]\nkind = "elevation"\nelevation_file = "{(FOLDER / "etaData.mat").as_posix()}"\n'
            f"ramp_time = 4.0\n\n" + text[end:])
    text = text.replace("[hydro]\n", f'[hydro]\ncache_dir = "{(SCENARIOS / "hydro_cache").as_posix()}"\n')
    text = text.replace("duration = 200.0", "duration = 12.0")
    (tmp_path / "eta_run.toml").write_text(text)
    result = run_scenario(load_scenario(tmp_path / "eta_run.toml"), tmp_path / "out.h5", in_process=True,
                          progress=False, log=None)
    summary = format_summary(result)
    assert "waves: elevation record" in summary
    assert "etaData.mat read as WEC-Sim elevation file (MATLAB 5 .mat" in summary
    assert "400 samples every 0.1 s" in summary
